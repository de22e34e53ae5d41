/* Shared by the speed-against-accuracy benchmarks (bench_workprecision,
 * bench_stability, bench_scaling): the options they all take, CPU time,
 * the output directory, the CSV and running gnuplot on a script. */
#ifndef ODECLOTH_BENCH_UTIL_H
#define ODECLOTH_BENCH_UTIL_H

#include <stdio.h>

typedef struct bench_opts {
    const char *prog;   /* for messages */
    const char *usage;  /* printed by --help */
    const char *out;    /* output directory, default out/bench */
    int grid;           /* --grid N (0: not given) */
    int fast, check;    /* --fast, --check */
} bench_opts;

/* Takes argv[*a] if it is --out DIR, --grid N (3..1001), --fast, --check
 * or --help / -h (prints o->usage), advancing *a past a value: 1 taken,
 * 0 not one of these, -1 bad value (message printed): exit 2, -2 help
 * printed: exit 0. */
int bench_option(bench_opts *o, int argc, char **argv, int *a);

/* The message for an option no one took; returns 2 (the exit status). */
int bench_unknown(const bench_opts *o, const char *arg);

/* CPU seconds of the process (CLOCK_PROCESS_CPUTIME_ID). */
double bench_cpu_now(void);
/* Wall seconds (CLOCK_MONOTONIC). */
double bench_wall_now(void);
/* qsort's comparison of doubles, ascending. */
int bench_cmp_double(const void *a, const void *b);

/* Creates o->out and opens o->out/<name>.csv for writing; NULL (message
 * printed) on failure. */
FILE *bench_open_csv(const bench_opts *o, const char *name);

/* Opens o->out/<name>.gp for writing the chart's script; NULL on failure. */
FILE *bench_open_script(const bench_opts *o, const char *name);

/* Runs gnuplot on o->out/<name>.gp and says what was written. */
void bench_run_gnuplot(const bench_opts *o, const char *name);

#endif
