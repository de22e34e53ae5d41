/* An ODE geom as triangles (geom_triangles.c). */
#ifndef ODECLOTH_GEOM_TRIANGLES_H
#define ODECLOTH_GEOM_TRIANGLES_H

#include "dcloth_internal.h"

/* how many triangles geom g of class cls (a box or a trimesh) has */
int dcloth_geom_triangle_count(dGeomID g, int cls);
/* its nt triangles in the world frame into tb, 9 coordinates each: a box's faces two triangles each, a
 * trimesh's as ODE hands them over */
void dcloth_geom_triangles(dGeomID g, int cls, int nt, double *tb);

#endif
