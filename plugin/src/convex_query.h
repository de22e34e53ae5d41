/* A geom set up for the cloth triangles' tests (convex_query.c). */
#ifndef ODECLOTH_CONVEX_QUERY_H
#define ODECLOTH_CONVEX_QUERY_H

#include <ccd/ccd.h>
#include "geom_support.h"
#include "polytope.h"
#include "triangle_query.h"

/* q set up for cloth triangles against surface s's geom over a step of h seconds, pointing into gs and box
 * (an exact box's polytope); ccd, fine: libccd's loose and tight settings. 0 where the geom has no
 * triangle tests; for a trimesh, q's per-triangle fields are left to dcloth_mesh_contacts. */
int dcloth_convex_query_of(dClothID c, const struct dcloth_surf *s, double h, convex_query *q, dcloth_geom_shape *gs,
                           dcloth_polytope *box, ccd_t *ccd, ccd_t *fine);

#endif
