/* bench_step: speed of the implicit step (make bench).
 *
 * Cotton cloth, 1 m square, 0.2 kg, pinned at two adjacent corners, starting
 * horizontal, 2 s simulated, the default solver (the Newton step; CG
 * relative tolerance 1e-3 for the linearised one), single thread. For each grid, step size and preconditioner:
 * steps per second (wall clock, median of the per-step times reported too) and
 * CG iterations per step. Writes DIR/bench_step.csv and, with gnuplot,
 * DIR/bench_step.png.
 *
 *   bench_step [--out DIR] [--grids 21,41,81,161] [--cap SECONDS] [--seconds T]
 *              [--precond jacobi,block,ssor,multigrid] [--hz 60,240] [--hash] [--reps N]
 *
 * --precond and --hz pick a subset of the table (the CSV then has only those
 * rows); --hash prints a hash of the final positions' bits after each row, to
 * check that a change to the solver left the results bitwise identical;
 * --reps N runs each row N times: steps/s and CPU steps/s are then the
 * median run's, and "best" adds up each step's fastest time over the runs
 * (the least disturbed by other work on a shared machine).
 *
 * A run whose wall time passes the cap stops early and is marked partial
 * (its figures are over the steps it took), so the whole table stays within
 * minutes on a small machine. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include "odecloth/cloth.h"
#include "bench_util.h"
#include "cli.h"

typedef struct result {
    int steps, done, failed;
    double steps_per_s, median_ms, iters;
    double cpu_steps_per_s;  /* over the process's CPU time: less noisy on a shared machine */
    double best_steps_per_s; /* over each step's fastest time in --reps runs */
    unsigned long long hash; /* FNV-1a of the final positions' bytes */
} result;

static unsigned long long fnv1a(const void *p, size_t n)
{
    const unsigned char *b = p;
    unsigned long long h = 1469598103934665603ULL;
    for (size_t k = 0; k < n; k++) h = (h ^ b[k]) * 1099511628211ULL;
    return h;
}

/* One run of the scene; dt[s] the wall time of step s. */
static result run_once(int N, double hz, cloth_precond pc, double seconds, double cap, double *dt)
{
    result r = {0};
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = N;
    d.solver.precond = pc;
    d.solver.cg_tolerance = 1e-3;
    d.material.density = 0.2; /* 1 m^2: 0.2 kg */
    cloth *c;
    cloth_error err;
    r.steps = (int)(seconds * hz + 0.5);
    if (cloth_create(&d, &c, &err) != CLOTH_OK) {
        fprintf(stderr, "bench_step: %s\n", err.message);
        r.failed = 1;
        return r;
    }
    const double *x = cloth_positions(c);
    cloth_pin(c, 0, x);
    cloth_pin(c, N - 1, x + 3 * (N - 1));
    double h = 1.0 / hz;
    long iters = 0;
    double t0 = bench_wall_now(), c0 = bench_cpu_now();
    for (int s = 0; s < r.steps; s++) {
        double a = bench_wall_now();
        cloth_step_stats st;
        if (cloth_step(c, h, &st) != CLOTH_OK) {
            fprintf(stderr, "bench_step: %dx%d step %d: %s\n", N, N, s, cloth_last_error(c));
            r.failed = 1;
            break;
        }
        dt[s] = bench_wall_now() - a;
        iters += st.iterations;
        r.done = s + 1;
        if (bench_wall_now() - t0 > cap) break;
    }
    double wall = bench_wall_now() - t0, cpu = bench_cpu_now() - c0;
    if (r.done > 0) {
        r.steps_per_s = r.done / wall;
        r.cpu_steps_per_s = r.done / cpu;
        r.iters = (double)iters / r.done;
    }
    r.hash = fnv1a(cloth_positions(c), 3 * (size_t)N * N * sizeof(double));
    cloth_destroy(c);
    return r;
}

/* The scene `reps` times (the runs are identical, step for step): steps/s
 * and CPU steps/s are the median run's; best_steps_per_s is over the sum of
 * each step's fastest time among the runs, the speed with the least
 * interference from other work on a shared machine. */
static result run(int N, double hz, cloth_precond pc, double seconds, double cap, int reps)
{
    int steps = (int)(seconds * hz + 0.5);
    double *dt = malloc((size_t)steps * sizeof *dt), *best = malloc((size_t)steps * sizeof *best);
    double *sps = malloc((size_t)reps * sizeof *sps), *cps = malloc((size_t)reps * sizeof *cps);
    result r = {0};
    int done = steps;
    for (int k = 0; k < reps; k++) {
        result q = run_once(N, hz, pc, seconds, cap, dt);
        if (k == 0) {
            r = q;
            qsort(memcpy(best, dt, (size_t)q.done * sizeof *dt), (size_t)q.done, sizeof *dt, bench_cmp_double);
            r.median_ms = q.done > 0 ? 1e3 * best[q.done / 2] : 0.0;
            memcpy(best, dt, (size_t)q.done * sizeof *dt);
        } else {
            for (int s = 0; s < q.done && s < done; s++)
                if (dt[s] < best[s]) best[s] = dt[s];
            r.failed |= q.failed;
        }
        if (q.done < done) done = q.done;
        sps[k] = q.steps_per_s;
        cps[k] = q.cpu_steps_per_s;
    }
    qsort(sps, (size_t)reps, sizeof *sps, bench_cmp_double);
    qsort(cps, (size_t)reps, sizeof *cps, bench_cmp_double);
    r.steps_per_s = sps[reps / 2];
    r.cpu_steps_per_s = cps[reps / 2];
    double sum = 0.0;
    for (int s = 0; s < done; s++) sum += best[s];
    r.best_steps_per_s = done > 0 ? done / sum : 0.0;
    free(dt);
    free(best);
    free(sps);
    free(cps);
    return r;
}

/* What the command line asks for */
typedef struct bench_args {
    const char *out;
    int grids[16], ng;
    double cap, seconds;
    int use_pc[4], use_hz[2], hash, reps;
} bench_args;

static const char *const pcn[4] = {"jacobi", "block", "ssor", "multigrid"};

/* The options into a: -1 to run, else the exit status (0 after --help, 2 on a bad option) */
static int parse_options(int argc, char **argv, bench_args *a)
{
    *a = (bench_args){"out/bench", {21, 41, 81, 161}, 4, 40.0, 2.0, {1, 1, 1, 1}, {1, 1}, 0, 1};
    static const struct option options[] = {
        {"help", no_argument, NULL, 'h'},          {"hash", no_argument, NULL, 'H'},
        {"precond", required_argument, NULL, 'p'}, {"hz", required_argument, NULL, 'z'},
        {"out", required_argument, NULL, 'o'},     {"cap", required_argument, NULL, 'c'},
        {"reps", required_argument, NULL, 'r'},    {"seconds", required_argument, NULL, 's'},
        {"grids", required_argument, NULL, 'g'},   {NULL, 0, NULL, 0},
    };
    cli_start();
    for (;;) {
        const char *arg = NULL;
        int opt = cli_next(argc, argv, options, &arg);
        char *v = optarg;
        if (opt == CLI_END) break;
        if (opt == 'h') {
            puts("usage: bench_step [--out DIR] [--grids 21,41,81,161] [--cap SECONDS] [--seconds T]\n"
                 "                  [--precond jacobi,block,ssor,multigrid] [--hz 60,240] [--hash] [--reps N]\n"
                 "Steps per second and CG iterations of backward Euler + MPCG for a pinned\n"
                 "cotton cloth, per grid, step size (1/60, 1/240 s) and preconditioner.\n"
                 "Writes DIR/bench_step.csv and DIR/bench_step.png (default DIR out/bench).\n"
                 "--precond, --hz: only those rows; --hash: print a hash of the final positions;\n"
                 "--reps N: each row N times (medians, and 'best': each step's fastest time).");
            return 0;
        } else if (opt == 'H') {
            a->hash = 1;
        } else if (opt == 'p') {
            for (int p = 0; p < 4; p++) a->use_pc[p] = 0;
            for (const char *s = v; *s;) {
                size_t len = strcspn(s, ",");
                int p = 0;
                while (p < 4 && !(strlen(pcn[p]) == len && !strncmp(s, pcn[p], len))) p++;
                if (p == 4) {
                    fprintf(stderr, "bench_step: unknown preconditioner in '%s'\n", v);
                    return 2;
                }
                a->use_pc[p] = 1;
                s += len;
                if (*s == ',') s++;
            }
        } else if (opt == 'z') {
            a->use_hz[0] = a->use_hz[1] = 0;
            for (char *s = v; *s;) {
                long hz = strtol(s, &s, 10);
                if (hz == 60) a->use_hz[0] = 1;
                else if (hz == 240) a->use_hz[1] = 1;
                else {
                    fprintf(stderr, "bench_step: --hz takes 60 and/or 240\n");
                    return 2;
                }
                if (*s == ',') s++;
                else break;
            }
        } else if (opt == 'o') {
            a->out = v;
        } else if (opt == 'c') {
            a->cap = atof(v);
        } else if (opt == 'r') {
            a->reps = atoi(v);
        } else if (opt == 's') {
            a->seconds = atof(v);
        } else if (opt == 'g') {
            a->ng = 0;
            for (char *s = v; *s && a->ng < 16;) {
                a->grids[a->ng] = (int)strtol(s, &s, 10);
                if (a->grids[a->ng] < 3) {
                    fprintf(stderr, "bench_step: grid sizes must be >= 3\n");
                    return 2;
                }
                a->ng++;
                if (*s == ',') s++;
                else break;
            }
        } else {
            fprintf(stderr, "bench_step: unknown or incomplete option '%s' (try --help)\n", arg);
            return 2;
        }
    }
    if (!(a->cap > 0.0) || !(a->seconds > 0.0) || a->reps < 1) {
        fprintf(stderr, "bench_step: --cap and --seconds must be > 0, --reps >= 1\n");
        return 2;
    }
    return -1;
}

/* The chart of DIR/bench_step.csv: steps/s and CG iterations against node count, log-log */
static void write_chart(const bench_opts *o)
{
    const char *out = o->out;
    FILE *gp = bench_open_script(o, "bench_step");
    if (!gp) return;
    fprintf(gp,
            "set terminal pngcairo size 1200,480 font ',10'\n"
            "set output '%s/bench_step.png'\n"
            "set datafile separator ','\n"
            "set multiplot layout 1,2 title 'odecloth: backward Euler + modified PCG, "
            "pinned cotton cloth, tol 1e-3, 1 thread'\n"
            "set logscale xy\nset grid\nset key left bottom\nset xlabel 'nodes'\n"
            "set ylabel 'steps per second'\n"
            "plot for [pc in 'jacobi block ssor multigrid'] for [hz in '60 240'] '%s/bench_step.csv' "
            "using (strcol(4) eq pc && strcol(3) eq hz ? $2 : 1/0):7 with linespoints title pc.' h=1/'.hz, "
            "30 with lines dt 2 lc 'black' title '30 steps/s'\n"
            "set key left top\nset ylabel 'CG iterations per step'\n"
            "plot for [pc in 'jacobi block ssor multigrid'] for [hz in '60 240'] '%s/bench_step.csv' "
            "using (strcol(4) eq pc && strcol(3) eq hz ? $2 : 1/0):9 with linespoints title pc.' h=1/'.hz\n"
            "unset multiplot\n",
            out, out, out);
    fclose(gp);
    bench_run_gnuplot(o, "bench_step");
}

int main(int argc, char **argv)
{
    bench_args a;
    int status = parse_options(argc, argv, &a);
    if (status >= 0) return status;
    const bench_opts o = {"bench_step", NULL, a.out, 0, 0, 0};
    FILE *csv = bench_open_csv(&o, "bench_step");
    if (!csv) return 1;
    fprintf(csv, "grid,nodes,hz,precond,steps,steps_done,steps_per_s,median_step_ms,cg_iterations,partial,"
                 "cpu_steps_per_s,best_steps_per_s\n");
    const double hzs[2] = {60.0, 240.0};
    const cloth_precond pcs[4] = {CLOTH_PRECOND_JACOBI, CLOTH_PRECOND_BLOCK_JACOBI, CLOTH_PRECOND_SSOR,
                                  CLOTH_PRECOND_MULTIGRID};
    printf("%-8s %-6s %-10s %10s %10s %10s %12s %10s %s\n", "grid", "h", "precond", "steps/s", "cpu st/s", "best st/s",
           "median ms", "CG it", "");
    for (int g = 0; g < a.ng; g++)
        for (int k = 0; k < 2; k++)
            for (int p = 0; p < 4; p++) {
                if (!a.use_hz[k] || !a.use_pc[p]) continue;
                result r = run(a.grids[g], hzs[k], pcs[p], a.seconds, a.cap, a.reps);
                int partial = r.done < r.steps;
                printf("%3dx%-4d 1/%-4.0f %-10s %10.1f %10.1f %10.1f %12.3f %10.1f %s", a.grids[g], a.grids[g], hzs[k],
                       pcn[p], r.steps_per_s, r.cpu_steps_per_s, r.best_steps_per_s, r.median_ms, r.iters,
                       r.failed  ? "FAILED"
                       : partial ? "(partial: wall cap)"
                                 : "");
                if (a.hash) printf(" hash %016llx", r.hash);
                printf("\n");
                fflush(stdout);
                fprintf(csv, "%d,%d,%.0f,%s,%d,%d,%.3f,%.4f,%.2f,%d,%.3f,%.3f\n", a.grids[g], a.grids[g] * a.grids[g],
                        hzs[k], pcn[p], r.steps, r.done, r.steps_per_s, r.median_ms, r.iters, partial || r.failed,
                        r.cpu_steps_per_s, r.best_steps_per_s);
            }
    fclose(csv);

    write_chart(&o);
    return 0;
}
