/* bench_workprecision: error against cost for every integrator.
 *
 * Two scenes, both the 1 m elastic cotton cloth (CLOTH_ELASTIC: no plastic
 * switching, so the smooth scene is smooth), 0.2 kg, starting horizontal:
 *   swing:   pinned at two adjacent corners, swinging under gravity (no contact);
 *   sphere:  free, falling onto a sphere of radius 0.3 m (0.25 s by default:
 *            the contacts start at about 0.18 s). The sphere is
 *            core-only: before each step every vertex whose predicted end
 *            position x + h v lies inside it gets a plane constraint (normal
 *            from the centre, target on the surface: frictionless), the others
 *            are released. No ODE: the cost is the cloth's alone.
 * Two families of them: the default, 21x21 at k_t 200 N/m with 2.5x cotton's
 * damping (c_t / k_t = 2.5e-4 s); --cotton, the preset itself (k_t 2000 N/m,
 * c_t / k_t = 1e-5 s) at 21x21 and 41x41, the swing 1 s (later the swing
 * amplifies every error, and no reference within reach converges,
 * docs/benchmarks.md), with more series: the Newton step
 * (CLOTH_NEWTON) converged to 1e-4 m/s and cut to one iteration (the
 * iterate kept unconverged), and backward Euler with each preconditioner.
 * Reference: BDF2 (the swing) or backward Euler (the sphere: BDF2 does not
 * converge through contact events, see make_reference) at h_ref with CG
 * tolerance 1e-10, exact Jacobian (--cotton: symplectic Euler at 1/98304,
 * see family_reference); it is run again at h_ref/2
 * and the RMS difference printed (it must be far below the smallest error
 * plotted). Error = RMS over vertices and over the sample times t = T/8,
 * 2T/8 .. T of |x - x_ref|; cost = CPU seconds (CLOCK_PROCESS_CPUTIME_ID) per
 * simulated second. A run that fails (a step returns CLOTH_ESTEP: NaN, strain,
 * CG, Newton) or whose error passes 1 m is "blown up": drawn as a cross on the chart's
 * top edge at the cost it had spent per simulated second until then.
 * Orders: each series' least-squares slope of log error against log h over
 * its asymptotic window, the (at most 4) smallest step sizes in a row whose
 * runs did not blow up, whose errors are at least 3x the reference's
 * change (resolved) and whose pairs' orders are within 0.25 of the finest
 * pair's; --order-window LO,HI fits over the rates LO..HI (Hz)
 * instead. The window is printed beside each order, in the chart's key too.
 * The accuracy-driven controller (cloth_adaptive_*, core/src/adaptive.c) is
 * run at several tolerances (default family only) and drawn on the same chart; for each it prints
 * the error against the request (tolerance x sample time, RMS), the
 * substeps, the share of frames stepped by symplectic Euler, its own global
 * estimate (RMS over the samples) against the true error, and the
 * frontier's cost at its error (the cheapest fixed-step series there,
 * log-log interpolated between step sizes).
 *
 * CSV columns: scene, series, steps per second (60 for the controller), CG
 * tolerance (the controller: its tolerance, m/s), requested error (the
 * controller), error m, CPU s per simulated s, CG iterations per step,
 * blown up (0/1), time reached s, why; the controller also: substeps per
 * frame, CG tolerance (geometric mean), share of symplectic frames, global
 * estimate m, the frontier's CPU s per s at its error; every row then:
 * grid (17), k_t N/m, Newton iterations per step, steps kept unconverged.
 * <name>_orders.csv (with a header) and <name>_orders.md: the fitted orders
 * with their windows.
 *
 *   bench_workprecision [--out DIR] [--grid N] [--scene swing|sphere] [--sphere-seconds T]
 *                       [--cotton] [--swing-seconds T] [--order-window LO,HI] [--fast] [--check]
 *
 * --fast: 11x11 grid, T = 1 s, fewer step sizes, swing only. --check: exit 1
 * unless the measured orders on the swing scene are 1 (backward Euler) and 2
 * (BDF2) within 10%, and each controller run meets its requested error
 * within 2x with its global estimate within [0.5, 2] of its true error (fast:
 * 3e-2, 3e-3, 1e-3 m/s on the swing; full: every tolerance, both scenes).
 * --cotton writes bench_workprecision_cotton.*; --check then asks that every
 * implicit series has an order and that each preconditioner's errors are
 * be_1e-5's within 1% (it has no controller).
 *
 * Test bench_workprecision in test/CMakeLists.txt.
 * Test bench_workprecision_cotton in test/CMakeLists.txt.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "odecloth/cloth.h"
#include "bench_util.h"

/* positions are compared every SAMPLE_DT seconds (T a multiple of it; every
 * step rate a multiple of 1 / SAMPLE_DT = 4 Hz, 60 fps included) */
#define SAMPLE_DT 0.25

enum { SWING = 0, SPHERE = 1 };
static const char *scene_name[2] = {"swing", "sphere"};
static const double sphere_c[3] = {0.2, 0.1, 0.55}, sphere_r = 0.3;

/* What a run's cloth is: the scene's grid and duration, and for the order
 * checks a damping factor and the definiteness rule. */
typedef struct config {
    int grid;
    double T;         /* simulated seconds, a multiple of SAMPLE_DT */
    int nsamp;        /* T / SAMPLE_DT */
    double damping;   /* factor on the preset's c_t and c_b */
    double k_t;       /* N/m, tension stiffness (the preset's: 2000) */
    int rule;         /* solver.definiteness_rule */
    double *swing_x0; /* the swing scene's settled start (3n), made once */
} config;

/* How a series solves its steps. */
typedef struct variant {
    cloth_method method;
    double cg_tol;         /* CLOTH_LINEARIZED's CG tolerance */
    cloth_precond precond; /* CLOTH_PRECOND_AUTO: the solver's default */
    int newton;            /* 0: linearised; n: CLOTH_NEWTON with at most n iterations (1: kept unconverged) */
} variant;

/* CLOTH_NEWTON's tolerance, m/s: an RMS velocity correction, so over 2 s at
 * most about 0.2 mm of position, under the errors it is compared with */
#define NEWTON_TOL 1e-4

/* The swing scene's start: the cloth hung in the xz plane from its two top
 * corners and settled (3 s of backward Euler at 100x the damping), then
 * pushed into a swing by a rigid rotation of 2 rad/s about the line through
 * the pins. Starting settled keeps the stiff stretch modes nearly unexcited:
 * the scene is smooth, which the order checks need. */
static const double swing_omega = 2.0;

static cloth_desc scene_desc(const config *cf, int scene, const variant *v)
{
    cloth_desc d = cloth_default_desc();
    d.solver.max_substep_halvings = 0; /* the method as it is: a failed step is a failure, not retried */
    d.rows = d.cols = cf->grid;
    d.material = cloth_material_preset(CLOTH_ELASTIC);
    d.material.density = 0.2;
    d.material.c_t *= cf->damping;
    d.material.c_b *= cf->damping;
    d.material.k_t = cf->k_t;
    d.solver.method = v->method;
    d.solver.precond = v->precond;
    d.solver.nonlinear = v->newton ? CLOTH_NEWTON : CLOTH_LINEARIZED; /* named, whatever the default */
    d.solver.cg_tolerance = v->cg_tol;
    d.solver.cg_max_iterations = 20000;
    d.solver.definiteness_rule = cf->rule;
    if (v->newton) {
        d.solver.newton_iterations = v->newton;
        d.solver.newton_tolerance = NEWTON_TOL;
        d.solver.keep_unconverged = v->newton == 1;
    }
    if (scene == SWING) {
        /* hanging: rows go down from z = 1. No elongation limit: its
         * projection is an inelastic velocity change, which would cap every
         * method at order 1 (the swing never comes near delta anyway) */
        d.axis_v[1] = 0.0;
        d.axis_v[2] = -1.0;
        d.solver.strain_limit_iterations = 0;
        d.material.k_delta = 0.0;
    }
    return d;
}

static cloth *new_cloth(const cloth_desc *d)
{
    cloth *c;
    cloth_error err;
    if (cloth_create(d, &c, &err) != CLOTH_OK) {
        fprintf(stderr, "bench_workprecision: %s\n", err.message);
        exit(1);
    }
    return c;
}

/* The settled hanging cloth's positions (3n), for cf->swing_x0. */
static double *settle_swing(const config *cf)
{
    const variant v = {CLOTH_BACKWARD_EULER, 1e-10, CLOTH_PRECOND_AUTO, 0};
    cloth_desc d = scene_desc(cf, SWING, &v);
    d.solver.definiteness_rule = 1;
    d.material.c_t = 100 * cloth_material_preset(CLOTH_ELASTIC).c_t;
    d.material.c_b = 100 * cloth_material_preset(CLOTH_ELASTIC).c_b;
    cloth *c = new_cloth(&d);
    const double *x = cloth_positions(c);
    cloth_pin(c, 0, x);
    cloth_pin(c, cf->grid - 1, x + 3 * (cf->grid - 1));
    for (int s = 0; s < 360; s++)
        if (cloth_step(c, 1.0 / 120, NULL) != CLOTH_OK) {
            fprintf(stderr, "bench_workprecision: settling failed: %s\n", cloth_last_error(c));
            exit(1);
        }
    size_t bytes = 3 * (size_t)cloth_vertex_count(c) * sizeof(double);
    double *x0 = malloc(bytes);
    if (!x0) exit(1);
    memcpy(x0, cloth_positions(c), bytes);
    cloth_destroy(c);
    return x0;
}

static cloth *make_cloth(const config *cf, int scene, const variant *var)
{
    cloth_desc d = scene_desc(cf, scene, var);
    cloth *c = new_cloth(&d);
    if (scene != SWING) return c;
    int n = cloth_vertex_count(c);
    const double *x = cloth_positions(c);
    double pin[3] = {x[0], x[1], x[2]};
    cloth_pin(c, 0, x);
    cloth_pin(c, cf->grid - 1, x + 3 * (cf->grid - 1));
    double *v = calloc(3 * (size_t)n, sizeof *v);
    if (!v) exit(1);
    for (int i = 0; i < n; i++) { /* omega x (x - pin), omega along +x */
        v[3 * i + 1] = -swing_omega * (cf->swing_x0[3 * i + 2] - pin[2]);
        v[3 * i + 2] = swing_omega * (cf->swing_x0[3 * i + 1] - pin[1]);
    }
    if (cloth_set_positions(c, cf->swing_x0) != CLOTH_OK || cloth_set_velocities(c, v) != CLOTH_OK) {
        fprintf(stderr, "bench_workprecision: %s\n", cloth_last_error(c));
        exit(1);
    }
    free(v);
    return c;
}

/* The core-only sphere: plane constraints on the vertices whose predicted end
 * position is inside; everything else free. Also the controller's callback. */
static int sphere_contacts(cloth *c, double h, void *user)
{
    (void)user;
    const double *x = cloth_positions(c), *v = cloth_velocities(c);
    int n = cloth_vertex_count(c);
    for (int i = 0; i < n; i++) {
        double p[3], d2 = 0.0;
        for (int a = 0; a < 3; a++) {
            p[a] = x[3 * i + a] + h * v[3 * i + a] - sphere_c[a];
            d2 += p[a] * p[a];
        }
        if (d2 >= sphere_r * sphere_r || d2 == 0.0) {
            cloth_release(c, i);
            continue;
        }
        double len = sqrt(d2);
        cloth_constraint k;
        memset(&k, 0, sizeof k);
        k.vertex = i;
        k.ndof = 1;
        for (int a = 0; a < 3; a++) k.axis[a] = p[a] / len;
        for (int a = 0; a < 3; a++) k.target[a] = sphere_c[a] + sphere_r * k.axis[a];
        cloth_set_constraint(c, &k);
    }
    return 0;
}

typedef struct run_result {
    int failed;       /* 1: a step failed or the error passed 1 m */
    double fail_time; /* s, simulated time reached */
    char why[64];
    double cpu_per_s;       /* CPU s per simulated s (over the time reached) */
    double cg_per_step;     /* mean CG iterations per step */
    double newton_per_step; /* mean Newton iterations per step (CLOTH_NEWTON) */
    long unconverged;       /* steps whose Newton iterate was kept unconverged */
    double error;           /* m, RMS against the reference (NAN if no reference) */
    double *samples;        /* nsamp x 3n positions */
    /* controller runs */
    double mean_substeps, mean_cg_tol;
    double explicit_frames; /* fraction of frames stepped by symplectic Euler */
    double estimate;        /* RMS over the samples of the controller's global estimate */
} run_result;

/* x (3n) - ref (3n): mean squared vertex distance */
static double msd(const double *x, const double *ref, int n)
{
    double s = 0.0;
    for (int k = 0; k < 3 * n; k++) s += (x[k] - ref[k]) * (x[k] - ref[k]);
    return s / n;
}

static double sample_time(int k) { return SAMPLE_DT * (k + 1); }

/* Keeps sample k of a run and adds its squared error against the reference
 * (if any) to *sq; a run whose error passes 1 m is marked blown up. */
static void take_sample(cloth *c, int k, const double *ref, run_result *r, double *sq)
{
    int n = cloth_vertex_count(c);
    memcpy(r->samples + (size_t)k * 3 * n, cloth_positions(c), 3 * (size_t)n * sizeof(double));
    if (!ref) return;
    double e = msd(cloth_positions(c), ref + (size_t)k * 3 * n, n);
    *sq += e;
    if (!(e <= 1.0)) {
        r->failed = 1;
        snprintf(r->why, sizeof r->why, "error > 1 m");
    }
}

/* A fixed-step run at hz steps per second (a multiple of 1 / SAMPLE_DT). */
static run_result run_fixed(const config *cf, int scene, const variant *v, double hz, const double *ref)
{
    run_result r = {0};
    cloth *c = make_cloth(cf, scene, v);
    int n = cloth_vertex_count(c);
    r.samples = calloc((size_t)cf->nsamp * 3 * n, sizeof *r.samples);
    double h = 1.0 / hz, sq = 0.0;
    long steps = 0, iters = 0, newton = 0;
    double t0 = bench_cpu_now();
    for (int k = 0; k < cf->nsamp && !r.failed; k++) {
        long until = lround(sample_time(k) * hz);
        for (; steps < until; steps++) {
            if (scene == SPHERE) sphere_contacts(c, h, NULL);
            cloth_step_stats st;
            if (cloth_step(c, h, &st) != CLOTH_OK) {
                r.failed = 1;
                snprintf(r.why, sizeof r.why, "%s", cloth_failure_string(st.failure));
                break;
            }
            iters += st.iterations;
            newton += st.newton;
            r.unconverged += st.unconverged;
        }
        if (!r.failed) take_sample(c, k, ref, &r, &sq);
    }
    double cpu = bench_cpu_now() - t0;
    r.fail_time = steps * h;
    r.cpu_per_s = r.fail_time > 0 ? cpu / r.fail_time : cpu;
    r.cg_per_step = steps ? (double)iters / steps : 0.0;
    r.newton_per_step = steps ? (double)newton / steps : 0.0;
    r.error = (ref && !r.failed) ? sqrt(sq / cf->nsamp) : NAN;
    cloth_destroy(c);
    return r;
}

/* The accuracy-driven controller at 60 frames per second. */
static run_result run_adaptive(const config *cf, int scene, double tol, const double *ref)
{
    run_result r = {0};
    const variant var = {CLOTH_BACKWARD_EULER, 1e-3, CLOTH_PRECOND_AUTO, 0};
    cloth *c = make_cloth(cf, scene, &var);
    int n = cloth_vertex_count(c);
    r.samples = calloc((size_t)cf->nsamp * 3 * n, sizeof *r.samples);
    cloth_adaptive_desc ad = cloth_adaptive_default_desc();
    ad.tolerance = tol;
    if (scene == SPHERE) ad.before_substep = sphere_contacts;
    cloth_adaptive *ctl;
    cloth_error err;
    if (cloth_adaptive_create(c, &ad, &ctl, &err) != CLOTH_OK) {
        fprintf(stderr, "bench_workprecision: %s\n", err.message);
        exit(1);
    }
    const double hz = 60.0, h = 1.0 / hz;
    double sq = 0.0, sub = 0.0, cgt = 0.0, gsq = 0.0;
    long frames = 0, steps = 0, iters = 0, sym = 0;
    cloth_adaptive_stats st = {0};
    double t0 = bench_cpu_now();
    for (int k = 0; k < cf->nsamp && !r.failed; k++) {
        long until = lround(sample_time(k) * hz);
        for (; frames < until; frames++) {
            cloth_status cs = cloth_adaptive_frame(ctl, c, h, &st);
            if (cs != CLOTH_OK) {
                r.failed = 1;
                snprintf(r.why, sizeof r.why, "%s", cloth_failure_string(st.failure));
                break;
            }
            steps += st.steps;
            iters += st.cg_iterations;
            sub += st.substeps;
            sym += st.method == CLOTH_SYMPLECTIC_EULER;
            cgt += log(st.cg_tolerance);
        }
        if (r.failed) break;
        memcpy(r.samples + (size_t)k * 3 * n, cloth_positions(c), 3 * (size_t)n * sizeof(double));
        sq += msd(cloth_positions(c), ref + (size_t)k * 3 * n, n);
        gsq += st.global_estimate * st.global_estimate;
    }
    double cpu = bench_cpu_now() - t0;
    r.fail_time = frames * h;
    r.cpu_per_s = r.fail_time > 0 ? cpu / r.fail_time : cpu;
    r.cg_per_step = steps ? (double)iters / steps : 0.0;
    r.error = r.failed ? NAN : sqrt(sq / cf->nsamp);
    r.mean_substeps = frames ? sub / frames : 0.0;
    r.mean_cg_tol = frames ? exp(cgt / frames) : 0.0;
    r.explicit_frames = frames ? (double)sym / frames : 0.0;
    r.estimate = r.failed ? NAN : sqrt(gsq / cf->nsamp);
    cloth_adaptive_destroy(ctl);
    cloth_destroy(c);
    return r;
}

/* RMS over the samples of the difference of two runs' positions */
static double rms_between(const double *a, const double *b, int n, int nsamp)
{
    double s = 0.0;
    for (int k = 0; k < nsamp; k++) s += msd(a + (size_t)k * 3 * n, b + (size_t)k * 3 * n, n);
    return sqrt(s / nsamp);
}

/* The order between consecutive step sizes: log(e1/e2) / log(hz2/hz1). */
static double order_of(double e1, double hz1, double e2, double hz2) { return log(e1 / e2) / log(hz2 / hz1); }

typedef struct reference {
    double *x;     /* nsamp x 3n */
    double change; /* m, RMS difference to the run at half its h */
    double cpu_per_s, cg_per_step;
} reference;

/* At hz with CG tolerance 1e-10 and the exact Jacobian (definiteness rule
 * off: the rule changes the solver, not the equations, and with it BDF2 is
 * only first order), and again at 2 hz to show it has converged. The swing:
 * BDF2. The sphere: backward Euler, as BDF2 does not converge through the
 * contacts: a vertex stopped by its plane constraint keeps, in BDF2's
 * x_n - x_{n-1}, the step before the contact, an error of the size of that
 * step's motion at every contact event, whatever h (docs/benchmarks.md).
 * Symplectic Euler (method given) for --cotton: see family_reference. */
static reference make_reference(const config *cf, int scene, cloth_method m, double hz)
{
    config rc = *cf;
    rc.rule = 0;
    const variant v = {m, 1e-10, CLOTH_PRECOND_AUTO, 0};
    run_result a = run_fixed(&rc, scene, &v, hz, NULL);
    run_result b = run_fixed(&rc, scene, &v, 2 * hz, NULL);
    if (a.failed || b.failed) {
        fprintf(stderr, "bench_workprecision: the reference run failed (%s%s)\n", a.why, b.why);
        exit(1);
    }
    reference R = {b.samples, rms_between(a.samples, b.samples, cf->grid * cf->grid, cf->nsamp), b.cpu_per_s,
                   b.cg_per_step};
    printf("reference: %s h = 1/%.0f%s (%.2f CPU s per s); at h = 1/%.0f it differs by %.3g m RMS\n",
           m == CLOTH_BDF2             ? "BDF2"
           : m == CLOTH_BACKWARD_EULER ? "backward Euler"
                                       : "symplectic Euler",
           2 * hz, m == CLOTH_SYMPLECTIC_EULER ? "" : ", CG tol 1e-10", b.cpu_per_s, hz, R.change);
    fflush(stdout);
    free(a.samples);
    return R;
}

/* The reference's method and coarser rate (it runs at twice it too). --cotton: symplectic Euler, which
 * leaves the stiff modes ringing: on the 21x21 swing's 1 s it moves 1.4e-7 m when its h is halved at
 * 1/98304, BDF2 3.3e-6 m at 1/12288, for 3x the CPU. */
static cloth_method family_reference(int cotton, int fast, int scene, double *hz)
{
    if (cotton) {
        *hz = fast ? 24576 : 98304;
        return CLOTH_SYMPLECTIC_EULER;
    }
    *hz = fast ? 4096 : 12288;
    if (scene == SWING) return CLOTH_BDF2;
    *hz *= 2; /* the sphere's reference is first order: twice the rate */
    return CLOTH_BACKWARD_EULER;
}

/* The controller's tolerance is m per simulated second: what it should reach
 * is the RMS over the sample times of tol * t. */
static double requested_error(const config *cf, double tol)
{
    double req = 0.0;
    for (int k = 0; k < cf->nsamp; k++) req += pow(tol * sample_time(k), 2);
    return sqrt(req / cf->nsamp);
}

/* The orders of convergence on the smooth swing scene, 11x11, 1 s, in the
 * range where theory applies. Backward Euler's asymptotic range needs
 * h below about c_t / k_t: beyond it the stiff stretch modes, which ring
 * (lightly damped) in the exact motion, are damped away by the method, an
 * error that does not shrink like h. The preset's 1e-5 s is out of a test's
 * reach (the chart shows orders of 0.7 to 1.3 there), so the check's cloth is
 * softer and more damped: k_t 200 N/m, c_t and c_b 2.5x (c_t / k_t =
 * 2.5e-4 s), with the default solver for backward Euler. BDF2 with the
 * definiteness rule off: the rule's Jacobian is not the exact one, which
 * makes the linearised BDF2 first order where links are compressed (the
 * chart's BDF2 uses the rule); the damping's Jacobian leaves out the terms
 * from the link's turning, a first-order error term too, small while the
 * damping is. Each: the orders over two halvings, both within 10%; the
 * reference (BDF2, exact Jacobian, 1/16384 and 1/32768) shared, and shown to
 * have converged. */
static int order_checks(void)
{
    static const double hz_be[] = {2048, 4096, 8192}, hz_bdf2[] = {1024, 2048, 4096};
    config cf = {11, 1.0, 4, 2.5, 200.0, 0, NULL};
    cf.swing_x0 = settle_swing(&cf);
    printf("== order checks: 11x11 swing, 1 s, k_t %g N/m, damping x%g\n", cf.k_t, cf.damping);
    reference R = make_reference(&cf, SWING, CLOTH_BDF2, 16384);
    int bad = 0;
    for (int k = 0; k < 2; k++) {
        cf.rule = k == 0;
        const variant v = {k == 0 ? CLOTH_BACKWARD_EULER : CLOTH_BDF2, 1e-10, CLOTH_PRECOND_AUTO, 0};
        double want = k == 0 ? 1.0 : 2.0, e[3];
        const double *hz = k == 0 ? hz_be : hz_bdf2;
        for (int j = 0; j < 3; j++) {
            run_result r = run_fixed(&cf, SWING, &v, hz[j], R.x);
            e[j] = r.failed ? NAN : r.error;
            printf("%s (rule %s) h = 1/%-5.0f error %.4g m%s\n", k == 0 ? "backward Euler" : "BDF2",
                   cf.rule ? "on" : "off", hz[j], e[j], r.failed ? " (failed)" : "");
            free(r.samples);
        }
        for (int j = 0; j < 2; j++) {
            double p = order_of(e[j], hz[j], e[j + 1], hz[j + 1]);
            int ok = fabs(p - want) <= 0.1 * want;
            printf("check: %s order between 1/%.0f and 1/%.0f: %.3f (want %.0f within 10%%): %s\n",
                   k == 0 ? "backward Euler" : "BDF2", hz[j], hz[j + 1], p, want, ok ? "ok" : "FAILED");
            bad |= !ok;
        }
        int ok = R.change < 0.1 * e[2];
        printf("check: reference change %.3g m < 0.1 x smallest error %.3g m: %s\n", R.change, e[2],
               ok ? "ok" : "FAILED");
        bad |= !ok;
    }
    free(R.x);
    free(cf.swing_x0);
    return bad;
}

typedef struct series {
    const char *label; /* the CSV's name */
    const char *title; /* the chart's */
    variant v;
    const double *hz; /* 0-terminated */
} series;

/* The fixed-step runs of a scene, for the frontier and the orders: error and
 * cost of each (error NaN if blown up), series by series in order of h. */
#define MAXPTS 16
#define MAXSERIES 16
typedef struct frontier {
    int nseries, npts[MAXSERIES];
    double hz[MAXSERIES][MAXPTS], err[MAXSERIES][MAXPTS], cpu[MAXSERIES][MAXPTS];
    const char *best; /* the series of the last frontier_cost */
} frontier;

/* The cheapest cost at which a fixed-step series reaches error e: on each
 * series, log-log interpolation between consecutive step sizes whose errors
 * bracket e (or a point at or below e); the least over the series. HUGE_VAL
 * if none reaches it. */
static double frontier_cost(frontier *F, const series *S, double e)
{
    double best = HUGE_VAL;
    F->best = "none";
    for (int s = 0; s < F->nseries; s++)
        for (int k = 0; k < F->npts[s]; k++) {
            double e1 = F->err[s][k], c1 = F->cpu[s][k], c = HUGE_VAL;
            if (!(e1 == e1)) continue;
            if (e1 <= e) c = c1;
            if (k > 0 && F->err[s][k - 1] == F->err[s][k - 1] && F->err[s][k - 1] > e && e1 <= e) {
                double e0 = F->err[s][k - 1], c0 = F->cpu[s][k - 1];
                c = exp(log(c0) + (log(c1) - log(c0)) * (log(e) - log(e0)) / (log(e1) - log(e0)));
            }
            if (c < best) {
                best = c;
                F->best = S[s].label;
            }
        }
    return best;
}

/* A series' fitted order and the window it was fitted over. */
typedef struct order_fit {
    double order; /* NAN: fewer than 2 points in the window */
    double hz_lo, hz_hi;
    int npts;
    double err_lo, err_hi; /* m, the errors at hz_lo and hz_hi */
} order_fit;

#define FIT_POINTS 4 /* the automatic window's size at most */
#define RESOLVED 3.0 /* a point counts when its error is this many times the reference's change */
#define AGREE 0.25   /* the automatic window's pairs' orders agree within this */

/* Whether point k of series s can be fitted: ran, resolved, and within the
 * given window (win[1] == 0: no window given). */
static int fittable(const frontier *F, int s, int k, double floor, const double win[2])
{
    double e = F->err[s][k], hz = F->hz[s][k];
    if (win[1] > 0) return e == e && e > 0 && hz >= win[0] && hz <= win[1];
    return e == e && e >= floor;
}

/* Least squares of log error on log h over the window. Without one given:
 * from the smallest fittable step size up, at most FIT_POINTS in a row,
 * while each pair's order is within AGREE of the finest pair's. */
static order_fit fit_order(const frontier *F, int s, double floor, const double win[2])
{
    order_fit o = {NAN, 0, 0, 0, NAN, NAN};
    int hi = F->npts[s] - 1, lo;
    const double *hz = F->hz[s], *e = F->err[s];
    while (hi >= 0 && !fittable(F, s, hi, floor, win)) hi--;
    if (hi < 0) return o;
    double p0 = hi > 0 ? order_of(e[hi - 1], hz[hi - 1], e[hi], hz[hi]) : NAN;
    for (lo = hi; lo > 0 && fittable(F, s, lo - 1, floor, win); lo--)
        if (win[1] == 0 &&
            (hi - lo + 1 == FIT_POINTS || !(fabs(order_of(e[lo - 1], hz[lo - 1], e[lo], hz[lo]) - p0) <= AGREE)))
            break;
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int k = lo; k <= hi; k++) {
        double x = log(hz[k]), y = log(e[k]);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    o.npts = hi - lo + 1;
    o.hz_lo = hz[lo], o.hz_hi = hz[hi];
    o.err_lo = e[lo], o.err_hi = e[hi];
    if (o.npts >= 2) o.order = -(o.npts * sxy - sx * sy) / (o.npts * sxx - sx * sx);
    return o;
}

/* "0.97 (1/192..1/1536)", or "-" with no fit. */
static void order_text(const order_fit *o, char *buf, size_t cap)
{
    if (o->order == o->order) snprintf(buf, cap, "%.2f (1/%.0f..1/%.0f)", o->order, o->hz_lo, o->hz_hi);
    else snprintf(buf, cap, "-");
}

/* The series of the default family and of --cotton, their step rates. */
static const double hz_impl[] = {24, 48, 60, 96, 192, 384, 768, 1536, 0}; /* 60: the headline */
static const double hz_impl_fast[] = {24, 48, 96, 192, 384, 0};
static const double hz_expl[] = {60, 1536, 3072, 6144, 12288, 24576, 49152, 98304, 0};
static const double hz_expl_fast[] = {1536, 6144, 24576, 0};
static const double hz_c_impl[] = {24, 60, 96, 192, 384, 768, 1536, 3072, 0};
static const double hz_c_few[] = {60, 192, 768, 3072, 0};
static const double hz_c_sympl[] = {60, 3072, 6144, 12288, 24576, 49152, 0};
static const double hz_c_expl[] = {60, 24576, 49152, 98304, 196608, 0};
static const double hz_c_fast[] = {60, 192, 768, 0};
static const double hz_c_fast_expl[] = {60, 24576, 196608, 0};

#define BE CLOTH_BACKWARD_EULER
#define AUTO CLOTH_PRECOND_AUTO
/* Fills S (room for MAXSERIES) with the family's series; returns how many. */
static int family_series(series *S, int cotton, int fast)
{
    const double *hi = fast ? hz_impl_fast : hz_impl, *he = fast ? hz_expl_fast : hz_expl;
    if (cotton) {
        hi = fast ? hz_c_fast : hz_c_impl;
        he = fast ? hz_c_fast_expl : hz_c_expl;
    }
    const double *hs = cotton ? (fast ? hz_c_fast_expl : hz_c_sympl) : he, *hf = fast ? hz_c_fast : hz_c_few;
    const series all[] = {
        {"explicit_euler", "explicit Euler", {CLOTH_EXPLICIT_EULER, 1e-3, AUTO, 0}, he},
        {"symplectic_euler", "symplectic Euler", {CLOTH_SYMPLECTIC_EULER, 1e-3, AUTO, 0}, hs},
        {"be_1e-2", "BE, CG tol 1e-2", {BE, 1e-2, AUTO, 0}, hi},
        {"be_1e-3", "BE, CG tol 1e-3", {BE, 1e-3, AUTO, 0}, hi},
        {"be_1e-5", "BE, CG tol 1e-5", {BE, 1e-5, AUTO, 0}, hi},
        {"bdf2_1e-5", "BDF2, CG tol 1e-5", {CLOTH_BDF2, 1e-5, AUTO, 0}, hi},
        {"newton_be", "Newton BE, 1e-4 m/s", {BE, 1e-3, AUTO, 64}, hi},
        {"newton_bdf2", "Newton BDF2, 1e-4 m/s", {CLOTH_BDF2, 1e-3, AUTO, 64}, hi},
        {"newton1_be", "Newton BE, 1 iteration", {BE, 1e-3, AUTO, 1}, hi},
        {"newton1_bdf2", "Newton BDF2, 1 iteration", {CLOTH_BDF2, 1e-3, AUTO, 1}, hi},
        {"be_1e-5_jacobi", "BE 1e-5, Jacobi", {BE, 1e-5, CLOTH_PRECOND_JACOBI, 0}, hf},
        {"be_1e-5_multigrid", "BE 1e-5, multigrid", {BE, 1e-5, CLOTH_PRECOND_MULTIGRID, 0}, hf},
        {"be_1e-5_ssor", "BE 1e-5, SSOR", {BE, 1e-5, CLOTH_PRECOND_SSOR, 0}, hf},
    };
    int n = cotton ? (int)(sizeof all / sizeof all[0]) : 6;
    memcpy(S, all, (size_t)n * sizeof *S);
    return n;
}
#undef BE
#undef AUTO

/* What main decided from the command line. */
typedef struct options {
    bench_opts o;
    int only; /* -1: both scenes, else SWING or SPHERE */
    int cotton;
    int grids[2], ngrids;
    double swing_T, sphere_T;
    double window[2]; /* --order-window LO,HI (Hz); [1] = 0: automatic */
    const char *name; /* output base name */
} options;

static const char usage[] =
    "usage: bench_workprecision [--out DIR] [--grid N] [--scene swing|sphere] [--sphere-seconds T]\n"
    "                           [--cotton] [--swing-seconds T] [--order-window LO,HI] [--fast] [--check]\n"
    "RMS position error against CPU time per simulated second for explicit,\n"
    "symplectic and backward Euler (CG tolerances 1e-2, 1e-3, 1e-5), BDF2 and the\n"
    "accuracy-driven controller, on a swinging and a sphere-draped cloth.\n"
    "Writes DIR/bench_workprecision.csv and .png (default DIR out/bench), and the\n"
    "fitted orders with their windows in DIR/bench_workprecision_orders.csv and .md.\n"
    "--sphere-seconds T: the sphere scene's duration (a multiple of 0.25 s, default 0.25).\n"
    "--swing-seconds T: the swing's (default 2; --fast and --cotton 1).\n"
    "--cotton: the cotton preset (k_t 2000 N/m, its damping) at 21x21 and 41x41 (or --grid N),\n"
    "also the Newton step (to 1e-4 m/s and one iteration) and each preconditioner, no\n"
    "controller; writes DIR/bench_workprecision_cotton.*.\n"
    "--order-window LO,HI: fit the orders over the step rates LO..HI Hz (default: each\n"
    "series' 4 smallest resolved step sizes).\n"
    "--fast: 11x11, swing only, 1 s. --check: exit 1 unless BE order 1 and BDF2\n"
    "order 2 (within 10%), the controller within 2x of its requested error and its\n"
    "global estimate within [0.5, 2] of its true error (--cotton: every implicit series\n"
    "has an order, each preconditioner's errors are be_1e-5's within 1%).";

/* Parses a duration option's value: a multiple of SAMPLE_DT up to 10 s. */
static int parse_seconds(const char *opt, const char *v, double *T)
{
    char *end;
    *T = strtod(v, &end);
    if (*end || !(*T >= SAMPLE_DT) || *T > 10 || fmod(*T, SAMPLE_DT) != 0.0) {
        fprintf(stderr, "bench_workprecision: %s '%s' must be a multiple of %g s up to 10\n", opt, v, SAMPLE_DT);
        return 0;
    }
    return 1;
}

enum { OPT_COTTON = BENCH_OWN, OPT_SCENE, OPT_SPHERE_SECONDS, OPT_SWING_SECONDS, OPT_ORDER_WINDOW };

static const struct option own_options[] = {
    {"cotton", no_argument, NULL, OPT_COTTON},
    {"scene", required_argument, NULL, OPT_SCENE},
    {"sphere-seconds", required_argument, NULL, OPT_SPHERE_SECONDS},
    {"swing-seconds", required_argument, NULL, OPT_SWING_SECONDS},
    {"order-window", required_argument, NULL, OPT_ORDER_WINDOW},
    {NULL, 0, NULL, 0},
};

/* This program's own options (bench_take_fn). */
static int take_option(void *ctx, int opt, const char *v)
{
    options *op = ctx;
    switch (opt) {
    case OPT_COTTON: op->cotton = 1; return 0;
    case OPT_SCENE:
        op->only = !strcmp(v, "swing") ? SWING : !strcmp(v, "sphere") ? SPHERE : -2;
        if (op->only == -2) {
            fprintf(stderr, "bench_workprecision: --scene '%s' must be swing or sphere\n", v);
            return 2;
        }
        return 0;
    case OPT_SPHERE_SECONDS: return parse_seconds("--sphere-seconds", v, &op->sphere_T) ? 0 : 2;
    case OPT_SWING_SECONDS: return parse_seconds("--swing-seconds", v, &op->swing_T) ? 0 : 2;
    default: { /* OPT_ORDER_WINDOW */
        char *end;
        op->window[0] = strtod(v, &end);
        op->window[1] = *end == ',' ? strtod(end + 1, &end) : 0.0;
        if (*end || !(op->window[0] > 0) || !(op->window[1] > op->window[0])) {
            fprintf(stderr, "bench_workprecision: --order-window '%s' must be LO,HI with 0 < LO < HI (Hz)\n", v);
            return 2;
        }
        return 0;
    }
    }
}

/* Fills op from the command line; returns -1 to go on, else the exit status. */
static int parse_options(options *op, int argc, char **argv)
{
    memset(op, 0, sizeof *op);
    op->o = (bench_opts){"bench_workprecision", usage, "out/bench", 0, 0, 0};
    op->only = -1;
    op->sphere_T = 0.25;
    int rc = bench_parse(&op->o, own_options, take_option, op, argc, argv);
    if (rc >= 0) return rc;
    if (!op->swing_T) op->swing_T = op->o.fast || op->cotton ? 1.0 : 2.0;
    op->name = op->cotton ? "bench_workprecision_cotton" : "bench_workprecision";
    op->ngrids = 1;
    op->grids[0] = op->o.fast ? 11 : 21;
    if (op->cotton && !op->o.fast && !op->o.grid) op->grids[op->ngrids++] = 41;
    if (op->o.grid) op->grids[0] = op->o.grid;
    return -1;
}

/* One scene's panel: its fixed-step runs, the reference's change and the
 * fitted orders (for the chart's key and the orders files). */
typedef struct panel {
    int scene, grid;
    double ref_change;
    frontier F;
    order_fit fit[MAXSERIES];
} panel;

/* Runs every series of S on the scene, writing CSV rows and filling P->F. */
static void run_series(const config *cf, panel *P, const series *S, int nseries, const reference *R, FILE *csv)
{
    frontier *F = &P->F;
    F->nseries = nseries;
    printf("%-18s %8s %12s %14s %8s %6s  %s\n", "series", "h", "error m", "CPU s / sim s", "CG it", "Newton", "");
    for (int s = 0; s < nseries; s++) {
        double prev_e = NAN, prev_hz = 0.0;
        for (const double *hz = S[s].hz; *hz > 0; hz++) {
            run_result r = run_fixed(cf, P->scene, &S[s].v, *hz, R->x);
            char note[128] = "";
            if (r.failed) snprintf(note, sizeof note, "BLOWN UP at t = %.3g s: %s", r.fail_time, r.why);
            else if (prev_e == prev_e)
                snprintf(note, sizeof note, "order %.3f", order_of(prev_e, prev_hz, r.error, *hz));
            if (r.unconverged)
                snprintf(note + strlen(note), sizeof note - strlen(note), " (%ld kept unconverged)", r.unconverged);
            printf("%-18s 1/%-6.0f %12.4g %14.4g %8.1f %6.2f  %s\n", S[s].label, *hz, r.error, r.cpu_per_s,
                   r.cg_per_step, r.newton_per_step, note);
            fflush(stdout);
            fprintf(csv, "%s,%s,%.0f,%g,,%.6g,%.6g,%.3f,%d,%g,%s,,,,,,%d,%g,%.3f,%ld\n", scene_name[P->scene],
                    S[s].label, *hz, S[s].v.cg_tol, r.error, r.cpu_per_s, r.cg_per_step, r.failed, r.fail_time, r.why,
                    cf->grid, cf->k_t, r.newton_per_step, r.unconverged);
            if (F->npts[s] < MAXPTS) {
                F->hz[s][F->npts[s]] = *hz;
                F->err[s][F->npts[s]] = r.failed ? NAN : r.error;
                F->cpu[s][F->npts[s]++] = r.cpu_per_s;
            }
            prev_e = r.failed ? NAN : r.error;
            prev_hz = *hz;
            free(r.samples);
        }
    }
}

/* The controller at each tolerance, against the frontier; returns 1 if a
 * check failed. */
static int run_controller(const config *cf, panel *P, const series *S, const double *tols, const reference *R,
                          int check, FILE *csv)
{
    int bad = 0;
    const char *sc = scene_name[P->scene];
    for (const double *t = tols; *t > 0; t++) {
        run_result r = run_adaptive(cf, P->scene, *t, R->x);
        double req = requested_error(cf, *t), fc = frontier_cost(&P->F, S, r.error);
        printf("%-18s tol %-6.0e %10.4g %14.4g %8.1f  requested %.3g m (ratio %.2f), %.2f substeps/frame "
               "(%.0f%% symplectic), CG tol %.2g; global estimate %.3g m (%.2f of the error); frontier at this "
               "error %.3g CPU s/s (%s: %.1fx)%s%s\n",
               "controller", *t, r.error, r.cpu_per_s, r.cg_per_step, req, r.error / req, r.mean_substeps,
               100 * r.explicit_frames, r.mean_cg_tol, r.estimate, r.estimate / r.error, fc, P->F.best,
               r.cpu_per_s / fc, r.failed ? " FAILED: " : "", r.why);
        fprintf(csv, "%s,controller,60,%g,%.6g,%.6g,%.6g,%.3f,%d,%g,%s,%.3f,%.3g,%.3f,%.6g,%.6g,%d,%g,,\n", sc, *t, req,
                r.error, r.cpu_per_s, r.cg_per_step, r.failed, r.fail_time, r.why, r.mean_substeps, r.mean_cg_tol,
                r.explicit_frames, r.estimate, fc, cf->grid, cf->k_t);
        if (check) {
            int ok = !r.failed && r.error <= 2.0 * req;
            printf("check: %s controller tol %g m/s: error %.3g <= 2 x requested %.3g: %s\n", sc, *t, r.error, req,
                   ok ? "ok" : "FAILED");
            bad |= !ok;
            double q = r.estimate / r.error;
            ok = q >= 0.5 && q <= 2.0;
            printf("check: %s controller tol %g m/s: global estimate / error %.2f in [0.5, 2]: %s\n", sc, *t, q,
                   ok ? "ok" : "FAILED");
            bad |= !ok;
        }
        free(r.samples);
    }
    return bad;
}

/* Prints and keeps each series' order with its window. */
static void fit_orders(panel *P, const series *S, const double win[2])
{
    for (int s = 0; s < P->F.nseries; s++) {
        P->fit[s] = fit_order(&P->F, s, RESOLVED * P->ref_change, win);
        char t[64];
        order_text(&P->fit[s], t, sizeof t);
        printf("order %-18s %s, %d points, errors %.3g .. %.3g m\n", S[s].label, t, P->fit[s].npts, P->fit[s].err_lo,
               P->fit[s].err_hi);
    }
}

/* Errors within 1% of each other, or both blown up (NaN). */
static int same_error(double a, double b) { return (a != a && b != b) || fabs(a / b - 1) <= 0.01; }

/* The --cotton check: every implicit series has an order, and each
 * preconditioner's errors are be_1e-5's within 1% (the same equations
 * solved to the same tolerance). Returns 1 if one fails. */
static int cotton_checks(const panel *P, const series *S)
{
    int bad = 0, be = -1;
    for (int s = 0; s < P->F.nseries; s++)
        if (!strcmp(S[s].label, "be_1e-5")) be = s;
    for (int s = 0; s < P->F.nseries; s++) {
        int implicit = S[s].v.method == CLOTH_BACKWARD_EULER || S[s].v.method == CLOTH_BDF2, ok = 1;
        if (implicit && !(P->fit[s].order == P->fit[s].order)) ok = 0;
        for (int k = 0; S[s].v.precond != CLOTH_PRECOND_AUTO && be >= 0 && k < P->F.npts[s]; k++)
            for (int j = 0; j < P->F.npts[be]; j++)
                if (P->F.hz[be][j] == P->F.hz[s][k] && !same_error(P->F.err[s][k], P->F.err[be][j])) ok = 0;
        printf("check: %s %s: %s%s: %s\n", scene_name[P->scene], S[s].label, implicit ? "has an order" : "ran",
               S[s].v.precond != CLOTH_PRECOND_AUTO ? ", errors be_1e-5's within 1%" : "", ok ? "ok" : "FAILED");
        bad |= !ok;
    }
    return bad;
}

/* Everything of one scene at one grid; returns 1 if a check failed. */
static int run_scene(config *cf, const options *op, panel *P, const series *S, int nseries, FILE *csv)
{
    static const double tols_full[] = {1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 0}, tols_fast[] = {3e-2, 3e-3, 1e-3, 0};
    const int sc = P->scene, fast = op->o.fast, check = op->o.check;
    cf->T = sc == SPHERE ? op->sphere_T : op->swing_T; /* the sphere: contacts from about 0.18 s */
    cf->nsamp = (int)lround(cf->T / SAMPLE_DT);
    printf("== %s, %dx%d, k_t %g N/m, damping x%g, T = %g s\n", scene_name[sc], cf->grid, cf->grid, cf->k_t,
           cf->damping, cf->T);
    double hz_ref;
    cloth_method m = family_reference(op->cotton, fast, sc, &hz_ref);
    reference R = make_reference(cf, sc, m, hz_ref);
    P->ref_change = R.change;
    fprintf(csv, "%s,reference_change,%.0f,%s,,%.6g,%.6g,%.3f,0,%g,,,,,,,%d,%g,,\n", scene_name[sc], hz_ref,
            m == CLOTH_SYMPLECTIC_EULER ? "" : "1e-10", R.change, R.cpu_per_s, R.cg_per_step, cf->T, cf->grid, cf->k_t);
    run_series(cf, P, S, nseries, &R, csv);
    double min_err = HUGE_VAL;
    for (int s = 0; s < nseries; s++)
        for (int k = 0; k < P->F.npts[s]; k++)
            if (P->F.err[s][k] < min_err) min_err = P->F.err[s][k];
    printf("smallest plotted error %.3g m; the reference changes by %.3g m (%.2g of it) when its h is halved\n",
           min_err, R.change, R.change / min_err);
    fit_orders(P, S, op->window);
    int bad = check && op->cotton ? cotton_checks(P, S) : 0;
    if (!op->cotton) bad |= run_controller(cf, P, S, fast ? tols_fast : tols_full, &R, check, csv);
    free(R.x);
    return bad;
}

/* The chart's colours, one a series (the controller last). */
static const char *const colours[] = {"#9400d3", "#009e73", "#56b4e9", "#e69f00", "#0072b2", "#d55e00",
                                      "#cc79a7", "#000000", "#8c564b", "#7f7f00", "#17becf", "#ff1493",
                                      "#2ca02c", "#b22222", "#708090", "#ff0000"};

/* One panel's plot command: each series with its order and window in the
 * key, blown-up runs as crosses on the top edge, the reference's change. */
static void chart_panel(FILE *gp, const char *csv, const panel *P, const series *S, int controller)
{
    const char *sc = scene_name[P->scene];
    fprintf(gp, "set title '%s, %dx%d'\nplot ", sc, P->grid, P->grid);
    for (int s = 0; s < P->F.nseries; s++) {
        char t[64];
        order_text(&P->fit[s], t, sizeof t);
        int dashed = S[s].v.newton || S[s].v.precond != CLOTH_PRECOND_AUTO;
        fprintf(gp,
                "'%s' using (strcol(1) eq '%s' && strcol(2) eq '%s' && $17 == %d && $9 == 0 ? $7 : 1/0):6 "
                "with linespoints pt %d lc rgb '%s' dt %d title '%s: p %s', \\\n  ",
                csv, sc, S[s].label, P->grid, s % 13 + 1, colours[s], dashed ? 2 : 1, S[s].title, t);
        fprintf(gp,
                "'%s' using (strcol(1) eq '%s' && strcol(2) eq '%s' && $17 == %d && $9 == 1 ? $7 : 1/0):(top) "
                "with points pt 2 ps 2 lc rgb '%s' notitle, \\\n  ",
                csv, sc, S[s].label, P->grid, colours[s]);
    }
    if (controller)
        fprintf(gp,
                "'%s' using (strcol(1) eq '%s' && strcol(2) eq 'controller' && $9 == 0 ? $7 : 1/0):6 "
                "with linespoints pt 7 lc rgb '%s' title 'controller (60 fps)', \\\n  ",
                csv, sc, colours[15]);
    fprintf(gp,
            "'%s' using (strcol(1) eq '%s' && strcol(2) eq 'reference_change' && $17 == %d ? 1e-3 : 1/0):6:"
            "(1e3):(0) with vectors nohead dt 2 lc 'black' title 'reference change (h_{ref} halved)'\n",
            csv, sc, P->grid);
}

/* The chart: a panel per scene and grid (rows: grids), through gnuplot. */
static void write_chart(const options *op, const panel *P, int np, const series *S)
{
    FILE *gp = bench_open_script(&op->o, op->name);
    if (!gp) return;
    int cols = np > 1 && P[1].grid == P[0].grid ? 2 : 1, rows = (np + cols - 1) / cols;
    char csv[1100], family[160];
    snprintf(csv, sizeof csv, "%s/%s.csv", op->o.out, op->name);
    if (op->cotton) snprintf(family, sizeof family, "elastic cotton preset, k_t 2000 N/m, c_t / k_t 1e-5 s,");
    else snprintf(family, sizeof family, "%dx%d elastic cloth, k_t 200 N/m, damping 2.5x cotton", P[0].grid, P[0].grid);
    fprintf(gp,
            "set terminal pngcairo size %d,%d font ',10'\nset output '%s/%s.png'\nset datafile separator ','\n"
            "set multiplot layout %d,%d title 'odecloth work-precision, %s (swing %g s, sphere %g s); crosses "
            "on the top edge: blown up; p: order fitted over (window)'\n"
            "set logscale xy\nset grid\nset key bottom left opaque font ',%d'\n"
            "set xlabel 'CPU seconds per simulated second'\nset ylabel 'RMS position error, m'\n"
            "set yrange [%s:3]\nset xrange [1e-3:%s]\nset format y '10^{%%L}'\nset format x '10^{%%L}'\ntop = 2\n",
            op->o.fast   ? 640
            : op->cotton ? 1600
                         : 1200,
            op->cotton ? 760 * rows : 520, op->o.out, op->name, rows, cols, family, op->swing_T, op->sphere_T,
            op->cotton ? 7 : 8, op->o.fast || op->cotton ? "1e-8" : "1e-5", op->cotton ? "1e3" : "30");
    for (int p = 0; p < np; p++) chart_panel(gp, csv, &P[p], S, !op->cotton);
    fprintf(gp, "unset multiplot\n");
    fclose(gp);
    bench_run_gnuplot(&op->o, op->name);
}

/* The point of series s at rate hz as "error m, CPU s / s" or why not. */
static void point_text(const frontier *F, int s, double hz, char *buf, size_t cap)
{
    snprintf(buf, cap, "-");
    for (int k = 0; k < F->npts[s]; k++)
        if (F->hz[s][k] == hz) {
            if (F->err[s][k] == F->err[s][k]) snprintf(buf, cap, "%.3g, %.3g", F->err[s][k], F->cpu[s][k]);
            else snprintf(buf, cap, "blown up");
        }
}

/* <name>_orders.csv and <name>_orders.md: each panel's orders with their
 * windows, and (the table) each series at h = 1/60 and its smallest error. */
static void write_orders(const options *op, const panel *P, int np, const series *S)
{
    char name[128];
    snprintf(name, sizeof name, "%s_orders", op->name);
    FILE *csv = bench_open_csv(&op->o, name);
    char path[1100];
    snprintf(path, sizeof path, "%s/%s.md", op->o.out, name);
    FILE *md = fopen(path, "w");
    if (!csv || !md) {
        fprintf(stderr, "bench_workprecision: cannot write %s\n", path);
        if (csv) fclose(csv);
        if (md) fclose(md);
        return;
    }
    fprintf(csv, "scene,grid,series,order,hz_lo,hz_hi,points,error_at_hz_lo_m,error_at_hz_hi_m,"
                 "reference_change_m,window\n");
    fprintf(md, "<!-- written by bench_workprecision%s: do not edit -->\n", op->cotton ? " --cotton" : "");
    for (int p = 0; p < np; p++) {
        fprintf(md,
                "\n%s, %dx%d (reference change %.2g m; order p over the window 1/hz_lo..1/hz_hi):\n\n"
                "| series | h = 1/60: error m, CPU s / s | p (window) | errors over the window, m |\n"
                "|---|---|---|---|\n",
                scene_name[P[p].scene], P[p].grid, P[p].grid, P[p].ref_change);
        for (int s = 0; s < P[p].F.nseries; s++) {
            const order_fit *o = &P[p].fit[s];
            char t[64], at60[64];
            order_text(o, t, sizeof t);
            point_text(&P[p].F, s, 60, at60, sizeof at60);
            fprintf(csv, "%s,%d,%s,%.4f,%.0f,%.0f,%d,%.4g,%.4g,%.4g,%s\n", scene_name[P[p].scene], P[p].grid,
                    S[s].label, o->order, o->hz_lo, o->hz_hi, o->npts, o->err_lo, o->err_hi, P[p].ref_change,
                    op->window[1] > 0 ? "given" : "auto");
            fprintf(md, "| %s | %s | %s | %.3g .. %.3g |\n", S[s].title, at60, t, o->err_lo, o->err_hi);
        }
    }
    fclose(csv);
    fclose(md);
}

int main(int argc, char **argv)
{
    options op;
    int rc = parse_options(&op, argc, argv);
    if (rc >= 0) return rc;
    series S[MAXSERIES];
    int nseries = family_series(S, op.cotton, op.o.fast);
    FILE *csv = bench_open_csv(&op.o, op.name);
    panel *P = calloc(4, sizeof *P);
    if (!csv || !P) return 1;
    int np = 0, bad = 0;
    for (int g = 0; g < op.ngrids; g++) {
        config cf = {op.grids[g], op.swing_T, 0, op.cotton ? 1.0 : 2.5, op.cotton ? 2000.0 : 200.0, 1, NULL};
        cf.swing_x0 = settle_swing(&cf);
        for (int sc = 0; sc < 2; sc++) {
            if ((op.o.fast && sc == SPHERE) || (op.only >= 0 && sc != op.only)) continue; /* the checks: smooth */
            P[np].scene = sc;
            P[np].grid = cf.grid;
            bad |= run_scene(&cf, &op, &P[np++], S, nseries, csv);
        }
        free(cf.swing_x0);
    }
    if (op.o.check && !op.cotton) bad |= order_checks();
    fclose(csv);
    write_orders(&op, P, np, S);
    write_chart(&op, P, np, S);
    free(P);
    if (op.o.check) printf("checks: %s\n", bad ? "FAILED" : "all passed");
    return bad;
}
