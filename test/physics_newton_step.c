/* Physics: the implicit step solved by Newton's method on its incremental
 * potential (solver.nonlinear CLOTH_NEWTON, newton.c).
 *
 * 1. Against an independent solver: a 5x5 cotton cloth without damping,
 *    pinned at two corners, stretched 2% and jittered out of plane, takes
 *    one backward Euler step of 1/60 s. The test solves the same equations,
 *    M (v1 - v0) = h (f(x0 + h v1) + M g) with the pins held, compressed
 *    links pushing along their direction at x0 + h v0, by its own dense
 *    Newton method (its own link forces, Jacobian by central differences,
 *    Gaussian elimination) to 1e-12; the library's v1 must match it to
 *    1e-6 of the velocity change, with the definiteness rule on and off
 *    (the rule is the linearised step's; Newton's matrix is its own).
 * 2. Orders: a soft 9x9 cloth (k_t = k_c = 20 N/m, so that the steps
 *    resolve its stretch modes) hanging from one corner swings from
 *    horizontal, damping on, the rule on, for 0.2 s at h = 1/400 ... 1/3200
 *    against 1/25600: the observed order of the end positions' RMS error is
 *    0.95-1.05 for backward Euler and 1.9-2.1 for BDF2.
 * 3. A step whose Newton solve cannot converge (one iteration allowed),
 *    with keep_unconverged, keeps its last iterate at the smallest
 *    substep: the scene goes on; without it the step fails, state unchanged.
 * 4. Each step near the same step solved tightly: a 41x41 cotton cloth at
 *    the defaults (multigrid, the linear solves stopped at a share of the
 *    tolerance) pinned at two corners falls and swings for 1.5 s; every
 *    third step is taken again from the same state at newton_tolerance
 *    1e-8 and CG 1e-10; the velocities' RMS difference weighted by mass
 *    must be within twice newton_tolerance, at 1e-2 and 2.5e-3, and the
 *    share must save CG iterations against the same steps without it.
 * 5. Bad parameters (nonlinear 99, newton_tolerance 0 / NaN, newton_rtol
 *    -1e-3 / 1 / NaN, newton_cg_tolerance 0 / NaN, newton_cg_share -0.1 / 1 /
 *    NaN, limit_tolerance 0 / 1,
 *    newton_iterations 0
 *    with CLOTH_NEWTON) are refused naming the field, the cloth's solver
 *    unchanged. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define H (1.0 / 60.0)

static cloth_desc small_desc(int n)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = n;
    d.width = d.height = 0.4;
    d.solver.nonlinear = CLOTH_NEWTON;
    d.solver.newton_iterations = 100;
    d.solver.newton_tolerance = 1e-12;
    d.solver.cg_tolerance = d.solver.newton_cg_tolerance = 1e-10;
    d.solver.max_substep_halvings = 0;
    d.solver.strain_limit_iterations = 0;
    return d;
}

/* The force on i of link (i, j) with law (k_hi, k_lo, rest, k_lim, lim) at
 * w = x_j - x_i: tension and the limit along w, compression along u0. */
static void link_force(const double *w, const double *u0, const double *law, double *f)
{
    double d = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    double ft = d >= law[2] ? law[0] * (d - law[2]) : 0.0;
    if (d > law[4]) ft += law[3] * (d - law[4]);
    double sc = w[0] * u0[0] + w[1] * u0[1] + w[2] * u0[2] - law[2];
    double fc = sc < 0.0 ? law[1] * sc : 0.0;
    for (int r = 0; r < 3; r++) f[r] = ft * w[r] / d + fc * u0[r];
}

/* The links' forces at xs, v0 = 0 so their predicted directions are x0's
 * (elastic links: the step starts from rest lengths, no plastic link) */
static void link_forces(cloth *aux, const double *x0, const double *xs, double *F)
{
    cloth_material m = cloth_get_desc(aux).material;
    memset(F, 0, sizeof *F * 3 * (size_t)cloth_vertex_count(aux));
    for (int t = 0; t < 2; t++)
        for (int e = 0; e < cloth_link_count(aux, (cloth_link_type)t); e++) {
            cloth_link L;
            cloth_get_link(aux, (cloth_link_type)t, e, &L);
            double seq[5] = {m.k_t, m.k_c, L.rest, m.k_delta * m.k_t, (1.0 + m.delta) * L.rest};
            double bend[5] = {m.k_b, m.k_b, L.rest, 0.0, HUGE_VAL};
            double w[3], u0[3], f[3], l0 = 0.0;
            for (int r = 0; r < 3; r++) {
                w[r] = xs[3 * L.j + r] - xs[3 * L.i + r];
                u0[r] = x0[3 * L.j + r] - x0[3 * L.i + r];
                l0 += u0[r] * u0[r];
            }
            for (int r = 0; r < 3; r++) u0[r] /= sqrt(l0);
            link_force(w, u0, t ? bend : seq, f);
            for (int r = 0; r < 3; r++) {
                F[3 * L.i + r] += f[r];
                F[3 * L.j + r] -= f[r];
            }
        }
}

/* F(v1) = M (v1 - v0) - h (f(x0 + h v1) + M g), pinned rows v1 - 0 */
static void be_residual(cloth *aux, const double *x0, const double *v0, const double *v1, const int *pinned, double *F,
                        double *xs)
{
    int n = cloth_vertex_count(aux);
    const double *m = cloth_masses(aux);
    double g = cloth_get_desc(aux).gravity[2];
    for (int k = 0; k < 3 * n; k++) xs[k] = x0[k] + H * v1[k];
    link_forces(aux, x0, xs, F);
    for (int k = 0; k < 3 * n; k++) {
        double fg = (k % 3 == 2) ? m[k / 3] * g : 0.0;
        F[k] = pinned[k / 3] ? v1[k] : m[k / 3] * (v1[k] - v0[k]) - H * (F[k] + fg);
    }
}

/* Solve a x = b (n x n, a destroyed) by Gaussian elimination with pivoting. */
static void gauss(double *a, double *b, int n)
{
    for (int c = 0; c < n; c++) {
        int p = c;
        for (int r = c + 1; r < n; r++)
            if (fabs(a[r * n + c]) > fabs(a[p * n + c])) p = r;
        for (int k = 0; k < n; k++) {
            double t = a[c * n + k];
            a[c * n + k] = a[p * n + k];
            a[p * n + k] = t;
        }
        double t = b[c];
        b[c] = b[p];
        b[p] = t;
        for (int r = c + 1; r < n; r++) {
            double f = a[r * n + c] / a[c * n + c];
            for (int k = c; k < n; k++) a[r * n + k] -= f * a[c * n + k];
            b[r] -= f * b[c];
        }
    }
    for (int c = n - 1; c >= 0; c--) {
        for (int k = c + 1; k < n; k++) b[c] -= a[c * n + k] * b[k];
        b[c] /= a[c * n + c];
    }
}

/* The test's own dense Newton on the backward Euler equations. */
static void dense_solve(cloth *aux, const double *x0, const double *v0, const int *pinned, double *v1)
{
    int N = 3 * cloth_vertex_count(aux);
    double *J = malloc(sizeof *J * (size_t)N * (size_t)N), *F = malloc(sizeof *F * (size_t)N);
    double *Fp = malloc(sizeof *Fp * (size_t)N), *Fm = malloc(sizeof *Fm * (size_t)N);
    double *xs = malloc(sizeof *xs * (size_t)N), *w = malloc(sizeof *w * (size_t)N);
    memcpy(v1, v0, sizeof *v1 * (size_t)N);
    for (int it = 0; it < 30; it++) {
        be_residual(aux, x0, v0, v1, pinned, F, xs);
        double fn = 0.0;
        for (int k = 0; k < N; k++) fn = fmax(fn, fabs(F[k]));
        if (fn < 1e-15) break;
        for (int c = 0; c < N; c++) {
            double e = 1e-7;
            memcpy(w, v1, sizeof *w * (size_t)N);
            w[c] += e;
            be_residual(aux, x0, v0, w, pinned, Fp, xs);
            w[c] -= 2 * e;
            be_residual(aux, x0, v0, w, pinned, Fm, xs);
            for (int r = 0; r < N; r++) J[r * N + c] = (Fp[r] - Fm[r]) / (2 * e);
        }
        for (int k = 0; k < N; k++) F[k] = -F[k];
        gauss(J, F, N);
        for (int k = 0; k < N; k++) v1[k] += F[k];
    }
    free(J), free(F), free(Fp), free(Fm), free(xs), free(w);
}

static void against_dense(int rule)
{
    cloth_desc d = small_desc(5);
    d.material.c_t = d.material.c_b = 0.0;
    d.solver.definiteness_rule = rule;
    cloth *c = NULL, *aux = NULL;
    if (!CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK && cloth_create(&d, &aux, NULL) == CLOTH_OK, "create")) return;
    int n = cloth_vertex_count(c), N = 3 * n;
    double *x0 = malloc(sizeof *x0 * (size_t)N), *v0 = calloc((size_t)N, sizeof *v0);
    double *ref = malloc(sizeof *ref * (size_t)N);
    int *pinned = calloc((size_t)n, sizeof *pinned);
    rng r = rng_seed(7);
    memcpy(x0, cloth_positions(c), sizeof *x0 * (size_t)N);
    for (int i = 0; i < n; i++) {
        x0[3 * i] *= 1.02;
        x0[3 * i + 2] += 0.004 * (rng_unit(&r) - 0.5);
    }
    pinned[0] = pinned[4] = 1;
    cloth_set_positions(c, x0);
    cloth_pin(c, 0, x0);
    cloth_pin(c, 4, x0 + 12);
    cloth_step_stats st;
    CHECK(cloth_step(c, H, &st) == CLOTH_OK, "rule %d: step: %s", rule, cloth_last_error(c));
    dense_solve(aux, x0, v0, pinned, ref);
    double err = 0.0, scale = 0.0;
    for (int k = 0; k < N; k++) {
        err = fmax(err, fabs(cloth_velocities(c)[k] - ref[k]));
        scale = fmax(scale, fabs(ref[k]));
    }
    CHECK(err <= 1e-6 * scale, "rule %d: v1 off the dense solve by %.3g (scale %.3g)", rule, err, scale);
    printf("rule %d: %d Newton iterations, %d CG; v1 vs dense Newton: %.3g of %.3g\n", rule, st.newton, st.iterations,
           err, scale);
    free(x0), free(v0), free(ref), free(pinned);
    cloth_destroy(c);
    cloth_destroy(aux);
}

/* the 9x9 swing's end positions after 0.2 s at h = 1/steps_per_s */
static void swing(cloth_method m, int steps_per_s, double *x_end)
{
    cloth_desc d = small_desc(9);
    d.material = cloth_material_preset(CLOTH_ELASTIC);
    /* soft enough that the steps resolve the stretch modes (h omega < 1):
     * the orders are asymptotic statements */
    d.material.k_t = d.material.k_c = 20.0;
    d.material.k_b = 2.0;
    d.material.k_delta = 0.0;
    d.solver.method = m;
    d.solver.newton_tolerance = 1e-10;
    d.solver.cg_tolerance = d.solver.newton_cg_tolerance = 1e-12;
    cloth *c = NULL;
    if (!CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK, "create")) return;
    cloth_pin(c, 0, cloth_positions(c));
    int steps = steps_per_s / 5;
    for (int s = 0; s < steps; s++)
        if (!CHECK(cloth_step(c, 1.0 / steps_per_s, NULL) == CLOTH_OK, "swing step %d: %s", s, cloth_last_error(c)))
            break;
    memcpy(x_end, cloth_positions(c), sizeof *x_end * 3 * 81);
    cloth_destroy(c);
}

static double rms_diff(const double *a, const double *b, int n)
{
    double s = 0.0;
    for (int k = 0; k < n; k++) s += (a[k] - b[k]) * (a[k] - b[k]);
    return sqrt(s / (n / 3));
}

static void orders(void)
{
    static const char *const name[2] = {"backward Euler", "BDF2"};
    const cloth_method m[2] = {CLOTH_BACKWARD_EULER, CLOTH_BDF2};
    const double want[2] = {1.0, 2.0};
    double ref[243], x[243], e[4];
    for (int k = 0; k < 2; k++) {
        swing(m[k], 25600, ref);
        for (int j = 0; j < 4; j++) {
            swing(m[k], 400 << j, x);
            e[j] = rms_diff(x, ref, 243);
        }
        /* first order: the finest ratio feels the reference's own error,
         * so the coarser two; second order: the coarsest step is not yet
         * asymptotic, so the finer two */
        double p1 = log2(e[k] / e[k + 1]), p2 = log2(e[k + 1] / e[k + 2]);
        printf("%s: RMS error %.3g %.3g %.3g %.3g m at h = 1/400..1/3200; orders %.3f %.3f %.3f\n", name[k], e[0], e[1],
               e[2], e[3], p1, p2, log2(e[2] / e[3]));
        CHECK(fabs(p1 - want[k]) <= 0.05 * want[k] && fabs(p2 - want[k]) <= 0.05 * want[k],
              "%s: orders %.3f, %.3f, expected %g within 5%%", name[k], p1, p2, want[k]);
    }
}


/* Newton given too few iterations to converge (one, at a tolerance no
 * step meets), keep_unconverged on: the scene must go on. A cloth pinned at two corners falls
 * for 30 steps: each returns OK with a finite state, keeps its unconverged
 * iterate (counted in stats.unconverged: 1 without halvings, 2^2 substeps
 * with two) and moves. How far such iterates are from the converged motion
 * is printed, not asserted: they can be far (docs/newton.md). */
static void goes_on(int halvings)
{
    cloth_desc d = small_desc(7);
    d.solver.max_substep_halvings = halvings;
    d.solver.strain_limit_iterations = 20;
    cloth *c = NULL, *ref = NULL;
    if (!CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK && cloth_create(&d, &ref, NULL) == CLOTH_OK, "create")) return;
    d.solver.newton_iterations = 1;
    d.solver.newton_tolerance = 1e-12;
    d.solver.keep_unconverged = 1;
    CHECK(cloth_set_solver(c, &d.solver) == CLOTH_OK, "set_solver: %s", cloth_last_error(c));
    const double *x = cloth_positions(c), *xr = cloth_positions(ref);
    for (int k = 0; k < 2; k++) {
        cloth_pin(c, k * 6, x + 3 * k * 6);
        cloth_pin(ref, k * 6, xr + 3 * k * 6);
    }
    int n = cloth_vertex_count(c), ok = 0, counted = 0;
    double z0 = x[3 * (n - 1) + 2];
    for (int s = 0; s < 30; s++) {
        cloth_step_stats st;
        ok += cloth_step(c, H, &st) == CLOTH_OK;
        counted += st.unconverged == (1 << halvings);
        cloth_step(ref, H, NULL);
    }
    /* the same, keep_unconverged off: the step fails, the state as it was */
    d.solver.keep_unconverged = 0;
    cloth_set_solver(c, &d.solver);
    cloth_state *before = cloth_state_create(c), *after = cloth_state_create(c);
    cloth_save(c, before);
    cloth_step_stats st;
    CHECK(cloth_step(c, H, &st) == CLOTH_ESTEP && st.failure == CLOTH_FAIL_NEWTON && st.unconverged == 0,
          "without keep_unconverged: failure %d, unconverged %d", (int)st.failure, st.unconverged);
    cloth_save(c, after);
    CHECK(cloth_state_diff(before, after) == 0.0, "a failed step changed the state");
    cloth_state_destroy(before);
    cloth_state_destroy(after);
    double z = x[3 * (n - 1) + 2], zr = xr[3 * (n - 1) + 2];
    printf("one Newton iteration a step, %d halvings: %d of 30 steps taken, %d counted unconverged; free corner "
           "fell %.4f m (converged: %.4f m)\n",
           halvings, ok, counted, z0 - z, z0 - zr);
    CHECK(ok == 30 && counted == 30, "the scene stopped: %d steps OK, %d counted", ok, counted);
    int finite = 1;
    for (int k = 0; k < 3 * n; k++) finite = finite && isfinite(x[k]) && isfinite(cloth_velocities(c)[k]);
    CHECK(finite, "the kept iterates left a non-finite state");
    CHECK(fabs(z - z0) > 1e-3, "the free corner did not move: %.4f m from %.4f", z, z0);
    cloth_destroy(c);
    cloth_destroy(ref);
}

static double mass_rms(const cloth *c, const double *a, const double *b)
{
    const double *m = cloth_masses(c);
    double s = 0.0, mt = 0.0;
    for (int i = 0; i < cloth_vertex_count(c); i++) {
        for (int r = 0; r < 3; r++) s += m[i] * (a[3 * i + r] - b[3 * i + r]) * (a[3 * i + r] - b[3 * i + r]);
        mt += m[i];
    }
    return sqrt(s / mt);
}

static void within_tolerance(double tol)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 41;
    d.solver.nonlinear = CLOTH_NEWTON;
    d.solver.newton_tolerance = tol;
    cloth_solver tight = d.solver, unshared = d.solver;
    unshared.newton_cg_share = tight.newton_cg_share = 0.0;
    tight.newton_tolerance = 1e-8;
    tight.newton_cg_tolerance = 1e-10;
    tight.newton_iterations = 100;
    cloth *c = NULL;
    if (!CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK, "create")) return;
    int n = cloth_vertex_count(c);
    cloth_pin(c, 0, cloth_positions(c));
    cloth_pin(c, 40, cloth_positions(c) + 3 * 40);
    cloth_state *s0 = cloth_state_create(c), *sa = cloth_state_create(c);
    double *va = malloc(3 * (size_t)n * sizeof *va), *vu = malloc(3 * (size_t)n * sizeof *vu), worst = 0.0;
    double worst_u = 0.0;
    long cg_default = 0, cg_tight = 0, cg_unshared = 0;
    int compared = 0;
    for (int s = 0; s < 90 && s0 && sa && va && vu; s++) {
        cloth_step_stats st;
        cloth_save(c, s0);
        if (!CHECK(cloth_step(c, H, &st) == CLOTH_OK, "step %d: %s", s, cloth_last_error(c))) break;
        if (s % 3) continue;
        cg_default += st.iterations;
        cloth_save(c, sa);
        memcpy(va, cloth_velocities(c), 3 * (size_t)n * sizeof *va);
        cloth_restore(c, s0);
        cloth_set_solver(c, &unshared);
        CHECK(cloth_step(c, H, &st) == CLOTH_OK, "unshared step %d: %s", s, cloth_last_error(c));
        cg_unshared += st.iterations;
        memcpy(vu, cloth_velocities(c), 3 * (size_t)n * sizeof *vu);
        cloth_restore(c, s0);
        cloth_set_solver(c, &tight);
        CHECK(cloth_step(c, H, &st) == CLOTH_OK, "tight step %d: %s", s, cloth_last_error(c));
        cg_tight += st.iterations;
        worst = fmax(worst, mass_rms(c, va, cloth_velocities(c)));
        worst_u = fmax(worst_u, mass_rms(c, vu, cloth_velocities(c)));
        compared++;
        cloth_set_solver(c, &d.solver);
        cloth_restore(c, sa);
    }
    printf("41x41 swing, newton_tolerance %.3g, %d steps compared: the step's velocities within %.3g m/s (RMS by "
           "mass) of the tight solve's, %.3g without newton_cg_share; CG iterations %ld, %ld without, %ld tight\n",
           tol, compared, worst, worst_u, cg_default, cg_unshared, cg_tight);
    CHECK(cg_default < cg_unshared, "newton_cg_share saved no CG iteration (%ld against %ld)", cg_default, cg_unshared);
    /* the size test bounds the last correction: the error is within it for
     * an iteration contracting by half or better, within twice it by 2/3 */
    CHECK(compared == 30 && worst <= 2.0 * tol, "the step is %.3g m/s off the tight one (tolerance %.3g)", worst, tol);
    free(va);
    free(vu);
    cloth_state_destroy(s0);
    cloth_state_destroy(sa);
    cloth_destroy(c);
}

static void bad_parameters(void)
{
    cloth_desc d = small_desc(5);
    cloth *c = NULL;
    if (!CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK, "create")) return;
    static const char *const field[15] = {"nonlinear",        "newton_tolerance",    "newton_tolerance",
                                          "limit_tolerance",  "limit_tolerance",     "newton_iterations",
                                          "keep_unconverged", "newton_cg_tolerance", "newton_cg_tolerance",
                                          "newton_rtol",      "newton_rtol",         "newton_rtol",
                                          "newton_cg_share",  "newton_cg_share",     "newton_cg_share"};
    for (int k = 0; k < 15; k++) {
        cloth_solver s = d.solver;
        switch (k) {
        case 0: s.nonlinear = (cloth_nonlinear)99; break;
        case 1: s.newton_tolerance = 0.0; break;
        case 2: s.newton_tolerance = NAN; break;
        case 3: s.limit_tolerance = 0.0; break;
        case 4: s.limit_tolerance = 1.0; break;
        case 5: s.newton_iterations = 0; break;
        case 6: s.keep_unconverged = 2; break;
        case 7: s.newton_cg_tolerance = 0.0; break;
        case 8: s.newton_cg_tolerance = NAN; break;
        case 9: s.newton_rtol = -1e-3; break;
        case 10: s.newton_rtol = 1.0; break;
        case 11: s.newton_rtol = NAN; break;
        case 12: s.newton_cg_share = -0.1; break;
        case 13: s.newton_cg_share = 1.0; break;
        default: s.newton_cg_share = NAN; break;
        }
        cloth_error err;
        CHECK(cloth_solver_validate(&s, &err) == CLOTH_EINVAL, "case %d accepted", k);
        CHECK(strstr(err.message, field[k]) != NULL, "case %d: message does not name %s: %s", k, field[k], err.message);
        CHECK(cloth_set_solver(c, &s) == CLOTH_EINVAL, "case %d: cloth_set_solver accepted it", k);
        cloth_solver now = cloth_get_desc(c).solver;
        CHECK(memcmp(&now, &d.solver, sizeof now) == 0, "case %d: the solver changed", k);
    }
    cloth_destroy(c);
}

int main(void)
{
    against_dense(1);
    against_dense(0);
    within_tolerance(1e-2);
    within_tolerance(2.5e-3);
    orders();
    goes_on(0);
    goes_on(2);
    bad_parameters();
    return check_summary();
}
