/* Physics: an inexact Newton step gains no energy, the bodies solved with
 * the cloth included.
 *
 * Backward Euler on a convex potential dissipates: the exact step loses at
 * least |dv|_M^2 / 2. The step's stop bounds what an inexact one can have
 * gained by the residual's work at the new velocities, the held bodies'
 * rows at theirs. A 3 kg body, its centre of mass 0.2 m off the vertex it
 * holds (it turns too), drags the centre of a 9x9 elastic cloth at
 * (2, 0, -2) m/s: no gravity, no dampers, no elongation limit, and solves
 * far looser than the defaults (newton_tolerance 0.05, newton_cg_tolerance
 * 0.3). Over 40 steps of 1/60 s the cloth's kinetic and spring energy plus
 * the body's never grow (1e-9 of it): left out of the bound, the body's
 * residual works unchecked and a step gains about 1e-3 J.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define N 9
#define H (1.0 / 60.0)
#define STEPS 40
#define BODY_MASS 3.0
#define BODY_INERTIA 0.05

static double body_energy(const double u[6])
{
    double e = 0.0;
    for (int a = 0; a < 3; a++) e += 0.5 * BODY_MASS * u[a] * u[a] + 0.5 * BODY_INERTIA * u[3 + a] * u[3 + a];
    return e;
}

static double total_energy(const cloth *c, const double u[6])
{
    cloth_energy e = cloth_energies(c);
    return e.kinetic + e.elastic + body_energy(u);
}

/* the velocity of the held point, u_lin + w x r, r = vertex - com */
static void point_velocity(const double u[6], const double r[3], double v[3])
{
    v[0] = u[0] + u[4] * r[2] - u[5] * r[1];
    v[1] = u[1] + u[5] * r[0] - u[3] * r[2];
    v[2] = u[2] + u[3] * r[1] - u[4] * r[0];
}

static cloth *make(void)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = CLOTH_NEWTON;
    d.rows = d.cols = N;
    d.gravity[0] = d.gravity[1] = d.gravity[2] = 0.0;
    d.material = cloth_material_preset(CLOTH_ELASTIC);
    d.material.k_delta = 0.0;              /* no elongation limit: its multipliers change the potential */
    d.material.c_t = d.material.c_b = 0.0; /* no dampers: the step's own dissipation only */
    d.solver.method = CLOTH_BACKWARD_EULER;
    d.solver.newton_tolerance = 0.05;
    d.solver.newton_cg_tolerance = 0.3;
    d.solver.newton_iterations = 64;
    d.solver.max_substep_halvings = 0;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return NULL;
    return c;
}

int main(void)
{
    cloth *c = make();
    if (!c) return check_summary();
    int ctr = (N / 2) * N + N / 2;
    double u[6] = {2.0, 0.0, -2.0, 0.0, 0.0, 0.0}, com[3];
    const double *x = cloth_positions(c);
    for (int a = 0; a < 3; a++) com[a] = x[3 * ctr + a] + (a == 2 ? 0.2 : 0.0);
    CHECK(cloth_set_vertex(c, ctr, x + 3 * ctr, u) == CLOTH_OK, "set vertex");
    double worst = -INFINITY, e0 = total_energy(c, u), before = e0;
    int newton = 0;
    for (int step = 0; step < STEPS; step++) {
        cloth_body b = {.mass = BODY_MASS, .inertia = {BODY_INERTIA, 0, 0, 0, BODY_INERTIA, 0, 0, 0, BODY_INERTIA}};
        memcpy(b.com, com, sizeof com);
        memcpy(b.velocity, u, sizeof u);
        if (!CHECK(cloth_set_bodies(c, &b, 1) == CLOTH_OK, "set_bodies: %s", cloth_last_error(c))) break;
        x = cloth_positions(c);
        double r[3] = {x[3 * ctr] - com[0], x[3 * ctr + 1] - com[1], x[3 * ctr + 2] - com[2]}, vp[3], target[3];
        point_velocity(u, r, vp);
        for (int a = 0; a < 3; a++) target[a] = x[3 * ctr + a] + H * vp[a];
        CHECK(cloth_pin(c, ctr, target) == CLOTH_OK, "pin: %s", cloth_last_error(c));
        CHECK(cloth_hold_by_body(c, ctr, 0) == CLOTH_OK, "hold: %s", cloth_last_error(c));
        cloth_step_stats st;
        if (!CHECK(cloth_step(c, H, &st) == CLOTH_OK, "step %d: %s", step, cloth_last_error(c))) break;
        newton += st.newton;
        double du[6];
        cloth_body_velocity_change(c, 0, du);
        for (int k = 0; k < 6; k++) u[k] += du[k];
        for (int a = 0; a < 3; a++) com[a] += H * u[a];
        double after = total_energy(c, u);
        worst = fmax(worst, after - before);
        before = after;
    }
    printf("energy %.6g J -> %.6g J, largest gain in a step %.3g J, %.2f Newton iterations a step\n", e0, before, worst,
           (double)newton / STEPS);
    CHECK(worst <= 1e-9 * e0, "a step gained %.3g J (energy %.3g J)", worst, e0);
    CHECK(before < e0, "the dampers dissipate: %.6g J after, %.6g J before", before, e0);
    cloth_destroy(c);
    return check_summary();
}
