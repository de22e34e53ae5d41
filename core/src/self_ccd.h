/* Continuous self-collision of a triangle mesh over one step: the vertices
 * move linearly from x0 to x1, and x1 is changed so that no vertex passes
 * through a triangle and no edge through an edge (Bridson, Fedkiw, Anderson
 * 2002; Provot 1997).
 *
 *   1. Impulses: each pair the sweep finds (ccd.h) gets an inelastic impulse
 *      along its normal, shared by inverse mass and the pair's weights, that
 *      brings it to end no closer than min(its start gap, eta / 2) (to first
 *      order). Momentum is kept. A few passes, each sweeping anew. An impulse
 *      that would move a corner more than twice the closing it undoes (held
 *      vertices leave the whole impulse to a light corner) is left to 2.
 *   2. Rigid impact zones: the vertices of the pairs still colliding are
 *      merged into zones, and each zone moves rigidly: its centre of mass
 *      moves as its momentum says and it turns by its angular velocity
 *      about it (the exact rotation over the step). Zones grow until no pair
 *      collides. Held vertices (inverse mass 0) keep their motion, and weigh
 *      SELF_CCD_HELD_MASS mean masses in a zone's fit; a zone they hold
 *      against each other may stay colliding.
 *   3. Edges the responses stretched are brought back to no longer than they
 *      were at x0 or at the x1 given, and the motion is swept again (1, 2);
 *      SELF_CCD_ROUNDS rounds at most, the last one without this.
 *
 * Pairs still colliding at the end are counted and returned, never dropped.
 * A pair counts as colliding when the sweep finds it: coplanar within eta at
 * some time in the step, and closing. The first sweep of a call tests every
 * pair whose swept boxes come within eta; later ones only the pairs with a
 * vertex that moved since the last sweep or was in one of its hits. */
#ifndef ODECLOTH_SELF_CCD_H
#define ODECLOTH_SELF_CCD_H

#include "tuning.h"

typedef struct self_ccd self_ccd;

typedef struct self_ccd_stats {
    int impulses;      /* impulses applied */
    int left;          /* impulses left to the zones (they would throw a corner) */
    int zone_rounds;   /* sweeps of the zone phases that merged zones */
    int zones;         /* zones of two or more vertices in the last zone phase */
    int zone_vertices; /* vertices in them */
    int rounds;        /* rounds of 1-3 */
    int unresolved;    /* pairs still colliding at the end */
    double stretch;    /* largest edge length over its limit at the end */
} self_ccd_stats;

/* A mesh of nvert vertices and ntri triangles (3 vertex indices each; its
 * edges are found here). NULL on bad input (an index out of range, a
 * triangle with a repeated corner) or out of memory. */
self_ccd *self_ccd_create(int nvert, int ntri, const int *tri);
void self_ccd_destroy(self_ccd *s); /* NULL is fine */

/* Resolve x0 -> x1 (3 nvert each; x1 changes); inv_mass 0: held; eta > 0 m;
 * st may be NULL. Returns the pairs left colliding; -1: bad input (x1 left
 * as it was) or out of memory (x1 may be partly resolved). */
int self_ccd_apply(self_ccd *s, const double *x0, double *x1, const double *inv_mass, double eta,
                   self_ccd_stats *st);

/* The pairs colliding over x0 -> x1 (a sweep, no response); -1 as above. */
int self_ccd_count(self_ccd *s, const double *x0, const double *x1, double eta);

#endif
