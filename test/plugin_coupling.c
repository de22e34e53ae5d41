/* Two-way coupling between a cloth and ODE bodies (plugin/src/body_coupling.c, reactions.c):
 * what the cloth does to a body must be what the body does to the cloth.
 * Default cloth everywhere: 21 x 21 nodes, 1 m square, horizontal at z = 1,
 * cotton, 0.2 kg; h = 1/60 s, dClothWorldStep (cloth, then dWorldStep).
 *
 *  1. A box resting on a cloth pinned at its four corners to the world.
 *     The cloth first sags alone for 2 s; then a 0.2 m, 0.5 kg box (a
 *     dynamic body, its geom in a dHashSpace) is put 1 mm above the highest
 *     vertex under its footprint, and the whole is stepped for 14 s.
 *     Asserted: every step succeeds; over the last 2 s, in every step, the
 *     four pin forces (dClothGetPinForce) balance the weight of box and
 *     cloth, |F_1 + ... + F_4 + (m + M) g| <= 0.02 (m + M) |g|, and the box's
 *     vertical velocity stays below 1 mm/s (no jitter). Run with the
 *     linearised step and with Newton's, whose triangle contacts let go the
 *     step after their own force pulled: a large pull dropped at once would
 *     kick the box (a pull P moves it by P h / m in a step).
 *  2. A cloth pinned by two adjacent corner vertices to a free-floating
 *     sphere (radius 5 cm), thrown: no gravity (world and cloth), the body
 *     starts at v = (1, 0.5, 2) m/s, w = (0, 0, 3) rad/s, the cloth at rest;
 *     2 s. Nothing external acts, so the total linear momentum
 *     sum m_i v_i + m_b v_b must stay at its initial value m_b v_0: asserted
 *     within 1% of |m_b v_0| at every step (and every step succeeds), for a
 *     body of 5 kg (25 x the cloth) and of 0.5 kg (2.5 x the cloth).
 *  3. A hanging cloth pulls its body. A 1 kg box on a frictionless vertical
 *     slider joint (to the world) holds the cloth by the two ends of one
 *     edge (vertices 0 and C - 1, on a rigid 1 m arm: local points -+0.5 m).
 *     Gravity acts on both; every step the user pushes the box up with
 *     (m_b + M) g. The joint takes no force along z, so the vertical momentum
 *     of box + cloth, P_z = m_b v_bz + sum m_i v_iz, has no net external force
 *     and stays 0 in closed form while the cloth falls, swings and settles.
 *     Without the cloth's pull the box would rise at M g / m_b = 1.96 m/s^2.
 *     Asserted: every step succeeds; |P_z| <= 1% of the largest |vertical
 *     momentum of the cloth| reached (about 0.25 N s) at every step; over the
 *     last 2 s of 20 s, the box's |v_z| < 1 mm/s and the two pin forces carry
 *     the cloth's weight, |F_1z + F_2z - M g| <= 0.02 M g.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define G 9.81
static const double H = 1.0 / 60;

static double cloth_mass(dClothID c)
{
    const double *m = cloth_masses(dClothGetCore(c));
    double s = 0;
    for (int i = 0; i < dClothGetVertexCount(c); i++) s += m[i];
    return s;
}

static void cloth_momentum(dClothID c, double P[3])
{
    const double *m = cloth_masses(dClothGetCore(c)), *v = cloth_velocities(dClothGetCore(c));
    P[0] = P[1] = P[2] = 0;
    for (int i = 0; i < dClothGetVertexCount(c); i++)
        for (int k = 0; k < 3; k++) P[k] += m[i] * v[3 * i + k];
}

/* ------------------------------------------- 1. a box resting on a cloth */

#define BOX_SETTLE 2.0
#define BOX_SECONDS 14.0
#define BOX_WINDOW 2.0

/* how: the cloth's step (the library's default, and Newton's, whose
 * triangle contacts let go where their own force pulls) */
static void box_on_cloth(cloth_nonlinear how)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -G);
    dSpaceID sp = dHashSpaceCreate(0);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.solver.nonlinear = how;
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) return;
    dClothSetFailureMode(c, DCLOTH_FAILURE_STOP); /* a failed step is an error here */
    int R = d.cloth.rows, C = d.cloth.cols, n = R * C, corner[4] = {0, C - 1, (R - 1) * C, R * C - 1};
    for (int k = 0; k < 4; k++)
        CHECK(dClothPinToWorld(c, corner[k], dClothGetPositions(c) + 3 * corner[k]) == CLOTH_OK, "pin: %s",
              dClothGetLastError(c));
    int ok = 1;
    for (int s = 1; s <= (int)(BOX_SETTLE / H + 0.5) && ok; s++)
        ok = CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "cloth alone, step %d: %s", s, dClothGetLastError(c));

    const double mb = 0.5, a = 0.2;
    const double *x = dClothGetPositions(c);
    double ztop = -INFINITY;
    for (int i = 0; i < n; i++)
        if (fabs(x[3 * i]) <= a / 2 && fabs(x[3 * i + 1]) <= a / 2) ztop = fmax(ztop, x[3 * i + 2]);
    dBodyID b = dBodyCreate(w);
    dMass m;
    dMassSetBoxTotal(&m, mb, a, a, a);
    dBodySetMass(b, &m);
    dGeomID g = dCreateBox(sp, a, a, a);
    dGeomSetBody(g, b);
    dBodySetPosition(b, 0, 0, ztop + d.thickness + 0.001 + a / 2);

    const double M = cloth_mass(c), W = (mb + M) * G;
    int steps = (int)(BOX_SECONDS / H + 0.5), window = steps - (int)(BOX_WINDOW / H + 0.5), done = 0;
    int bad_f = 0, bad_v = 0;
    double worst_f = 0, worst_v = 0, fsum_last[3] = {0, 0, 0};
    for (int s = 1; s <= steps && ok; s++) {
        ok = CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "box on cloth, step %d (t = %.3f s after the box): %s",
                   s, s * H, dClothGetLastError(c));
        if (!ok) {
            printf("box on cloth: step %d failed; the box was at z %.4f, v_z %+.3f m/s (put at %.4f)\n", s,
                   dBodyGetPosition(b)[2], dBodyGetLinearVel(b)[2], ztop + d.thickness + 0.001 + a / 2);
            break;
        }
        done = s;
        if (s <= window) continue;
        double F[3] = {0, 0, 0}, f[3];
        for (int k = 0; k < 4; k++) {
            dClothGetPinForce(c, corner[k], f);
            for (int q = 0; q < 3; q++) F[q] += f[q];
        }
        double r[3] = {F[0], F[1], F[2] - W}, e = norm3(r) / W, vz = fabs(dBodyGetLinearVel(b)[2]);
        memcpy(fsum_last, F, sizeof F);
        worst_f = fmax(worst_f, e);
        worst_v = fmax(worst_v, vz);
        if (!(e <= 0.02) && bad_f++ < 3)
            CHECK(0, "t = %.3f s: pin forces (%.4f, %.4f, %.4f) N do not balance (m + M) g = %.4f N (%.2f%% off)",
                  s * H, F[0], F[1], F[2], W, 100 * e);
        if (!(vz < 1e-3) && bad_v++ < 3)
            CHECK(0, "t = %.3f s: the box's vertical velocity is %.3g m/s (jitter)", s * H, dBodyGetLinearVel(b)[2]);
    }
    CHECK(done == steps, "box on cloth: only %d of %d steps done; the at-rest window was %s", done, steps,
          done > window ? "cut short" : "never reached");
    if (done > window)
        printf("box on cloth (%s), last %.0f s: pin forces sum z %.4f N vs (m + M) g = %.4f N; worst imbalance "
               "%.3f%%, worst box |v_z| %.3g m/s\n",
               how == CLOTH_NEWTON ? "Newton" : "linearised", BOX_WINDOW, fsum_last[2], W, 100 * worst_f, worst_v);
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

/* ------------------------------------- 2. a thrown body with a cloth */

#define THROW_SECONDS 2.0

static void thrown(double mb)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, 0);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.gravity[0] = d.cloth.gravity[1] = d.cloth.gravity[2] = 0;
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, 0, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) {
        dWorldDestroy(w);
        return;
    }
    dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
    dBodyID b = sphere_holding(w, c, mb);
    dBodySetLinearVel(b, 1.0, 0.5, 2.0);
    dBodySetAngularVel(b, 0, 0, 3.0);
    double P0[3];
    for (int k = 0; k < 3; k++) P0[k] = mb * dBodyGetLinearVel(b)[k];
    double P0n = norm3(P0), worst = 0, worst_t = 0, cloth_peak = 0;
    int steps = (int)(THROW_SECONDS / H + 0.5), done = 0, bad = 0;
    for (int s = 1; s <= steps; s++) {
        if (!CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "thrown, body %g kg, step %d: %s", mb, s,
                   dClothGetLastError(c)))
            break;
        done = s;
        double P[3], e[3];
        cloth_momentum(c, P);
        cloth_peak = fmax(cloth_peak, norm3(P));
        for (int k = 0; k < 3; k++) e[k] = P[k] + mb * dBodyGetLinearVel(b)[k] - P0[k];
        double rel = norm3(e) / P0n;
        if (rel > worst) worst = rel, worst_t = s * H;
        if (!(rel <= 0.01) && bad++ < 3)
            CHECK(0,
                  "thrown, body %g kg, t = %.3f s: momentum off by (%.4g, %.4g, %.4g) N s, %.2f%% of |P0| = %.4g N s",
                  mb, s * H, e[0], e[1], e[2], 100 * rel, P0n);
    }
    CHECK(done == steps, "thrown, body %g kg: only %d of %d steps done", mb, done, steps);
    printf("thrown, body %g kg (cloth %.2f kg): %d steps, |P0| = %.3f N s, cloth momentum up to %.3f N s; worst "
           "momentum error %.3f%% of |P0| (t = %.3f s)\n",
           mb, cloth_mass(c), done, P0n, cloth_peak, 100 * worst, worst_t);
    dClothDestroy(c);
    dWorldDestroy(w);
}

/* ------------------------------ 3. a hanging cloth pulls its body */

#define SLIDER_SECONDS 20.0
#define SLIDER_WINDOW 2.0

static void slider(void)
{
    const double mb = 1.0;
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -G);
    dClothDesc d = dClothDefaultDesc();
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, 0, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) {
        dWorldDestroy(w);
        return;
    }
    dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
    int C = d.cloth.cols, pins[2] = {0, C - 1};
    const double *x = dClothGetPositions(c);
    dBodyID b = dBodyCreate(w);
    dMass m;
    dMassSetBoxTotal(&m, mb, 0.1, 0.1, 0.1);
    dBodySetMass(b, &m);
    double p0[3] = {0.5 * (x[0] + x[3 * (C - 1)]), x[1], x[2]};
    dBodySetPosition(b, p0[0], p0[1], p0[2]);
    dJointID j = dJointCreateSlider(w, 0);
    dJointAttach(j, b, 0);
    dJointSetSliderAxis(j, 0, 0, 1);
    for (int k = 0; k < 2; k++) {
        dReal lp[3] = {x[3 * pins[k]] - p0[0], x[3 * pins[k] + 1] - p0[1], x[3 * pins[k] + 2] - p0[2]};
        CHECK(dClothPinToBody(c, pins[k], b, lp) == CLOTH_OK, "dClothPinToBody: %s", dClothGetLastError(c));
    }
    const double M = cloth_mass(c);
    int steps = (int)(SLIDER_SECONDS / H + 0.5), window = steps - (int)(SLIDER_WINDOW / H + 0.5), done = 0;
    double *Pz = malloc((size_t)steps * sizeof *Pz), pc_peak = 0, worst_f = 0, worst_v = 0, fz_last = 0;
    int bad_f = 0, bad_v = 0;
    for (int s = 1; s <= steps; s++) {
        dBodyAddForce(b, 0, 0, (mb + M) * G);
        if (!CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "slider, step %d: %s", s, dClothGetLastError(c))) break;
        done = s;
        double P[3];
        cloth_momentum(c, P);
        pc_peak = fmax(pc_peak, fabs(P[2]));
        Pz[s - 1] = P[2] + mb * dBodyGetLinearVel(b)[2];
        if (s <= window) continue;
        double f[3], fz = 0, vz = fabs(dBodyGetLinearVel(b)[2]);
        for (int k = 0; k < 2; k++) {
            dClothGetPinForce(c, pins[k], f);
            fz += f[2];
        }
        fz_last = fz;
        double e = fabs(fz - M * G) / (M * G);
        worst_f = fmax(worst_f, e);
        worst_v = fmax(worst_v, vz);
        if (!(e <= 0.02) && bad_f++ < 3)
            CHECK(0, "slider, t = %.3f s: pin forces z %.5f N do not carry the cloth's weight %.5f N (%.2f%% off)",
                  s * H, fz, M * G, 100 * e);
        if (!(vz < 1e-3) && bad_v++ < 3)
            CHECK(0, "slider, t = %.3f s: the box still moves at v_z = %.3g m/s", s * H, dBodyGetLinearVel(b)[2]);
    }
    CHECK(done == steps, "slider: only %d of %d steps done", done, steps);
    /* P_z = 0 throughout, against the cloth's own momentum scale */
    double worst_p = 0, worst_pt = 0;
    int bad_p = 0;
    for (int s = 1; s <= done; s++) {
        if (fabs(Pz[s - 1]) > worst_p) worst_p = fabs(Pz[s - 1]), worst_pt = s * H;
        if (!(fabs(Pz[s - 1]) <= 0.01 * pc_peak) && bad_p++ < 3)
            CHECK(0,
                  "slider, t = %.3f s: vertical momentum of box + cloth %.4g N s, not 0 (1%% of the cloth's peak %.4g "
                  "N s is %.3g)",
                  s * H, Pz[s - 1], pc_peak, 0.01 * pc_peak);
    }
    if (bad_p > 3) printf("slider: ... %d steps over the momentum bound in all\n", bad_p);
    printf("slider: cloth's peak |P_z| %.4f N s; worst |P_z| of box + cloth %.4g N s (%.2f%% of it, t = %.2f s); box "
           "at z %.4f (started at %.4f); last %.0f s: box |v_z| <= %.3g m/s, pin forces z %.5f N vs M g %.5f N (worst "
           "%.3f%% off)\n",
           pc_peak, worst_p, 100 * worst_p / pc_peak, worst_pt, dBodyGetPosition(b)[2], p0[2], SLIDER_WINDOW, worst_v,
           fz_last, M * G, 100 * worst_f);
    free(Pz);
    dClothDestroy(c);
    dWorldDestroy(w);
}

/* A light body thrown with the cloth (0.5 kg, the cloth 0.2 kg) runs here:
 * the body is solved with the cloth (cloth_body), which explicit coupling
 * cannot do. The box resting on the cloth (1.) needs the triangle contacts'
 * geometry refined within the shell (plugin/src/triangles.c): without it,
 * changes of the contact set under the box kick it. */
int main(void)
{
    dInitODE2(0);
    box_on_cloth(CLOTH_LINEARIZED);
    box_on_cloth(CLOTH_NEWTON);
    thrown(5.0);
    thrown(0.5);
    slider();
    dCloseODE();
    return check_summary();
}
