/* Cloth triangles against convex geoms (dcloth.h, step 2): each triangle near a box, capsule, cylinder
 * or convex, grown by thickness and margin, is tested with libccd's GJK + EPA, so an edge or corner
 * cannot pass between a coarse cloth's vertices (design: docs/contacts.md, "Design notes"). */
#include <ccd/ccd.h>
#include <string.h>
#include "dcloth_internal.h"
#include "body_motion.h"
#include "geom_support.h"
#include "mesh_contacts.h"
#include "polytope.h"
#include "triangle_query.h"
#include "triangles.h"

int dcloth_triangle_contacts(dClothID c, const struct dcloth_surf *sf, double h)
{
    dGeomID g = sf->g;
    if (!dClothGetTriangleTests(c, g)) return 0;
    dcloth_geom_shape gs;
    /* a convex without points handed over: vertex contacts only */
    if (!dcloth_geom_shape_of(c, g, &gs) && gs.cls != dTriMeshClass) return 0;
    double t = sf->thickness;
    ccd_t ccd, fine;
    dcloth_triangle_ccd(t, &ccd, &fine);
    convex_query q = {.shape = &gs,
                      .support = dcloth_geom_support,
                      .center = dcloth_geom_center,
                      .g = g,
                      .body = dGeomGetBody(g),
                      .surf = sf};
    q.moving = dcloth_geom_speed(g) * h > SWEEP_NEGLIGIBLE * t; /* not ODE's jitter of a body at rest */
    q.cls = gs.cls;
    dcloth_polytope box;
    if (gs.cls == dBoxClass && !dcloth_geom_list_has(&c->tri_epa, g)) {
        const dReal *o = dGeomGetPosition(g);
        double oc[3] = {o[0], o[1], o[2]};
        dcloth_polytope_box(&box, oc, dGeomGetRotation(g), gs.half);
        q.poly = &box;
    }
    if (gs.cls == dTriMeshClass) return dcloth_mesh_contacts(c, &q, h, &ccd, &fine);
    dReal aabb[6];
    dGeomGetAABB(g, aabb);
    for (int a = 0; a < 6; a++) q.aabb[a] = aabb[a];
    q.span = dcloth_diagonal(q.aabb);
    int hits = 0;
    for (int k = 0; k < c->ntri; k++) hits += dcloth_triangle_query(c, &q, k, h, &ccd, &fine);
    return hits;
}
