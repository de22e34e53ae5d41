/* Demo: the --view window (examples/common/view.c), run as the user would,
 * from the build directory (CTest's working directory), on drape_table
 * (--short, an 11 x 11 cloth, alpha 0.8, --trace: every step's stats).
 *
 *   1. without --view: the reference output;
 *   2. --view with no display (DISPLAY and WAYLAND_DISPLAY unset): exit 0,
 *      one line "--view: no display (...); running headless", and the same
 *      output as 1 (every step's stats, the phases, the metrics but wall
 *      time);
 *   3. when xvfb-run (and xauth) are there: --view-frames 200 under Xvfb: the
 *      window opens (no "running headless"), 200 frames are drawn, the last
 *      written to <out>/view.png, the demo runs on headless, exit 0, and the
 *      output is again the same as 1: the view does not change the run; the
 *      offscreen pictures (OSMesa; the draped one is taken at step 150, with
 *      the window open) are byte for byte those of 1.
 *      Without xvfb-run this part is skipped (said, not failed: the project
 *      has no skip convention).
 * A build without GLFW says so in 2 and 3 ("built without GLFW") and is
 * checked for that instead. Skipped whole if examples/drape_table is not
 * built (ODECLOTH_BUILD_EXAMPLES off).
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

#define DEMO DEMO_ENV "examples/drape_table"
#define DEMO_PATH "examples/drape_table"
#define ARGS "--short --grid 11 --alpha 0.8 --trace --size 160x120"
#define OUT "demo_view_out"

/* The run's own output: every line but the view's ("--view", "wrote"),
 * each cut at "wall" (wall time differs from run to run). */
static char *results(const char *text)
{
    char *out = malloc(strlen(text) + 1), *o = out;
    if (!out) return NULL;
    for (const char *p = text; *p;) {
        const char *e = strchr(p, '\n');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        char buf[1024];
        snprintf(buf, sizeof buf, "%.*s", (int)(len < sizeof buf ? len : sizeof buf - 1), p);
        if (!strstr(buf, "--view") && !strstr(buf, "wrote")) {
            char *w = strstr(buf, "wall");
            if (w) *w = '\0';
            o += sprintf(o, "%s\n", buf);
        }
        p += len + (e ? 1 : 0);
    }
    *o = '\0';
    return out;
}

/* Check that a view run left the reference output alone. */
static void same_run(const char *what, const char *ref, const char *text)
{
    char *a = results(ref), *b = results(text);
    int same = a && b && !strcmp(a, b);
    size_t steps = 0;
    for (const char *p = a; p && (p = strstr(p, "\nstep ")); p++) steps++;
    CHECK(same, "%s: the same output as without --view (every step's stats, phases, metrics)", what);
    CHECK(steps > 600, "%s: the reference traced %zu steps (> 600)", what, steps);
    if (same) printf("%s: same output as without --view (%zu steps traced)\n", what, steps);
    free(a);
    free(b);
}

int main(void)
{
    struct stat sb;
    if (stat(DEMO_PATH, &sb)) {
        printf("demo_view: %s not built (run from the build directory, with the examples): skipped\n", DEMO_PATH);
        return 0;
    }
    mkdir(OUT, 0777);
    const char *ref_log = OUT "/reference.txt", *none_log = OUT "/no_display.txt", *xvfb_log = OUT "/xvfb.txt";
    CHECK(demo_run(DEMO " " ARGS " --out " OUT "/reference", ref_log) == 0, "reference run exits 0");
    char *ref = demo_slurp(ref_log, NULL);
    CHECK(ref != NULL, "read %s", ref_log);
    if (!ref) return check_summary();

    /* 2. no display */
    int rc = demo_run("env -u DISPLAY -u WAYLAND_DISPLAY " DEMO " " ARGS " --view --out " OUT "/no_display", none_log);
    char *text = demo_slurp(none_log, NULL);
    CHECK(rc == 0, "--view without a display: exit 0 (got %d)", rc);
    int built = text && !strstr(text, "built without GLFW");
    if (text && built)
        CHECK(strstr(text, "drape_table: --view: no display (DISPLAY and WAYLAND_DISPLAY unset); running headless\n") !=
                  NULL,
              "--view without a display says so in one line and runs headless");
    else CHECK(text && strstr(text, "--view: built without GLFW"), "a build without GLFW says so");
    if (text) same_run("no display", ref, text);
    free(text);

    /* 3. a window under Xvfb */
    if (!demo_have("xvfb-run") || !demo_have("xauth")) {
        printf("demo_view: xvfb-run or xauth not found: the windowed run is skipped\n");
    } else {
        remove(OUT "/xvfb/view.png");
        rc = demo_run("xvfb-run -a -s '-screen 0 640x480x24' " DEMO " " ARGS " --view-frames 200 --out " OUT "/xvfb",
                      xvfb_log);
        text = demo_slurp(xvfb_log, NULL);
        CHECK(rc == 0, "--view-frames 200 under xvfb-run: exit 0 (got %d)", rc);
        if (text && built) {
            CHECK(!strstr(text, "running headless"), "under Xvfb the window opens (no 'running headless')");
            CHECK(strstr(text, "--view: 200 frames shown, window closed; running on headless") != NULL,
                  "200 frames drawn, then the window closes and the demo runs on");
            CHECK(stat(OUT "/xvfb/view.png", &sb) == 0 && sb.st_size > 1000,
                  "the last frame written to " OUT "/xvfb/view.png");
        }
        if (text) same_run("xvfb", ref, text);
        /* the offscreen pictures (OSMesa), the draped one taken at step 150
         * while the window was open, are those of the reference run */
        const char *pics[] = {"alpha0.8_draped.png", "alpha0.8_after.png", "drape_table.png"};
        for (int k = 0; k < 3; k++) {
            char a[256], b[256];
            snprintf(a, sizeof a, OUT "/reference/%s", pics[k]);
            snprintf(b, sizeof b, OUT "/xvfb/%s", pics[k]);
            char *pa = demo_slurp(a, NULL), *pb = demo_slurp(b, NULL);
            struct stat sa, sbb;
            if (pa && !stat(a, &sa))
                CHECK(pb && !stat(b, &sbb) && sa.st_size == sbb.st_size && !memcmp(pa, pb, (size_t)sa.st_size),
                      "%s: the same picture with the window open as without", pics[k]);
            free(pa);
            free(pb);
        }
        free(text);
    }
    free(ref);
    return check_summary();
}
