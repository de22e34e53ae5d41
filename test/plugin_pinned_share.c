/* Plugin: a triangle contact's lift moves the vertices the step moves, its pinned ones taking none.
 *
 * A 3 x 3 cloth (10 cm, 5 cm links, thickness T = 5 mm) lies flat and still at z = 0, no gravity,
 * its row at y = 0 pinned. A static box turned 45 degrees about x pokes its top edge, along x at
 * y = Y = 3 cm, UP = 0.5 mm through the cloth between its first two rows, 13 mm or more from every
 * vertex: the cloth is T + UP into the shell there, and the contact point weighs the pinned row
 * 1 - Y / L = 0.4.
 *
 * Asserted after one step of 1/60 s: max_penetration_all (before the step) is T + UP, and the edge is
 * at least (1 - TOL) T from the cloth, by the exact distance from the edge's point to each link
 * from the pinned row in its plane x = const (the cloth's triangles there are one plane, the next
 * row rising alike): the next row rises by (T + UP) / 0.6. Shared with the pinned row too (w_a lift /
 * sum w_b^2 over all three), the free vertices move the contact point by only the free part of
 * sum w_b^2 of the lift, and the edge ends millimetres inside the shell. TOL = 0.05: the solve's
 * tolerance, not the rule. */
#include <math.h>
#include <stdio.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define T 0.005
#define L 0.05 /* the links */
#define Y 0.03
#define UP 0.0005
#define TOL 0.05

/* distance from (py, pz) to the segment (ay, az)-(by, bz) */
static double point_segment(double py, double pz, double ay, double az, double by, double bz)
{
    double dy = by - ay, dz = bz - az, l2 = dy * dy + dz * dz;
    double s = l2 > 0.0 ? ((py - ay) * dy + (pz - az) * dz) / l2 : 0.0;
    s = s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
    double ey = ay + s * dy - py, ez = az + s * dz - pz;
    return sqrt(ey * ey + ez * ez);
}

int main(void)
{
    dInitODE2(0);
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, 0);
    dSpaceID sp = dHashSpaceCreate(0);
    const double centre[3] = {L, L, 0}, u[3] = {1, 0, 0}, v[3] = {0, 1, 0};
    dClothID c = flat_cloth(w, sp, 3, 2 * L, centre, u, v, 0.0, T);
    if (!c) return check_summary();
    dGeomID box = dCreateBox(sp, 0.3, 0.1, 0.1);
    dMatrix3 R;
    dRFromAxisAndAngle(R, 1, 0, 0, M_PI / 4);
    dGeomSetRotation(box, R);
    dGeomSetPosition(box, L, Y, UP - 0.05 * sqrt(2.0));
    const dReal *x = dClothGetPositions(c);
    for (int i = 0; i < 3; i++) dClothPinToWorld(c, i, x + 3 * i);
    int ok = CHECK(dClothStep(c, 1.0 / 60.0) == CLOTH_OK, "step: %s", dClothGetLastError(c));
    x = dClothGetPositions(c);
    double least = INFINITY;
    for (int i = 0; i < 3; i++) /* the link from pinned vertex i to the free one beyond it, in x = const */
        least = fmin(least, point_segment(Y, UP, x[3 * i + 1], x[3 * i + 2], x[3 * i + 10], x[3 * i + 11]));
    const dClothStepStats *st = dClothGetStats(c);
    printf("after one step: the edge %.4f mm from the cloth (shell %.1f mm), the next row at z = %.4f, %.4f, %.4f mm; "
           "max_penetration_all before it %.4f mm; strain %.4f\n",
           1e3 * least, 1e3 * T, 1e3 * x[11], 1e3 * x[14], 1e3 * x[17], 1e3 * st->max_penetration_all,
           st->core.max_strain);
    CHECK(ok && least >= (1.0 - TOL) * T, "the edge %.4f mm from the cloth after one step, under %.4f mm", 1e3 * least,
          1e3 * (1.0 - TOL) * T);
    for (int i = 3; i < 6; i++)
        CHECK(fabs(x[3 * i + 2] - (T + UP) * L / Y) <= TOL * T,
              "vertex %d at z = %.4f mm, not (T + UP) L / Y = %.4f mm", i, 1e3 * x[3 * i + 2], 1e3 * (T + UP) * L / Y);
    CHECK(fabs(st->max_penetration_all - (T + UP)) <= 1e-3 * T,
          "max_penetration_all %.4f mm before the step, not %.1f mm", 1e3 * st->max_penetration_all, 1e3 * (T + UP));
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
    dCloseODE();
    return check_summary();
}
