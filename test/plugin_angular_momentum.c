/* Plugin: the totals of cloth + body conserved in zero gravity, not only the
 * exchange (test/plugin_momentum.c). A 0.5 kg sphere (radius 5 cm) holds an
 * 11x11 cotton cloth 0.4 m square by two vertices, h = 1/60 s, 60 steps:
 *   0. free, thrown at (1, 0.5, 2) m/s spinning at 3 rad/s about z: linear
 *      momentum and angular momentum about a fixed point (the sphere's start);
 *   1. in a ball joint at its centre, spinning about z: angular momentum about
 *      the anchor (the joint's force acts there: no torque about it);
 *   2. on a hinge along y through its centre, spinning about y: the angular
 *      momentum's component along the axis about the anchor;
 *   3. free and at rest in a wind: the totals change by the air's impulses
 *      (cloth_air_force, cloth_air_torque) and nothing else;
 *   4, 5. a free 20 x 10 x 5 cm box of the same mass, thrown and spinning,
 *      ODE's gyroscopic term on and off.
 * Each step's change of the total (to 1e-6 of the torque impulse exchanged,
 * h sum |x_i - p| |f_i| over the cloth's pin forces f_i; h sum |f_i| for
 * linear momentum) is split into its parts: the cloth's (its change, the
 * body's before ODE's step, plus the torque impulse the body took from it),
 * with backward Euler's own -h sum m_i v_i x dv_i for comparison, and ODE's
 * (the body's change in dWorldStep less that impulse). The plugin turns out
 * what the cloth's step leaves (dClothStepStats.turned): asserted big enough
 * that the bound could fail without it. A sphere's inertia is isotropic, so
 * ODE's update keeps its angular momentum exactly; a box's is ODE's own
 * rotation update, measured, and the box's assertion is the cloth's part.
 * Energy of cloth + body is printed: the turn gives back what the frozen
 * directions took from the rotation, so it is asserted no higher at the end
 * than at the start only (without wind).
 */
#include <math.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define H (1.0 / 60.0)
#define STEPS 60

/* The cloth's linear momentum P and angular momentum L about p */
static void cloth_momenta(dClothID c, const double p[3], double P[3], double L[3])
{
    const cloth *core = dClothGetCore(c);
    const double *x = cloth_positions(core), *v = cloth_velocities(core), *m = cloth_masses(core);
    memset(P, 0, 3 * sizeof *P);
    memset(L, 0, 3 * sizeof *L);
    for (int i = 0; i < dClothGetVertexCount(c); i++) {
        double r[3] = {x[3 * i] - p[0], x[3 * i + 1] - p[1], x[3 * i + 2] - p[2]}, t[3];
        cross(r, v + 3 * i, t);
        for (int k = 0; k < 3; k++) {
            P[k] += m[i] * v[3 * i + k];
            L[k] += m[i] * t[k];
        }
    }
}

/* The body's linear momentum P and angular momentum L about p: m (c - p) x v
 * plus its spin R I R^T w */
static void body_momenta(dBodyID b, const double p[3], double P[3], double L[3])
{
    dMass ms;
    dBodyGetMass(b, &ms);
    const dReal *c = dBodyGetPosition(b), *v = dBodyGetLinearVel(b), *w = dBodyGetAngularVel(b);
    const dReal *R = dBodyGetRotation(b); /* 3 rows of 4 */
    double r[3] = {c[0] - p[0], c[1] - p[1], c[2] - p[2]}, vv[3] = {v[0], v[1], v[2]}, wl[3], Iw[3];
    cross(r, vv, L);
    for (int k = 0; k < 3; k++) wl[k] = R[k] * w[0] + R[4 + k] * w[1] + R[8 + k] * w[2]; /* R^T w */
    for (int k = 0; k < 3; k++) Iw[k] = ms.I[4 * k] * wl[0] + ms.I[4 * k + 1] * wl[1] + ms.I[4 * k + 2] * wl[2];
    for (int k = 0; k < 3; k++) {
        P[k] = ms.mass * v[k];
        L[k] = ms.mass * L[k] + R[4 * k] * Iw[0] + R[4 * k + 1] * Iw[1] + R[4 * k + 2] * Iw[2];
    }
}

/* The impulses the body took this step (its accumulators after dClothStep):
 * J linear, K angular about p; *sf, *st the exchange's scales. */
static void exchanged(dClothID c, dBodyID b, const double p[3], double J[3], double K[3], double *sf, double *st)
{
    const dReal *F = dBodyGetForce(b), *T = dBodyGetTorque(b), *cb = dBodyGetPosition(b);
    double r[3] = {cb[0] - p[0], cb[1] - p[1], cb[2] - p[2]}, f[3] = {F[0], F[1], F[2]}, t[3];
    cross(r, f, t);
    for (int k = 0; k < 3; k++) {
        J[k] = H * F[k];
        K[k] = H * (t[k] + T[k]);
    }
    const dReal *x = dClothGetPositions(c);
    *sf = *st = 0.0;
    for (int i = 0; i < dClothGetVertexCount(c); i++) {
        dReal fp[3];
        dClothGetPinForce(c, i, fp);
        double fi[3] = {fp[0], fp[1], fp[2]}, ri[3] = {x[3 * i] - p[0], x[3 * i + 1] - p[1], x[3 * i + 2] - p[2]};
        *sf += H * norm3(fi);
        *st += H * norm3(fi) * norm3(ri);
    }
}

/* Backward Euler's own change of the cloth's angular momentum this step,
 * -h sum m_i v_i x dv_i, v0 the velocities before it */
static void euler_drift(dClothID c, const double *v0, double B[3])
{
    const cloth *core = dClothGetCore(c);
    const double *v = cloth_velocities(core), *m = cloth_masses(core);
    memset(B, 0, 3 * sizeof *B);
    for (int i = 0; i < dClothGetVertexCount(c); i++) {
        double dv[3] = {v[3 * i] - v0[3 * i], v[3 * i + 1] - v0[3 * i + 1], v[3 * i + 2] - v0[3 * i + 2]}, t[3];
        cross(v + 3 * i, dv, t);
        for (int k = 0; k < 3; k++) B[k] -= H * m[i] * t[k];
    }
}

/* the component along axis (unit), or the whole vector (axis NULL) */
static double part(const double *a, const double *axis)
{
    return axis ? fabs(a[0] * axis[0] + a[1] * axis[1] + a[2] * axis[2]) : norm3(a);
}

/* kinetic and elastic energy of cloth and body (no gravity: zero) */
static double energy(dClothID c, dBodyID b)
{
    cloth_energy e = cloth_energies(dClothGetCore(c));
    dMass ms;
    dBodyGetMass(b, &ms);
    const dReal *v = dBodyGetLinearVel(b), *w = dBodyGetAngularVel(b), *R = dBodyGetRotation(b);
    double wl[3], E = e.kinetic + e.elastic + 0.5 * ms.mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++) wl[k] = R[k] * w[0] + R[4 + k] * w[1] + R[8 + k] * w[2];
    for (int k = 0; k < 3; k++)
        E += 0.5 * wl[k] * (ms.I[4 * k] * wl[0] + ms.I[4 * k + 1] * wl[1] + ms.I[4 * k + 2] * wl[2]);
    return E;
}

typedef struct worst {
    double total, cloth, euler, ode, linear, turned, rise, e0, e1;
} worst;

/* Steps the scene, measuring each step's changes about p (along axis if not
 * NULL; linear momentum too if lin) relative to the exchange. */
static worst run(dWorldID w, dClothID c, dBodyID b, const double p[3], const double *axis, int lin)
{
    worst m = {0, 0, 0, 0, 0, 0, 0, energy(c, b), 0};
    int n = dClothGetVertexCount(c);
    double v0[3 * 121];
    if (!CHECK(n <= 121, "%d vertices: v0 holds 121", n)) return m;
    for (int s = 0; s < STEPS; s++) {
        double Pc0[3], Lc0[3], Pb0[3], Lb0[3], Pc1[3], Lc1[3], Pb1[3], Lb1[3], J[3], K[3], B[3], sf, st;
        cloth_momenta(c, p, Pc0, Lc0);
        body_momenta(b, p, Pb0, Lb0);
        double E0 = energy(c, b);
        memcpy(v0, cloth_velocities(dClothGetCore(c)), 3 * (size_t)n * sizeof *v0);
        if (!CHECK(dClothStep(c, H) == CLOTH_OK, "step %d: %s", s, dClothGetLastError(c))) break;
        exchanged(c, b, p, J, K, &sf, &st);
        double Pbm[3], Lbm[3]; /* the body's share of the turn, before ODE's step */
        body_momenta(b, p, Pbm, Lbm);
        euler_drift(c, v0, B);
        cloth_momenta(c, p, Pc1, Lc1);
        dWorldStep(w, H);
        body_momenta(b, p, Pb1, Lb1);
        m.rise = fmax(m.rise, (energy(c, b) - E0) / m.e0);
        double tot[3], cl[3], od[3], pt[3], fa[3], ta[3], C[3];
        cloth_air_force(dClothGetCore(c), fa);
        cloth_air_torque(dClothGetCore(c), ta);
        cross(p, fa, C);
        for (int k = 0; k < 3; k++) {
            ta[k] -= C[k]; /* about p */
            cl[k] = Lc1[k] - Lc0[k] + Lbm[k] - Lb0[k] + K[k] - H * ta[k];
            od[k] = Lb1[k] - Lbm[k] - K[k];
            tot[k] = cl[k] + od[k];
            pt[k] = Pc1[k] - Pc0[k] + Pb1[k] - Pb0[k] - H * fa[k];
        }
        memcpy(C, dClothGetStats(c)->turned, sizeof C);
        if (!(st > 0.0)) continue;
        m.total = fmax(m.total, part(tot, axis) / st);
        m.cloth = fmax(m.cloth, part(cl, axis) / st);
        m.euler = fmax(m.euler, part(B, axis) / st);
        m.turned = fmax(m.turned, part(C, axis) / st);
        m.ode = fmax(m.ode, part(od, axis) / st);
        if (lin) m.linear = fmax(m.linear, norm3(pt) / sf);
    }
    m.e1 = energy(c, b);
    return m;
}

/* scene 0 free, 1 ball joint, 2 hinge, 3 free and at rest in a wind */
static void held(int scene)
{
    static const char *const name[6] = {"free sphere",       "sphere in a ball joint",
                                        "sphere on a hinge", "free sphere in a wind",
                                        "free box",          "free box, gyroscopic term off"};
    int joint = scene >= 3 ? 0 : scene, box = scene >= 4;
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, 0);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = 11;
    d.cloth.width = d.cloth.height = 0.4;
    d.cloth.origin[0] = 0.8;
    d.cloth.origin[1] = 0.9;
    d.cloth.origin[2] = 1.2;
    d.cloth.gravity[2] = 0.0;
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, 0, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) {
        dWorldDestroy(w);
        return;
    }
    dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
    dBodyID b = sphere_holding(w, c, 0.5);
    if (box) { /* the same mass, a 20 x 10 x 5 cm box: its inertia not isotropic */
        dMass ms;
        dMassSetBoxTotal(&ms, 0.5, 0.2, 0.1, 0.05);
        dBodySetMass(b, &ms);
        dBodySetGyroscopicMode(b, scene == 4);
    }
    const dReal *pb = dBodyGetPosition(b);
    double p[3] = {pb[0], pb[1], pb[2]}, y[3] = {0, 1, 0}, thrown = scene == 0 || box;
    dBodySetLinearVel(b, thrown * 1.0, thrown * 0.5, thrown * 2.0);
    dBodySetAngularVel(b, box ? 1.0 : 0.0, joint == 2 ? 3.0 : 0.0, joint == 2 || scene == 3 ? 0.0 : 3.0);
    if (joint == 1) {
        dJointID j = dJointCreateBall(w, 0);
        dJointAttach(j, b, 0);
        dJointSetBallAnchor(j, p[0], p[1], p[2]);
    } else if (joint == 2) {
        dJointID j = dJointCreateHinge(w, 0);
        dJointAttach(j, b, 0);
        dJointSetHingeAnchor(j, p[0], p[1], p[2]);
        dJointSetHingeAxis(j, 0, 1, 0);
    }
    cloth_air air = {{3.0, 0.0, 4.0}, 1.0, 0.5};
    if (scene == 3) cloth_set_air(dClothGetCore(c), &air);
    worst m = run(w, c, b, p, joint == 2 ? y : NULL, joint == 0);
    printf("%s: change of the total angular momentum%s at most %.2e of the torque impulse exchanged; the "
           "cloth's part %.2e (turned out %.2e, backward Euler's -h sum m v x dv %.2e), ODE's %.2e; linear %.2e\n",
           name[scene], scene == 3 ? " beyond the air's" : "", m.total, m.cloth, m.turned, m.euler, m.ode, m.linear);
    printf("  energy of cloth + body %.6g J to %.6g J, largest rise in a step %.2e of the start's\n", m.e0, m.e1,
           m.rise);
    /* without the turn the cloth's part would be its size: big enough to see */
    CHECK(m.turned >= 1e-3, "%s: the turn, %.3g of the exchange, too small to test", name[scene], m.turned);
    CHECK((box || m.total <= 1e-6) && m.cloth <= 1e-6, "%s: angular momentum made: %.3g (the cloth's part %.3g)",
          name[scene], m.total, m.cloth);
    /* a sphere's inertia is isotropic: ODE's update keeps its spin exactly;
     * a box's is not, and ODE's rotation update is its own (measured) */
    if (!box)
        CHECK(m.ode <= 1e-6, "%s: ODE's update changed the sphere's angular momentum by %.3g", name[scene], m.ode);
    CHECK(m.linear <= 1e-6, "%s: linear momentum made: %.3g", name[scene], m.linear);
    CHECK(scene == 3 || m.e1 <= m.e0, "%s: energy rose from %.6g J to %.6g J", name[scene], m.e0, m.e1);
    dClothDestroy(c);
    dWorldDestroy(w);
}

int main(void)
{
    dInitODE2(0);
    for (int scene = 0; scene < 6; scene++) held(scene);
    dCloseODE();
    return check_summary();
}
