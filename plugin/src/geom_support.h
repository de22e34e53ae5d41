/* An ODE geom as libccd sees it (geom_support.c). */
#ifndef ODECLOTH_GEOM_SUPPORT_H
#define ODECLOTH_GEOM_SUPPORT_H

#include <ccd/ccd.h>
#include "dcloth_internal.h"

typedef struct dcloth_geom_shape {
    dGeomID g;
    int cls;           /* the geom's class                                   */
    double half[3];    /* box half lengths; capsule / cylinder: r, half length */
    const double *pts; /* convex: points in the geom's frame, and how many   */
    int npts;
} dcloth_geom_shape;

/* geom g's shape into s (g and cls always): 1 for a box, capsule, cylinder, or a convex whose points
 * the user handed over (dClothSetConvexPoints); 0 for the others */
int dcloth_geom_shape_of(dClothID c, dGeomID g, dcloth_geom_shape *s);
/* libccd's support and centre functions of a dcloth_geom_shape */
void dcloth_geom_support(const void *obj, const ccd_vec3_t *dir, ccd_vec3_t *out);
void dcloth_geom_center(const void *obj, ccd_vec3_t *out);

#endif
