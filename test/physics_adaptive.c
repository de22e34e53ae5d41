/* Physics: the accuracy-driven controller (cloth_adaptive_*, core/src/adaptive.c).
 *
 * 1. Bad input: every invalid descriptor field (tolerance, substep range, CG
 *    range, velocity weight: zero, negative, NaN, inf, crossed ranges) and
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
 *    and 2 times the requested tolerance * 1 s (it aims at 0.7 of the budget
 *    and changes the substeps by whole numbers), for tolerances 1e-1 .. 1e-3.
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
        CHECK(s == CLOTH_EINVAL && st.failure == CLOTH_FAIL_BAD_STEP, "frame_dt %g: status %d failure %d",
              bad_dt[k], (int)s, (int)st.failure);
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
        cloth_desc desc = cloth_get_desc(c);
        cloth_solver user = desc.solver;
        user.method = CLOTH_BDF2; /* the controller steps backward Euler, then gives this back */
        user.cg_tolerance = 0.25;
        if (kind == 1) user.cg_max_iterations = 1;
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
        if (kind == 1) {
            CHECK(st.failure == CLOTH_FAIL_CG_MAX_ITER, "failure %d (%s), expected CG_MAX_ITER", (int)st.failure,
                  cloth_failure_string(st.failure));
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
    for (size_t t = 0; t < sizeof tols / sizeof tols[0]; t++) {
        cloth *c = make_cloth(0);
        if (!c) return;
        int n = cloth_vertex_count(c);
        double z0 = cloth_positions(c)[2];
        cloth_adaptive_desc d = cloth_adaptive_default_desc();
        d.tolerance = tols[t];
        cloth_adaptive *a = NULL;
        cloth_error err;
        if (!CHECK(cloth_adaptive_create(c, &d, &a, &err) == CLOTH_OK, "create: %s", err.message)) continue;
        const double dt = 1.0 / 60;
        double lag = 0.0; /* g sum h_k^2 / 2: backward Euler's lag behind the exact fall */
        int est_ok = 1;
        for (int f = 0; f < 60; f++) {
            cloth_adaptive_stats st;
            if (!CHECK(cloth_adaptive_frame(a, c, dt, &st) == CLOTH_OK, "frame %d: %s", f, cloth_last_error(c)))
                break;
            double h = dt / st.substeps;
            lag += st.substeps * g * h * h / 2;
            /* no acceleration change in free fall: the estimate is the
             * position part alone, n h^2 g / 2 (up to the CG's error) */
            if (f > 0 && fabs(st.error_estimate - st.substeps * g * h * h / 2) > 1e-3 * st.error_estimate) est_ok = 0;
        }
        CHECK(est_ok, "tol %g: estimate is not n h^2 g / 2", tols[t]);
        double T = 1.0, exact = z0 - g * T * T / 2, err_max = 0.0, err_rms = 0.0;
        const double *x = cloth_positions(c);
        for (int i = 0; i < n; i++) {
            double e = fabs(x[3 * i + 2] - (exact - lag)); /* closed form of backward Euler */
            if (e > err_max) err_max = e;
            err_rms += pow(x[3 * i + 2] - exact, 2);
        }
        err_rms = sqrt(err_rms / n);
        CHECK(err_max < 1e-9, "tol %g: positions differ from backward Euler's closed form by %g m", tols[t], err_max);
        double req = tols[t] * T;
        CHECK(err_rms <= 2.0 * req && err_rms >= 0.25 * req, "tol %g m/s: error after 1 s %g m, requested %g m",
              tols[t], err_rms, req);
        printf("free fall, tolerance %g m/s: error after 1 s %.4g m (%.2f of requested)\n", tols[t], err_rms,
               err_rms / req);
        cloth_adaptive_destroy(a);
        cloth_destroy(c);
    }
}

int main(void)
{
    bad_descriptors();
    rollback();
    free_fall();
    return check_summary();
}
