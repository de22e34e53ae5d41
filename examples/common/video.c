/* --video: each run recorded as <out>/<tag>.mp4, frames rendered from the
 * run's camera at VIDEO_FPS frames per simulated second and piped to ffmpeg
 * (raw RGB on its standard input, H.264 out). The recording only reads the
 * scene, so a run with --video is the run without it. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include "demo.h"

#define VIDEO_FPS 30

static struct {
    FILE *pipe;
    char path[1100], tag[64];
    int w, h;
    long next;  /* the next frame's number */
    int failed; /* this run's recording gave up (said why) */
    int errors; /* failures since the last demo_video_finish */
} V;

int demo_video_fps(void) { return VIDEO_FPS; }

/* Whether an executable `name` is on PATH. */
static int on_path(const char *name)
{
    const char *path = getenv("PATH");
    if (!path) return 0;
    for (const char *p = path;;) {
        const char *colon = strchr(p, ':');
        size_t len = colon ? (size_t)(colon - p) : strlen(p);
        char file[4096];
        if (len + strlen(name) + 2 < sizeof file) {
            snprintf(file, sizeof file, "%.*s/%s", (int)len, len ? p : ".", name);
            if (access(file, X_OK) == 0) return 1;
        }
        if (!colon) return 0;
        p = colon + 1;
    }
}

int demo_video_check(const demo_opts *o)
{
    if (!o->video) return 0;
    if (!demo_render_available()) {
        fprintf(stderr, "%s: --video: no pictures: %s\n", o->prog, demo_render_unavailable_reason());
        return -1;
    }
    if (!on_path("ffmpeg")) {
        fprintf(stderr, "%s: --video: ffmpeg not found on PATH (Debian: apt-get install ffmpeg, or make video)\n",
                o->prog);
        return -1;
    }
    if (strchr(o->out, '\'')) {
        fprintf(stderr, "%s: --video: --out '%s' has a quote, which the ffmpeg command line cannot take\n", o->prog,
                o->out);
        return -1;
    }
    return 0;
}

static void fail(const demo_opts *o, const char *why)
{
    fprintf(stderr, "%s: --video: %s: %s\n", o->prog, V.path, why);
    V.failed = 1;
    V.errors++;
}

static int close_pipe(const demo_opts *o)
{
    if (!V.pipe) return 0;
    int st = pclose(V.pipe);
    V.pipe = NULL;
    if (st == -1 || !WIFEXITED(st) || WEXITSTATUS(st) != 0) {
        char why[96];
        int exited = st != -1 && WIFEXITED(st);
        snprintf(why, sizeof why, "ffmpeg failed (%s %d; its messages, if any, above)",
                 exited ? "exit status" : "wait status", exited ? WEXITSTATUS(st) : st);
        fail(o, why);
        return -1;
    }
    printf("  wrote %s (%ld frames)\n", V.path, V.next);
    return 0;
}

static void open_pipe(const demo_opts *o, const char *tag)
{
    snprintf(V.tag, sizeof V.tag, "%s", tag);
    snprintf(V.path, sizeof V.path, "%s/%s.mp4", o->out, tag);
    V.w = o->width & ~1, V.h = o->height & ~1; /* H.264 in yuv420p: even sizes */
    V.next = 0;
    V.failed = 0;
    char cmd[1400];
    snprintf(cmd, sizeof cmd,
             "ffmpeg -nostdin -y -loglevel error -f rawvideo -pix_fmt rgb24 -s %dx%d -r %d -i - "
             "-c:v libx264 -pix_fmt yuv420p -crf 20 -movflags +faststart '%s'",
             V.w, V.h, VIDEO_FPS, V.path);
    signal(SIGPIPE, SIG_IGN); /* ffmpeg gone: a write error, said, rather than death */
    fflush(NULL);
    V.pipe = popen(cmd, "w");
    if (!V.pipe) fail(o, strerror(errno));
}

static void write_frame(const demo_opts *o, const demo_image *im, long copies)
{
    char label[96];
    static const unsigned char ink[3] = {40, 40, 48};
    demo_image *f = demo_image_create(V.w, V.h, ink);
    if (!f) {
        fail(o, "out of memory for a frame");
        return;
    }
    demo_blit(f, im, 0, 0);
    snprintf(label, sizeof label, "%s  t %.2f s", V.tag, (double)V.next / VIDEO_FPS);
    demo_text(f, 8, 8, 2, ink, label);
    for (long k = 0; k < copies && !V.failed; k++)
        if (fwrite(f->rgb, 3, (size_t)V.w * (size_t)V.h, V.pipe) != (size_t)V.w * (size_t)V.h)
            fail(o, "ffmpeg stopped reading frames");
    demo_image_destroy(f);
}

void demo_video_hook(const demo_opts *o, const char *tag, int step, int total, const demo_camera *cam, dSpaceID space,
                     dClothID *cloths, int n)
{
    if (!o->video) return;
    if (step == 1 || strcmp(tag, V.tag)) { /* a new run */
        close_pipe(o);
        open_pipe(o, tag);
    }
    /* frame k shows simulated time k / VIDEO_FPS; step s ends at s / hz */
    long due = 0;
    while ((double)(V.next + due) * o->hz <= (double)step * VIDEO_FPS) due++;
    if (due > 0 && V.pipe && !V.failed) {
        demo_image *im = demo_render(cam, space, cloths, n, o->smooth, V.w, V.h);
        if (!im) fail(o, "the frame could not be rendered");
        else write_frame(o, im, due);
        demo_image_destroy(im);
    }
    V.next += due;
    if (step == total) close_pipe(o);
}

int demo_video_finish(const demo_opts *o)
{
    if (!o->video) return 0;
    close_pipe(o);
    int errors = V.errors;
    V.errors = 0;
    V.tag[0] = '\0';
    return errors ? -1 : 0;
}
