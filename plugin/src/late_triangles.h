/* Cloth triangles a solve carried into a geom's shell unseen (late_triangles.c). */
#ifndef ODECLOTH_LATE_TRIANGLES_H
#define ODECLOTH_LATE_TRIANGLES_H

#include "odecloth/dcloth.h"

/* After a solve of the step of h seconds (from c->step.x0, v0 to the cloth's positions): each cloth
 * triangle that ended deeper than RESOLVE_DEPTH in a convex geom's shell, which the start's swept test
 * did not reach, tested again over the motion the solve found; how many vertex contacts that set. */
int dcloth_late_triangles(dClothID c, double h);

#endif
