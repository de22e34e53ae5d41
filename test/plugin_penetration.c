/* Plugin: the stats' max_penetration_all is the deepest point of the cloth inside a geom's shell,
 * between the vertices too.
 *
 * A coarse cloth (3 x 3 vertices, 1 m, thickness T = 5 mm) lies flat and still at z = 0, no gravity.
 * One static geom at a time presses a feature into the middle of a cell, E = 0.4 T above the
 * cloth's plane, every vertex at least 0.1 m from it:
 *   - a box (0.3 x 0.1 x 0.1 m) turned 45 degrees about x, its lowest edge along x at z = E, by its
 *     geometry, (dClothSetExactTriangleTests off) by EPA, and as 12 triangles (the mesh's prisms);
 *   - a capsule and a cylinder (radius 5 cm) lying along x, their lowest line at z = E;
 *   - a cube (0.1 m) turned so that one corner points straight down, at z = E;
 *   - the box, geom and mesh, turned about y instead, its lowest edge along y over the link between
 *     two vertices, triangle tests off: the links' tests against its edges.
 * Asserted after one step: max_penetration_all = T - E, the closed form (the cloth's plane at z = 0 is
 * its deepest point; the vertices themselves are far outside every shell), within 1e-3 T for the
 * exact box's separating axes and 1e-2 T for EPA and the rest (EPA's tolerance is 1e-6 T, its grown
 * shapes' rounding is the margin). The mesh box lowered to z = -E, its edge through the link: at
 * least T (a point of the link on the surface) and at most T + E, the link's deepest point. The
 * same geoms raised to z = 1.5 T (outside the shell) give 0. */
#include <math.h>
#include <stdio.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define T 0.005
#define E (0.4 * T)
#define OUT (1.5 * T)

enum { BOX, BOX_EPA, CAPSULE, CYLINDER, CORNER, MESH, LINKS, LINKS_MESH, THROUGH, NSCENE };
static const char *const names[NSCENE] = {"box edge (exact)",
                                          "box edge (EPA)",
                                          "capsule",
                                          "cylinder",
                                          "cube corner",
                                          "box mesh edge (prisms)",
                                          "box edge over a link (link tests)",
                                          "box mesh edge over a link (link tests)",
                                          "box mesh through a link (link tests)"};
static dReal mesh_v[24];
static dTriIndex mesh_t[36];

/* The scene's geom in sp (a mesh's data in *td, else 0), its lowest point at height z over (x, y) */
static dGeomID scene_geom(dSpaceID sp, int scene, double x, double y, double z, dTriMeshDataID *td)
{
    dMatrix3 R;
    dGeomID g;
    double below; /* how far below its centre that point is */
    const double r = 0.05;
    *td = 0;
    if (scene == MESH) {
        const double e[3] = {0.15, 0.05, 0.05};
        g = box_geom(sp, e, 1, mesh_v, mesh_t, td);
        dRFromAxisAndAngle(R, 1, 0, 0, M_PI / 4);
        below = 0.05 * sqrt(2.0);
    } else if (scene == LINKS_MESH || scene == THROUGH) {
        const double e[3] = {0.05, 0.15, 0.05};
        g = box_geom(sp, e, 1, mesh_v, mesh_t, td);
        dRFromAxisAndAngle(R, 0, 1, 0, M_PI / 4);
        below = 0.05 * sqrt(2.0);
    } else if (scene == CAPSULE || scene == CYLINDER) {
        g = scene == CAPSULE ? dCreateCapsule(sp, r, 0.3) : dCreateCylinder(sp, r, 0.3);
        dRFromAxisAndAngle(R, 0, 1, 0, M_PI / 2); /* its axis along x */
        below = r;
    } else if (scene == CORNER) {
        g = dCreateBox(sp, 0.1, 0.1, 0.1);
        /* the corner (1, 1, 1) turned onto -z: about the axis (1, 1, 1) x (0, 0, -1) */
        double ax[3] = {-1, 1, 0}, ang = M_PI - acos(1.0 / sqrt(3.0));
        dRFromAxisAndAngle(R, ax[0], ax[1], ax[2], ang);
        below = 0.05 * sqrt(3.0);
    } else if (scene == LINKS) {
        g = dCreateBox(sp, 0.1, 0.3, 0.1);
        dRFromAxisAndAngle(R, 0, 1, 0, M_PI / 4);
        below = 0.05 * sqrt(2.0);
    } else {
        g = dCreateBox(sp, 0.3, 0.1, 0.1);
        dRFromAxisAndAngle(R, 1, 0, 0, M_PI / 4);
        below = 0.05 * sqrt(2.0);
    }
    dGeomSetRotation(g, R);
    dGeomSetPosition(g, x, y, z + below);
    return g;
}

/* max_penetration_all after one step with the scene's geom's lowest point at height z */
static double figure(int scene, double z)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, 0);
    dSpaceID sp = dHashSpaceCreate(0);
    const double centre[3] = {0.5, 0.5, 0}, u[3] = {1, 0, 0}, v[3] = {0, 1, 0};
    dClothID c = flat_cloth(w, sp, 3, 1.0, centre, u, v, 0.0, T);
    double pen = NAN;
    dTriMeshDataID td = 0;
    if (c) {
        /* the middle of the cell [0, 0.5]^2, or over the link x = 0.5 between y = 0 and 0.5 */
        int links = scene == LINKS || scene == LINKS_MESH || scene == THROUGH;
        dGeomID g = scene_geom(sp, scene, links ? 0.5 : 0.25, 0.25, z, &td);
        if (scene == BOX_EPA) dClothSetExactTriangleTests(c, g, 0);
        if (links) dClothSetTriangleTests(c, g, 0);
        if (CHECK(dClothStep(c, 1.0 / 60.0) == CLOTH_OK, "%s: step: %s", names[scene], dClothGetLastError(c)))
            pen = dClothGetStats(c)->max_penetration_all;
        dClothDestroy(c);
    }
    dSpaceDestroy(sp);
    if (td) dGeomTriMeshDataDestroy(td);
    dWorldDestroy(w);
    return pen;
}

int main(void)
{
    dInitODE2(0);
    for (int s = 0; s < NSCENE; s++) {
        double in = figure(s, s == THROUGH ? -E : E), out = figure(s, OUT);
        double tol = (s == BOX ? 1e-3 : 1e-2) * T;
        printf("%-40s: max_penetration_all %.6f mm pressed in, %.6f mm clear of the shell\n", names[s], 1e3 * in,
               1e3 * out);
        if (s == THROUGH)
            CHECK(in >= T && in <= T + E, "%s: max_penetration_all %.6f mm, outside [%.1f, %.1f] mm", names[s],
                  1e3 * in, 1e3 * T, 1e3 * (T + E));
        else
            CHECK(fabs(in - (T - E)) <= tol, "%s: max_penetration_all %.6f mm, closed form %.6f mm (tolerance %.3f)",
                  names[s], 1e3 * in, 1e3 * (T - E), 1e3 * tol);
        CHECK(out == 0.0, "%s: max_penetration_all %.6f mm with the geom outside the shell", names[s], 1e3 * out);
    }
    dCloseODE();
    return check_summary();
}
