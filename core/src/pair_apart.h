/* Cheap proofs that a vertex-triangle or edge-edge pair is farther apart than D: an axis separating
 * their projections by more than D (with a rounding margin); 1 found, 0 proves nothing. The _gap forms
 * return the widest separation found (a distance lower bound), stopping at the first >= `enough`. */
#ifndef ODECLOTH_PAIR_APART_H
#define ODECLOTH_PAIR_APART_H

#include "tuning.h"

/* Triangle (a, b, c)'s frame into f (12): its unit normal, then the unit
 * normals of its sides (ab, bc, ca) in its plane, outward; zeros when it is
 * degenerate (its tests then prove nothing). */
void oc_pair_apart_frame(const double *a, const double *b, const double *c, double *f);

/* Point p beyond D of triangle (a, b, c), f its frame: off its plane or
 * outside one of its sides. */
int oc_pair_apart_point_triangle(const double *p, const double *a, const double *b, const double *c, const double *f,
                                 double D);
double oc_pair_apart_point_triangle_gap(const double *p, const double *a, const double *b, const double *c,
                                        const double *f, double enough);

/* Segment ab beyond D of segment cd: along the normal of both, or along the
 * normal to one from the other's first end. */
int oc_pair_apart_edges(const double *a, const double *b, const double *c, const double *d, double D);
double oc_pair_apart_edges_gap(const double *a, const double *b, const double *c, const double *d, double enough);

#endif
