/* Plugin: a cloth between two walls, driven at one of them, keeps out of both.
 *
 * Two static boxes face each other across a slot a little wider than the
 * cloth's two thicknesses (thickness T = 5 mm): wall A's face at y = -(T +
 * EA), wall B's at y = T + EB, EA < EB, so each vertex of a cloth lying in
 * the slot's middle plane (y = 0) has A as its contact (the nearer) and B as
 * its opposite. The cloth (N x N, side L, in the xz plane, no gravity) is
 * thrown toward B at V m/s, h V = 17 mm a step, more than the room to B's
 * shell (EB). Also with the walls as kinematic bodies starting OPEN farther
 * out and closing in at VW each, while the cloth is thrown, until each has
 * 0.2 T of room left.
 *
 * Asserted, every step: the step succeeds, and the deepest point of the
 * cloth in any geom's shell (dClothStepStats.max_penetration_all) is at most
 * the thickness: the cloth goes through neither wall's face. At the end
 * every vertex lies between the two faces.
 *
 * Why: a vertex moving off its contact is left free, a candidate on that
 * contact's plane alone; the opposite surface it moves into must be held
 * within the same step (the vertex's second surface), else the step carries
 * it h V into the opposite wall (docs/contacts.md, "How deep the cloth goes"). */
#include <math.h>
#include <stdio.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define N 9
#define L 0.2
#define EA 0.0005
#define EB 0.001
#define V 1.0
#define VW 0.05
#define OPEN 0.005 /* m, the closing walls start this much farther out */
#define STEPS 30
#define WALL_HALF 0.5  /* walls' half size along x and z */
#define WALL_DEPTH 0.1 /* and their half thickness along y */

typedef struct result {
    int failed_step;
    double deepest; /* m, the largest max_penetration_all over the steps */
    int deepest_step;
    double outside; /* m, the farthest a vertex ends beyond a wall's face (0: none) */
} result;

static result run(int moving)
{
    result r = {-1, 0.0, -1, 0.0};
    const double T = dClothDefaultDesc().thickness;
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, 0);
    dSpaceID sp = dHashSpaceCreate(0);
    dGeomID wall[2];
    dBodyID body[2] = {0, 0};
    const double face[2] = {-(T + EA + moving * OPEN), T + EB + moving * OPEN};
    for (int k = 0; k < 2; k++) {
        wall[k] = dCreateBox(sp, 2 * WALL_HALF, 2 * WALL_DEPTH, 2 * WALL_HALF);
        double y = face[k] + (k ? WALL_DEPTH : -WALL_DEPTH);
        if (moving) {
            body[k] = dBodyCreate(w);
            dBodySetKinematic(body[k]);
            dGeomSetBody(wall[k], body[k]);
            dBodySetPosition(body[k], 0, y, 0);
        } else {
            dGeomSetPosition(wall[k], 0, y, 0);
        }
    }
    const double centre[3] = {0, 0, 0}, u[3] = {1, 0, 0}, vv[3] = {0, 0, 1};
    dClothID c = flat_cloth(w, sp, N, L, centre, u, vv, 0.0, T);
    if (!c) return r;
    const double g0[3] = {0, 0, 0};
    cloth_set_gravity(dClothGetCore(c), g0);
    int n = dClothGetVertexCount(c);
    double vel[3 * N * N];
    for (int i = 0; i < n; i++) vel[3 * i] = 0, vel[3 * i + 1] = V, vel[3 * i + 2] = 0;
    cloth_set_velocities(dClothGetCore(c), vel);
    const double h = 1.0 / 60.0;
    double yface[2] = {face[0], face[1]};
    for (int s = 0; s < STEPS; s++) {
        /* moving: each wall closes in at VW while it leaves more than 0.2 T of room */
        for (int k = 0; k < 2 && moving; k++) {
            double room = fabs(yface[k]) - T, vy = room - VW * h > 0.2 * T ? VW : 0.0;
            dBodySetLinearVel(body[k], 0, k ? -vy : vy, 0);
            yface[k] += (k ? -vy : vy) * h;
        }
        if (dClothWorldStep(w, &c, 1, h, 0) != CLOTH_OK) {
            r.failed_step = s;
            printf("    step %d: %s\n", s, dClothGetLastError(c));
            break;
        }
        double d = dClothGetStats(c)->max_penetration_all;
        if (d > r.deepest) r.deepest = d, r.deepest_step = s;
    }
    const dReal *x = dClothGetPositions(c);
    for (int i = 0; i < n && r.failed_step < 0; i++) {
        r.outside = fmax(r.outside, x[3 * i + 1] - yface[1]);
        r.outside = fmax(r.outside, yface[0] - x[3 * i + 1]);
    }
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
    return r;
}

int main(void)
{
    dInitODE2(0);
    const double T = dClothDefaultDesc().thickness;
    for (int moving = 0; moving < 2; moving++) {
        const char *name = moving ? "closing walls" : "static walls";
        result r = run(moving);
        printf("%-13s: deepest point %.2f mm in a %.1f mm shell (step %d); at the end %.2f mm beyond a face%s\n", name,
               1e3 * r.deepest, 1e3 * T, r.deepest_step, 1e3 * r.outside, r.failed_step >= 0 ? "; a step failed" : "");
        CHECK(r.failed_step < 0, "%s: step %d failed", name, r.failed_step);
        CHECK(r.deepest <= T, "%s: a point of the cloth %.2f mm into a %.1f mm shell (step %d)", name, 1e3 * r.deepest,
              1e3 * T, r.deepest_step);
        CHECK(r.outside <= 0.0, "%s: a vertex ends %.2f mm beyond a wall's face", name, 1e3 * r.outside);
    }
    dCloseODE();
    return check_summary();
}
