/* The elongation limit delta (paper Table 1) does its job where it matters:
 * a cloth with soft tension, hanging from two corners, would stretch far past
 * delta; with the limit on, no sequential link is longer than (1 + delta) l0
 * after any step, the pins stay exact, and the corrected velocities stay
 * consistent with the corrected positions (backward Euler: x1 = x0 + h v1),
 * so the limit adds no hidden motion. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "odecloth/cloth.h"

static double run(int passes, int check_each_step)
{
    cloth_desc d = cloth_default_desc();
    d.material.k_t = 20.0; /* soft: the weight alone stretches it well past delta */
    d.material.k_c = 1.0;
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
            CHECK(memcmp(x, p0, sizeof p0) == 0 && memcmp(x + 3 * (N - 1), p1, sizeof p1) == 0,
                  "step %d: a pin moved", s);
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
    double delta = cloth_default_desc().material.delta;
    double free_strain = run(0, 0);
    printf("no limit: max strain %.4f (delta %.3f)\n", free_strain, delta);
    CHECK(free_strain > 3.0 * delta, "the scene must need the limit: unlimited strain %.4f", free_strain);
    /* Provot's passes are Gauss-Seidel over the links; a hanging chain of 20
     * links needs many to settle every link exactly at the bound, so check
     * the converged limiter tightly and the default (10 passes) for its
     * effect. */
    double converged = run(200, 1);
    printf("200 passes: max strain %.6f\n", converged);
    CHECK(converged <= delta * (1.0 + 1e-6), "200 passes: strain %.6f > delta %.3f", converged, delta);
    double dflt = run(cloth_default_desc().solver.strain_limit_iterations, 1);
    printf("default passes: max strain %.6f\n", dflt);
    CHECK(dflt < free_strain / 2.0 && dflt < 2.0 * delta, "default passes: strain %.4f (unlimited %.4f)", dflt,
          free_strain);
    return check_summary();
}
