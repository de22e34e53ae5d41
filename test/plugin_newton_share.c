/* Plugin: Newton's linear solves stop at their share of the step's goal
 * (solver.newton_cg_share) only while no dynamic body holds the cloth: what
 * a shorter solve leaves over goes to the bodies that hold it.
 *
 * The default plugin cloth (21x21, cotton, Newton) hangs from corner 0 of
 * row 0, and the other corner of the row is pinned either
 *   1. to a 2 kg body on a hinge to the world (coupled explicitly), or
 *   2. to the world at the same point;
 * 40 steps at h = 1/60, each run with the share at its default and at 0.
 * Asserted: with the body, both runs end bitwise alike (same positions, same
 * CG iterations, the body's position too); pinned to the world, the share
 * saves CG iterations. */
#include <math.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"

#define H (1.0 / 60.0)
#define STEPS 40
#define N 21

typedef struct run {
    double x[3 * N * N], body[3], moved; /* the body's end position, and how far it went */
    long cg;
} run;

static void hang(int with_body, double share, run *out)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.solver.nonlinear = CLOTH_NEWTON;
    d.cloth.solver.newton_cg_share = share;
    dClothID c = NULL;
    cloth_error err;
    memset(out, 0, sizeof *out);
    if (!CHECK(dClothCreate(w, 0, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) {
        dWorldDestroy(w);
        return;
    }
    const dReal *x = dClothGetPositions(c);
    dReal p0[3] = {x[0], x[1], x[2]}, p1[3] = {x[3 * (N - 1)], x[3 * (N - 1) + 1], x[3 * (N - 1) + 2]};
    dBodyID b = 0;
    CHECK(dClothPinToWorld(c, 0, p0) == CLOTH_OK, "pin: %s", dClothGetLastError(c));
    if (with_body) {
        b = dBodyCreate(w);
        dMass m;
        dMassSetSphereTotal(&m, 2.0, 0.05);
        dBodySetMass(b, &m);
        dBodySetPosition(b, p1[0], p1[1] - 0.1, p1[2]);
        dJointID j = dJointCreateHinge(w, 0);
        dJointAttach(j, b, 0);
        dJointSetHingeAnchor(j, p1[0], p1[1] - 0.2, p1[2]);
        dJointSetHingeAxis(j, 1, 0, 0);
        dReal local[3] = {0, 0.1, 0};
        CHECK(dClothPinToBody(c, N - 1, b, local) == CLOTH_OK, "pin to body: %s", dClothGetLastError(c));
    } else {
        CHECK(dClothPinToWorld(c, N - 1, p1) == CLOTH_OK, "pin: %s", dClothGetLastError(c));
    }
    for (int s = 0; s < STEPS; s++) {
        if (!CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "step %d: %s", s, dClothGetLastError(c))) break;
        out->cg += dClothGetStats(c)->cg_all;
    }
    memcpy(out->x, dClothGetPositions(c), sizeof out->x);
    if (b) {
        memcpy(out->body, dBodyGetPosition(b), sizeof out->body);
        out->moved = sqrt(pow(out->body[0] - p1[0], 2) + pow(out->body[1] - (p1[1] - 0.1), 2) +
                          pow(out->body[2] - p1[2], 2));
    }
    dClothDestroy(c);
    dWorldDestroy(w);
}

int main(void)
{
    dInitODE2(0);
    static run a, z;
    double share = dClothDefaultDesc().cloth.solver.newton_cg_share;
    hang(1, share, &a);
    hang(1, 0.0, &z);
    int same = memcmp(a.x, z.x, sizeof a.x) == 0 && memcmp(a.body, z.body, sizeof a.body) == 0;
    printf("on a hinged body (moved %.3f m): CG iterations %ld with the share %.2f, %ld without; states %s\n", a.moved,
           a.cg, share, z.cg, same ? "bitwise alike" : "DIFFERENT");
    CHECK(same && a.cg == z.cg, "a dynamic body holds the cloth, yet the share changed the run");
    CHECK(a.moved > 1e-3, "the body moved only %.3g m: the cloth does not pull it", a.moved);
    hang(0, share, &a);
    hang(0, 0.0, &z);
    printf("pinned to the world: CG iterations %ld with the share, %ld without\n", a.cg, z.cg);
    CHECK(a.cg < z.cg, "pinned to the world, the share saved no CG iteration (%ld against %ld)", a.cg, z.cg);
    dCloseODE();
    return check_summary();
}
