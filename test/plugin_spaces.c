/* Plugin: what a contact's reach may meet in the user's scene (the contacts
 * judged by the body's approach, plugin/src/broadphase.c).
 *
 * 1. ODE's quadtree space cannot hand out its geoms (dSpaceGetGeom aborts
 *    there, "not yet implemented"): a cloth colliding with a quadtree
 *    space, or with a hash space holding one, steps, and settles on the box
 *    in it (no vertex below the box's top).
 * 2. A body whose velocity is NaN (or infinite) next to the cloth: the step
 *    neither gives every vertex a contact (its reach would be infinite) nor
 *    kicks the cloth; its contacts are left out, the rest of the
 *    cloth steps as without it. The control, the ball at rest, does touch
 *    the cloth (so the bad cases are near enough to matter).
 */
#include <math.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"

#define H (1.0 / 60)

/* a 21x21 cloth 5 cm over a static 0.6 m box (top at z = 0.6) in space sp */
static dClothID cloth_over_box(dWorldID w, dSpaceID sp, dSpaceID box_space)
{
    dGeomID box = dCreateBox(box_space, 0.6, 0.6, 0.6);
    dGeomSetPosition(box, 0, 0, 0.3);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.origin[2] = 0.65;
    cloth_error err;
    dClothID c = NULL;
    if (CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "create: %s", err.message))
        dClothSetFailureMode(c, DCLOTH_FAILURE_STOP); /* a failed step is an error here */
    return c;
}

static double lowest_over_box(dClothID c)
{
    const dReal *x = dClothGetPositions(c);
    double lo = INFINITY;
    for (int i = 0; i < dClothGetVertexCount(c); i++)
        if (fabs(x[3 * i]) < 0.29 && fabs(x[3 * i + 1]) < 0.29) lo = fmin(lo, x[3 * i + 2]);
    return lo;
}

static void quadtree(int nested)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dVector3 centre = {0, 0, 0}, extents = {4, 4, 4};
    dSpaceID top = nested ? dHashSpaceCreate(0) : dQuadTreeSpaceCreate(0, centre, extents, 4);
    dSpaceID inner = nested ? dQuadTreeSpaceCreate(top, centre, extents, 4) : top;
    dClothID c = cloth_over_box(w, top, inner);
    const char *name = nested ? "a quadtree in a hash space" : "a quadtree space";
    int ok = c != NULL;
    for (int k = 0; k < 120 && ok; k++)
        ok = CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "%s: step %d: %s", name, k, dClothGetLastError(c));
    if (ok) {
        double lo = lowest_over_box(c);
        CHECK(lo >= 0.6, "%s: a vertex over the box is %.4f m high, below its top (0.6 m)", name, lo);
        printf("%s: 120 steps, lowest vertex over the box %.4f m (top 0.6 m)\n", name, lo);
    }
    dClothDestroy(c);
    dSpaceDestroy(top);
    dWorldDestroy(w);
}

static void nan_body(int field)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dClothID c = cloth_over_box(w, sp, sp);
    /* a ball resting on the cloth's corner region, its velocity made bad */
    dBodyID b = dBodyCreate(w);
    dMass m;
    dMassSetSphereTotal(&m, 0.5, 0.1);
    dBodySetMass(b, &m);
    dBodySetPosition(b, 0.35, 0.35, 0.65 + 0.1 + 0.003);
    dGeomID g = dCreateSphere(sp, 0.1);
    dGeomSetBody(g, b);
    /* field 3: the control, a finite velocity (the ball does touch the cloth) */
    double bad = field == 2 ? INFINITY : NAN;
    if (field == 0) dBodySetLinearVel(b, bad, 0, 0);
    else if (field < 3) dBodySetAngularVel(b, 0, bad, 0);
    const char *name = field == 0   ? "linear velocity NaN"
                       : field == 1 ? "angular velocity NaN"
                       : field == 2 ? "angular velocity inf"
                                    : "velocity 0 (control)";
    if (c) {
        cloth_status s = dClothStep(c, H);
        const dClothStepStats *st = dClothGetStats(c);
        const dReal *v = cloth_velocities(dClothGetCore(c));
        double vmax = 0.0;
        int finite = 1;
        for (int i = 0; i < 3 * dClothGetVertexCount(c); i++) {
            finite &= isfinite(v[i]) != 0;
            vmax = fmax(vmax, fabs(v[i]));
        }
        CHECK(s == CLOTH_OK, "%s: step: %s", name, dClothGetLastError(c));
        CHECK(finite, "%s: a velocity is not finite after the step", name);
        if (field == 3) CHECK(st->contacts > 0, "%s: the ball resting on the cloth makes no contact", name);
        else CHECK(st->contacts < 100, "%s: %d contacts (the ball's reach was infinite)", name, st->contacts);
        CHECK(vmax < 1.0, "%s: a vertex at %.3g m/s after one step (kicked)", name, vmax);
        printf("%s: %d contacts, fastest vertex %.3g m/s\n", name, st->contacts, vmax);
    }
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

int main(void)
{
    dInitODE2(0);
    quadtree(0);
    quadtree(1);
    for (int f = 0; f < 4; f++) nan_body(f);
    dCloseODE();
    return check_summary();
}
