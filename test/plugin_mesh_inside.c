/* Plugin: a vertex behind a triangle mesh's face is pushed out, as from a box.
 *
 * A flat 21 x 21 cloth (1 m, thickness T = 5 mm, friction 0) starts DEPTH =
 * 2 mm below the top face (z = 0) of a static box 1.2 x 1.2 x 0.2 m, so every
 * vertex is inside it; the box is ODE's box geom, or the same box as 12
 * triangles, with its triangle tests on (the default) or off (vertex
 * contacts only, dClothSetTriangleTests). Stepped by dClothWorldStep at 1/60 s for 1 s under gravity.
 *
 * Asserted: every step succeeds; after the first step and at the end every
 * vertex is out of the box (z >= 0), at the end resting on its shell (z
 * within TOL = 0.2 T of T); and the mesh's end heights equal the box geom's
 * (closed form, an independent distance) within TOL.
 *
 * Why: ODE's sphere-trimesh test reports nothing for a sphere whose centre
 * is on or behind a triangle, and the plugin measures a trimesh vertex with
 * such a sphere; a vertex behind a face needs another measure. */
#include <math.h>
#include <stdio.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define DEPTH 0.002
#define HALF 0.6
#define HZ 0.1
#define TOL_FRAC 0.2

typedef struct result {
    int failed_step;
    double first_low; /* least z after the first step */
    double low, high; /* least and greatest z at the end */
    double z[441];    /* the end heights */
} result;

static void run(int mesh, int tests, result *r)
{
    r->failed_step = -1;
    r->first_low = r->low = INFINITY;
    r->high = -INFINITY;
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    static dReal v[24];
    static dTriIndex t[36];
    const double e[3] = {HALF, HALF, HZ};
    dTriMeshDataID td = 0;
    dGeomID box;
    if (mesh) {
        box_mesh(e, v, t);
        td = dGeomTriMeshDataCreate();
        dGeomTriMeshDataBuildDouble(td, v, 3 * sizeof(dReal), 8, t, 36, 3 * sizeof(dTriIndex));
        box = dCreateTriMesh(sp, td, 0, 0, 0);
    } else {
        box = dCreateBox(sp, 2 * HALF, 2 * HALF, 2 * HZ);
    }
    dGeomSetPosition(box, 0, 0, -HZ);
    const double centre[3] = {0, 0, -DEPTH}, u[3] = {1, 0, 0}, vv[3] = {0, 1, 0};
    const double T = 0.005;
    dClothID c = flat_cloth(w, sp, 21, 1.0, centre, u, vv, 0.0, T);
    if (c) dClothSetTriangleTests(c, box, tests);
    const int steps = 60;
    for (int s = 0; c && s < steps; s++) {
        if (dClothWorldStep(w, &c, 1, 1.0 / 60.0, 0) != CLOTH_OK) {
            r->failed_step = s;
            printf("    step %d: %s\n", s, dClothGetLastError(c));
            break;
        }
        const dReal *x = dClothGetPositions(c);
        for (int i = 0; s == 0 && i < dClothGetVertexCount(c); i++) r->first_low = fmin(r->first_low, x[3 * i + 2]);
    }
    if (c && r->failed_step < 0) {
        const dReal *x = dClothGetPositions(c);
        for (int i = 0; i < dClothGetVertexCount(c); i++) {
            r->z[i] = x[3 * i + 2];
            r->low = fmin(r->low, r->z[i]);
            r->high = fmax(r->high, r->z[i]);
        }
    }
    dClothDestroy(c);
    dSpaceDestroy(sp);
    if (td) dGeomTriMeshDataDestroy(td);
    dWorldDestroy(w);
}

int main(void)
{
    dInitODE2(0);
    const double T = 0.005, tol = TOL_FRAC * T;
    static result r[3];
    const char *names[3] = {"box geom", "box mesh", "box mesh, vertex contacts only"};
    for (int mode = 0; mode < 3; mode++) {
        const char *name = names[mode];
        run(mode > 0, mode < 2, &r[mode]);
        const result *q = &r[mode];
        printf("%-30s: lowest vertex after the first step %+.2f mm; at the end %+.2f to %+.2f mm%s\n", name,
               1e3 * q->first_low, 1e3 * q->low, 1e3 * q->high, q->failed_step >= 0 ? "; a step failed" : "");
        CHECK(q->failed_step < 0, "%s: step %d failed", name, q->failed_step);
        CHECK(q->first_low >= 0.0, "%s: a vertex is %.2f mm inside the box after the first step", name,
              -1e3 * q->first_low);
        CHECK(q->low >= T - tol && q->high <= T + tol, "%s: end heights %.2f to %.2f mm, not within %.1f of %.1f mm",
              name, 1e3 * q->low, 1e3 * q->high, 1e3 * tol, 1e3 * T);
    }
    for (int mode = 1; mode < 3; mode++) {
        double diff = 0.0;
        for (int i = 0; i < 441; i++) diff = fmax(diff, fabs(r[mode].z[i] - r[0].z[i]));
        printf("largest difference of end heights, %s against geom: %.3f mm\n", names[mode], 1e3 * diff);
        CHECK(diff <= tol, "%s and box geom end heights differ by %.2f mm (%.1f)", names[mode], 1e3 * diff, 1e3 * tol);
    }
    dCloseODE();
    return check_summary();
}
