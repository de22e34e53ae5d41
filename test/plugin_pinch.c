/* Plugin: a cloth squeezed between two bodies ends between them.
 *
 * The default plugin cloth (21 x 21, 1 m, cotton, thickness T = 5 mm) lies
 * flat on a static box (1.2 x 1.2 x 0.2 m, top face at z = 0; ODE's box
 * geom, or the same box as 12 triangles). A kinematic plate (0.5 x 0.5 x
 * 0.1 m, the same kind of geom as the lower box) comes down on its middle at
 * V = 0.5 m/s from 3 cm above and stops with its underside GAP = 6 mm above
 * the lower box's top: less than the cloth's two thicknesses (10 mm), so
 * every vertex under the plate has both surfaces within its thickness and
 * cannot keep a thickness from both. Stepped by dClothWorldStep at 1/60 s
 * for 1.5 s (the plate stops after 0.048 s).
 *
 * Asserted, every step: the step succeeds, and no vertex is below the lower
 * top (z >= 0) or, where it is under the plate, above the plate's underside
 * (z <= GAP): squeezed, a vertex is held between the two surfaces, not
 * pushed through one of them. At the end the vertices under the plate lie
 * midway, at GAP / 2, within TOL = 0.2 T, each surface taking half the
 * shortfall (the targets of two opposing contacts that cannot both be met
 * are averaged). They are at rest there: the velocity the plugin reports
 * for each is at most VREST = 1 mm/s (0.017 mm a step), as the plate stopped
 * a second before; what pushed a pinched vertex to midway is a displacement,
 * not a velocity (the shortfall over h, 0.12 m/s, is not left on it).
 *
 * Why: a vertex that keeps one contact only, the nearer surface's, gets a
 * target on that surface's shell inside the other's: with box geoms it ends
 * off midway, with box meshes it goes through a box and steps fail. A vertex
 * contact with a static geom that replaces a moving body's must not keep
 * that body's velocity. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define GAP 0.006
#define SPEED 0.5
#define START 0.03
#define PLATE_HALF 0.25
#define PLATE_HZ 0.05
#define LOW_HALF 0.6
#define LOW_HZ 0.1
#define TOL_FRAC 0.2
#define VREST 1e-3

typedef struct result {
    int failed_step;
    double low, high; /* least z over all vertices; greatest z of those under the plate */
    int low_step, high_step;
    double mid_err; /* at the end, largest |z - GAP/2| under the plate */
    double speed;   /* at the end, largest vertex speed under the plate */
    int under;      /* vertices under the plate at the end */
} result;

static result run(int mesh)
{
    result r = {-1, INFINITY, -INFINITY, -1, -1, 0.0, 0.0, 0};
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    static dReal lv[24], pv[24];
    static dTriIndex lt[36], pt[36];
    const double le[3] = {LOW_HALF, LOW_HALF, LOW_HZ}, pe[3] = {PLATE_HALF, PLATE_HALF, PLATE_HZ};
    dTriMeshDataID ld = 0, pd = 0;
    dGeomID low, plate;
    if (mesh) {
        box_mesh(le, lv, lt);
        box_mesh(pe, pv, pt);
        ld = dGeomTriMeshDataCreate();
        pd = dGeomTriMeshDataCreate();
        dGeomTriMeshDataBuildDouble(ld, lv, 3 * sizeof(dReal), 8, lt, 36, 3 * sizeof(dTriIndex));
        dGeomTriMeshDataBuildDouble(pd, pv, 3 * sizeof(dReal), 8, pt, 36, 3 * sizeof(dTriIndex));
        low = dCreateTriMesh(sp, ld, 0, 0, 0);
        plate = dCreateTriMesh(sp, pd, 0, 0, 0);
    } else {
        low = dCreateBox(sp, 2 * LOW_HALF, 2 * LOW_HALF, 2 * LOW_HZ);
        plate = dCreateBox(sp, 2 * PLATE_HALF, 2 * PLATE_HALF, 2 * PLATE_HZ);
    }
    dGeomSetPosition(low, 0, 0, -LOW_HZ);
    dBodyID pb = dBodyCreate(w);
    dBodySetKinematic(pb);
    dGeomSetBody(plate, pb);
    dBodySetPosition(pb, 0, 0, START + PLATE_HZ);
    dBodySetLinearVel(pb, 0, 0, -SPEED);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.origin[0] = -0.5 * d.cloth.width;
    d.cloth.origin[1] = -0.5 * d.cloth.height;
    d.cloth.origin[2] = d.thickness; /* resting on the lower top */
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) return r;
    dClothSetFailureMode(c, DCLOTH_FAILURE_STOP); /* a failed step is an error here */
    const double h = 1.0 / 60.0;
    const int steps = 90;
    int n = dClothGetVertexCount(c);
    for (int s = 0; s < steps; s++) {
        /* the plate stops where its underside is GAP above the top */
        double bottom = dBodyGetPosition(pb)[2] - PLATE_HZ;
        double v = bottom - SPEED * h > GAP ? SPEED : (bottom - GAP) / h;
        dBodySetLinearVel(pb, 0, 0, -v);
        if (dClothWorldStep(w, &c, 1, h, 0) != CLOTH_OK) {
            r.failed_step = s;
            printf("    step %d: %s\n", s, dClothGetLastError(c));
            break;
        }
        const dReal *x = dClothGetPositions(c);
        bottom = dBodyGetPosition(pb)[2] - PLATE_HZ;
        for (int i = 0; i < n; i++) {
            const dReal *p = x + 3 * i;
            if (p[2] < r.low) r.low = p[2], r.low_step = s;
            if (fabs(p[0]) < PLATE_HALF && fabs(p[1]) < PLATE_HALF && p[2] - bottom > r.high)
                r.high = p[2] - bottom, r.high_step = s;
        }
    }
    if (r.failed_step < 0) {
        const dReal *x = dClothGetPositions(c);
        const double *v = cloth_velocities(dClothGetCore(c));
        double cell = d.cloth.width / (d.cloth.cols - 1);
        for (int i = 0; i < n; i++) {
            const dReal *p = x + 3 * i;
            if (fabs(p[0]) > PLATE_HALF - cell || fabs(p[1]) > PLATE_HALF - cell) continue;
            r.under++;
            r.mid_err = fmax(r.mid_err, fabs(p[2] - 0.5 * GAP));
            r.speed = fmax(r.speed,
                           sqrt(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]));
        }
    }
    dClothDestroy(c);
    dSpaceDestroy(sp);
    if (ld) dGeomTriMeshDataDestroy(ld);
    if (pd) dGeomTriMeshDataDestroy(pd);
    dWorldDestroy(w);
    return r;
}

int main(void)
{
    dInitODE2(0);
    const double tol = TOL_FRAC * dClothDefaultDesc().thickness;
    for (int mesh = 0; mesh < 2; mesh++) {
        const char *name = mesh ? "box meshes" : "box geoms";
        result r = run(mesh);
        printf("%-10s: lowest vertex %+.2f mm (step %d), highest under the plate %+.2f mm from its underside (step "
               "%d); at the end %d vertices under it, at most %.2f mm from midway, at most %.2g m/s%s\n",
               name, 1e3 * r.low, r.low_step, 1e3 * r.high, r.high_step, r.under, 1e3 * r.mid_err, r.speed,
               r.failed_step >= 0 ? "; a step failed" : "");
        CHECK(r.failed_step < 0, "%s: step %d failed", name, r.failed_step);
        CHECK(r.low >= -1e-9, "%s: a vertex went %.2f mm below the lower top (step %d)", name, -1e3 * r.low,
              r.low_step);
        CHECK(r.high <= 1e-9, "%s: a vertex went %.2f mm above the plate's underside (step %d)", name, 1e3 * r.high,
              r.high_step);
        CHECK(r.under > 0 && r.mid_err <= tol, "%s: %d vertices under the plate, up to %.2f mm from midway (%.1f)",
              name, r.under, 1e3 * r.mid_err, 1e3 * tol);
        CHECK(r.speed <= VREST, "%s: a vertex under the plate moves at %.3g m/s at rest (%g)", name, r.speed, VREST);
    }
    dCloseODE();
    return check_summary();
}
