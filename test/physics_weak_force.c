/* Physics: a weak force moves a Newton-stepped cloth as the closed form says.
 *
 * A free 21 x 21 cotton cloth in zero gravity, pushed by a uniform force per
 * unit mass a (per-vertex external forces m_i a), translates rigidly:
 * backward Euler's v after t is exactly a t, the springs never stretched. At
 * h = 1/60 the force's velocity change per step, h a, is below the default
 * newton_tolerance (1e-2 m/s) for a = 0.05 and 0.3 m/s^2, so a step that
 * took its warm start whenever the residual was under the absolute tolerance
 * would never move the cloth. Asserted after 1 s:
 *   - defaults (newton_tolerance 1e-2, newton_rtol 1e-2): every step
 *     succeeds, the mean velocity along a is within 1% of a t (a linear
 *     solve stopped at an absolute error would bias every step alike), and
 *     the first step iterates rather than keep its warm start;
 *   - newton_tolerance 1e-3: within 1% of a t;
 *   - a = 2 m/s^2 (h a above the tolerance): within 1% at the defaults. */
#include <math.h>
#include <stdlib.h>

#include "odecloth/cloth.h"
#include "check.h"

#define H (1.0 / 60.0)

/* mean x velocity after 1 s under a (m/s^2); *first: Newton iterations of the first step */
static double push(double a, double atol, int *first)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = CLOTH_NEWTON;
    d.solver.newton_tolerance = atol;
    d.gravity[0] = d.gravity[1] = d.gravity[2] = 0.0;
    cloth *c = NULL;
    if (!CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK, "cloth_create")) return NAN;
    int n = cloth_vertex_count(c);
    double *f = calloc(3 * (size_t)n, sizeof *f);
    for (int i = 0; i < n; i++) f[3 * i] = a * cloth_masses(c)[i];
    cloth_set_external_forces(c, f);
    int ok = 1;
    for (int k = 0; k < 60; k++) {
        cloth_step_stats st;
        ok = ok && cloth_step(c, H, &st) == CLOTH_OK;
        if (k == 0) *first = st.newton;
    }
    CHECK(ok, "a = %g, newton_tolerance %g: every step succeeds", a, atol);
    double vx = 0.0;
    for (int i = 0; i < n; i++) vx += cloth_velocities(c)[3 * i] / n;
    free(f);
    cloth_destroy(c);
    return vx;
}

int main(void)
{
    const double weak[2] = {0.05, 0.3};
    for (int k = 0; k < 2; k++) {
        double a = weak[k];
        int first = 0;
        double v = push(a, 1e-2, &first);
        printf("a = %g m/s^2: v after 1 s %.6f at the defaults (first step %d iterations)\n", a, v, first);
        CHECK(fabs(v - a) <= 0.01 * a, "a = %g: defaults move the cloth at %.6f m/s, closed form %g", a, v, a);
        CHECK(first >= 1, "a = %g: the first step took its warm start unsolved", a);
        v = push(a, 1e-3, &first);
        printf("a = %g m/s^2: v after 1 s %.6f at newton_tolerance 1e-3\n", a, v);
        CHECK(fabs(v - a) <= 0.01 * a, "a = %g, newton_tolerance 1e-3: v %.6f m/s, closed form %g", a, v, a);
    }
    int first = 0;
    double v = push(2.0, 1e-2, &first);
    printf("a = 2 m/s^2: v after 1 s %.6f at the defaults\n", v);
    CHECK(fabs(v - 2.0) <= 0.01 * 2.0, "a = 2: v %.6f m/s, closed form 2", v);
    return check_summary();
}
