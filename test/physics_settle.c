/* Physics: a cloth hung from two corners comes to rest, holds its pins and
 * its elongation limit on the way, and at rest the pins carry its weight.
 *
 * The default cloth (21 x 21 nodes, 1 m, cotton, backward Euler + block-
 * Jacobi MPCG at tolerance 1e-3, 10 Provot passes), horizontal at first,
 * pinned at its two corners of row 0 at their rest positions, falls and
 * swings under gravity at h = 1/60 s for 30 s. Asserted:
 *   - every step succeeds;
 *   - every step, the pinned vertices are at their targets to 1e-15 m
 *     (the step computes x0 + h (v0 + dv) with the pins' dv chosen to land
 *     there: a rounding or two of coordinates of size <= 1);
 *   - every step, cloth_max_strain <= delta + 1e-6 (delta = 0.03, the
 *     elongation limit; the slack covers only the finite number of Provot
 *     passes), and the step's stats.max_strain is the cloth's;
 *   - over the last 2 s, the kinetic energy stays below 1e-4 of its peak
 *     (the peak comes in the first swing, about 0.5 J). Why 1e-4: a residual
 *     oscillation of kinetic energy E in a mode of angular frequency w makes
 *     inertial forces of amplitude about w sqrt(2 M E); for the ~2-3 rad/s
 *     swinging modes of this cloth (M = 0.2 kg) E = 1e-4 x 0.53 J gives
 *     0.009-0.014 N, 0.5-0.7% of the weight, so this bound and the 1%
 *     force balance below are about the same statement of "at rest";
 *   - over the last 2 s, the sum of the two pin forces (cloth_constraint_
 *     force) balances the weight: |F_1 + F_2 + M g| <= 0.01 M |g|.
 * How long: the kinetic energy's envelope decays by about 2x every 2.3 s
 * after the first swing (backward Euler's numerical damping plus 1% link
 * damping), so 10 s is not enough and 30 s leaves a margin on both bounds.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define SECONDS 30.0
#define WINDOW 2.0

int main(void)
{
    cloth_desc d = cloth_default_desc();
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) return check_summary();
    int n = cloth_vertex_count(c), pins[2] = {0, d.cols - 1};
    double target[2][3], mtot = 0, delta = d.material.delta;
    for (int k = 0; k < 2; k++) {
        memcpy(target[k], cloth_positions(c) + 3 * pins[k], sizeof target[k]);
        CHECK(cloth_pin(c, pins[k], target[k]) == CLOTH_OK, "cloth_pin: %s", cloth_last_error(c));
    }
    for (int i = 0; i < n; i++) mtot += cloth_masses(c)[i];
    double W[3] = {mtot * d.gravity[0], mtot * d.gravity[1], mtot * d.gravity[2]};
    double Wn = sqrt(W[0] * W[0] + W[1] * W[1] + W[2] * W[2]);

    const double h = 1.0 / 60;
    int nsteps = (int)(SECONDS / h + 0.5), window_start = nsteps - (int)(WINDOW / h + 0.5);
    double peak = 0, ke_window = 0, fdev_window = 0, pin_worst = 0, strain_worst = -INFINITY;
    int pin_bad = 0, strain_bad = 0, stats_bad = 0;
    for (int s = 1; s <= nsteps; s++) {
        cloth_step_stats st;
        if (!CHECK(cloth_step(c, h, &st) == CLOTH_OK, "step %d: %s", s, cloth_last_error(c))) break;
        const double *x = cloth_positions(c);
        for (int k = 0; k < 2; k++)
            for (int a = 0; a < 3; a++) {
                double e = fabs(x[3 * pins[k] + a] - target[k][a]);
                pin_worst = fmax(pin_worst, e);
                if (!(e <= 1e-15) && pin_bad++ < 5)
                    CHECK(0, "step %d: pin %d component %d off its target by %.3g m", s, pins[k], a, e);
            }
        double ms = cloth_max_strain(c);
        strain_worst = fmax(strain_worst, ms);
        if (!(ms <= delta + 1e-6) && strain_bad++ < 5)
            CHECK(0, "step %d: max strain %.9f > delta %g (after %d Provot passes; %d links over in the first)", s, ms,
                  delta, d.solver.strain_limit_iterations, st.strain_limited);
        if (st.max_strain != ms && stats_bad++ < 5)
            CHECK(0, "step %d: stats.max_strain %.17g != cloth_max_strain %.17g", s, st.max_strain, ms);
        double ke = st.energy.kinetic;
        peak = fmax(peak, ke);
        if (s > window_start) {
            double f0[3], f1[3], r[3];
            cloth_constraint_force(c, pins[0], f0);
            cloth_constraint_force(c, pins[1], f1);
            for (int a = 0; a < 3; a++) r[a] = f0[a] + f1[a] + W[a];
            ke_window = fmax(ke_window, ke);
            fdev_window = fmax(fdev_window, sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) / Wn);
            if (s == nsteps)
                printf("at %.0f s: pin forces sum (%.5f, %.5f, %.5f) N, weight M g = (%.5f, %.5f, %.5f) N\n", s * h,
                       f0[0] + f1[0], f0[1] + f1[1], f0[2] + f1[2], W[0], W[1], W[2]);
        }
    }
    printf("%.0f s at h = 1/60: peak kinetic energy %.4f J; over the last %.0f s: max kinetic energy %.3e of the "
           "peak, max pin-force imbalance %.3f%% of the weight\n",
           SECONDS, peak, WINDOW, ke_window / peak, 100 * fdev_window);
    printf("every step: pins off target by <= %.3g m; max strain <= %.6f (delta %g)\n", pin_worst, strain_worst, delta);
    CHECK(peak > 0.1, "peak kinetic energy %.3g J: the cloth did not fall", peak);
    CHECK(ke_window <= 1e-4 * peak, "not at rest: kinetic energy reached %.3g of its peak in the last %g s",
          ke_window / peak, WINDOW);
    CHECK(fdev_window <= 0.01, "pin forces do not balance the weight: |F1 + F2 + M g| = %.3g%% of M |g|",
          100 * fdev_window);
    cloth_destroy(c);
    return check_summary();
}
