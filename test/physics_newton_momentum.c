/* Physics: a free cloth stepped by Newton's method keeps linear momentum
 * exactly, whatever its solver tolerances.
 *
 * The links' forces and dampers act equal and opposite, so over a step the
 * cloth's momentum changes by exactly h sum_i f_i (backward Euler and BDF2
 * alike: BDF2's P1 - (4 P0 - P-1) / 3 = 2h/3 sum f, and with a constant
 * force P1 - P0 = h sum f once the first step is taken). The linear solves
 * of a Newton step stop at a tolerance and leave a residual; its sum must
 * not show up as momentum. A 15 x 15 cotton cloth, jittered so its links
 * pull and push, spinning and drifting, in zero gravity, with random
 * per-vertex forces, 30 steps of 1/60 s at the solver's defaults:
 *   |P(t) - P(0) - t sum f| <= 1e-12 of the impulse t sum |f| + |P(0)|.
 * At newton_tolerance 1e-2 the solves' residual alone is about 1e-4 of it. */
#include <math.h>
#include <stdlib.h>

#include "odecloth/cloth.h"
#include "check.h"

#define N 15
#define H (1.0 / 60.0)
#define STEPS 30

static double momentum(const cloth *c, double P[3])
{
    const double *v = cloth_velocities(c), *m = cloth_masses(c);
    double s = 0.0;
    P[0] = P[1] = P[2] = 0.0;
    for (int i = 0; i < cloth_vertex_count(c); i++)
        for (int r = 0; r < 3; r++) {
            P[r] += m[i] * v[3 * i + r];
            s += m[i] * fabs(v[3 * i + r]);
        }
    return s;
}

static void run(cloth_method method, const char *name)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = N;
    d.solver.method = method;
    d.solver.nonlinear = CLOTH_NEWTON;
    d.gravity[0] = d.gravity[1] = d.gravity[2] = 0.0;
    cloth *c = NULL;
    if (!CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK, "%s: cloth_create", name)) return;
    int n = cloth_vertex_count(c);
    double *x = malloc(3 * (size_t)n * sizeof *x), *v = malloc(3 * (size_t)n * sizeof *v);
    double *f = malloc(3 * (size_t)n * sizeof *f), F[3] = {0, 0, 0}, fabs_sum = 0.0;
    rng g = rng_seed(42);
    for (int i = 0; i < n; i++) {
        const double *x0 = cloth_positions(c) + 3 * i;
        for (int r = 0; r < 3; r++) {
            x[3 * i + r] = x0[r] + 0.004 * (rng_unit(&g) - 0.5);
            f[3 * i + r] = 0.002 * (rng_unit(&g) - 0.5);
            F[r] += f[3 * i + r];
            fabs_sum += fabs(f[3 * i + r]);
        }
        /* a drift, a spin about z and some noise */
        v[3 * i] = 0.3 - 2.0 * x0[1] + 0.05 * (rng_unit(&g) - 0.5);
        v[3 * i + 1] = -0.1 + 2.0 * x0[0] + 0.05 * (rng_unit(&g) - 0.5);
        v[3 * i + 2] = 0.2 + 0.05 * (rng_unit(&g) - 0.5);
    }
    for (int i = 0; i < n; i++) CHECK(cloth_set_vertex(c, i, x + 3 * i, v + 3 * i) == CLOTH_OK, "set vertex %d", i);
    CHECK(cloth_set_external_forces(c, f) == CLOTH_OK, "%s: forces", name);
    double P0[3], scale = momentum(c, P0), worst = 0.0;
    int at = 0;
    for (int k = 1; k <= STEPS; k++) {
        cloth_step_stats st;
        if (!CHECK(cloth_step(c, H, &st) == CLOTH_OK, "%s: step %d: %s", name, k, cloth_last_error(c))) break;
        double P[3], t = k * H;
        momentum(c, P);
        for (int r = 0; r < 3; r++) {
            double e = fabs(P[r] - P0[r] - t * F[r]) / (t * fabs_sum + scale);
            if (e > worst) worst = e, at = k;
        }
    }
    printf("%s: worst momentum error %.3g of the impulse scale (step %d)\n", name, worst, at);
    CHECK(worst <= 1e-12, "%s: momentum off t sum f by %.3g of the impulse scale at step %d", name, worst, at);
    free(x);
    free(v);
    free(f);
    cloth_destroy(c);
}

int main(void)
{
    run(CLOTH_BACKWARD_EULER, "backward Euler");
    run(CLOTH_BDF2, "BDF2");
    return check_summary();
}
