/* Continuous self-collision of a triangle mesh over one step (Bridson, Fedkiw, Anderson 2002; Provot
 * 1997): x1 is changed so no vertex passes through a triangle nor edge through edge, by impulses, then
 * rigid impact zones, then unstretching; pairs left colliding are returned (docs/self_collision.md). */
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

/* Resolve x0 -> x1 (3 nvert each; x1 changes); inv_mass 0: held; eta > 0 m; st may be NULL. Returns
 * the pairs left colliding; -1: bad input (x1 unchanged) or out of memory (x1 may be partly resolved). */
int self_ccd_apply(self_ccd *s, const double *x0, double *x1, const double *inv_mass, double eta, self_ccd_stats *st);

/* The pairs colliding over x0 -> x1 (a sweep, no response); -1 as above. */
int self_ccd_count(self_ccd *s, const double *x0, const double *x1, double eta);

#endif
