/* Physics: the accuracy-driven controller (cloth_adaptive_*, core/src/adaptive.c).
 *
 * 1. Bad input: every invalid descriptor field (tolerance, substep range, CG
 *    range, velocity weight: zero, negative, NaN, inf, crossed ranges; the
 *    global_estimate and allow_explicit flags other than 0 and 1) and
 *    NULL arguments are refused by cloth_adaptive_create with CLOTH_EINVAL, a
 *    message, and *out NULL; cloth_adaptive_frame refuses a bad frame time
 *    and another cloth with the state unchanged (cloth_state_diff == 0).
 * 2. Rollback: a before_substep callback that fails on its 3rd call, and a
 *    solver that cannot converge (cg_max_iterations 1, so every substep
 *    count fails up to max_substeps), both give CLOTH_ESTEP with the cloth
 *    exactly as before the frame and the user's solver settings back.
 * 3. Free fall against the closed form: a free cloth falls rigidly (no spring
 *    is stretched), where backward Euler's position after substeps h_k is the
 *    exact one minus g sum h_k^2 / 2 (v_k = v_0 + g sum h, x_k = x_0 + sum h
 *    v_k). From the substeps the controller reports, that sum predicts the
 *    cloth's position to 1e-9 m; the frame's estimate is n h^2 g / 2 exactly
 *    (no change of acceleration); and the error after 1 s lies between 0.25
 *    and 2 times the requested tolerance * 1 s (it aims at 0.7 of the budget,
 *    or with the global estimate 0.5 of the request, and changes the
 *    substeps by whole numbers), for tolerances 1e-1 .. 1e-3, with the local
 *    estimate and with the global one. The global estimate is exact here:
 *    the shadow at 2 h lags twice as far, so x_2h - x_h is the lag itself;
 *    it must equal it to 1e-9 m after every frame (explicit steps off).
 * 4. The global estimate against an independent fine-step run (see
 *    global_estimate_against_reference below).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

static cloth *make_cloth(int pinned)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 9;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) return NULL;
    if (pinned) {
        const double *x = cloth_positions(c);
        cloth_pin(c, 0, x);
        cloth_pin(c, 8, x + 3 * 8);
    }
    return c;
}

static void bad_descriptors(void)
{
    cloth *c = make_cloth(1);
    if (!c) return;
    const double bad_pos[] = {0.0, -1e-3, NAN, INFINITY, -INFINITY};
    for (int field = 0; field < 6; field++)
        for (size_t k = 0; k < sizeof bad_pos / sizeof bad_pos[0]; k++) {
            cloth_adaptive_desc d = cloth_adaptive_default_desc();
            switch (field) {
            case 0: d.tolerance = bad_pos[k]; break;
            case 1: d.velocity_weight = bad_pos[k]; break;
            case 2: d.cg_tolerance_min = bad_pos[k]; break;
            case 3: d.cg_tolerance_max = k == 0 ? 1.0 : bad_pos[k]; break; /* 1 is out too */
            case 4: d.min_substeps = k == 0 ? 0 : -(int)k; break;
            default: d.max_substeps = d.min_substeps - 1 - (int)k; break;
            }
            cloth_adaptive *a = (cloth_adaptive *)&d; /* must be set to NULL */
            cloth_error err = {CLOTH_OK, ""};
            cloth_status s = cloth_adaptive_create(c, &d, &a, &err);
            CHECK(s == CLOTH_EINVAL && a == NULL && err.message[0] != '\0',
                  "field %d value %zu: status %d, out %p, message '%s'", field, k, (int)s, (void *)a, err.message);
        }
    cloth_adaptive_desc d = cloth_adaptive_default_desc();
    d.cg_tolerance_min = 1e-2;
    d.cg_tolerance_max = 1e-3; /* crossed */
    cloth_adaptive *a = NULL;
    cloth_error err = {CLOTH_OK, ""};
    CHECK(cloth_adaptive_create(c, &d, &a, &err) == CLOTH_EINVAL && !a, "crossed CG range accepted");
    const int bad_flag[] = {-1, 2, 1000};
    for (int field = 0; field < 2; field++)
        for (size_t k = 0; k < sizeof bad_flag / sizeof bad_flag[0]; k++) {
            d = cloth_adaptive_default_desc();
            if (field == 0) d.global_estimate = bad_flag[k];
            else d.allow_explicit = bad_flag[k];
            a = NULL;
            err.message[0] = '\0';
            CHECK(cloth_adaptive_create(c, &d, &a, &err) == CLOTH_EINVAL && !a && err.message[0] != '\0',
                  "%s = %d accepted", field == 0 ? "global_estimate" : "allow_explicit", bad_flag[k]);
        }
    d = cloth_adaptive_default_desc();
    CHECK(cloth_adaptive_create(NULL, &d, &a, &err) == CLOTH_EINVAL && !a, "NULL cloth accepted");
    CHECK(cloth_adaptive_create(c, NULL, &a, &err) == CLOTH_EINVAL && !a, "NULL descriptor accepted");
    CHECK(cloth_adaptive_create(c, &d, NULL, &err) == CLOTH_EINVAL, "NULL out accepted");
    CHECK(cloth_adaptive_create(c, &d, &a, NULL) == CLOTH_OK && a, "valid descriptor refused (err NULL)");

    /* bad frame times and another cloth: refused, nothing changed */
    cloth *other = make_cloth(1);
    cloth_state *before = cloth_state_create(c), *after = cloth_state_create(c);
    cloth_step(c, 1.0 / 60, NULL); /* some motion first */
    cloth_save(c, before);
    const double bad_dt[] = {0.0, -0.0, -1.0 / 60, NAN, INFINITY, -INFINITY};
    for (size_t k = 0; k < sizeof bad_dt / sizeof bad_dt[0]; k++) {
        cloth_adaptive_stats st;
        cloth_status s = cloth_adaptive_frame(a, c, bad_dt[k], &st);
        cloth_save(c, after);
        CHECK(s == CLOTH_EINVAL && st.failure == CLOTH_FAIL_BAD_STEP, "frame_dt %g: status %d failure %d", bad_dt[k],
              (int)s, (int)st.failure);
        CHECK(cloth_state_diff(before, after) == 0.0, "frame_dt %g changed the state", bad_dt[k]);
        CHECK(strstr(cloth_last_error(c), "frame_dt") != NULL, "message '%s'", cloth_last_error(c));
    }
    if (other) {
        cloth_state *o0 = cloth_state_create(other), *o1 = cloth_state_create(other);
        cloth_save(other, o0);
        CHECK(cloth_adaptive_frame(a, other, 1.0 / 60, NULL) == CLOTH_EINVAL, "another cloth accepted");
        cloth_save(other, o1);
        CHECK(cloth_state_diff(o0, o1) == 0.0, "another cloth changed");
        cloth_state_destroy(o0);
        cloth_state_destroy(o1);
    }
    CHECK(cloth_adaptive_frame(NULL, c, 1.0 / 60, NULL) == CLOTH_EINVAL, "NULL controller accepted");
    CHECK(cloth_adaptive_frame(a, NULL, 1.0 / 60, NULL) == CLOTH_EINVAL, "NULL cloth accepted");
    cloth_adaptive_destroy(NULL);
    cloth_adaptive_destroy(a);
    cloth_state_destroy(before);
    cloth_state_destroy(after);
    cloth_destroy(other);
    cloth_destroy(c);
}

static int calls;
static int fail_third(cloth *c, double h, void *user)
{
    (void)c;
    (void)h;
    (void)user;
    return ++calls == 3;
}

static int same_solver(const cloth_solver *a, const cloth_solver *b)
{
    return a->method == b->method && a->precond == b->precond && a->cg_tolerance == b->cg_tolerance &&
           a->cg_max_iterations == b->cg_max_iterations && a->definiteness_rule == b->definiteness_rule;
}

static void rollback(void)
{
    for (int kind = 0; kind < 2; kind++) {
        cloth *c = make_cloth(1);
        if (!c) return;
        /* one ordinary step first, so that the pins carry constraint forces
         * the failed frame must give back */
        CHECK(cloth_step(c, 1.0 / 240, NULL) == CLOTH_OK, "first step: %s", cloth_last_error(c));
        double f0[6], f1[6];
        cloth_constraint_force(c, 0, f0);
        cloth_constraint_force(c, 8, f0 + 3);
        cloth_desc desc = cloth_get_desc(c);
        cloth_solver user = desc.solver;
        user.method = CLOTH_BDF2; /* the controller steps backward Euler, then gives this back */
        user.cg_tolerance = 0.25;
        /* kind 1 fails every attempt: the linearised step's CG capped at one
         * iteration, Newton's step at one iteration of an unreachable tolerance */
        int newton = user.nonlinear == CLOTH_NEWTON;
        if (kind == 1 && newton) user.newton_iterations = 1, user.newton_tolerance = 1e-12;
        if (kind == 1 && !newton) { /* block Jacobi: one multigrid iteration can meet the tolerance */
            user.cg_max_iterations = 1;
            user.precond = CLOTH_PRECOND_BLOCK_JACOBI;
        }
        CHECK(cloth_set_solver(c, &user) == CLOTH_OK, "set_solver: %s", cloth_last_error(c));
        cloth_adaptive_desc d = cloth_adaptive_default_desc();
        d.min_substeps = 4; /* so the callback's 3rd call is inside the first attempt */
        d.max_substeps = 16;
        if (kind == 0) d.before_substep = fail_third;
        cloth_adaptive *a = NULL;
        cloth_error err;
        if (!CHECK(cloth_adaptive_create(c, &d, &a, &err) == CLOTH_OK, "create: %s", err.message)) continue;
        cloth_state *before = cloth_state_create(c), *after = cloth_state_create(c);
        cloth_save(c, before);
        calls = 0;
        cloth_adaptive_stats st;
        cloth_status s = cloth_adaptive_frame(a, c, 1.0 / 60, &st);
        cloth_save(c, after);
        CHECK(s == CLOTH_ESTEP, "kind %d: status %d, expected CLOTH_ESTEP", kind, (int)s);
        CHECK(cloth_state_diff(before, after) == 0.0, "kind %d: state changed by %g", kind,
              cloth_state_diff(before, after));
        cloth_solver now = cloth_get_desc(c).solver;
        CHECK(same_solver(&now, &user), "kind %d: the user's solver was not given back", kind);
        cloth_constraint_force(c, 0, f1);
        cloth_constraint_force(c, 8, f1 + 3);
        CHECK(f0[2] != 0.0 && !memcmp(f0, f1, sizeof f0),
              "kind %d: the pins' constraint forces were not given back (z %g, %g before; %g, %g after)", kind, f0[2],
              f0[5], f1[2], f1[5]);
        if (kind == 1) {
            cloth_failure want = newton ? CLOTH_FAIL_NEWTON : CLOTH_FAIL_CG_MAX_ITER;
            CHECK(st.failure == want, "failure %d (%s), expected %s", (int)st.failure, cloth_failure_string(st.failure),
                  cloth_failure_string(want));
            CHECK(st.substeps == d.max_substeps && st.attempts >= 2, "gave up at %d substeps after %d attempts",
                  st.substeps, st.attempts);
        } else {
            CHECK(calls == 3 && st.steps == 2, "callback calls %d, steps %d", calls, st.steps);
        }
        cloth_adaptive_destroy(a);
        cloth_state_destroy(before);
        cloth_state_destroy(after);
        cloth_destroy(c);
    }
}

static void free_fall(void)
{
    const double g = 9.81, tols[] = {1e-1, 1e-2, 1e-3};
    for (int global = 0; global < 2; global++)
        for (size_t t = 0; t < sizeof tols / sizeof tols[0]; t++) {
            cloth *c = make_cloth(0);
            if (!c) return;
            int n = cloth_vertex_count(c);
            double z0 = cloth_positions(c)[2];
            cloth_adaptive_desc d = cloth_adaptive_default_desc();
            d.tolerance = tols[t];
            d.global_estimate = global;
            d.allow_explicit = 0; /* backward Euler's closed form */
            cloth_adaptive *a = NULL;
            cloth_error err;
            if (!CHECK(cloth_adaptive_create(c, &d, &a, &err) == CLOTH_OK, "create: %s", err.message)) continue;
            const double dt = 1.0 / 60;
            double lag = 0.0; /* g sum h_k^2 / 2: backward Euler's lag behind the exact fall */
            int est_ok = 1, glob_ok = 1, method_ok = 1;
            double glob_worst = 0.0;
            for (int f = 0; f < 60; f++) {
                cloth_adaptive_stats st;
                if (!CHECK(cloth_adaptive_frame(a, c, dt, &st) == CLOTH_OK, "frame %d: %s", f, cloth_last_error(c)))
                    break;
                double h = dt / st.substeps;
                lag += st.substeps * g * h * h / 2;
                /* no acceleration change in free fall: the local estimate is
                 * the position part alone, n h^2 g / 2 (up to the CG's error) */
                if (f > 0 && fabs(st.error_estimate - st.substeps * g * h * h / 2) > 1e-3 * st.error_estimate)
                    est_ok = 0;
                /* the global one: the shadow's lag is g sum (2 h)^2 / 2 over
                 * half the substeps, twice the cloth's, so the difference is
                 * exactly the cloth's error, the lag (every vertex the same) */
                if (global) {
                    double e = fabs(st.global_estimate - lag);
                    if (e > glob_worst) glob_worst = e;
                    if (!(e <= 1e-9)) glob_ok = 0;
                    if (st.substeps % 2) glob_ok = 0;
                } else if (!isnan(st.global_estimate)) {
                    glob_ok = 0;
                }
                if (st.method != CLOTH_BACKWARD_EULER) method_ok = 0;
            }
            CHECK(est_ok, "tol %g: estimate is not n h^2 g / 2", tols[t]);
            CHECK(glob_ok,
                  "global %d tol %g: global estimate differs from the lag by %g m (or odd substeps, or "
                  "not NaN without a shadow)",
                  global, tols[t], glob_worst);
            CHECK(method_ok, "tol %g: a frame not stepped by backward Euler with allow_explicit 0", tols[t]);
            double T = 1.0, exact = z0 - g * T * T / 2, err_max = 0.0, err_rms = 0.0;
            const double *x = cloth_positions(c);
            for (int i = 0; i < n; i++) {
                double e = fabs(x[3 * i + 2] - (exact - lag)); /* closed form of backward Euler */
                if (e > err_max) err_max = e;
                err_rms += pow(x[3 * i + 2] - exact, 2);
            }
            err_rms = sqrt(err_rms / n);
            CHECK(err_max < 1e-9, "tol %g: positions differ from backward Euler's closed form by %g m", tols[t],
                  err_max);
            double req = tols[t] * T;
            CHECK(err_rms <= 2.0 * req && err_rms >= 0.25 * req, "tol %g m/s: error after 1 s %g m, requested %g m",
                  tols[t], err_rms, req);
            printf("free fall, %s estimate, tolerance %g m/s: error after 1 s %.4g m (%.2f of requested)%s\n",
                   global ? "global" : "local", tols[t], err_rms, err_rms / req,
                   global ? ", global estimate = error to 1e-9 m" : "");
            cloth_adaptive_destroy(a);
            cloth_destroy(c);
        }
}

/* A soft 9x9 cloth (k_t 200 N/m, damping 2.5x the elastic preset's, no
 * elongation limit), horizontal, pinned at two corners, swinging down
 * under gravity for 1 s. */
static cloth *make_swing(cloth_method m, double cg_tol, int rule)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 9;
    d.material = cloth_material_preset(CLOTH_ELASTIC);
    d.material.density = 0.2;
    d.material.k_t = 200.0;
    d.material.c_t *= 2.5;
    d.material.c_b *= 2.5;
    d.material.k_delta = 0.0;
    d.solver.strain_limit_iterations = 0;
    d.solver.method = m;
    d.solver.cg_tolerance = cg_tol;
    /* Newton's step, if the default, as tight (its stop in m/s) */
    d.solver.newton_cg_tolerance = d.solver.newton_tolerance = cg_tol;
    d.solver.cg_max_iterations = 20000;
    d.solver.definiteness_rule = rule;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) return NULL;
    const double *x = cloth_positions(c);
    cloth_pin(c, 0, x);
    cloth_pin(c, 8, x + 3 * 8);
    return c;
}

/* positions (3n) at t = 0.25, 0.5, 0.75, 1 s (4 x 3n) of fixed steps at hz */
static double *swing_fixed(cloth_method m, double hz)
{
    cloth *c = make_swing(m, 1e-10, 0);
    if (!c) return NULL;
    size_t n3 = 3 * (size_t)cloth_vertex_count(c);
    double *x = malloc(4 * n3 * sizeof *x);
    long k = 0;
    for (int s = 0; x && s < 4; s++) {
        for (; k < lround(hz * 0.25 * (s + 1)); k++)
            if (!CHECK(cloth_step(c, 1.0 / hz, NULL) == CLOTH_OK, "reference step %ld: %s", k, cloth_last_error(c)))
                break;
        memcpy(x + s * n3, cloth_positions(c), n3 * sizeof *x);
    }
    cloth_destroy(c);
    return x;
}

static double rms_between(const double *a, const double *b, int n, int samples)
{
    double s = 0.0;
    for (int k = 0; k < 3 * n * samples; k++) s += (a[k] - b[k]) * (a[k] - b[k]);
    return sqrt(s / (n * samples));
}

/* 4. The global estimate against an independent fine-step run: the swing
 *    above, against BDF2 (exact Jacobian, CG 1e-10) at 1/16384 s, shown
 *    converged (1/8192 within a tenth of the smallest error checked), at
 *    t = 0.25, 0.5, 0.75 and 1 s. The controller's global estimate at each
 *    of them must be within [0.5, 2] of its true error there; with backward
 *    Euler at 1e-2 m/s, with symplectic Euler allowed at 1e-3 m/s (where it
 *    must be chosen: cheaper than backward Euler there), and at fixed
 *    substep counts (min = max: plain Richardson). The adaptive runs must
 *    meet their request within 2x as the chart measures it: RMS over the
 *    four times of the error against that of tolerance * t. */
static void global_estimate_against_reference(void)
{
    double *ref = swing_fixed(CLOTH_BDF2, 16384), *ref2 = swing_fixed(CLOTH_BDF2, 8192);
    if (!ref || !ref2) return;
    const int n = 81;
    const size_t n3 = 3 * (size_t)n;
    double ref_change = rms_between(ref, ref2, n, 4), req_rms = sqrt((0.0625 + 0.25 + 0.5625 + 1.0) / 4);
    struct {
        double tol;
        int explicit_ok, nmin, nmax;
    } runs[] = {{1e-2, 0, 1, 1024}, {1e-3, 1, 1, 1024}, {1e-2, 0, 8, 8}, {1e-2, 0, 32, 32}};
    double smallest = HUGE_VAL;
    double *x = malloc(4 * n3 * sizeof *x);
    for (size_t r = 0; x && r < sizeof runs / sizeof runs[0]; r++) {
        cloth *c = make_swing(CLOTH_BACKWARD_EULER, 1e-3, 1);
        if (!c) continue;
        cloth_adaptive_desc d = cloth_adaptive_default_desc();
        d.tolerance = runs[r].tol;
        d.allow_explicit = runs[r].explicit_ok;
        d.min_substeps = runs[r].nmin;
        d.max_substeps = runs[r].nmax;
        cloth_adaptive *a = NULL;
        cloth_error err;
        if (!CHECK(cloth_adaptive_create(c, &d, &a, &err) == CLOTH_OK, "create: %s", err.message)) continue;
        cloth_adaptive_stats st;
        int frames = 0, sym = 0;
        double sub = 0.0, q[4] = {0}, qlo = HUGE_VAL, qhi = 0.0;
        for (int f = 0; f < 60; f++) {
            if (!CHECK(cloth_adaptive_frame(a, c, 1.0 / 60, &st) == CLOTH_OK, "frame %d: %s", f, cloth_last_error(c)))
                break;
            frames++;
            sym += st.method == CLOTH_SYMPLECTIC_EULER;
            sub += st.substeps;
            if ((f + 1) % 15 == 0) {
                int s = (f + 1) / 15 - 1;
                memcpy(x + s * n3, cloth_positions(c), n3 * sizeof *x);
                q[s] = st.global_estimate / rms_between(x + s * n3, ref + s * n3, n, 1);
                qlo = fmin(qlo, q[s]);
                qhi = fmax(qhi, q[s]);
            }
        }
        double e = rms_between(x, ref, n, 4), e_end = rms_between(x + 3 * n3, ref + 3 * n3, n, 1);
        if (e < smallest) smallest = e;
        printf("swing, tol %g, substeps %d..%d, explicit %s: error %.4g m RMS (%.2f of requested; at 1 s %.2f), "
               "global estimate / error at 0.25 .. 1 s: %.2f %.2f %.2f %.2f; %.1f substeps per frame, %d of %d "
               "frames symplectic\n",
               runs[r].tol, runs[r].nmin, runs[r].nmax, runs[r].explicit_ok ? "allowed" : "off", e,
               e / (runs[r].tol * req_rms), e_end / runs[r].tol, q[0], q[1], q[2], q[3], sub / frames, sym, frames);
        CHECK(qlo >= 0.5 && qhi <= 2.0, "tol %g run %zu: global estimate / error %g .. %g", runs[r].tol, r, qlo, qhi);
        if (runs[r].nmax > runs[r].nmin)
            CHECK(e <= 2.0 * runs[r].tol * req_rms, "tol %g: error %g m RMS over twice the request %g m", runs[r].tol,
                  e, runs[r].tol * req_rms);
        if (runs[r].explicit_ok)
            CHECK(sym >= frames / 2, "tol %g: symplectic Euler chosen in only %d of %d frames", runs[r].tol, sym,
                  frames);
        else CHECK(sym == 0, "tol %g: symplectic Euler used with allow_explicit 0", runs[r].tol);
        cloth_adaptive_destroy(a);
        cloth_destroy(c);
    }
    printf("swing reference: BDF2 1/16384 s, 1/8192 differs by %.3g m RMS\n", ref_change);
    CHECK(ref_change < 0.1 * smallest, "reference change %g m not under a tenth of the smallest error %g m", ref_change,
          smallest);
    free(x);
    free(ref);
    free(ref2);
}

/* (1) A cloth switched to multigrid after the controller is made steps: the
 * shadow's solver needs the levels cloth_set_solver builds; (2) the substeps
 * stay in the user's range (min = max = 3 runs 3), not rounded to even. */
static void review_cases(void)
{
    cloth *c = make_cloth(1);
    if (!c) return;
    cloth_adaptive *a = NULL;
    cloth_error err;
    cloth_adaptive_desc d = cloth_adaptive_default_desc();
    if (CHECK(cloth_adaptive_create(c, &d, &a, &err) == CLOTH_OK, "create: %s", err.message)) {
        cloth_solver sv = cloth_get_desc(c).solver;
        sv.precond = CLOTH_PRECOND_MULTIGRID;
        CHECK(cloth_set_solver(c, &sv) == CLOTH_OK, "set_solver: %s", cloth_last_error(c));
        cloth_adaptive_stats st;
        for (int f = 0; f < 3; f++)
            CHECK(cloth_adaptive_frame(a, c, 1.0 / 60, &st) == CLOTH_OK, "multigrid frame %d: %s", f,
                  cloth_last_error(c));
        cloth_adaptive_destroy(a);
    }
    d.min_substeps = d.max_substeps = 3;
    a = NULL;
    if (CHECK(cloth_adaptive_create(c, &d, &a, &err) == CLOTH_OK, "create 3..3: %s", err.message)) {
        for (int f = 0; f < 4; f++) {
            cloth_adaptive_stats st;
            if (!CHECK(cloth_adaptive_frame(a, c, 1.0 / 60, &st) == CLOTH_OK, "3..3 frame %d: %s", f,
                       cloth_last_error(c)))
                break;
            CHECK(st.substeps == 3, "substeps 3..3: frame %d took %d", f, st.substeps);
        }
        cloth_adaptive_destroy(a);
    }
    cloth_destroy(c);
}

int main(void)
{
    bad_descriptors();
    rollback();
    review_cases();
    free_fall();
    global_estimate_against_reference();
    return check_summary();
}
