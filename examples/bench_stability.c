/* bench_stability: where each integrator fails (issue 6.2).
 *
 * Scene: the 1 m cotton cloth (21x21, 0.2 kg) pinned at two adjacent corners
 * that are 0.8 m apart, so the cloth between them is compressed by 20% for
 * the whole run: it starts flat, shrunk to 0.8 of its size in its plane with a
 * random rumple of 1 mm out of it (0.1 mm in it), and falls under gravity. For each method
 * (explicit Euler, symplectic Euler, backward Euler with and without the
 * definiteness rule, BDF2), step size h from 1/2000 to 1/10 s (log spaced)
 * and tension stiffness k_t over 3 decades (the preset's 2000 N/m in the
 * middle), the run of T seconds is "stable" or fails, and why:
 *   NaN        a step produced NaN or inf;
 *   energy     the total energy (elastic + kinetic + gravitational) rose past
 *              its start by more than 0.1 M g (1 m) (no force in the scene
 *              adds energy: pins do no work, damping removes it);
 *   CG max it  the modified CG did not converge within 2000 iterations;
 *   CG indef.  CG met non-positive curvature (the matrix is indefinite:
 *              possible only with the definiteness rule off);
 *   strain     a sequential link passed 50% strain after the elongation limit.
 * The core's step reports all but the energy (cloth_step_stats.failure).
 *
 * Theory, drawn on the chart: a link of stiffness k and damping c along it
 * makes, for every mode of the grid, s^2 + (c mu/m) s + k mu/m = 0 (mu the
 * mode's eigenvalue of the link Laplacian). Explicit Euler needs
 * |1 + h s| < 1, which for underdamped modes is h < c / k whatever mu:
 * h_E = c_t / k_t (1e-5 s for cotton; the bending links' c_b / k_b = 1e-4 s
 * is the larger). Symplectic Euler needs about h w_max < 2, w_max^2 the
 * largest eigenvalue of M^-1 K at the start (power iteration on finite
 * differences of cloth_internal_forces): h_S = 2 / w_max, which scales as
 * 1/sqrt(k_t).
 *
 *   bench_stability [--out DIR] [--grid N] [--seconds T] [--fast] [--check]
 *
 * --fast: 11x11, T = 0.25 s, 5 x 4 cells. --check (exit 1 unless all hold):
 * backward Euler with the rule is stable at every tested h at k_t = 2000;
 * without the rule it breaks down (CG indefinite) somewhere in this
 * compressed scene; at 21x21 (k_t = 2000, 13 h from 1/2000 to 1/10 s) backward
 * Euler is stable at every h <= 1/30 s and fails elsewhere only on the first step
 * (and not at all with the default substep retry); in the theory scene (9x9) at
 * k_t = 2000, scanning h up
 * by 2^(1/4), explicit Euler first fails between h_E and 3 h_E, symplectic
 * Euler between h_S / 2 and 2 h_S.
 *
 * ctest: bench stability --fast --check --out out/bench_fast
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "odecloth/cloth.h"
#include "bench_util.h"

enum { STABLE = 0, F_NAN, F_ENERGY, F_CGMAX, F_CGINDEF, F_STRAIN, NSTATUS };
static const char *status_name[NSTATUS] = {"stable", "NaN", "energy growth", "CG max iterations",
                                           "CG indefinite", "strain"};

typedef struct method_cfg {
    const char *key, *title;
    cloth_method method;
    int rule;
} method_cfg;

static const method_cfg methods[] = {
    {"explicit", "explicit Euler", CLOTH_EXPLICIT_EULER, 1},
    {"symplectic", "symplectic Euler", CLOTH_SYMPLECTIC_EULER, 1},
    {"be_rule", "backward Euler, definiteness rule", CLOTH_BACKWARD_EULER, 1},
    {"be_norule", "backward Euler, no definiteness rule", CLOTH_BACKWARD_EULER, 0},
    {"bdf2", "BDF2, definiteness rule", CLOTH_BDF2, 1},
};
#define NMETHODS ((int)(sizeof methods / sizeof methods[0]))
#define THEORY_STRETCH 0.01

/* The map's scene (stretch = 0): pins 0.8 m apart, the cloth shrunk to 0.8
 * and rumpled by 1 mm (a fixed pseudo-random sequence, the same for every
 * run), gravity on. The theory scene (stretch > 0): the cloth stretched by
 * that strain in its plane, rumpled the same, its four corners pinned, no
 * gravity, no elongation limit (whose projection caps a growing mode at
 * delta and hides it): every link in tension, where the linear theory holds. */
/* substep retries of a failed step: 0 (the method as it is: a failed step is
 * a failure) everywhere but the 21x21 check's second run */
static int retry_halvings = 0;

static cloth *make_scene(int grid, double k_t, const method_cfg *m, double stretch)
{
    cloth_desc d = cloth_default_desc();
    d.solver.max_substep_halvings = retry_halvings;
    d.rows = d.cols = grid;
    d.material.density = 0.2;
    d.material.k_t = k_t;
    d.solver.method = m->method;
    d.solver.definiteness_rule = m->rule;
    if (stretch > 0.0) { /* the linear theory has no elongation limit */
        d.gravity[2] = 0.0;
        d.solver.strain_limit_iterations = 0;
        d.material.k_delta = 0.0;
    }
    cloth *c;
    cloth_error err;
    if (cloth_create(&d, &c, &err) != CLOTH_OK) {
        fprintf(stderr, "bench_stability: %s\n", err.message);
        exit(1);
    }
    int n = cloth_vertex_count(c);
    double *x = malloc(3 * (size_t)n * sizeof *x), scale = stretch > 0.0 ? 1.0 + stretch : 0.8;
    if (!x) exit(1);
    memcpy(x, cloth_positions(c), 3 * (size_t)n * sizeof *x);
    unsigned long long s = 0x5eed5eedULL;
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) {
            /* the default cloth is centred on the z axis, in the xy plane */
            if (a < 2) x[3 * i + a] *= scale;
            s = s * 6364136223846793005ULL + 1442695040888963407ULL;
            x[3 * i + a] += (a < 2 ? 1e-4 : 1e-3) * ((double)(s >> 11) / 9007199254740992.0 - 0.5);
        }
    if (cloth_set_positions(c, x) != CLOTH_OK) {
        fprintf(stderr, "bench_stability: %s\n", cloth_last_error(c));
        exit(1);
    }
    const int corners[4] = {0, grid - 1, n - grid, n - 1};
    for (int k = 0; k < (stretch > 0.0 ? 4 : 2); k++) cloth_pin(c, corners[k], x + 3 * corners[k]);
    free(x);
    return c;
}

static double total_energy(const cloth *c)
{
    cloth_energy e = cloth_energies(c);
    return e.elastic + e.kinetic + e.gravitational;
}

typedef struct outcome {
    int status;
    double time; /* s, simulated time reached */
} outcome;

static outcome run(int grid, double k_t, const method_cfg *m, double h, double T, double stretch)
{
    cloth *c = make_scene(grid, k_t, m, stretch);
    double e0 = total_energy(c), mass = 0.0;
    for (int i = 0; i < cloth_vertex_count(c); i++) mass += cloth_masses(c)[i];
    /* more than 0.1 M g (1 m) above the start; in the theory scene (no
     * gravity, nothing to fall) more than 10% above the start */
    double margin = stretch > 0.0 ? 0.1 * fabs(e0) : 0.1 * mass * 9.81 * 1.0;
    long steps = lround(T / h);
    outcome o = {STABLE, 0.0};
    for (long s = 0; s < steps && o.status == STABLE; s++) {
        cloth_step_stats st;
        if (cloth_step(c, h, &st) != CLOTH_OK) {
            switch (st.failure) {
            case CLOTH_FAIL_CG_MAX_ITER: o.status = F_CGMAX; break;
            case CLOTH_FAIL_CG_INDEFINITE: o.status = F_CGINDEF; break;
            case CLOTH_FAIL_STRAIN: o.status = F_STRAIN; break;
            default: o.status = F_NAN; break;
            }
        } else {
            double e = total_energy(c);
            if (!(e <= e0 + margin)) o.status = isfinite(e) ? F_ENERGY : F_NAN;
        }
        o.time = (s + (o.status == STABLE)) * h;
    }
    cloth_destroy(c);
    return o;
}

/* w_max^2: the largest eigenvalue of M^-1 K (K = -df/dx of the springs in
 * the theory scene, stretched by 1%, pinned vertices held), by power iteration on the
 * symmetric M^-1/2 K M^-1/2 with K w from central differences of
 * cloth_internal_forces (velocities zero: no damping force). */
static double omega_max(int grid, double k_t)
{
    method_cfg m = {"", "", CLOTH_BACKWARD_EULER, 1};
    cloth *c = make_scene(grid, k_t, &m, THEORY_STRETCH);
    int n = cloth_vertex_count(c);
    size_t n3 = 3 * (size_t)n;
    double *x0 = malloc(n3 * sizeof *x0), *w = malloc(n3 * sizeof *w), *xp = malloc(n3 * sizeof *xp),
           *fp = malloc(n3 * sizeof *fp), *fm = malloc(n3 * sizeof *fm);
    if (!x0 || !w || !xp || !fp || !fm) exit(1);
    memcpy(x0, cloth_positions(c), n3 * sizeof *x0);
    const double *mass = cloth_masses(c);
    for (size_t k = 0; k < n3; k++) w[k] = (k * 7919 % 13) / 13.0 - 0.5 + (k % 3 == 2 ? 0.3 : 0.0);
    double lambda = 0.0;
    for (int it = 0; it < 200; it++) {
        double norm = 0.0;
        for (size_t k = 0; k < n3; k++) {
            cloth_constraint kc;
            cloth_get_constraint(c, (int)(k / 3), &kc);
            if (kc.ndof == 3) w[k] = 0.0;
            norm += w[k] * w[k];
        }
        norm = sqrt(norm);
        for (size_t k = 0; k < n3; k++) w[k] /= norm;
        const double eps = 1e-7;
        for (int sgn = 0; sgn < 2; sgn++) {
            for (size_t k = 0; k < n3; k++) xp[k] = x0[k] + (sgn ? -eps : eps) * w[k] / sqrt(mass[k / 3]);
            cloth_set_positions(c, xp);
            cloth_internal_forces(c, sgn ? fm : fp);
        }
        double rq = 0.0;
        for (size_t k = 0; k < n3; k++) {
            double y = -(fp[k] - fm[k]) / (2 * eps) / sqrt(mass[k / 3]); /* M^-1/2 K M^-1/2 w */
            rq += y * w[k];
            w[k] = y;
        }
        if (it > 20 && fabs(rq - lambda) <= 1e-6 * fabs(rq)) {
            lambda = rq;
            break;
        }
        lambda = rq;
    }
    free(x0);
    free(w);
    free(xp);
    free(fp);
    free(fm);
    cloth_destroy(c);
    return sqrt(fabs(lambda));
}

/* The first h, going up by factor 2^(1/4) from h_lo, at which a run of the
 * theory scene of T seconds (at least 50 steps) fails; HUGE_VAL if none up
 * to h_hi. */
static double first_unstable(int grid, double k_t, const method_cfg *m, double h_lo, double h_hi, double T)
{
    for (double h = h_lo; h <= h_hi * 1.0001; h *= pow(2.0, 0.25)) {
        outcome o = run(grid, k_t, m, h, fmax(T, 50 * h), THEORY_STRETCH);
        if (o.status != STABLE) {
            printf("  %s: first failure at h = %.3g s (%s at t = %.3g s)\n", m->title, h, status_name[o.status],
                   o.time);
            return h;
        }
    }
    return HUGE_VAL;
}

static const char usage[] =
    "usage: bench_stability [--out DIR] [--grid N] [--seconds T] [--fast] [--check]\n"
    "Stable or failed (NaN, energy growth, CG max iterations, CG indefinite, strain)\n"
    "for each method, step size 1/2000..1/10 s and tension stiffness k_t, on a\n"
    "cotton cloth compressed between two pins. Writes DIR/bench_stability.csv and\n"
    ".png (default DIR out/bench). --fast: 11x11, 0.25 s. --check: exit 1 unless\n"
    "backward Euler is stable throughout at k_t 2000, fails without the\n"
    "definiteness rule, and explicit / symplectic Euler fail where theory says.";

int main(int argc, char **argv)
{
    bench_opts o = {"bench_stability", usage, "out/bench", 0, 0, 0};
    double T = 1.0;
    for (int a = 1; a < argc; a++) {
        const char *v = a + 1 < argc ? argv[a + 1] : NULL;
        int took = bench_option(&o, argc, argv, &a);
        if (took < 0) return took == -1 ? 2 : 0;
        if (took) continue;
        if (v && !strcmp(argv[a], "--seconds")) {
            char *end;
            T = strtod(v, &end);
            if (*end || !(T > 0.0) || !isfinite(T)) {
                fprintf(stderr, "bench_stability: --seconds '%s' must be a number > 0\n", v);
                return 2;
            }
            a++;
        } else {
            return bench_unknown(&o, argv[a]);
        }
    }
    const int fast = o.fast, check = o.check, grid = o.grid ? o.grid : fast ? 11 : 21;
    if (fast) T = 0.25;
    FILE *csv = bench_open_csv(&o, "bench_stability");
    if (!csv) return 1;
    const double k_ref = 2000.0, c_t = cloth_material_preset(CLOTH_COTTON).c_t;
    const int nh = fast ? 5 : 13, nk = fast ? 4 : 7;
    double hs[13], ks[7];
    for (int i = 0; i < nh; i++) hs[i] = (1.0 / 2000) * pow(200.0, (double)i / (nh - 1));
    /* 20 .. 20000 N/m, the preset's 2000 among them */
    for (int j = 0; j < nk; j++) ks[j] = 20.0 * pow(10.0, j * (fast ? 1.0 : 0.5));
    double wmax[7];
    for (int j = 0; j < nk; j++) wmax[j] = omega_max(grid, ks[j]);
    int bad = 0, be_fail_at_ref = 0, norule_indef = 0;
    printf("%dx%d cotton cloth compressed between pins, T = %g s; h from 1/2000 to 1/10 s\n", grid, grid, T);
    for (int mi = 0; mi < NMETHODS; mi++) {
        const method_cfg *m = &methods[mi];
        printf("== %s\n%10s", m->title, "k_t \\ 1/h");
        for (int i = 0; i < nh; i++) printf(" %6.0f", 1.0 / hs[i]);
        printf("\n");
        for (int j = 0; j < nk; j++) {
            printf("%10.0f", ks[j]);
            for (int i = 0; i < nh; i++) {
                outcome o = run(grid, ks[j], m, hs[i], T, 0.0);
                static const char mark[NSTATUS] = {'.', 'N', 'E', 'C', 'I', 'S'};
                printf(" %6c", mark[o.status]);
                fflush(stdout);
                fprintf(csv, "%s,%g,%.6g,%d,%s,%.4g,%.4g,%.4g\n", m->key, ks[j], hs[i], o.status,
                        status_name[o.status], o.time, c_t / ks[j], 2.0 / wmax[j]);
                if (fabs(ks[j] - k_ref) < 1e-9 && o.status != STABLE && m->method == CLOTH_BACKWARD_EULER && m->rule)
                    be_fail_at_ref = 1;
                if (o.status == F_CGINDEF && !m->rule && fabs(ks[j] - k_ref) < 1e-9) norule_indef = 1;
            }
            printf("   (h_E = %.2g s, h_S = %.2g s)\n", c_t / ks[j], 2.0 / wmax[j]);
        }
    }
    printf("legend: . stable, N NaN, E energy growth, C CG max iterations, I CG indefinite, S strain\n");
    fclose(csv);

    if (check) {
        printf("== checks (k_t = %g N/m)\n", k_ref);
        printf("check: backward Euler with the rule stable at every h: %s\n", be_fail_at_ref ? "FAILED" : "ok");
        printf("check: backward Euler without the rule breaks down (CG indefinite): %s\n",
               norule_indef ? "ok" : "FAILED");
        bad |= be_fail_at_ref || !norule_indef;
        /* the theory scene on a 9x9 grid (its own w_max), 0.5 s: a mode
         * growing at rate mu (h k - c) / (2 m) needs h somewhat past h_E to
         * grow 10% of the energy within the run; stated factors: explicit
         * in [1, 3] h_E, symplectic in [0.5, 2] h_S */
        const int tg = 9;
        double w = omega_max(tg, k_ref), hE = c_t / k_ref, hS = 2.0 / w;
        printf("theory (9x9, stretched 1%%, 4 corners pinned, no gravity, no elongation limit): h_E = c_t / k_t = "
               "%.3g s; w_max = %.4g rad/s, h_S = 2 / w_max = %.3g s\n", hE, w, hS);
        double fE = first_unstable(tg, k_ref, &methods[0], hE * 0.99, hE * 4, 0.5);
        double fS = first_unstable(tg, k_ref, &methods[1], hS / 2, hS * 4, 0.5);
        int okE = fE >= hE * 0.99 && fE <= 3 * hE, okS = fS >= hS / 2 && fS <= 2 * hS;
        printf("check: explicit Euler first fails at %.3g s = %.2f h_E (want 1 to 3): %s\n", fE, fE / hE,
               okE ? "ok" : "FAILED");
        printf("check: symplectic Euler first fails at %.3g s = %.2f h_S (want 0.5 to 2): %s\n", fS, fS / hS,
               okS ? "ok" : "FAILED");
        bad |= !okE || !okS;
        /* The demo's resolution, 21x21: the same scene over the whole h
         * range (13 h from 1/2000 to 1/10 s, also in --fast; T as the map's),
         * backward Euler with the rule at k_t = 2000. Measured: stable up to
         * 1/38 s; from 1/24 s the first step from the 20%-compressed start
         * fails by strain (at 1/10 the linearised step stretches a link to 21
         * times its length, too far for the elongation limit's projection),
         * never a later one, and with the step's substep retry (the library's
         * default, 4 halvings, off in this chart) the first step is taken in
         * substeps and the run is stable to the end. Checked: every h <= 1/30 s
         * stable without retry; elsewhere failures only on the first step,
         * and none with the retry. */
        const int g21 = 21;
        int fail21 = 0, bad21 = 0;
        printf("backward Euler with the rule, %dx%d, k_t %g N/m, %g s, h 1/2000 .. 1/10:\n", g21, g21, k_ref, T);
        for (int i = 0; i < 13; i++) {
            double h = (1.0 / 2000) * pow(200.0, i / 12.0);
            outcome o = run(g21, k_ref, &methods[2], h, T, 0.0), r = o;
            if (o.status != STABLE) {
                retry_halvings = 4;
                r = run(g21, k_ref, &methods[2], h, T, 0.0);
                retry_halvings = 0;
            }
            printf("  h 1/%-4.0f %s", 1.0 / h, status_name[o.status]);
            if (o.status != STABLE)
                printf(" at t = %.3g s (with the default retry: %s at t = %.3g s)", o.time, status_name[r.status], r.time);
            printf("\n");
            fail21 += o.status != STABLE;
            bad21 += o.status != STABLE && (h <= 1.0 / 30 || o.time > 0 || r.status != STABLE);
        }
        int ok21 = bad21 == 0;
        printf("check: %dx%d backward Euler stable at every h <= 1/30 s, failing elsewhere only on the first step "
               "and stable with the retry (%d of 13 h fail, %d of them otherwise): %s\n", g21, g21, fail21, bad21, ok21 ? "ok" : "FAILED");
        bad |= !ok21;
    }

    FILE *gp = bench_open_script(&o, "bench_stability");
    if (gp) {
        fprintf(gp,
                "set terminal pngcairo size 1200,760 font ',10'\n"
                "set output '%s/bench_stability.png'\n"
                "set datafile separator ','\n"
                "set multiplot layout 2,3 title 'odecloth stability: %dx%d cotton cloth compressed 20%% between "
                "two pins, %g s; dashed: h_E = c_t/k_t, dotted: h_S = 2/w_{max}'\n"
                "set logscale xy\nset xrange [3e-4:0.15]\nset yrange [12:32000]\n"
                "set xlabel 'h, s'\nset ylabel 'k_t, N/m'\nset format x '10^{%%L}'\nset format y '10^{%%L}'\n"
                "set cbrange [-0.5:5.5]\nunset colorbox\nset key off\n"
                "set palette maxcolors 6 defined (0 '#4daf4a', 1 '#e41a1c', 2 '#ff7f00', 3 '#984ea3', "
                "4 '#377eb8', 5 '#a65628')\n"
                "M = 'explicit symplectic be_rule be_norule bdf2'\n"
                "array T[5] = ['explicit Euler', 'symplectic Euler', 'backward Euler, rule', "
                "'backward Euler, no rule', 'BDF2, rule']\n"
                "do for [i=1:5] {\n"
                "  set title T[i]\n"
                "  plot '%s/bench_stability.csv' using (strcol(1) eq word(M,i) ? $3 : 1/0):2:4 "
                "with points pt 5 ps %s lc palette, "
                "'' using (strcol(1) eq word(M,i) ? $7 : 1/0):2 with lines dt 2 lc 'black', "
                "'' using (strcol(1) eq word(M,i) ? $8 : 1/0):2 with lines dt 3 lc 'black'\n"
                "}\n"
                "set title 'legend'\nunset border\nunset tics\nunset xlabel\nunset ylabel\nset key center center\n"
                "unset logscale\nset xrange [0:1]\nset yrange [0:1]\n"
                "array L[6] = ['stable', 'NaN', 'energy growth', 'CG max iterations', 'CG indefinite', "
                "'strain']\n"
                "plot for [s=1:6] 2 with points pt 5 ps 2 lc palette cb (s - 1) title L[s]\n"
                "unset multiplot\n",
                o.out, grid, grid, T, o.out, fast ? "2.5" : "2");
        fclose(gp);
        bench_run_gnuplot(&o, "bench_stability");
    }
    if (check) printf("checks: %s\n", bad ? "FAILED" : "all passed");
    return bad;
}
