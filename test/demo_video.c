/* Demo: --video (examples/common/video.c) run as a user would, from the
 * build directory, on drape_table (--short, a 7 x 7 cloth, alpha 0.8,
 * 64 x 48 frames, --obj):
 *   1. no ffmpeg on PATH: exit 1 (not a signal), a message naming ffmpeg,
 *      no video file;
 *   2. an ffmpeg that fails at once (a script on PATH exiting 3): exit 1,
 *      not killed by the broken pipe, a message saying ffmpeg failed;
 *   3. when ffmpeg and ffprobe are there: the video holds one frame per
 *      1/30 s of the run's timeline plus the first (drape.h: 2.5 s settle,
 *      six 1 s phases, 2.5 s settle: 331 frames), and the OBJ files and
 *      metrics are those of the same run without --video, byte for byte.
 *      Without them this part is skipped (said, not failed).
 * Skipped whole if examples/drape_table is not built.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "demo_shell.h"

#define DEMO_PATH "examples/drape_table"
#define ARGS "--short --grid 7 --alpha 0.8 --size 64x48 --obj"
#define OUT "demo_video_out"
#define FRAMES (30 * (25 + 60 + 25) / 10 + 1)

static int contains(const char *log, const char *what)
{
    char *s = demo_slurp(log, NULL);
    int yes = s && strstr(s, what);
    free(s);
    return yes;
}

static int exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

static int same_file(const char *a, const char *b)
{
    size_t na, nb;
    char *x = demo_slurp(a, &na), *y = demo_slurp(b, &nb);
    int same = x && y && na == nb && !memcmp(x, y, na);
    free(x);
    free(y);
    return same;
}

/* The metrics lines of a log (the "alpha..." lines), each cut at "wall". */
static void metrics(const char *log, char *out, size_t cap)
{
    char *s = demo_slurp(log, NULL);
    size_t n = 0;
    out[0] = '\0';
    for (char *p = s ? strtok(s, "\n") : NULL; p; p = strtok(NULL, "\n")) {
        if (strncmp(p, "alpha", 5)) continue;
        char *w = strstr(p, "wall");
        if (w) *w = '\0';
        n += (size_t)snprintf(out + n, n < cap ? cap - n : 0, "%s\n", p);
    }
    free(s);
}

static void with_ffmpeg(void)
{
    if (!demo_have("ffmpeg") || !demo_have("ffprobe")) {
        printf("demo_video: part 3 skipped: no ffmpeg or ffprobe on PATH (make video installs them)\n");
        return;
    }
    CHECK(demo_run(DEMO_ENV DEMO_PATH " " ARGS " --out " OUT "/plain", OUT "/plain.txt") == 0,
          "run without --video exits 0");
    CHECK(demo_run(DEMO_ENV DEMO_PATH " " ARGS " --video --out " OUT "/video", OUT "/video.txt") == 0,
          "--video run exits 0");
    CHECK(demo_run("ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames "
                   "-of csv=p=0 " OUT "/video/alpha0.8.mp4",
                   OUT "/frames.txt") == 0,
          "ffprobe reads the video");
    char *frames = demo_slurp(OUT "/frames.txt", NULL);
    int n = frames ? atoi(frames) : -1;
    CHECK(n == FRAMES, "the video has %d frames (%d: 11 s at 30 frames a second, and the first)", n, FRAMES);
    free(frames);
    static const char *const objs[] = {"alpha0.8_draped.obj", "alpha0.8_after.obj"};
    for (int i = 0; i < 2; i++) {
        char a[256], b[256];
        snprintf(a, sizeof a, OUT "/plain/%s", objs[i]);
        snprintf(b, sizeof b, OUT "/video/%s", objs[i]);
        CHECK(same_file(a, b), "%s: the same bytes with and without --video", objs[i]);
    }
    static char ma[8192], mb[8192];
    metrics(OUT "/plain.txt", ma, sizeof ma);
    metrics(OUT "/video.txt", mb, sizeof mb);
    CHECK(ma[0] && !strcmp(ma, mb), "the metrics with and without --video are the same");
}

int main(void)
{
    if (!exists(DEMO_PATH)) {
        printf("demo_video: %s not built (run from the build directory, with the examples): skipped\n", DEMO_PATH);
        return 0;
    }
    mkdir(OUT, 0777);
    mkdir(OUT "/bin", 0777);
    /* 1: PATH without ffmpeg (the shell finds env before PATH changes) */
    remove(OUT "/none/alpha0.8.mp4");
    int st = demo_run(DEMO_ENV "PATH=/nonexistent " DEMO_PATH " " ARGS " --video --out " OUT "/none", OUT "/none.txt");
    CHECK(st == 1, "no ffmpeg: exit 1 (got %d)", st);
    CHECK(contains(OUT "/none.txt", "--video: ffmpeg not found on PATH"), "no ffmpeg: said so");
    CHECK(!exists(OUT "/none/alpha0.8.mp4"), "no ffmpeg: no video written");

    /* 2: an ffmpeg that exits at once with an error */
    FILE *f = fopen(OUT "/bin/ffmpeg", "w");
    CHECK(f != NULL, "wrote the failing ffmpeg");
    if (f) {
        fputs("#!/bin/sh\nexit 3\n", f);
        fclose(f);
        chmod(OUT "/bin/ffmpeg", 0755);
        st = demo_run(DEMO_ENV "PATH=" OUT "/bin:/usr/bin:/bin " DEMO_PATH " " ARGS " --video --out " OUT "/broken",
                      OUT "/broken.txt");
        CHECK(st == 1, "failing ffmpeg: exit 1, not a signal (got %d)", st);
        CHECK(contains(OUT "/broken.txt", "ffmpeg"), "failing ffmpeg: said so");
    }
    with_ffmpeg();
    return check_summary();
}
