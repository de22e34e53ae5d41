/* Continuous collision of four linearly moving points (point-triangle, edge-edge; Bridson, Fedkiw,
 * Anderson 2002): each root in [0, 1] of the coplanarity cubic is tested in order, and the hit is
 * the first within eta and approaching, so an early graze does not hide a later crossing. */
#ifndef ODECLOTH_CCD_H
#define ODECLOTH_CCD_H

typedef struct ccd_hit {
    double t;    /* time of the event in [0, 1] */
    double w[4]; /* weights: sum_k w[k] x_k is the first primitive's point
                    minus the second's (point-triangle: 1, -barycentric;
                    edge-edge: 1 - s, s, -(1 - u), -u); they sum to 0 */
    double n[3]; /* unit normal at the event, from the second primitive to
                    the first (touching there: the plane's normal, on the
                    side the first started) */
    double dist; /* distance at the event */
} ccd_hit;

/* 1 and *hit filled on a hit, else 0. eta > 0. */
int oc_ccd_point_triangle(const double *x0, const double *x1, double eta, ccd_hit *hit);
int oc_ccd_edge_edge(const double *x0, const double *x1, double eta, ccd_hit *hit);

/* The weights (as ccd_hit's) of the closest points of a point and a
 * triangle, or with edge_edge of two edges, at the four points x (12). */
void oc_ccd_pair_weights(int edge_edge, const double *x, double *w);

/* The roots in [0, 1] of c[0] + c[1] t + c[2] t^2 + c[3] t^3 into t,
 * ascending (a turning point within ftol of zero counts). Returns their
 * number (0-3), or -1 when every coefficient is within ftol of zero. */
int oc_ccd_cubic_roots(const double *c, double ftol, double *t);

#endif
