/* Plugin: momentum is exchanged between the cloth and ODE bodies, never
 * created (plugin/src/reactions.c). After dClothStep and before dWorldStep a
 * body's force and torque accumulators hold what the cloth gave it; the
 * cloth got its pin and contact forces (dClothGetPinForce,
 * dClothGetContactForce) at its vertices' end-of-step positions, where the
 * implicit step evaluates them. So, with f_i those forces, x_i the vertices
 * and F_b, T_b a body's accumulators at its centre c_b, every step must give
 *   sum_i f_i + sum_b F_b = 0,  sum_i x_i x f_i - C + sum_b (c_b x F_b + T_b) = 0,
 * C the couple of the angular momentum no force explains that the moving
 * bodies got (dClothStepStats; each scene has one moving body)
 * (about the world's origin, 1 m or more from every point), asserted to
 * 1e-6 of sum_i |f_i| (in N m for the second, on a 1 m scale). Scenes, an
 * 11x11 cotton cloth 0.4 m square, h = 1/60 s, 60 steps:
 *   1. zero gravity: a free 0.5 kg sphere holds the cloth by two vertices,
 *      thrown at (1, 0.5, 2) m/s spinning at 3 rad/s about z;
 *   2. the same sphere held at its centre by a ball joint to the world;
 *   3. the same sphere on a hinge along y through its centre;
 *   4. gravity on: the cloth dropped flat and centred onto a 2 kg box
 *      resting on a plane, with friction;
 *   5. zero gravity, a wind (cloth_set_air): the free sphere of 1 holding
 *      the cloth at rest; cloth + sphere gain, each step, the air's impulse
 *      h cloth_air_force and nothing else (to 1e-6 of it).
 * The box's largest torque about its vertical axis in 4 is printed, not
 * asserted, off the origin: positions there are not mirror-symmetric to the
 * bit. Centred at the origin, by Newton to 1e-9 m/s, with the floor's contact
 * joints made before the cloth's step (as in dClothWorldStep), the box is held
 * and takes no momentum turn: its torque about z is zero up to rounding,
 * asserted each step s within (s + 1) kappa eps sum_i |x_i| |f_i| (largest so
 * far), eps the machine's, kappa a Gershgorin bound of the step matrix's
 * condition number (symmetric_bound). With the floor's joints made after the
 * cloth's step the box is free to the plugin and takes the turn's share of
 * the angular momentum the solves leave: asserted within 1e-9 (vertex
 * contacts) and 1e-6 (triangle tests) of the cloth's weight times the box's
 * size, and at rounding with block-Jacobi CG, whose iterates are mirror
 * images as the scene is (about the plane x = y, the grid's diagonals too).
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define H (1.0 / 60.0)
#define STEPS 60

/* The exchange's imbalance this step: |force sum| and |torque sum| over
 * sum |f_i|, the forces of pins and of contacts with b's geoms (the plane,
 * static, takes its own), b the one body. */
static void imbalance(dClothID c, dBodyID b, double *ef, double *et, double *scale)
{
    const dReal *x = dClothGetPositions(c);
    double F[3] = {0, 0, 0}, T[3] = {0, 0, 0}, s = 0.0;
    for (int i = 0; i < dClothGetVertexCount(c); i++) {
        dReal fp[3], fc[3];
        dGeomID g = 0;
        dClothGetPinForce(c, i, fp);
        dClothGetContactForce(c, i, fc);
        dClothGetVertexContact(c, i, &g, NULL, NULL);
        if (!g || dGeomGetBody(g) != b) fc[0] = fc[1] = fc[2] = 0.0;
        double f[3] = {fp[0] + fc[0], fp[1] + fc[1], fp[2] + fc[2]}, t[3];
        cross(x + 3 * i, f, t);
        for (int r = 0; r < 3; r++) {
            F[r] += f[r];
            T[r] += t[r];
        }
        s += norm3(f);
    }
    /* b, the only moving body, got all of the couple (in its accumulator) */
    const double *couple = dClothGetStats(c)->couple;
    for (int r = 0; r < 3; r++) T[r] -= couple[r];
    const dReal *Fb = dBodyGetForce(b), *Tb = dBodyGetTorque(b), *cb = dBodyGetPosition(b);
    double fb[3] = {Fb[0], Fb[1], Fb[2]}, pb[3] = {cb[0], cb[1], cb[2]}, t[3];
    cross(pb, fb, t);
    for (int r = 0; r < 3; r++) {
        F[r] += fb[r];
        T[r] += t[r] + Tb[r];
    }
    *ef = norm3(F);
    *et = norm3(T);
    *scale = s;
}

/* an 11x11 cloth 0.4 m square centred on (cx, cy) at height z; newton: by
 * Newton's method to 1e-9 m/s */
static dClothID make_cloth(dWorldID w, dSpaceID sp, double cx, double cy, double z, int gravity, int newton)
{
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = 11;
    d.cloth.width = d.cloth.height = 0.4;
    d.cloth.origin[0] = cx - 0.2;
    d.cloth.origin[1] = cy - 0.2;
    d.cloth.origin[2] = z;
    d.cloth.solver.cg_tolerance = 1e-10;
    if (newton) {
        d.cloth.solver.nonlinear = CLOTH_NEWTON;
        d.cloth.solver.newton_tolerance = 1e-9;
        d.cloth.solver.newton_cg_tolerance = 1e-10;
    }
    if (!gravity) d.cloth.gravity[2] = 0.0;
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) return NULL;
    dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
    return c;
}

/* Steps the scene, asserting the exchange every step; returns the worst
 * relative imbalances of force and torque. */
static void run(const char *name, dWorldID w, dSpaceID sp, dClothID c, dBodyID b, double *wf, double *wt)
{
    dJointGroupID contacts = dJointGroupCreate(0);
    *wf = *wt = 0.0;
    int exchanged = 0;
    for (int s = 0; s < STEPS; s++) {
        if (!CHECK(dClothStep(c, H) == CLOTH_OK, "%s, step %d: %s", name, s, dClothGetLastError(c))) break;
        double ef, et, scale;
        imbalance(c, b, &ef, &et, &scale);
        if (scale > 0.0) {
            exchanged++;
            *wf = fmax(*wf, ef / scale);
            *wt = fmax(*wt, et / scale);
        }
        (void)sp;
        dWorldStep(w, H);
        dJointGroupEmpty(contacts);
    }
    dJointGroupDestroy(contacts);
    printf("%s: %d steps exchanged force; worst imbalance of force %.2e, of torque %.2e (of sum |f_i|)\n", name,
           exchanged, *wf, *wt);
    CHECK(exchanged > STEPS / 2, "%s: the cloth and the body exchanged force in %d steps only", name, exchanged);
    CHECK(*wf <= 1e-6 && *wt <= 1e-6, "%s: momentum created: force %.3g, torque %.3g of sum |f_i|", name, *wf, *wt);
}

/* In zero gravity, make_cloth's cloth held by a free 0.5 kg sphere at two
 * vertices into *b (NULL if the cloth could not be made). */
static dClothID held_by_sphere(dWorldID w, dBodyID *b)
{
    dWorldSetGravity(w, 0, 0, 0);
    dClothID c = make_cloth(w, 0, 1.0, 1.1, 1.2, 0, 0);
    if (c) *b = sphere_holding(w, c, 0.5);
    return c;
}

/* 1-3: the sphere holding the cloth by two vertices; joint 0 none, 1 ball,
 * 2 hinge */
static void held(int joint)
{
    static const char *const name[3] = {"free sphere", "sphere in a ball joint", "sphere on a hinge"};
    dWorldID w = dWorldCreate();
    dBodyID b = 0;
    dClothID c = held_by_sphere(w, &b);
    if (!c) {
        dWorldDestroy(w);
        return;
    }
    const dReal *p0 = dBodyGetPosition(b);
    dBodySetLinearVel(b, joint ? 0.0 : 1.0, joint ? 0.0 : 0.5, joint ? 0.0 : 2.0);
    dBodySetAngularVel(b, 0, joint == 2 ? 3.0 : 0.0, joint == 2 ? 0.0 : 3.0);
    dJointID j = 0;
    if (joint == 1) {
        j = dJointCreateBall(w, 0);
        dJointAttach(j, b, 0);
        dJointSetBallAnchor(j, p0[0], p0[1], p0[2]);
    } else if (joint == 2) {
        j = dJointCreateHinge(w, 0);
        dJointAttach(j, b, 0);
        dJointSetHingeAnchor(j, p0[0], p0[1], p0[2]);
        dJointSetHingeAxis(j, 0, 1, 0);
    }
    double wf, wt;
    run(name[joint], w, 0, c, b, &wf, &wt);
    dClothDestroy(c);
    dWorldDestroy(w);
}

/* kappa eps for cloth c's step of H: the step matrix I + M^-1 (h^2 K + h C) has eigenvalues in [1, 1 + its
 * largest Gershgorin row sum], each vertex at most 8 links of each kind, a stretched sequential link k_t (1 +
 * k_delta); m the least vertex mass */
static double symmetric_bound(dClothID c)
{
    const cloth *core = dClothGetCore(c);
    cloth_material m = cloth_get_desc(core).material;
    const double *mass = cloth_masses(core);
    double mmin = INFINITY;
    for (int i = 0; i < dClothGetVertexCount(c); i++) mmin = fmin(mmin, mass[i]);
    double k = m.k_t * (1.0 + m.k_delta) + m.k_c + m.k_b + m.k_s, damp = m.c_t + m.c_b;
    return (1.0 + 2.0 * 8.0 * (H * H * k + H * damp) / mmin) * DBL_EPSILON;
}

/* sum_i |x_i| |f_i| over cloth c's contact forces f_i at its vertices x_i */
static double arm_force_sum(dClothID c)
{
    const dReal *x = dClothGetPositions(c);
    double sum = 0.0;
    for (int i = 0; i < dClothGetVertexCount(c); i++) {
        dReal fc[3];
        dClothGetContactForce(c, i, fc);
        double f[3] = {fc[0], fc[1], fc[2]}, r[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
        sum += norm3(r) * norm3(f);
    }
    return sum;
}

/* The box rests on the plane: a contact joint at each corner, in the
 * contact group (emptied after the world's step). */
static void rest_on_plane(dWorldID w, dJointGroupID contacts, dGeomID box, dGeomID plane)
{
    dContactGeom cg[8];
    int n = dCollide(box, plane, 8, cg, sizeof cg[0]);
    for (int k = 0; k < n; k++) {
        dContact ct;
        memset(&ct, 0, sizeof ct);
        ct.surface.mode = 0;
        ct.surface.mu = 0.8;
        ct.geom = cg[k];
        dJointAttach(dJointCreateContact(w, contacts, &ct), dGeomGetBody(box), 0);
    }
}

/* Scene 4, the box at (cx, cy): newton, by Newton's method (2: with
 * block-Jacobi CG); tri, the box's triangle tests on; first, the floor's
 * contacts made before the cloth's step. Returns the box's largest torque about z. */
static double landing(double cx, double cy, int newton, int tri, int first)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dGeomID plane = dCreatePlane(sp, 0, 0, 1, 0);
    const double side = 0.2;
    dBodyID b = dBodyCreate(w);
    dMass m;
    dMassSetBoxTotal(&m, 2.0, side, side, side);
    dBodySetMass(b, &m);
    dGeomID g = dCreateBox(sp, side, side, side);
    dGeomSetBody(g, b);
    dBodySetPosition(b, cx, cy, side / 2);
    dClothID c = make_cloth(w, sp, cx, cy, side + 0.02, 1, newton);
    if (!c) {
        dSpaceDestroy(sp);
        dWorldDestroy(w);
        return NAN;
    }
    dClothSetTriangleTests(c, g, tri);
    dClothSetEdgeTests(c, g, tri); /* vertex contacts only, or triangle tests */
    if (newton == 2) {             /* the box's contacts decided by its geometry, CG by block Jacobi */
        CHECK(dClothSetExactTriangleTests(c, g, 1) == CLOTH_OK, "exact triangle tests: %s", dClothGetLastError(c));
        cloth_solver sv = cloth_get_desc(dClothGetCore(c)).solver;
        sv.precond = CLOTH_PRECOND_BLOCK_JACOBI;
        CHECK(cloth_set_solver(dClothGetCore(c), &sv) == CLOTH_OK, "cloth_set_solver");
    }
    dJointGroupID contacts = dJointGroupCreate(0);
    double worst_tz = 0.0, wf = 0.0, wt = 0.0, weight = 0.2 * 0.16 * 9.81, armf = 0.0, worst_rel = 0.0;
    double keps = symmetric_bound(c);
    int touched = 0;
    for (int s = 0; s < STEPS; s++) {
        if (first) rest_on_plane(w, contacts, g, plane);
        if (!CHECK(dClothStep(c, H) == CLOTH_OK, "landing, step %d: %s", s, dClothGetLastError(c))) break;
        double ef, et, scale;
        imbalance(c, b, &ef, &et, &scale);
        if (scale > 0.0) {
            touched++;
            wf = fmax(wf, ef / scale);
            wt = fmax(wt, et / scale);
        }
        worst_tz = fmax(worst_tz, fabs(dBodyGetTorque(b)[2]));
        armf = fmax(armf, arm_force_sum(c));
        if (armf > 0.0) worst_rel = fmax(worst_rel, fabs(dBodyGetTorque(b)[2]) / ((s + 1) * keps * armf));
        if (!first) rest_on_plane(w, contacts, g, plane);
        dWorldStep(w, H);
        dJointGroupEmpty(contacts);
    }
    printf("landing on a box at (%g, %g)%s%s: %d steps in contact; worst imbalance of force %.2e, of torque "
           "%.2e; box torque about z at most %.3g N m (cloth weight x box size %.3g N m)\n",
           cx, cy,
           newton == 2 ? ", by Newton with block-Jacobi CG"
           : newton    ? ", by Newton"
                       : "",
           tri ? "" : ", vertex contacts only", touched, wf, wt, worst_tz, weight * side);
    CHECK(touched > 10, "landing: the cloth touched the box in %d steps only", touched);
    /* mirror-symmetric: at the origin, and iterates mirror images (block
     * Jacobi) or the box held by the floor (no momentum turn on it) */
    if (cx == 0.0 && cy == 0.0 && newton && (newton == 2 || first)) {
        printf("  torque about z at most %.3g of its rounding bound (s + 1) kappa eps sum |x_i| |f_i|, kappa eps "
               "%.3g\n",
               worst_rel, keps);
        CHECK(worst_rel <= 1.0, "symmetric landing: the box's torque about z reached %.3g of its rounding bound",
              worst_rel);
    }
    CHECK(wf <= 1e-6 && wt <= 1e-6, "landing: momentum created: force %.3g, torque %.3g of sum |f_i|", wf, wt);
    dJointGroupDestroy(contacts);
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
    return worst_tz / (weight * side);
}

/* Linear momentum of the cloth and body b */
static void momentum(dClothID c, dBodyID b, double P[3])
{
    const cloth *core = dClothGetCore(c);
    const double *v = cloth_velocities(core), *m = cloth_masses(core);
    const dReal *vb = dBodyGetLinearVel(b);
    dMass mb;
    dBodyGetMass(b, &mb);
    for (int r = 0; r < 3; r++) P[r] = mb.mass * vb[r];
    for (int i = 0; i < dClothGetVertexCount(c); i++)
        for (int r = 0; r < 3; r++) P[r] += m[i] * v[3 * i + r];
}

/* 5: the air's push on a cloth held by a free body moves both */
static void windy(void)
{
    dWorldID w = dWorldCreate();
    dBodyID b = 0;
    dClothID c = held_by_sphere(w, &b);
    if (!c) {
        dWorldDestroy(w);
        return;
    }
    cloth_air air = {{3.0, 0.0, 4.0}, 1.0, 0.5};
    CHECK(cloth_set_air(dClothGetCore(c), &air) == CLOTH_OK, "cloth_set_air");
    double worst = 0.0, total = 0.0, P0[3], P1[3];
    for (int s = 0; s < STEPS; s++) {
        momentum(c, b, P0);
        if (!CHECK(dClothStep(c, H) == CLOTH_OK, "wind, step %d: %s", s, dClothGetLastError(c))) break;
        dWorldStep(w, H);
        double fa[3], e[3];
        cloth_air_force(dClothGetCore(c), fa);
        momentum(c, b, P1);
        for (int r = 0; r < 3; r++) e[r] = P1[r] - P0[r] - H * fa[r];
        worst = fmax(worst, norm3(e) / (H * norm3(fa)));
        total += H * norm3(fa);
    }
    const dReal *vb = dBodyGetLinearVel(b);
    printf("wind on a cloth held by a free sphere: air impulse %.3g N s over the run; worst momentum error %.2e "
           "of the step's air impulse; sphere moving at (%.3g, %.3g, %.3g) m/s\n",
           total, worst, vb[0], vb[1], vb[2]);
    CHECK(total > 1e-2, "wind: the air's impulse %.3g N s is too small to test", total);
    CHECK(worst <= 1e-6, "wind: cloth + sphere gained %.3g of the air's impulse beyond it", worst);
    CHECK(vb[0] > 0.0 && vb[2] > 0.0, "wind: the sphere is not carried downwind");
    dClothDestroy(c);
    dWorldDestroy(w);
}

int main(void)
{
    dInitODE2(0);
    for (int joint = 0; joint < 3; joint++) held(joint);
    landing(1.0, 1.1, 0, 1, 1);
    /* at the origin (mirror-symmetric positions), by Newton, the floor's
     * contacts made before the cloth's step (as dClothWorldStep has them):
     * the box is held, and its torque about its axis stays at rounding */
    landing(0.0, 0.0, 1, 0, 1);
    double held = landing(0.0, 0.0, 1, 1, 1);
    landing(0.0, 0.0, 2, 1, 1);
    /* the floor's contacts made after the cloth's step: to the plugin the
     * box is free and takes the momentum turn's share, at the solves' tolerance */
    double tz = landing(0.0, 0.0, 1, 0, 0);
    CHECK(tz <= 1e-9, "symmetric landing: the box's torque about z reached %.3g of weight x size", tz);
    tz = landing(0.0, 0.0, 1, 1, 0);
    CHECK(tz <= 1e-6, "symmetric landing, triangle tests: the box's torque about z reached %.3g of weight x size", tz);
    CHECK(held <= 1e-2 * tz, "symmetric landing: the held box's torque %.3g, the free one's %.3g (weight x size)", held,
          tz);
    /* and with block-Jacobi CG, whose iterates are mirror images: at rounding */
    landing(0.0, 0.0, 2, 1, 0);
    windy();
    dCloseODE();
    return check_summary();
}
