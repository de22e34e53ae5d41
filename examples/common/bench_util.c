/* See bench_util.h. */
#define _POSIX_C_SOURCE 200809L
#include "bench_util.h"
#include "cli.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { BENCH_FAST = 1, BENCH_CHECK, BENCH_OUT, BENCH_GRID };

static const struct option bench_common[] = {
    {"help", no_argument, NULL, 'h'},
    {"fast", no_argument, NULL, BENCH_FAST},
    {"check", no_argument, NULL, BENCH_CHECK},
    {"out", required_argument, NULL, BENCH_OUT},
    {"grid", required_argument, NULL, BENCH_GRID},
};
#define BENCH_NCOMMON (int)(sizeof bench_common / sizeof bench_common[0])
#define BENCH_MAX_OWN 32

/* The options every benchmark takes: 1 taken, 0 not one of them, -1 bad
 * value (message printed). */
static int common_option(bench_opts *o, int opt, const char *v)
{
    switch (opt) {
    case BENCH_FAST: o->fast = 1; return 1;
    case BENCH_CHECK: o->check = 1; return 1;
    case BENCH_OUT:
        if (!*v || strchr(v, '\'')) { /* the path goes into shell commands in quotes */
            fprintf(stderr, "%s: --out '%s': give a non-empty directory name without a ' in it\n", o->prog, v);
            return -1;
        }
        o->out = v;
        return 1;
    case BENCH_GRID: {
        char *end;
        long g = strtol(v, &end, 10);
        if (end == v || *end || g < 3 || g > 1001) {
            fprintf(stderr, "%s: --grid '%s' must be a whole number in [3, 1001]\n", o->prog, v);
            return -1;
        }
        o->grid = (int)g;
        return 1;
    }
    default: return 0;
    }
}

static int unknown(const bench_opts *o, const char *arg)
{
    fprintf(stderr, "%s: unknown or incomplete option '%s' (try --help)\n", o->prog, arg);
    return 2;
}

int bench_parse(bench_opts *o, const struct option *own, bench_take_fn take, void *ctx, int argc, char **argv)
{
    struct option all[BENCH_NCOMMON + BENCH_MAX_OWN + 1];
    int n = 0;
    for (int k = 0; k < BENCH_NCOMMON; k++) all[n++] = bench_common[k];
    for (int k = 0; own && own[k].name; k++) {
        if (k == BENCH_MAX_OWN) abort(); /* a program's table larger than this file allows */
        all[n++] = own[k];
    }
    all[n] = (struct option){NULL, 0, NULL, 0};
    cli_start();
    for (;;) {
        const char *arg = NULL;
        int opt = cli_next(argc, argv, all, &arg);
        if (opt == CLI_END) break;
        if (opt == 'h') {
            puts(o->usage);
            return 0;
        }
        if (opt < 0) return unknown(o, arg);
        int took = common_option(o, opt, optarg);
        if (took < 0) return 2;
        if (took) continue;
        int rc = take(ctx, opt, optarg);
        if (rc) return rc;
    }
    return -1;
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
