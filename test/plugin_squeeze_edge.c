/* Plugin: a cloth folded over a bar's edge and squeezed by a closing plate keeps out of both.
 *
 * A 5 x 5 cloth (20 cm, 5 cm links, thickness T = 5 mm, friction 0) lies level on the shell of a
 * static bar (4 x 4 cm across, its top at z = 0, its side at y = 2 cm), its first row pinned on the
 * top at y = 0, the rest beyond the side. Gravity folds it down over the edge; a kinematic plate
 * (upright, its face along x) closes at V = 0.1 m/s from y = 28 cm to SLOT beyond the bar's side
 * and stays: SLOT = 2 T (the cloth fits exactly between them) and 4 T. 4 s at 1/60 s.
 *
 * Asserted every step: the step succeeds, no vertex comes nearer the plate's face than
 * (1 - TOL) T (TOL = 0.2, as plugin_colliders), and the plugin's max_penetration_all (the deepest
 * point of the cloth in any shell, triangles included) stays under TOL T.
 *
 * Why: where the bar's edge reaches a vertex through a triangle's contact, the plate's contact
 * of that vertex is its second surface, and a vertex pinched between the plate and the bar's side
 * keeps the bar's top as its second; with one plane a vertex the contact flips between the bar and
 * the plate each step, each target driving the vertex into the other (10-21 mm into the plate). */
#include <math.h>
#include <stdio.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define T 0.005
#define V 0.1
#define TOL 0.2
#define HALF 0.02 /* the bar's and the plate's half thickness */

typedef struct result {
    int failed;
    double nearest, pen; /* least distance of a vertex to the plate's face; largest max_penetration_all */
    int nearest_step, pen_step;
} result;

static result run(double slot)
{
    result r = {-1, INFINITY, 0.0, -1, -1};
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dGeomID bar = dCreateBox(sp, 1.0, 2 * HALF, 2 * HALF);
    dGeomSetPosition(bar, 0.1, 0.0, -HALF);
    dGeomID plate = dCreateBox(sp, 1.0, 2 * HALF, 0.5);
    dBodyID pb = dBodyCreate(w);
    dBodySetKinematic(pb);
    dGeomSetBody(plate, pb);
    dBodySetPosition(pb, 0.1, 0.28 + HALF, 0.1);
    const int n = 5;
    const double centre[3] = {0.1, 0.1, T}, u[3] = {1, 0, 0}, v[3] = {0, 1, 0};
    dClothID c = flat_cloth(w, sp, n, 0.2, centre, u, v, 0.0, T);
    if (!c) return r;
    const dReal *x = dClothGetPositions(c);
    for (int i = 0; i < n; i++) dClothPinToWorld(c, i, x + 3 * i);
    const double h = 1.0 / 60.0;
    for (int s = 0; s < 240; s++) {
        double face = dBodyGetPosition(pb)[1] - HALF, stop = HALF + slot;
        dBodySetLinearVel(pb, 0, face - V * h > stop ? -V : (stop - face) / h, 0);
        if (dClothWorldStep(w, &c, 1, h, 0) != CLOTH_OK) {
            r.failed = s;
            printf("    step %d: %s\n", s, dClothGetLastError(c));
            break;
        }
        double p = dClothGetStats(c)->max_penetration_all;
        if (p > r.pen) r.pen = p, r.pen_step = s;
        x = dClothGetPositions(c);
        face = dBodyGetPosition(pb)[1] - HALF;
        for (int i = 0; i < n * n; i++)
            if (face - x[3 * i + 1] < r.nearest) r.nearest = face - x[3 * i + 1], r.nearest_step = s;
    }
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
    return r;
}

int main(void)
{
    dInitODE2(0);
    const double slots[2] = {2 * T, 4 * T};
    for (int k = 0; k < 2; k++) {
        result r = run(slots[k]);
        printf("slot %.0f mm: nearest vertex %.3f mm from the plate (step %d), max_penetration_all %.3f mm (step "
               "%d)%s\n",
               1e3 * slots[k], 1e3 * r.nearest, r.nearest_step, 1e3 * r.pen, r.pen_step,
               r.failed >= 0 ? "; a step failed" : "");
        CHECK(r.failed < 0, "slot %.0f mm: step %d failed", 1e3 * slots[k], r.failed);
        CHECK(r.nearest >= (1.0 - TOL) * T, "slot %.0f mm: a vertex %.3f mm from the plate (step %d)", 1e3 * slots[k],
              1e3 * r.nearest, r.nearest_step);
        CHECK(r.pen < TOL * T, "slot %.0f mm: max_penetration_all %.3f mm (step %d)", 1e3 * slots[k], 1e3 * r.pen,
              r.pen_step);
    }
    dCloseODE();
    return check_summary();
}
