/* Plugin: a heavy body caught by a taut cloth, solved by Newton's method.
 * A 41x41 cotton cloth, 1 m, 0.2 kg, flat at z = 1 m with its four corners
 * pinned to the world; a 1 kg ball (r 0.1 m) starts 15 mm above its shell
 * (and, a second run, on it) and falls onto its centre at 5 m/s. 40 steps
 * of 1/60 s (dClothWorldStep, DCLOTH_FAILURE_STOP, solver.nonlinear
 * CLOTH_NEWTON). The cloth can stop the ball only by stretching to its
 * elongation limit, so the limit must hold against the ball's momentum, and
 * the ball's contacts move with it:
 *   - every step succeeds (whole or in substeps);
 *   - the ball is caught: it never ends below the cloth, and from 0.2 s on
 *     it moves at under 0.5 m/s;
 *   - no step gains energy (cloth elastic, kinetic and gravitational plus
 *     the ball's) beyond 1e-3 J: the pins are fixed and do no work, and the
 *     impact is inelastic. The first contact step included: a vertex the
 *     ball reaches within the step is held on its surface only while it
 *     pushes (a contact pulling it across the gap would do work);
 *   - no sequential link ends past (1 + delta) l0 by more than 1e-3 of it.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "odecloth/dcloth.h"
#include "check.h"

#define N 41
#define H (1.0 / 60.0)
#define STEPS 40
#define Z 1.0
#define R 0.1
#define M_BALL 1.0
#define G 9.81

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static double energy(const cloth *core, dBodyID ball)
{
    cloth_energy e = cloth_energies(core);
    const double *v = dBodyGetLinearVel(ball), *w = dBodyGetAngularVel(ball);
    return e.elastic + e.kinetic + e.gravitational + 0.5 * M_BALL * dot(v, v) + 0.2 * M_BALL * R * R * dot(w, w) +
           M_BALL * G * dBodyGetPosition(ball)[2];
}

/* is the ball's centre below the cloth vertex nearest it in plan? */
static int below(const cloth *core, dBodyID ball)
{
    const double *b = dBodyGetPosition(ball), *x = cloth_positions(core);
    int best = 0;
    double d2 = INFINITY;
    for (int i = 0; i < cloth_vertex_count(core); i++) {
        double dx = x[3 * i] - b[0], dy = x[3 * i + 1] - b[1];
        if (dx * dx + dy * dy < d2) d2 = dx * dx + dy * dy, best = i;
    }
    return b[2] < x[3 * best + 2];
}

/* the largest (d - (1 + delta) l0) / ((1 + delta) l0) over the grid's
 * horizontal, vertical and diagonal neighbours */
static double worst_excess(const cloth *core, double delta)
{
    const double *x = cloth_positions(core);
    double l0 = 1.0 / (N - 1), worst = -INFINITY;
    const int di[4] = {0, 1, 1, 1}, dj[4] = {1, 0, 1, -1};
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++)
            for (int k = 0; k < 4; k++) {
                int i2 = i + di[k], j2 = j + dj[k];
                if (i2 >= N || j2 < 0 || j2 >= N) continue;
                const double *a = x + 3 * (i * N + j), *b = x + 3 * (i2 * N + j2);
                double w[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
                double rest = k < 2 ? l0 : l0 * sqrt(2.0), lim = (1.0 + delta) * rest;
                worst = fmax(worst, (sqrt(dot(w, w)) - lim) / lim);
            }
    return worst;
}

/* one throw, the ball's shell start_gap above the cloth's */
static void throw_ball(double start_gap)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -G);
    dSpaceID sp = dHashSpaceCreate(0);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = N;
    d.cloth.material = cloth_material_preset(CLOTH_COTTON);
    d.cloth.material.density = 0.2;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.5;
    d.cloth.origin[2] = Z;
    d.cloth.solver.nonlinear = CLOTH_NEWTON;
    dClothID c = NULL;
    if (!CHECK(dClothCreate(w, sp, &d, &c, NULL) == CLOTH_OK, "dClothCreate")) return;
    dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
    cloth *core = dClothGetCore(c);
    const int corner[4] = {0, N - 1, (N - 1) * N, N * N - 1};
    for (int k = 0; k < 4; k++)
        CHECK(dClothPinToWorld(c, corner[k], cloth_positions(core) + 3 * corner[k]) == CLOTH_OK, "pin %d", corner[k]);
    dBodyID ball = dBodyCreate(w);
    dMass m;
    dMassSetSphereTotal(&m, M_BALL, R);
    dBodySetMass(ball, &m);
    dGeomID g = dCreateSphere(sp, R);
    dGeomSetBody(g, ball);
    dBodySetPosition(ball, 0, 0, Z + R + d.thickness + start_gap);
    dBodySetLinearVel(ball, 0, 0, -5.0);

    double delta = d.cloth.material.delta, e0 = energy(core, ball), worst_gain = -INFINITY, worst_link = -INFINITY;
    int touched = -1;
    for (int k = 0; k < STEPS; k++) {
        cloth_status s = dClothWorldStep(w, &c, 1, H, 0);
        if (!CHECK(s == CLOTH_OK, "step %d failed: %s", k, dClothGetLastError(c))) break;
        double e1 = energy(core, ball);
        if (touched < 0 && dClothGetStats(c)->contacts > 0) touched = k;
        worst_gain = fmax(worst_gain, e1 - e0);
        e0 = e1;
        CHECK(!below(core, ball), "step %d: the ball below the cloth", k);
        if ((k + 1) * H >= 0.2)
            CHECK(fabs(dBodyGetLinearVel(ball)[2]) < 0.5, "step %d: the ball at %.3f m/s", k,
                  dBodyGetLinearVel(ball)[2]);
        worst_link = fmax(worst_link, worst_excess(core, delta));
    }
    printf("ball from %.0f mm above the shell: first contact at step %d; largest gain of a step %.3g J; ball vz "
           "at the end %.3f m/s; worst link past the limit %.2e of it\n",
           1e3 * start_gap, touched, worst_gain, dBodyGetLinearVel(ball)[2], worst_link);
    CHECK(touched >= 0 && touched < 3, "first contact at step %d", touched);
    CHECK(worst_gain <= 1e-3, "ball from %g m: a step gained %.3g J", start_gap, worst_gain);
    CHECK(worst_link <= 1e-3, "ball from %g m: a link %.3g past the limit", start_gap, worst_link);
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

int main(void)
{
    dInitODE2(0);
    throw_ball(0.015);
    throw_ball(0.0);
    dCloseODE();
    return check_summary();
}
