/* EPA's direction taken toward the nearer side of a shape it barely overlaps (epa_side.c). */
#ifndef ODECLOTH_EPA_SIDE_H
#define ODECLOTH_EPA_SIDE_H

#include <ccd/ccd.h>

/* Where the origin lies within rounding of the Minkowski difference's face, EPA's direction can point
 * through the far side of shape 1 (the overlap along it the shape's whole extent). Given EPA's answer
 * (depth, dir from shape 1 toward shape 2), the reversed direction, of less overlap by the supports by
 * more than tol, is taken, no deeper than that overlap: 0; -1 if nothing overlaps along it (apart). */
int dcloth_epa_near_side(ccd_support_fn s1, const void *o1, ccd_support_fn s2, const void *o2, double tol,
                         ccd_real_t *depth, ccd_vec3_t *dir);

#endif
