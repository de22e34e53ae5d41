/* What the tests that run a demo as a user would share (demo_view.c,
 * demo_video.c): a shell command with its output to a log, the log read
 * back, whether a tool is on PATH. Header-only, like check.h. */
#ifndef ODECLOTH_TEST_DEMO_SHELL_H
#define ODECLOTH_TEST_DEMO_SHELL_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "sanitizer.h"

/* In a sanitizer build the children run with LeakSanitizer off: Mesa leaks
 * a few hundred bytes of its own (OSMesa's context; libxcb and the GLX /
 * DRI modules GLFW unloads at glfwTerminate, whose frames LSan cannot
 * name, so no suppression can match them); memory errors are still caught.
 * (Under valgrind the view's frames leak nothing of ours.) */
#ifdef ODECLOTH_ASAN
#define DEMO_ENV "env ASAN_OPTIONS=detect_leaks=0 "
#else
#define DEMO_ENV "env "
#endif

/* Run a shell command with its output (stdout and stderr) to `log`; its
 * exit status, minus the signal that ended it, or -1000 if it did not run. */
static int demo_run(const char *cmd, const char *log)
{
    char line[2048];
    snprintf(line, sizeof line, "%s > %s 2>&1", cmd, log);
    printf("$ %s\n", line);
    fflush(stdout);
    int st = system(line);
    if (st == -1) return -1000;
    return WIFEXITED(st) ? WEXITSTATUS(st) : WIFSIGNALED(st) ? -WTERMSIG(st) : -1000;
}

/* A file's bytes with a NUL after them (len, if not NULL, gets their
 * count); NULL if it cannot be read. */
static char *demo_slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 1 << 16, n = 0;
    char *s = malloc(cap);
    for (size_t k; s && (k = fread(s + n, 1, cap - n - 1, f)) > 0;) {
        n += k;
        if (n + 1 == cap) {
            char *t = realloc(s, cap *= 2);
            if (!t) free(s);
            s = t;
        }
    }
    fclose(f);
    if (s) s[n] = '\0';
    if (s && len) *len = n;
    return s;
}

static int demo_have(const char *tool)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "command -v %s > /dev/null 2>&1", tool);
    int st = system(cmd);
    return st != -1 && WIFEXITED(st) && WEXITSTATUS(st) == 0;
}

#endif
