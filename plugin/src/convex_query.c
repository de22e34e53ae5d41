/* A geom as the cloth triangles' tests see it (triangle_query.h): its shape, libccd's settings, an exact
 * box's polytope, its bounds over the step. */
#include <ccd/ccd.h>
#include "dcloth_internal.h"
#include "body_motion.h"
#include "convex_query.h"

int dcloth_convex_query_of(dClothID c, const struct dcloth_surf *sf, double h, convex_query *q, dcloth_geom_shape *gs,
                           dcloth_polytope *box, ccd_t *ccd, ccd_t *fine)
{
    dGeomID g = sf->g;
    if (!dClothGetTriangleTests(c, g)) return 0;
    /* a convex without points handed over: vertex contacts only */
    if (!dcloth_geom_shape_of(c, g, gs) && gs->cls != dTriMeshClass) return 0;
    double t = sf->thickness;
    dcloth_triangle_ccd(t, ccd, fine);
    *q = (convex_query){.shape = gs,
                        .support = dcloth_geom_support,
                        .center = dcloth_geom_center,
                        .g = g,
                        .body = dGeomGetBody(g),
                        .surf = sf};
    q->travel = dcloth_geom_speed(g) * h;
    q->moving = q->travel > SWEEP_NEGLIGIBLE * t; /* not ODE's jitter of a body at rest */
    q->cls = gs->cls;
    if (gs->cls == dBoxClass && !dcloth_geom_list_has(&c->tri_epa, g)) {
        const dReal *o = dGeomGetPosition(g);
        double oc[3] = {o[0], o[1], o[2]};
        dcloth_polytope_box(box, oc, dGeomGetRotation(g), gs->half);
        q->poly = box;
    }
    if (gs->cls == dTriMeshClass) return 1;
    dReal aabb[6];
    dGeomGetAABB(g, aabb);
    for (int a = 0; a < 6; a++) q->aabb[a] = aabb[a];
    q->span = dcloth_diagonal(q->aabb);
    return 1;
}
