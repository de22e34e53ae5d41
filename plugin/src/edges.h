/* The cloth's links against the edges and corners of boxes, trimeshes and
 * convexes (edges.c): the contacts that keep a body's edge from passing
 * between two vertices where no triangle test runs. */
#ifndef ODECLOTH_EDGES_H
#define ODECLOTH_EDGES_H

#include <ccd/ccd.h>
#include "odecloth/dcloth.h"
#include "broadphase.h"

struct dcloth_geom_shape; /* geom_support.h */

/* A link [a, b] grown by r, libccd's second shape against a geom */
typedef struct dcloth_seg_shape {
    const double *a, *b;
    double r;
} dcloth_seg_shape;
/* libccd set up for a geom (obj1, a dcloth_geom_shape) against a dcloth_seg_shape at thickness t */
void dcloth_link_ccd(double t, ccd_t *ccd);
/* The distance from convex cv to link [a, b] if under r (0 or less: they meet), n the way out of the
 * convex toward it; INFINITY if not (EPA's direction taken toward the near side, epa_side.h) */
double dcloth_link_distance(const struct dcloth_geom_shape *cv, const double *a, const double *b, double r, ccd_t *ccd,
                            double n[3]);

/* The link tests' scratch: a box's or trimesh's triangles, 9 world coordinates each, then 6 box bounds
 * each; their grid and a stamp each */
struct edge_scratch {
    double *tri;
    int cap;
    int *start, *ent, *stamp;
    int start_cap, ent_cap, stamp_cap;
};

/* Each sequential link whose middle comes nearer geom s->g than its ends, within the shell and the
 * step's approach (at least `extra` m), holds both ends on the plane through the nearest point (c->vc_new).
 * Boxes, trimeshes, convexes without triangle tests; the vertex contacts set, or -1 on no memory. */
int dcloth_edge_contacts(dClothID c, const struct dcloth_surf *s, double h, double extra);

#endif
