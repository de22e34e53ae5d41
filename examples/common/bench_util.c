/* See bench_util.h. */
#define _POSIX_C_SOURCE 200809L
#include "bench_util.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

int bench_option(bench_opts *o, int argc, char **argv, int *a)
{
    const char *arg = argv[*a], *v = *a + 1 < argc ? argv[*a + 1] : NULL;
    if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
        puts(o->usage);
        return -2;
    }
    if (!strcmp(arg, "--fast")) {
        o->fast = 1;
        return 1;
    }
    if (!strcmp(arg, "--check")) {
        o->check = 1;
        return 1;
    }
    if (!v || (strcmp(arg, "--out") && strcmp(arg, "--grid"))) return 0;
    ++*a;
    if (!strcmp(arg, "--out")) {
        if (!*v || strchr(v, '\'')) { /* the path goes into shell commands in quotes */
            fprintf(stderr, "%s: --out '%s': give a non-empty directory name without a ' in it\n", o->prog, v);
            return -1;
        }
        o->out = v;
        return 1;
    }
    char *end;
    long g = strtol(v, &end, 10);
    if (end == v || *end || g < 3 || g > 1001) {
        fprintf(stderr, "%s: --grid '%s' must be a whole number in [3, 1001]\n", o->prog, v);
        return -1;
    }
    o->grid = (int)g;
    return 1;
}

int bench_unknown(const bench_opts *o, const char *arg)
{
    fprintf(stderr, "%s: unknown or incomplete option '%s' (try --help)\n", o->prog, arg);
    return 2;
}

double bench_cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

double bench_wall_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

int bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static FILE *open_in_out(const bench_opts *o, const char *name, const char *ext)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.%s", o->out, name, ext);
    FILE *f = fopen(path, "w");
    if (!f) fprintf(stderr, "%s: cannot write %s: %s\n", o->prog, path, strerror(errno));
    return f;
}

FILE *bench_open_csv(const bench_opts *o, const char *name)
{
    char cmd[1100];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s'", o->out);
    if (system(cmd) != 0) {
        fprintf(stderr, "%s: cannot create %s\n", o->prog, o->out);
        return NULL;
    }
    return open_in_out(o, name, "csv");
}

FILE *bench_open_script(const bench_opts *o, const char *name) { return open_in_out(o, name, "gp"); }

void bench_run_gnuplot(const bench_opts *o, const char *name)
{
    char cmd[1100];
    snprintf(cmd, sizeof cmd, "gnuplot '%s/%s.gp'", o->out, name);
    if (system(cmd) != 0) fprintf(stderr, "%s: gnuplot failed; the CSV is in %s\n", o->prog, o->out);
    else printf("wrote %s/%s.csv and %s/%s.png\n", o->out, name, o->out, name);
}
