/* Physics: a step that fails whole is retried in substeps (solver field
 * max_substep_halvings), and past the bound fails with the state intact.
 *
 * Scene: the default cloth (21 x 21 cotton, 1 m) pinned at corners 0 and
 * C-1, hung for 1 s at h = 1/60; then corner C-1's pin is jerked 0.25 m
 * along +x within one step of 1/60 s (15 m/s).
 *
 * Run with the linearised step and with Newton's.
 * 1. Without retries (max_substep_halvings 0) that step fails (linearised:
 *    strain past strain_fail; Newton: its iterations run out): CLOTH_ESTEP,
 *    state bitwise unchanged.
 * 2. With retries (4) it succeeds: failure NONE, first_failure the whole
 *    step's, halvings >= 1 and substeps = 2^halvings. Independent check: the
 *    same substeps taken by hand (retries off, 2^halvings steps of
 *    h / 2^halvings, each substep's pin targets set to the straight-line
 *    interpolation x0 + (t/h)(target - x0) ourselves) give bitwise the same
 *    positions and velocities, and their mean constraint force equals the
 *    retried step's (1e-12 relative).
 *    Closed forms: the pinned corner ends on its target (1e-12 m) with the
 *    velocity (target - x0) / h of the whole step (1e-9 m/s), as a moving pin
 *    must in every substep; the still pin ends where it was with velocity 0.
 * 3. Pins pulled 1 m further apart (2 m between corners of a 1 m row of 20
 *    links): whatever the substep, some sequential link of the row ends at
 *    strain >= 1 > strain_fail 0.5, so the step fails at the bound:
 *    CLOTH_ESTEP, failure as in 1, halvings == 4, state bitwise intact
 *    (positions, velocities, plastic state, constraint forces), and putting
 *    the pin back and stepping on gives bitwise the run that never tried.
 * 4. Bad values of the field are refused by cloth_create and cloth_set_solver.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

static const double H = 1.0 / 60;

/* The solver under test, and the failure its whole step reports where the
 * jerk is too much: the linearised step's strain, or Newton's iterations
 * running out (converged, the strain would be the row's share). */
static cloth_nonlinear solver;
static cloth_failure too_much(void) { return solver == CLOTH_NEWTON ? CLOTH_FAIL_NEWTON : CLOTH_FAIL_STRAIN; }

/* The hung scene; *p1 receives the pin of corner C-1. */
static cloth *hung(int halvings, double p1[3])
{
    cloth_desc d = cloth_default_desc();
    d.solver.max_substep_halvings = halvings;
    d.solver.nonlinear = solver;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) return NULL;
    int C = cloth_cols(c);
    const double *x = cloth_positions(c);
    memcpy(p1, x + 3 * (C - 1), 3 * sizeof *p1);
    cloth_pin(c, 0, x);
    cloth_pin(c, C - 1, p1);
    for (int s = 0; s < 60; s++)
        if (!CHECK(cloth_step(c, H, NULL) == CLOTH_OK, "hanging step %d: %s", s, cloth_last_error(c))) break;
    return c;
}

static int same_bits(const double *a, const double *b, size_t n) { return memcmp(a, b, n * sizeof *a) == 0; }

static void forces(const cloth *c, double *f)
{
    for (int i = 0; i < cloth_vertex_count(c); i++) cloth_constraint_force(c, i, f + 3 * i);
}

static void jerk(void)
{
    double p1[3];
    cloth *off = hung(0, p1), *on = hung(4, p1), *hand = hung(0, p1);
    if (!off || !on || !hand) return;
    int n = cloth_vertex_count(on), C = cloth_cols(on);
    size_t n3 = 3 * (size_t)n;
    double target[3] = {p1[0] + 0.25, p1[1], p1[2]};
    double x0[3];
    memcpy(x0, cloth_positions(on) + 3 * (C - 1), sizeof x0);

    /* 1. fails whole */
    cloth_state *s0 = cloth_state_create(off), *s1 = cloth_state_create(off);
    cloth_save(off, s0);
    cloth_pin(off, C - 1, target);
    cloth_step_stats st;
    cloth_status r = cloth_step(off, H, &st);
    cloth_save(off, s1);
    CHECK(r == CLOTH_ESTEP, "jerk without retries: returned %s, expected a failure", cloth_status_string(r));
    CHECK(st.failure == too_much(), "jerk without retries: failure %s, expected %s", cloth_failure_string(st.failure),
          cloth_failure_string(too_much()));
    CHECK(st.halvings == 0 && st.substeps == 1, "jerk without retries: halvings %d substeps %d", st.halvings,
          st.substeps);
    CHECK(cloth_state_diff(s0, s1) == 0.0, "jerk without retries: state changed (%g)", cloth_state_diff(s0, s1));
    printf("jerk 0.25 m in h = 1/60 s, whole step: %s (%s)\n", cloth_status_string(r),
           cloth_failure_string(st.failure));

    /* 2. succeeds in substeps */
    cloth_pin(on, C - 1, target);
    r = cloth_step(on, H, &st);
    CHECK(r == CLOTH_OK, "jerk with 4 halvings: %s", cloth_last_error(on));
    CHECK(st.failure == CLOTH_FAIL_NONE, "failure %s", cloth_failure_string(st.failure));
    CHECK(st.first_failure == too_much(), "first_failure %s, expected %s", cloth_failure_string(st.first_failure),
          cloth_failure_string(too_much()));
    CHECK(st.substeps > 1 && st.halvings >= 1 && st.halvings <= 4, "substeps %d halvings %d", st.substeps, st.halvings);
    CHECK(st.substeps_failed >= 1 + (st.halvings - 1), "substeps_failed %d < %d", st.substeps_failed, st.halvings);
    CHECK(cloth_last_stats(on)->substeps == st.substeps, "cloth_last_stats disagrees");
    printf("with max_substep_halvings 4: ok in %d substeps (%d halvings, %d failed attempts, %d CG iterations), "
           "max strain %.3f\n",
           st.substeps, st.halvings, st.substeps_failed, st.iterations, st.max_strain);

    /* the pins' closed forms */
    const double *x = cloth_positions(on), *v = cloth_velocities(on);
    double ep = 0.0, ev = 0.0;
    for (int r2 = 0; r2 < 3; r2++) {
        ep = fmax(ep, fabs(x[3 * (C - 1) + r2] - target[r2]));
        ev = fmax(ev, fabs(v[3 * (C - 1) + r2] - (target[r2] - x0[r2]) / H));
    }
    CHECK(ep <= 1e-12, "jerked pin ends %.3g m off its target", ep);
    CHECK(ev <= 1e-9, "jerked pin's velocity is %.3g m/s off (target - x0) / h = %.6g m/s", ev,
          (target[0] - x0[0]) / H);
    CHECK(fabs(v[0]) + fabs(v[1]) + fabs(v[2]) <= 1e-9, "still pin moves: v = (%g, %g, %g)", v[0], v[1], v[2]);

    /* the same substeps by hand, retries off: 2^halvings equal substeps from
     * the step's start, pin targets interpolated here */
    double *favg = calloc(n3, sizeof *favg), *f = calloc(n3, sizeof *f), *xs = malloc(n3 * sizeof *xs);
    memcpy(xs, cloth_positions(hand), n3 * sizeof *xs);
    cloth_constraint k0;
    cloth_get_constraint(hand, 0, &k0);
    const int pv[2] = {0, C - 1};
    const double *pt[2] = {k0.target, target};
    int parts = 1 << st.halvings, taken = 0;
    CHECK(st.substeps == parts, "%d substeps, expected 2^halvings = %d", st.substeps, parts);
    for (int k = 0; k < parts; k++) {
        double frac = (double)(k + 1) / parts, tg[3];
        for (int p = 0; p < 2; p++) {
            const double *a = xs + 3 * pv[p];
            for (int r2 = 0; r2 < 3; r2++) tg[r2] = frac == 1.0 ? pt[p][r2] : a[r2] + frac * (pt[p][r2] - a[r2]);
            cloth_pin(hand, pv[p], tg);
        }
        if (!CHECK(cloth_step(hand, H / parts, NULL) == CLOTH_OK, "by hand, substep %d of %d: %s", k, parts,
                   cloth_last_error(hand)))
            break;
        forces(hand, f);
        for (size_t q = 0; q < n3; q++) favg[q] += f[q] / parts;
        taken++;
    }
    CHECK(taken == st.substeps, "by hand: %d substeps, the driver %d", taken, st.substeps);
    CHECK(same_bits(cloth_positions(hand), x, n3), "by hand: positions differ from the retried step");
    CHECK(same_bits(cloth_velocities(hand), v, n3), "by hand: velocities differ from the retried step");
    forces(on, f);
    double fe = 0.0, fm = 0.0;
    for (size_t q = 0; q < n3; q++) {
        fe = fmax(fe, fabs(f[q] - favg[q]));
        fm = fmax(fm, fabs(favg[q]));
    }
    CHECK(fm > 1.0 && fe <= 1e-12 * fm, "constraint forces: %.3g N off the substeps' mean (largest %.3g N)", fe, fm);
    free(favg);
    free(f);
    free(xs);
    cloth_state_destroy(s0);
    cloth_state_destroy(s1);
    cloth_destroy(off);
    cloth_destroy(on);
    cloth_destroy(hand);
}

static void impossible(void)
{
    double p1[3];
    cloth *a = hung(4, p1), *b = hung(4, p1);
    if (!a || !b) return;
    int n = cloth_vertex_count(a), C = cloth_cols(a);
    size_t n3 = 3 * (size_t)n;
    cloth_state *s0 = cloth_state_create(a), *s1 = cloth_state_create(a), *sb = cloth_state_create(b);
    double *f0 = malloc(n3 * sizeof *f0), *f1 = malloc(n3 * sizeof *f1);
    cloth_save(a, s0);
    forces(a, f0);
    double far[3] = {p1[0] + 1.0, p1[1], p1[2]};
    cloth_pin(a, C - 1, far);
    cloth_step_stats st;
    cloth_status r = cloth_step(a, H, &st);
    cloth_save(a, s1);
    forces(a, f1);
    CHECK(r == CLOTH_ESTEP, "pins 2 m apart: returned %s, expected a failure", cloth_status_string(r));
    CHECK(st.failure == too_much(), "pins 2 m apart: failure %s", cloth_failure_string(st.failure));
    CHECK(st.first_failure == too_much(), "first_failure %s", cloth_failure_string(st.first_failure));
    CHECK(st.halvings == 4, "halvings %d, expected the bound 4", st.halvings);
    CHECK(cloth_state_diff(s0, s1) == 0.0, "state changed by the failed retries (%g)", cloth_state_diff(s0, s1));
    CHECK(same_bits(f0, f1, n3), "constraint forces changed by the failed retries");
    CHECK(strstr(cloth_last_error(a), "h/16") != NULL, "message does not name the bound: %s", cloth_last_error(a));
    printf("pins pulled 2 m apart: %s: %s (%d failed attempts)\n", cloth_status_string(r), cloth_last_error(a),
           st.substeps_failed);
    /* no trace */
    cloth_pin(a, C - 1, p1);
    for (int s = 0; s < 5; s++) {
        CHECK(cloth_step(a, H, NULL) == CLOTH_OK, "after the failure, step %d: %s", s, cloth_last_error(a));
        CHECK(cloth_step(b, H, NULL) == CLOTH_OK, "reference step %d: %s", s, cloth_last_error(b));
    }
    cloth_save(a, s1);
    cloth_save(b, sb);
    CHECK(cloth_state_diff(s1, sb) == 0.0, "the failed retries left a trace: %g", cloth_state_diff(s1, sb));
    free(f0);
    free(f1);
    cloth_state_destroy(s0);
    cloth_state_destroy(s1);
    cloth_state_destroy(sb);
    cloth_destroy(a);
    cloth_destroy(b);
}

static void bad_field(void)
{
    const int bad[] = {-1, 17, 1000, -2147483647 - 1};
    cloth_desc d = cloth_default_desc();
    cloth *c = NULL;
    cloth_error err;
    CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message);
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        cloth_desc e = d;
        e.solver.max_substep_halvings = bad[k];
        cloth *o = NULL;
        CHECK(cloth_create(&e, &o, &err) == CLOTH_EINVAL && o == NULL, "create with halvings %d accepted", bad[k]);
        CHECK(strstr(err.message, "max_substep_halvings") != NULL, "message does not name the field: %s", err.message);
        if (c) {
            CHECK(cloth_set_solver(c, &e.solver) == CLOTH_EINVAL, "set_solver with halvings %d accepted", bad[k]);
            CHECK(cloth_get_desc(c).solver.max_substep_halvings == d.solver.max_substep_halvings,
                  "a refused solver was kept");
        }
    }
    cloth_destroy(c);
}

int main(void)
{
    const cloth_nonlinear both[2] = {CLOTH_LINEARIZED, CLOTH_NEWTON};
    for (int k = 0; k < 2; k++) {
        solver = both[k];
        printf("%s step:\n", solver == CLOTH_NEWTON ? "Newton" : "linearised");
        jerk();
        impossible();
    }
    bad_field();
    return check_summary();
}
