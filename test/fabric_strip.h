/* The cantilever strip of physics_fabric_cantilever and physics_newton_rest:
 * 4 nodes wide, rows 0 and 1 to be pinned as a clamp, n cells beyond row 1
 * at the spacing dy that makes its overhang (n + 1/2) dy twice the fabric's
 * bending length; origin at 0. Returns dy; *d gets the grid (not the fabric). */
#ifndef FABRIC_STRIP_H
#define FABRIC_STRIP_H
#include "odecloth/cloth.h"
#include "odecloth/fabric.h"

static inline double fabric_strip_desc(const cloth_fabric *f, int n, cloth_desc *d)
{
    double dy = 2.0 * cloth_fabric_bending_length(f) / (n + 0.5);
    *d = cloth_default_desc();
    d->rows = n + 2;
    d->cols = 4;
    d->width = 3.0 * dy;
    d->height = (n + 1) * dy;
    d->origin[0] = d->origin[1] = d->origin[2] = 0.0;
    return dy;
}
#endif
