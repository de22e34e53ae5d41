/* bench_tension: the Newton step's work with tension plasticity on and off
 * (material.tension_yield, tension_set; docs/materials.md).
 *
 * Scene: the 1 m cotton cloth (N x N, default solver: backward Euler, Newton)
 * hanging in a vertical plane from its two top corners, which move apart by
 * 2.5% of the width over 1 s (past the yield, within the elongation limit of
 * 3%), stay 1 s, and come back over 1 s; 60 steps/s. Run with the option off
 * (the preset) and on (tension_yield 0.01, tension_set 0.5), one after the
 * other, for each grid.
 *
 * Prints per run: Newton iterations per step (median, mean, max), CG
 * iterations per step (median), steps retried in substeps, links carrying a
 * set at the end, the largest set, and the wall time; CSV per step: grid,
 * option (0 off, 1 on), step, Newton iterations, CG iterations, halvings,
 * wall ms, Newton iterations so far; the chart (bench_tension.png) those
 * running totals against the step, one panel per grid.
 *
 *   bench_tension [--out DIR] [--grid N] [--fast]
 *
 * Default grids 41 and 81; --grid N one grid; --fast 21x21.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "bench_util.h"

#define STEPS 180

typedef struct run_stats {
    int newton[STEPS], cg[STEPS], halvings, sets;
    double max_set, wall;
} run_stats;

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

static double median_int(const int *v, int n)
{
    int *s = malloc((size_t)n * sizeof *s);
    memcpy(s, v, (size_t)n * sizeof *s);
    qsort(s, (size_t)n, sizeof *s, cmp_int);
    double m = n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
    free(s);
    return m;
}

/* one run of the scene at grid N, the option on or off; 0 or -1 on failure */
static int run(int N, int on, run_stats *r, FILE *csv)
{
    int total = 0;
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = N;
    d.origin[0] = -0.5, d.origin[1] = 0.0, d.origin[2] = 1.0;
    d.axis_v[0] = d.axis_v[1] = 0.0, d.axis_v[2] = -1.0; /* rows go down: hanging, at rest */
    if (on) d.material.tension_yield = 0.01, d.material.tension_set = 0.5;
    cloth *c = NULL;
    cloth_error err;
    if (cloth_create(&d, &c, &err) != CLOTH_OK) {
        fprintf(stderr, "bench_tension: %s\n", err.message);
        return -1;
    }
    const double h = 1.0 / 60, *x = cloth_positions(c);
    double a[3] = {x[0], x[1], x[2]}, b[3] = {x[3 * (N - 1)], x[3 * (N - 1) + 1], x[3 * (N - 1) + 2]};
    memset(r, 0, sizeof *r);
    double t0 = bench_wall_now();
    for (int k = 0; k < STEPS; k++) {
        double s = k < 60 ? (k + 1) / 60.0 : k < 120 ? 1.0 : (STEPS - 1 - k) / 60.0;
        double pa[3] = {a[0] - 0.0125 * s, a[1], a[2]}, pb[3] = {b[0] + 0.0125 * s, b[1], b[2]};
        cloth_pin(c, 0, pa);
        cloth_pin(c, N - 1, pb);
        cloth_step_stats st;
        double w = bench_wall_now();
        if (cloth_step(c, h, &st) != CLOTH_OK) {
            fprintf(stderr, "bench_tension: %dx%d, option %d, step %d failed: %s\n", N, N, on, k, cloth_last_error(c));
            cloth_destroy(c);
            return -1;
        }
        r->newton[k] = st.newton;
        r->cg[k] = st.iterations;
        r->halvings += st.halvings;
        total += st.newton;
        if (csv)
            fprintf(csv, "%d,%d,%d,%d,%d,%d,%.3f,%d\n", N, on, k, st.newton, st.iterations, st.halvings,
                    1e3 * (bench_wall_now() - w), total);
    }
    r->wall = bench_wall_now() - t0;
    for (int e = 0; e < cloth_link_count(c, CLOTH_SEQUENTIAL); e++) {
        cloth_link L;
        cloth_get_link(c, CLOTH_SEQUENTIAL, e, &L);
        r->sets += L.plastic;
        r->max_set = fmax(r->max_set, L.l1 / L.rest - 1.0);
    }
    cloth_destroy(c);
    return 0;
}

/* running Newton totals against the step, off and on, one panel per grid */
static void chart(const bench_opts *o, const int *grids, int ng)
{
    FILE *gp = bench_open_script(o, "bench_tension");
    if (!gp) return;
    fprintf(gp,
            "set terminal pngcairo size %d,420 font ',10'\nset output '%s/bench_tension.png'\n"
            "set datafile separator ','\nset grid\nset key left top\nset xlabel 'step (1/60 s)'\n"
            "set ylabel 'Newton iterations so far'\n"
            "set multiplot layout 1,%d title 'two corners 2.5%% apart and back: tension plasticity off and on'\n",
            420 * ng + 100, o->out, ng);
    for (int g = 0; g < ng; g++)
        fprintf(gp,
                "set title '%dx%d'\nplot '%s/bench_tension.csv' using ($1 == %d && $2 == 0 ? $3 : 1/0):8 "
                "with lines lw 2 title 'off', '' using ($1 == %d && $2 == 1 ? $3 : 1/0):8 with lines lw 2 dt 2 "
                "title 'on (yield 0.01, share 0.5)'\n",
                grids[g], grids[g], o->out, grids[g], grids[g]);
    fprintf(gp, "unset multiplot\n");
    fclose(gp);
    bench_run_gnuplot(o, "bench_tension");
}

int main(int argc, char **argv)
{
    bench_opts o = {"bench_tension", "usage: bench_tension [--out DIR] [--grid N] [--fast]\n", "out/bench", 0, 0, 0};
    int rc = bench_parse(&o, NULL, NULL, NULL, argc, argv);
    if (rc >= 0) return rc;
    int grids[2] = {41, 81}, ng = 2;
    if (o.grid) grids[0] = o.grid, ng = 1;
    else if (o.fast) grids[0] = 21, ng = 1;
    FILE *csv = bench_open_csv(&o, "bench_tension");
    if (!csv) return 1;
    fprintf(csv, "grid,option,step,newton,cg,halvings,wall_ms,newton_total\n");
    printf("two corners of the 1 m cotton cloth 2.5%% apart and back, %d steps of 1/60 s\n", STEPS);
    printf("grid  option  newton/step median mean max  cg/step median  retried  links set  max set  wall s\n");
    int fail = 0;
    for (int g = 0; g < ng; g++)
        for (int on = 0; on < 2; on++) {
            run_stats r;
            if (run(grids[g], on, &r, csv) != 0) {
                fail = 1;
                continue;
            }
            double mean = 0.0;
            int mx = 0;
            for (int k = 0; k < STEPS; k++) {
                mean += r.newton[k] / (double)STEPS;
                mx = r.newton[k] > mx ? r.newton[k] : mx;
            }
            printf("%4d  %-6s  %18.1f %5.2f %3d  %14.1f  %7d  %9d  %7.4f  %6.2f\n", grids[g], on ? "on" : "off",
                   median_int(r.newton, STEPS), mean, mx, median_int(r.cg, STEPS), r.halvings, r.sets, r.max_set,
                   r.wall);
            fflush(stdout);
        }
    fclose(csv);
    chart(&o, grids, ng);
    return fail;
}
