/* Physics: under the Newton step (solver.nonlinear = CLOTH_NEWTON, backward
 * Euler, library defaults otherwise) a cloth left alone loses energy in every
 * step and comes to rest.
 *
 * Why every step: the step minimises a convex potential whose compressed
 * branch acts along each link's direction at the step's start, where it
 * equals the springs' energy and elsewhere exceeds it; so an exact step
 * cannot gain energy (kinetic + elastic + gravitational), and an inexact one
 * stops only once the energy it may hold too many is a small part of what
 * the exact step dissipates (docs/newton.md).
 *
 * Scenes:
 *   - physics_settle's: the default 21 x 21 cloth pinned at two corners,
 *     30 s at h = 1/60. Asserted: every step succeeds; no step's energy
 *     exceeds the last's by more than 1e-6 of the peak kinetic energy (the
 *     stop's floor, 1e-4 newton_tolerance, leaves some at rest); over the
 *     last 2 s the kinetic energy stays below 1e-4 of its peak and the pins
 *     carry the weight within 1% (physics_settle's bounds, and why).
 *   - physics_fabric_cantilever's strip: cotton and polyester, 6 cells past
 *     the clamp (rows 0 and 1 pinned), h = 0.01 s. Asserted: every step
 *     succeeds, none gains energy beyond 1e-6 of the peak kinetic energy,
 *     and within 5000 steps every velocity is below 1e-6 m/s.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "odecloth/fabric.h"
#include "check.h"
#include "fabric_strip.h"

#define SLACK 1e-6 /* of the peak kinetic energy: what the stop may leave at rest */

static double total(const cloth_energy *e) { return e->kinetic + e->elastic + e->gravitational; }

static void settle(void)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = CLOTH_NEWTON;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) return;
    int n = cloth_vertex_count(c), pins[2] = {0, d.cols - 1};
    double mtot = 0.0;
    for (int k = 0; k < 2; k++) cloth_pin(c, pins[k], cloth_positions(c) + 3 * pins[k]);
    for (int i = 0; i < n; i++) mtot += cloth_masses(c)[i];
    double W = mtot * fabs(d.gravity[2]);
    const double h = 1.0 / 60;
    int nsteps = 1800, window = nsteps - 120, gains = 0, worst_step = 0;
    cloth_energy e0 = cloth_energies(c);
    double E0 = total(&e0), peak = 0.0, worst = 0.0, ke_window = 0.0, fdev = 0.0;
    for (int s = 1; s <= nsteps; s++) {
        cloth_step_stats st;
        if (!CHECK(cloth_step(c, h, &st) == CLOTH_OK, "settle, step %d: %s", s, cloth_last_error(c))) break;
        double E = total(&st.energy);
        peak = fmax(peak, st.energy.kinetic);
        if (E - E0 > 0.0) gains++;
        if (E - E0 > worst) {
            worst = E - E0;
            worst_step = s;
        }
        E0 = E;
        if (s > window) {
            double f0[3], f1[3], r[3];
            cloth_constraint_force(c, pins[0], f0);
            cloth_constraint_force(c, pins[1], f1);
            for (int a = 0; a < 3; a++) r[a] = f0[a] + f1[a] + mtot * d.gravity[a];
            ke_window = fmax(ke_window, st.energy.kinetic);
            fdev = fmax(fdev, sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) / W);
        }
    }
    printf("settle: %d of %d steps gained energy, the most %.3g J (step %d); peak kinetic energy %.4f J; over the "
           "last 2 s: kinetic energy up to %.3e of the peak, pin forces off the weight by %.3f%%\n",
           gains, nsteps, worst, worst_step, peak, ke_window / peak, 100.0 * fdev);
    CHECK(worst <= SLACK * peak, "settle: step %d gained %.3g J (%.3g of the peak kinetic energy)", worst_step, worst,
          worst / peak);
    CHECK(ke_window <= 1e-4 * peak, "settle: not at rest: kinetic energy %.3g of its peak in the last 2 s",
          ke_window / peak);
    CHECK(fdev <= 0.01, "settle: the pins carry the weight only within %.3g%%", 100.0 * fdev);
    cloth_destroy(c);
}

static void strip(const char *name, cloth_fabric_kind kind)
{
    cloth_fabric f = cloth_fabric_preset(kind);
    const int cells = 6;
    cloth_desc d;
    fabric_strip_desc(&f, cells, &d);
    cloth_error err;
    cloth *c = NULL;
    if (!CHECK(cloth_fabric_apply(&f, &d, &err) == CLOTH_OK, "%s: %s", name, err.message)) return;
    d.solver.nonlinear = CLOTH_NEWTON;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "%s: %s", name, err.message)) return;
    const double *x = cloth_positions(c), *v = cloth_velocities(c);
    for (int i = 0; i < 2 * d.cols; i++) cloth_pin(c, i, x + 3 * i);
    cloth_energy e0 = cloth_energies(c);
    double E0 = total(&e0), peak = 0.0, worst = 0.0, vmax = HUGE_VAL;
    int steps = 0, worst_step = 0;
    for (; steps < 5000 && !(vmax < 1e-6 && steps > 10); steps++) {
        cloth_step_stats st;
        if (!CHECK(cloth_step(c, 0.01, &st) == CLOTH_OK, "%s, step %d: %s", name, steps, cloth_last_error(c))) break;
        double E = total(&st.energy);
        peak = fmax(peak, st.energy.kinetic);
        if (E - E0 > worst) {
            worst = E - E0;
            worst_step = steps;
        }
        E0 = E;
        vmax = 0.0;
        for (int i = 0; i < 3 * cloth_vertex_count(c); i++) vmax = fmax(vmax, fabs(v[i]));
    }
    printf("%s strip: largest speed %.3g m/s after %d steps; the most a step gained %.3g J, peak kinetic energy "
           "%.3g J\n",
           name, vmax, steps, worst, peak);
    CHECK(worst <= SLACK * peak, "%s strip: step %d gained %.3g J (%.3g of the peak kinetic energy)", name, worst_step,
          worst, worst / peak);
    CHECK(vmax < 1e-6, "%s strip: still moving at %.3g m/s after %d steps", name, vmax, steps);
    cloth_destroy(c);
}

int main(void)
{
    settle();
    strip("cotton", CLOTH_FABRIC_COTTON);
    strip("polyester", CLOTH_FABRIC_POLYESTER);
    return check_summary();
}
