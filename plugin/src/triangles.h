/* Cloth triangles against convex geoms and trimeshes (triangles.c). */
#ifndef ODECLOTH_TRIANGLES_H
#define ODECLOTH_TRIANGLES_H

#include "odecloth/dcloth.h"
#include "broadphase.h"

/* The triangle tests' (triangles.c, triangle_query.c) count of queries so far: a vertex contact
 * notes the one that set it (vcontact's query) */
struct triangle_tests {
    unsigned query;
};

/* cloth triangles against a box (by its geometry, polytope.c), capsule, cylinder, convex or trimesh (libccd) over a step of h
 * seconds with the geom's surface s, setting deeper contacts of their vertices in c->vc_new.
 * Returns the number of vertex contacts set (0 for other classes). */
int dcloth_triangle_contacts(dClothID c, const struct dcloth_surf *s, double h);

#endif
