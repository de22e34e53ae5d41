/* Shared by the speed-against-accuracy benchmarks (bench_workprecision,
 * bench_stability, bench_scaling): the options they all take, CPU time,
 * the output directory, the CSV and running gnuplot on a script. */
#ifndef ODECLOTH_BENCH_UTIL_H
#define ODECLOTH_BENCH_UTIL_H

#include <getopt.h>
#include <stdio.h>

typedef struct bench_opts {
    const char *prog;  /* for messages */
    const char *usage; /* printed by --help */
    const char *out;   /* output directory, default out/bench */
    int grid;          /* --grid N (0: not given) */
    int fast, check;   /* --fast, --check */
} bench_opts;

/* A program's own options: a getopt_long table ending in a zero entry whose
 * vals are BENCH_OWN and up, and take(ctx, val, value): 0 taken, else the
 * exit status (message printed). */
enum { BENCH_OWN = 256 };
typedef int (*bench_take_fn)(void *ctx, int opt, const char *value);

/* Parses argv: --out DIR, --grid N (3..1001), --fast, --check and --help / -h
 * (prints o->usage) into o, the program's own options through take. Returns
 * -1 to go on, 0 after --help, else the exit status (2: message printed). */
int bench_parse(bench_opts *o, const struct option *own, bench_take_fn take, void *ctx, int argc, char **argv);

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
