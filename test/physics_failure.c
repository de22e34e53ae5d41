/* Physics: a step that fails reports why and leaves the state exactly as it
 * was; a bad step size is refused the same way.
 *
 * 1. Explicit Euler past its stability limit: the default cloth (21 x 21
 *    cotton; one sequential link of k = 2000 N/m between nodes of ~5e-4 kg
 *    gives w = sqrt(k/m) ~ 2000 rad/s, so w h ~ 33 >> 2 at h = 1/60) with a
 *    1e-4 m random jitter, stepped until a step fails (at most 200 steps).
 *    Before every step the state is saved. Asserted: some step fails; it
 *    returns CLOTH_ESTEP with stats.failure NAN or STRAIN (the same in
 *    cloth_last_stats); cloth_state_diff(before, after) == 0 exactly; the
 *    failure stats carry the energies of the unchanged state. The same for
 *    symplectic Euler (stable only for w h < 2).
 * 2. Backward Euler whose CG cannot converge (cg_max_iterations 1, tolerance
 *    1e-12, on a swinging cloth): CLOTH_ESTEP, failure CG_MAX_ITER, state
 *    unchanged; and the failure leaves no trace: restoring the solver and
 *    stepping on gives bitwise the same state as a run that never failed
 *    (for BDF2 too, whose history and warm start ride along in the state).
 * 3. h = 0, -0, -1, -1e-300, NaN, -NaN, +inf, -inf, for every method (after
 *    3 good steps, so BDF2 has history): CLOTH_EINVAL, failure
 *    BAD_STEP, state unchanged, and the next valid step matches a run that
 *    never saw the bad call (bitwise).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

static const char *mname[] = {"backward Euler", "explicit Euler", "symplectic Euler", "BDF2"};

static cloth *make_cloth(cloth_method m, int pinned)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = CLOTH_LINEARIZED; /* its CG failures: Newton takes a cut-short solve */
    d.solver.method = m;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) return NULL;
    int n = cloth_vertex_count(c);
    double *x = malloc(sizeof(double) * 3 * n);
    memcpy(x, cloth_positions(c), sizeof(double) * 3 * n);
    rng g = rng_seed(0xfa11u);
    for (int k = 0; k < 3 * n; k++) x[k] += 1e-4 * rng_range(&g, -1, 1);
    CHECK(cloth_set_positions(c, x) == CLOTH_OK, "set_positions: %s", cloth_last_error(c));
    if (pinned) {
        int C = cloth_cols(c);
        cloth_pin(c, 0, x);
        cloth_pin(c, C - 1, x + 3 * (C - 1));
    }
    free(x);
    return c;
}

static void unstable(cloth_method m)
{
    cloth *c = make_cloth(m, 0);
    if (!c) return;
    cloth_state *before = cloth_state_create(c), *after = cloth_state_create(c);
    int failed_at = -1;
    for (int s = 0; s < 200; s++) {
        cloth_save(c, before);
        cloth_energy e0 = cloth_energies(c);
        cloth_step_stats st;
        cloth_status r = cloth_step(c, 1.0 / 60, &st);
        if (r == CLOTH_OK) continue;
        failed_at = s;
        cloth_save(c, after);
        CHECK(r == CLOTH_ESTEP, "%s: failing step returned %d (%s), expected CLOTH_ESTEP", mname[m], (int)r,
              cloth_status_string(r));
        CHECK(st.failure == CLOTH_FAIL_NAN || st.failure == CLOTH_FAIL_STRAIN,
              "%s: failure %d (%s), expected NAN or STRAIN", mname[m], (int)st.failure,
              cloth_failure_string(st.failure));
        CHECK(cloth_last_stats(c)->failure == st.failure, "%s: cloth_last_stats disagrees", mname[m]);
        double diff = cloth_state_diff(before, after);
        CHECK(diff == 0.0, "%s: state changed by the failing step: cloth_state_diff = %.3g", mname[m], diff);
        CHECK(st.energy.kinetic == e0.kinetic && st.energy.elastic == e0.elastic,
              "%s: failure stats energy (%.17g, %.17g) is not the unchanged state's (%.17g, %.17g)", mname[m],
              st.energy.kinetic, st.energy.elastic, e0.kinetic, e0.elastic);
        CHECK(strlen(cloth_last_error(c)) > 0, "%s: no error message", mname[m]);
        printf("%s at h = 1/60: step %d failed (%s): %s; state unchanged: diff %g\n", mname[m], s,
               cloth_failure_string(st.failure), cloth_last_error(c), diff);
        break;
    }
    CHECK(failed_at >= 0, "%s: 200 steps at w h ~ 33 without a failure", mname[m]);
    cloth_state_destroy(before);
    cloth_state_destroy(after);
    cloth_destroy(c);
}

/* CG capped at one iteration: fails, rolls back, leaves no trace */
static void cg_cap(cloth_method m)
{
    const double h = 1.0 / 60;
    cloth *a = make_cloth(m, 1), *b = make_cloth(m, 1);
    if (!a || !b) return;
    cloth_state *sa = cloth_state_create(a), *sb = cloth_state_create(b), *s0 = cloth_state_create(a);
    for (int s = 0; s < 30; s++) { /* get swinging (and, for BDF2, past the startup step) */
        CHECK(cloth_step(a, h, NULL) == CLOTH_OK, "%s: step %d: %s", mname[m], s, cloth_last_error(a));
        CHECK(cloth_step(b, h, NULL) == CLOTH_OK, "%s: step %d: %s", mname[m], s, cloth_last_error(b));
    }
    cloth_desc d = cloth_get_desc(a);
    cloth_solver good = d.solver, capped = d.solver;
    capped.cg_max_iterations = 1;
    capped.cg_tolerance = 1e-12;
    CHECK(cloth_set_solver(a, &capped) == CLOTH_OK, "set_solver: %s", cloth_last_error(a));
    cloth_save(a, s0);
    cloth_step_stats st;
    cloth_status r = cloth_step(a, h, &st);
    cloth_save(a, sa);
    CHECK(r == CLOTH_ESTEP, "%s, CG capped at 1 iteration: returned %d (%s)", mname[m], (int)r, cloth_status_string(r));
    CHECK(st.failure == CLOTH_FAIL_CG_MAX_ITER, "%s, CG capped: failure %d (%s), expected CG_MAX_ITER", mname[m],
          (int)st.failure, cloth_failure_string(st.failure));
    CHECK(cloth_state_diff(s0, sa) == 0.0, "%s, CG capped: state changed (diff %.3g)", mname[m],
          cloth_state_diff(s0, sa));
    /* no trace: continue both with the good solver */
    CHECK(cloth_set_solver(a, &good) == CLOTH_OK, "set_solver: %s", cloth_last_error(a));
    for (int s = 0; s < 5; s++) {
        CHECK(cloth_step(a, h, NULL) == CLOTH_OK, "%s after failure: step %d: %s", mname[m], s, cloth_last_error(a));
        CHECK(cloth_step(b, h, NULL) == CLOTH_OK, "%s reference: step %d: %s", mname[m], s, cloth_last_error(b));
    }
    cloth_save(a, sa);
    cloth_save(b, sb);
    CHECK(cloth_state_diff(sa, sb) == 0.0,
          "%s: a failed step left a trace: 5 steps later the state differs by %.3g "
          "from a run that never failed",
          mname[m], cloth_state_diff(sa, sb));
    cloth_state_destroy(sa);
    cloth_state_destroy(sb);
    cloth_state_destroy(s0);
    cloth_destroy(a);
    cloth_destroy(b);
}

static void bad_h(cloth_method m)
{
    /* a stable h for each method (explicit: w_max h ~ 0.1) */
    const double good_h = (m == CLOTH_EXPLICIT_EULER || m == CLOTH_SYMPLECTIC_EULER) ? 1e-5 : 1.0 / 60;
    const double bad[] = {0.0, -0.0, -1.0, -1e-300, NAN, -NAN, INFINITY, -INFINITY};
    cloth *a = make_cloth(m, 1), *b = make_cloth(m, 1);
    if (!a || !b) return;
    cloth_state *s0 = cloth_state_create(a), *s1 = cloth_state_create(a), *sb = cloth_state_create(b);
    for (int s = 0; s < 3; s++) {
        CHECK(cloth_step(a, good_h, NULL) == CLOTH_OK, "%s: %s", mname[m], cloth_last_error(a));
        CHECK(cloth_step(b, good_h, NULL) == CLOTH_OK, "%s: %s", mname[m], cloth_last_error(b));
    }
    cloth_save(a, s0);
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        cloth_step_stats st;
        memset(&st, 0xff, sizeof st);
        cloth_status r = cloth_step(a, bad[k], &st);
        cloth_save(a, s1);
        CHECK(r == CLOTH_EINVAL, "%s, h = %g: returned %d (%s), expected CLOTH_EINVAL", mname[m], bad[k], (int)r,
              cloth_status_string(r));
        CHECK(st.failure == CLOTH_FAIL_BAD_STEP, "%s, h = %g: failure %d, expected BAD_STEP", mname[m], bad[k],
              (int)st.failure);
        CHECK(cloth_state_diff(s0, s1) == 0.0, "%s, h = %g: state changed (diff %.3g)", mname[m], bad[k],
              cloth_state_diff(s0, s1));
    }
    /* and the next good steps are those of a run that never saw them */
    for (int s = 0; s < 3; s++) {
        CHECK(cloth_step(a, good_h, NULL) == CLOTH_OK, "%s after bad h: %s", mname[m], cloth_last_error(a));
        cloth_step(b, good_h, NULL);
    }
    cloth_save(a, s1);
    cloth_save(b, sb);
    CHECK(cloth_state_diff(s1, sb) == 0.0, "%s: refused bad h left a trace (diff %.3g)", mname[m],
          cloth_state_diff(s1, sb));
    CHECK(cloth_step(NULL, good_h, NULL) == CLOTH_EINVAL, "cloth_step(NULL) did not return CLOTH_EINVAL");
    cloth_state_destroy(s0);
    cloth_state_destroy(s1);
    cloth_state_destroy(sb);
    cloth_destroy(a);
    cloth_destroy(b);
}

int main(void)
{
    unstable(CLOTH_EXPLICIT_EULER);
    unstable(CLOTH_SYMPLECTIC_EULER);
    cg_cap(CLOTH_BACKWARD_EULER);
    cg_cap(CLOTH_BDF2);
    for (int m = CLOTH_BACKWARD_EULER; m <= CLOTH_BDF2; m++) bad_h((cloth_method)m);
    return check_summary();
}
