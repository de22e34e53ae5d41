/* The elongation limit delta (paper Table 1) does its job where it matters:
 * a cloth with soft tension, hanging from two corners, would stretch far past
 * delta; with the limit on, no sequential link is longer than (1 + delta) l0
 * after any step, the pins stay exact, and the corrected velocities stay
 * consistent with the corrected positions (backward Euler: x1 = x0 + h v1),
 * so the limit adds no hidden motion.
 *
 * Two mechanisms hold delta: the stiffening past the limit (material.k_delta,
 * a k_delta k_t spring on the excess, inside the implicit solve) and the
 * projection after the step (solver.strain_limit_iterations Newton steps).
 * Runs, each 120 steps of 1/60 s:
 *   unlimited        k_delta 0,   projection off: must exceed 3 delta;
 *   stiffening only  k_delta 100, projection off: below a third of the
 *                    unlimited strain (it may stay above delta; printed);
 *   projection only  k_delta 0,   200 steps allowed: <= delta (1 + 1e-6);
 *   both             k_delta 100, 200 steps allowed and the default: the same. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "odecloth/cloth.h"

static double run(int passes, double k_delta, int check_each_step)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = CLOTH_LINEARIZED; /* the linearised step's projection is tested */
    d.material.k_t = 20.0;                 /* soft: the weight alone stretches it well past delta */
    d.material.k_c = 1.0;
    d.material.k_delta = k_delta;
    d.solver.strain_limit_iterations = passes;
    d.solver.strain_fail = 10.0; /* let the unlimited run stretch */
    cloth *c;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return NAN;
    int n = cloth_vertex_count(c), N = d.cols;
    double p0[3], p1[3];
    memcpy(p0, cloth_positions(c), sizeof p0);
    memcpy(p1, cloth_positions(c) + 3 * (N - 1), sizeof p1);
    cloth_pin(c, 0, p0);
    cloth_pin(c, N - 1, p1);
    double h = 1.0 / 60.0, worst = 0.0, worst_consistency = 0.0;
    double *xprev = malloc(3 * (size_t)n * sizeof *xprev);
    for (int s = 0; s < 120; s++) {
        memcpy(xprev, cloth_positions(c), 3 * (size_t)n * sizeof *xprev);
        cloth_step_stats st;
        if (!CHECK(cloth_step(c, h, &st) == CLOTH_OK, "step %d: %s", s, cloth_last_error(c))) break;
        double ms = cloth_max_strain(c);
        if (ms > worst) worst = ms;
        const double *x = cloth_positions(c), *v = cloth_velocities(c);
        for (int k = 0; k < 3 * n; k++) {
            double e = fabs(x[k] - (xprev[k] + h * v[k]));
            if (e > worst_consistency) worst_consistency = e;
        }
        if (check_each_step) {
            CHECK(memcmp(x, p0, sizeof p0) == 0 && memcmp(x + 3 * (N - 1), p1, sizeof p1) == 0, "step %d: a pin moved",
                  s);
        }
    }
    if (check_each_step)
        CHECK(worst_consistency <= 1e-12, "x1 - (x0 + h v1) reached %.3g m: positions and velocities disagree",
              worst_consistency);
    free(xprev);
    cloth_destroy(c);
    return worst;
}

int main(void)
{
    double delta = cloth_default_desc().material.delta, k_delta = cloth_default_desc().material.k_delta;
    /* no stiffening, no projection */
    double free_strain = run(0, 0.0, 0);
    printf("no limit (k_delta 0, projection off): max strain %.4f (delta %.3f)\n", free_strain, delta);
    CHECK(free_strain > 3.0 * delta, "the scene must need the limit: unlimited strain %.4f", free_strain);
    /* the stiffening alone: strain well down, but not necessarily <= delta */
    double stiff = run(0, k_delta, 1);
    printf("stiffening only (k_delta %g, projection off): max strain %.6f\n", k_delta, stiff);
    CHECK(stiff < free_strain / 3.0, "stiffening only: strain %.6f, want < unlimited %.4f / 3", stiff, free_strain);
    /* the projection alone must hold delta */
    double proj = run(200, 0.0, 1);
    printf("projection only (k_delta 0, 200 steps allowed): max strain %.9f\n", proj);
    CHECK(proj <= delta * (1.0 + 1e-6), "projection only: strain %.9f > delta %.3f", proj, delta);
    /* The projection converged (200 Newton steps allowed; it stops when no
     * link is over) and with the default number of steps must both hold
     * delta to 1e-6 of itself. */
    double converged = run(200, k_delta, 1);
    printf("both (k_delta %g, 200 steps allowed): max strain %.9f\n", k_delta, converged);
    CHECK(converged <= delta * (1.0 + 1e-6), "200 steps: strain %.9f > delta %.3f", converged, delta);
    double dflt = run(cloth_default_desc().solver.strain_limit_iterations, k_delta, 1);
    printf("both (k_delta %g, default %d steps): max strain %.9f\n", k_delta,
           cloth_default_desc().solver.strain_limit_iterations, dflt);
    CHECK(dflt <= delta * (1.0 + 1e-6), "default steps: strain %.9f > delta %.3f (unlimited %.4f)", dflt, delta,
          free_strain);
    return check_summary();
}
