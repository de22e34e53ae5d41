/* Physics: a step solved again from where its last solve ended
 * (cloth_set_warm_start), as the ODE plugin solves a step again after its
 * contacts changed.
 *
 * A 21x21 cotton cloth under Newton, pinned at two adjacent corners, falls
 * and swings for 0.5 s; then from the same state a step is taken twice: from
 * the library's own starts, and after cloth_restore with the first solve's
 * velocity change as the warm start. Asserted: the second solve takes fewer
 * Newton iterations than the first, and ends within newton_tolerance of it
 * (mass-weighted RMS of the velocities). cloth_set_warm_start refuses a NULL
 * cloth, a NULL dv and a non-finite one, leaving none set; a warm start acts
 * for one step, and not on the linearised step. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define H (1.0 / 60.0)

/* mass-weighted RMS of a - b over n vertices (m/s) */
static double rms_diff(const double *m, const double *a, const double *b, int n)
{
    double s = 0.0, mt = 0.0;
    for (int i = 0; i < n; i++) {
        for (int r = 0; r < 3; r++) s += m[i] * (a[3 * i + r] - b[3 * i + r]) * (a[3 * i + r] - b[3 * i + r]);
        mt += m[i];
    }
    return sqrt(s / mt);
}

static void solved_again(void)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 21;
    d.solver.nonlinear = CLOTH_NEWTON;
    cloth *c = NULL;
    if (!CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK, "cloth_create")) return;
    int n = cloth_vertex_count(c);
    const double *x = cloth_positions(c);
    cloth_pin(c, 0, x);
    cloth_pin(c, d.cols - 1, x + 3 * (d.cols - 1));
    cloth_step_stats st;
    int ok = 1;
    for (int k = 0; k < 30; k++) ok = ok && cloth_step(c, H, &st) == CLOTH_OK;
    CHECK(ok, "the swing's steps succeed");
    cloth_state *s0 = cloth_state_create(c);
    double *v0 = malloc(3 * (size_t)n * sizeof *v0), *v1 = malloc(3 * (size_t)n * sizeof *v1);
    double *dv = malloc(3 * (size_t)n * sizeof *dv);
    if (!CHECK(s0 && v0 && v1 && dv, "memory")) return;
    cloth_save(c, s0);
    memcpy(v0, cloth_velocities(c), 3 * (size_t)n * sizeof *v0);
    cloth_step_stats first, again;
    CHECK(cloth_step(c, H, &first) == CLOTH_OK, "the step");
    memcpy(v1, cloth_velocities(c), 3 * (size_t)n * sizeof *v1);
    for (size_t q = 0; q < 3 * (size_t)n; q++) dv[q] = v1[q] - v0[q];
    cloth_restore(c, s0);
    CHECK(cloth_set_warm_start(c, dv) == CLOTH_OK, "cloth_set_warm_start");
    CHECK(cloth_step(c, H, &again) == CLOTH_OK, "the step solved again");
    double diff = rms_diff(cloth_masses(c), v1, cloth_velocities(c), n);
    printf("Newton iterations %d, solved again from its end %d; velocities %.3g m/s apart\n", first.newton,
           again.newton, diff);
    CHECK(again.newton < first.newton, "solved again: %d Newton iterations against %d", again.newton, first.newton);
    CHECK(diff <= d.solver.newton_tolerance, "solved again: %g m/s from the first solve", diff);
    /* refused, and the warm start used for one step only: the next steps as the first did */
    dv[7] = NAN;
    CHECK(cloth_set_warm_start(c, dv) == CLOTH_EINVAL, "a non-finite dv refused");
    CHECK(cloth_set_warm_start(c, NULL) == CLOTH_EINVAL, "a NULL dv refused");
    CHECK(cloth_set_warm_start(NULL, v0) == CLOTH_EINVAL, "a NULL cloth refused");
    cloth_restore(c, s0);
    cloth_step_stats plain;
    CHECK(cloth_step(c, H, &plain) == CLOTH_OK, "the step after the refusals");
    CHECK(plain.newton == first.newton && rms_diff(cloth_masses(c), v1, cloth_velocities(c), n) == 0.0,
          "after the refusals the step is the first's: %d Newton iterations against %d", plain.newton, first.newton);
    /* the linearised step ignores it: a huge warm start changes nothing */
    cloth_solver sv = cloth_get_desc(c).solver;
    sv.nonlinear = CLOTH_LINEARIZED;
    CHECK(cloth_set_solver(c, &sv) == CLOTH_OK, "the linearised step");
    cloth_restore(c, s0);
    CHECK(cloth_step(c, H, &plain) == CLOTH_OK, "a linearised step");
    memcpy(v1, cloth_velocities(c), 3 * (size_t)n * sizeof *v1);
    for (size_t q = 0; q < 3 * (size_t)n; q++) dv[q] = 1e300;
    cloth_restore(c, s0);
    CHECK(cloth_set_warm_start(c, dv) == CLOTH_OK, "a huge warm start");
    CHECK(cloth_step(c, H, &again) == CLOTH_OK, "a linearised step after a huge warm start: %s", cloth_last_error(c));
    CHECK(rms_diff(cloth_masses(c), v1, cloth_velocities(c), n) == 0.0, "the linearised step took the warm start");
    free(v0);
    free(v1);
    free(dv);
    cloth_state_destroy(s0);
    cloth_destroy(c);
}

int main(void)
{
    solved_again();
    return check_summary();
}
