/* Plugin: a cloth hitting a body fast. A 41x41 cloth (1 m, 0.2 kg, the plugin's defaults) starts flat
 * 2 cm above the shell of a static body, falling at 6 or 10 m/s (dropped from about 1.8 and 5 m), and
 * takes 60 steps of 1/60 s (dClothStep) onto each of five bodies over a floor: a box turned about all
 * three axes, the same box as a trimesh, a capsule lying along y, an upright cylinder and a sphere. At 10 m/s the cloth moves
 * 17 cm in a step, 33 times its 5 mm thickness. Every step must:
 *   - succeed whole or in substeps, no cloth held (DCLOTH_FAILURE_STOP);
 *   - keep every sequential link within twice the elongation limit, strain <= 2 delta;
 *   - keep every point of the cloth out of the bodies' shells: the plugin's max_penetration_all (the
 *     deepest vertex, triangle or link, before the step) within the thickness.
 * At the end the cloth lies on the body: its lowest vertex 10 cm or more above the floor.
 * Run with the argument "corner" (ctest's plugin_fast_drop_corner), the two boxes alone; without it
 * the others. The box's top corner meets a cell that the first step's contacts nearly stopped, which the
 * step then drags down onto it: the late triangle tests' case (docs/contacts.md, "How deep the
 * cloth goes").
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define N 41
#define H (1.0 / 60.0)
#define STEPS 60
#define FLOOR (-0.5)

enum { BOX, MESH_BOX, CAPSULE, CYLINDER, SPHERE, NBODY };
static const char *const names[NBODY] = {"turned box", "mesh box", "capsule", "cylinder", "sphere"};

/* Body k in sp; a mesh's data in *td (0 for the others), its arrays in v and t */
static dGeomID make_body(dSpaceID sp, int k, dReal v[24], dTriIndex t[36], dTriMeshDataID *td)
{
    dMatrix3 R;
    dGeomID g;
    const double e[3] = {0.2, 0.2, 0.2};
    *td = 0;
    switch (k) {
    case BOX:
    case MESH_BOX:
        g = box_geom(sp, e, k == MESH_BOX, v, t, td);
        dRFromEulerAngles(R, 0.3, 0.2, 0.5);
        dGeomSetRotation(g, R);
        return g;
    case CAPSULE:
        g = dCreateCapsule(sp, 0.1, 0.6);
        dRFromAxisAndAngle(R, 1, 0, 0, M_PI / 2);
        dGeomSetRotation(g, R);
        return g;
    case CYLINDER: return dCreateCylinder(sp, 0.2, 0.3);
    default: return dCreateSphere(sp, 0.25);
    }
}

/* One drop onto body k at speed v (m/s): its checks, and a line of figures */
static void drop(int k, double speed)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dReal mv[24];
    dTriIndex mt[36];
    dTriMeshDataID td;
    dGeomID body = make_body(sp, k, mv, mt, &td);
    dCreatePlane(sp, 0, 0, 1, FLOOR);
    dReal aabb[6];
    dGeomGetAABB(body, aabb);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = N;
    d.cloth.material.density = 0.2;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.5;
    d.cloth.origin[2] = aabb[5] + d.thickness + 0.02;
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "create: %s", err.message)) {
        dSpaceDestroy(sp);
        if (td) dGeomTriMeshDataDestroy(td);
        dWorldDestroy(w);
        return;
    }
    dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
    cloth *core = dClothGetCore(c);
    int n = cloth_vertex_count(core);
    double *v = calloc(3 * (size_t)n, sizeof *v);
    for (int i = 0; v && i < n; i++) v[3 * i + 2] = -speed;
    if (v) cloth_set_velocities(core, v);
    double strain = 0.0, pen = 0.0, delta = d.cloth.material.delta;
    int failed = 0, substepped = 0;
    for (int s = 0; s < STEPS && !failed; s++) {
        failed = !CHECK(dClothStep(c, H) == CLOTH_OK, "%s at %.0f m/s, step %d: %s", names[k], speed, s,
                        dClothGetLastError(c));
        const dClothStepStats *st = dClothGetStats(c);
        substepped += st->core.substeps > 1;
        strain = fmax(strain, cloth_max_strain(core));
        pen = fmax(pen, st->max_penetration_all);
    }
    const double *x = cloth_positions(core);
    double lowest = INFINITY;
    for (int i = 0; i < n; i++) lowest = fmin(lowest, x[3 * i + 2]);
    printf("%-10s at %2.0f m/s: %d failed, %d substepped, strain %.4f, deepest %.2f mm in a shell, lowest vertex "
           "%.3f m above the floor\n",
           names[k], speed, failed, substepped, strain, 1e3 * pen, lowest - FLOOR);
    CHECK(strain <= 2.0 * delta, "%s at %.0f m/s: strain %.4f past 2 delta", names[k], speed, strain);
    CHECK(pen <= d.thickness, "%s at %.0f m/s: a point %.2f mm inside a %.1f mm shell", names[k], speed, 1e3 * pen,
          1e3 * d.thickness);
    CHECK(lowest - FLOOR >= 0.1, "%s at %.0f m/s: the cloth fell off, lowest vertex %.3f m above the floor", names[k],
          speed, lowest - FLOOR);
    free(v);
    dClothDestroy(c);
    dSpaceDestroy(sp);
    if (td) dGeomTriMeshDataDestroy(td);
    dWorldDestroy(w);
}

int main(int argc, char **argv)
{
    dInitODE2(0);
    const double speeds[2] = {6.0, 10.0};
    int corner = argc > 1 && !strcmp(argv[1], "corner");
    for (int k = corner ? BOX : CAPSULE; k < (corner ? MESH_BOX + 1 : NBODY); k++)
        for (int s = 0; s < 2; s++) drop(k, speeds[s]);
    dCloseODE();
    return check_summary();
}
