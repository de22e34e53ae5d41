/* bench_scaling: cost against node count.
 *
 * bench_step's scene (a 1 m, 0.2 kg cotton cloth pinned at two adjacent
 * corners, starting horizontal), the default solver (cloth_default_desc),
 * h = 1/60 s, for grids from 21x21 up: per grid the median
 * CPU time of a step (CLOCK_PROCESS_CPUTIME_ID) and the mean CG iterations
 * over the first --steps steps, and the memory per node. Memory: the growth
 * of the process's resident set (/proc/self/statm) from before cloth_create
 * to after the first step (so the lazily touched pages of the work arrays
 * count), divided by the nodes (on small grids the allocator's reuse of
 * freed pages makes it noisy). The slope of log(time) on log(nodes)
 * (least squares) is the scaling exponent; the chart draws time per step,
 * CG iterations and bytes per node with a linear-scaling line through the
 * smallest grid.
 *
 *   bench_scaling [--out DIR] [--grids 21,41,81,121,161 | --grid N] [--steps N] [--fast]
 *
 * --fast: grids 11, 21, 41 and 10 steps.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "odecloth/cloth.h"
#include "bench_util.h"

/* resident set size in bytes, or -1 */
static double rss_bytes(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    if (!f) return -1.0;
    long size, resident;
    int ok = fscanf(f, "%ld %ld", &size, &resident) == 2;
    fclose(f);
    return ok ? (double)resident * (double)sysconf(_SC_PAGESIZE) : -1.0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

typedef struct result {
    int steps;
    double median_ms, iters, bytes_per_node;
    int failed;
} result;

static result run(int N, int steps)
{
    result r = {0};
    double rss0 = rss_bytes();
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = N;
    d.material.density = 0.2;
    cloth *c;
    cloth_error err;
    if (cloth_create(&d, &c, &err) != CLOTH_OK) {
        fprintf(stderr, "bench_scaling: %s\n", err.message);
        r.failed = 1;
        return r;
    }
    const double *x = cloth_positions(c);
    cloth_pin(c, 0, x);
    cloth_pin(c, N - 1, x + 3 * (N - 1));
    double *dt = malloc((size_t)steps * sizeof *dt);
    if (!dt) exit(1);
    long iters = 0;
    for (int s = 0; s < steps; s++) {
        cloth_step_stats st;
        double t0 = bench_cpu_now();
        cloth_status cs = cloth_step(c, 1.0 / 60, &st);
        dt[s] = bench_cpu_now() - t0;
        if (s == 0) r.bytes_per_node = (rss_bytes() - rss0) / ((double)N * N);
        if (cs != CLOTH_OK) {
            fprintf(stderr, "bench_scaling: %dx%d step %d: %s\n", N, N, s, cloth_last_error(c));
            r.failed = 1;
            break;
        }
        iters += st.iterations;
        r.steps = s + 1;
    }
    if (r.steps > 0) {
        qsort(dt, (size_t)r.steps, sizeof *dt, cmp_double);
        r.median_ms = 1e3 * dt[r.steps / 2];
        r.iters = (double)iters / r.steps;
    }
    free(dt);
    cloth_destroy(c);
    return r;
}

static const char usage[] =
    "usage: bench_scaling [--out DIR] [--grids 21,41,81,121,161 | --grid N] [--steps N] [--fast]\n"
    "CPU time per step, CG iterations and memory per node of backward Euler +\n"
    "MPCG (h = 1/60, tol 1e-3) against node count, with the scaling exponent.\n"
    "Writes DIR/bench_scaling.csv and .png (default DIR out/bench).";

enum { OPT_STEPS = BENCH_OWN, OPT_GRIDS };

static const struct option own_options[] = {
    {"steps", required_argument, NULL, OPT_STEPS},
    {"grids", required_argument, NULL, OPT_GRIDS},
    {NULL, 0, NULL, 0},
};

typedef struct scaling_opts {
    int grids[16], ng, steps;
} scaling_opts;

/* --steps N, --grids A,B,... (bench_take_fn). */
static int take_option(void *ctx, int opt, const char *v)
{
    scaling_opts *so = ctx;
    if (opt == OPT_STEPS) {
        char *end;
        long s = strtol(v, &end, 10);
        if (*end || s < 1 || s > 100000) {
            fprintf(stderr, "bench_scaling: --steps '%s' must be a whole number in [1, 100000]\n", v);
            return 2;
        }
        so->steps = (int)s;
        return 0;
    }
    so->ng = 0;
    for (const char *p = v; *p && so->ng < 16;) {
        char *end;
        long g = strtol(p, &end, 10);
        if (end == p || g < 3 || g > 2000) {
            fprintf(stderr, "bench_scaling: --grids '%s': sizes must be whole numbers in [3, 2000]\n", v);
            return 2;
        }
        so->grids[so->ng++] = (int)g;
        p = *end == ',' ? end + 1 : end;
        if (*end && *end != ',') {
            fprintf(stderr, "bench_scaling: --grids '%s': separate sizes with commas\n", v);
            return 2;
        }
    }
    return 0;
}

int main(int argc, char **argv)
{
    bench_opts o = {"bench_scaling", usage, "out/bench", 0, 0, 0};
    scaling_opts so = {{21, 41, 81, 121, 161}, 5, 30};
    int rc = bench_parse(&o, own_options, take_option, &so, argc, argv);
    if (rc >= 0) return rc;
    int *grids = so.grids, ng = so.ng, steps = so.steps;
    if (o.check) {
        fprintf(stderr, "bench_scaling: --check: this benchmark asserts nothing (timings are not tests)\n");
        return 2;
    }
    if (o.grid) { /* one grid */
        grids[0] = o.grid;
        ng = 1;
    } else if (o.fast) {
        static const int g[3] = {11, 21, 41};
        memcpy(grids, g, sizeof g);
        ng = 3;
    }
    if (o.fast) steps = 10;
    FILE *csv = bench_open_csv(&o, "bench_scaling");
    if (!csv) return 1;
    fprintf(csv, "grid,nodes,steps,median_step_ms,cg_iterations,rss_bytes_per_node,failed\n");
    printf("%-9s %8s %14s %8s %16s\n", "grid", "nodes", "median ms", "CG it", "RSS B/node");
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int nfit = 0;
    for (int g = 0; g < ng; g++) {
        result r = run(grids[g], steps);
        double n = (double)grids[g] * grids[g];
        printf("%3dx%-5d %8.0f %14.3f %8.1f %16.0f%s\n", grids[g], grids[g], n, r.median_ms, r.iters, r.bytes_per_node,
               r.failed ? "  FAILED" : "");
        fflush(stdout);
        fprintf(csv, "%d,%.0f,%d,%.5g,%.2f,%.0f,%d\n", grids[g], n, r.steps, r.median_ms, r.iters, r.bytes_per_node,
                r.failed);
        if (!r.failed && r.median_ms > 0) {
            sx += log(n);
            sy += log(r.median_ms);
            sxx += log(n) * log(n);
            sxy += log(n) * log(r.median_ms);
            nfit++;
        }
    }
    fclose(csv);
    double slope = nfit >= 2 ? (nfit * sxy - sx * sy) / (nfit * sxx - sx * sx) : NAN;
    printf("scaling exponent (least squares, time per step ~ nodes^p): p = %.2f\n", slope);

    FILE *gp = bench_open_script(&o, "bench_scaling");
    if (gp) {
        fprintf(gp,
                "set terminal pngcairo size 1200,420 font ',10'\n"
                "set output '%s/bench_scaling.png'\n"
                "set datafile separator ','\n"
                "set multiplot layout 1,3 title 'odecloth scaling: backward Euler + block-Jacobi MPCG, cotton, "
                "h = 1/60, tol 1e-3; fitted exponent p = %.2f'\n"
                "set logscale xy\nset grid\nset key left top\nset xlabel 'nodes'\n"
                "stats '%s/bench_scaling.csv' using 2:4 nooutput prefix 'A'\n"
                "n0 = A_min_x\nt0 = A_min_y\n"
                "set ylabel 'CPU ms per step (median)'\n"
                "plot '%s/bench_scaling.csv' using 2:4 with linespoints pt 7 title 'measured', "
                "t0 * x / n0 with lines dt 2 lc 'black' title 'linear'\n"
                "set ylabel 'CG iterations per step'\n"
                "plot '%s/bench_scaling.csv' using 2:5 with linespoints pt 7 title 'block Jacobi'\n"
                "set ylabel 'bytes per node'\nunset logscale y\nset yrange [0:*]\n"
                "plot '%s/bench_scaling.csv' using 2:6 with linespoints pt 7 title 'resident set growth'\n"
                "unset multiplot\n",
                o.out, slope, o.out, o.out, o.out, o.out);
        fclose(gp);
        bench_run_gnuplot(&o, "bench_scaling");
    }
    return 0;
}
