/* EPA's direction taken toward the nearer side of a shape it barely overlaps (epa_side.c). */
#ifndef ODECLOTH_EPA_SIDE_H
#define ODECLOTH_EPA_SIDE_H

#include <ccd/ccd.h>

/* EPA's answer (depth, dir from shape 1 toward 2) through shape 1's far side, its supports' overlap
 * along dir far past depth, is reversed where that overlaps less by more than tol, no deeper than
 * that overlap: 0; -1 if nothing overlaps along the reverse (apart). */
int dcloth_epa_near_side(ccd_support_fn s1, const void *o1, ccd_support_fn s2, const void *o2, double tol,
                         ccd_real_t *depth, ccd_vec3_t *dir);

#endif
