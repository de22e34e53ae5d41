/* Cloth triangles against convex geoms (dcloth.h, step 2): each triangle near a box, capsule, cylinder
 * or convex, grown by thickness and margin, is tested with libccd's GJK + EPA, so an edge or corner
 * cannot pass between a coarse cloth's vertices (design: docs/contacts.md, "Design notes"). */
#include <ccd/ccd.h>
#include <string.h>
#include "dcloth_internal.h"
#include "convex_query.h"
#include "geom_support.h"
#include "mesh_contacts.h"
#include "polytope.h"
#include "triangle_query.h"
#include "triangles.h"

int dcloth_triangle_contacts(dClothID c, const struct dcloth_surf *sf, double h)
{
    dcloth_geom_shape gs;
    dcloth_polytope box;
    convex_query q;
    ccd_t ccd, fine;
    if (!dcloth_convex_query_of(c, sf, h, &q, &gs, &box, &ccd, &fine)) return 0;
    if (gs.cls == dTriMeshClass) return dcloth_mesh_contacts(c, &q, h, &ccd, &fine);
    int hits = 0;
    for (int k = 0; k < c->ntri; k++) hits += dcloth_triangle_query(c, &q, k, h, &ccd, &fine);
    return hits;
}
