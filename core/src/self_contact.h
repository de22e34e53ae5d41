/* Self-contact inside the Newton step (Li et al. 2020, IPC): each vertex-triangle and edge-edge pair
 * closer than the thickness D adds kappa b(d), b(d) = -(d - D)^2 ln(d / D), to the potential, and each
 * update stops short of the first touch, so no iterate passes through (docs/self_collision.md). */
#ifndef ODECLOTH_SELF_CONTACT_H
#define ODECLOTH_SELF_CONTACT_H

#include "internal.h"

typedef struct self_contact self_contact;

/* The work done since creation (for tests and benchmarks) */
typedef struct self_contact_work {
    long rebuilds;      /* candidate lists built (broadphase runs) */
    long extended;      /* candidate lists grown for a few vertices */
    long relisted;      /* close-pair lists made (passes over every candidate) */
    int candidates;     /* pairs in the last list */
    int tested, active; /* the last evaluation's pairs whose distance it computed; within D */
    double seconds;     /* wall time spent in oc_self_contact_eval and oc_self_contact_max_step */
} self_contact_work;

/* The grid's triangles as selfcollision.c lists them (3 ntri corners, kept
 * by pointer; their edges are found here), thickness D. NULL: out of memory. */
self_contact *oc_self_contact_create(int n, int ntri, const int *tri, double thickness);
void oc_self_contact_destroy(self_contact *s); /* NULL is fine; unbinds its cloth */

/* Let the Newton steps of c feel s (s leaves any cloth it was bound to). */
void oc_self_contact_bind(self_contact *s, cloth *c);
/* cloth_destroy: c is going. */
void oc_self_contact_unbind_cloth(cloth *c);

/* A step's barrier stiffness, for dx/dv = cfac and the cloth's masses. */
void oc_self_contact_begin(self_contact *s, const cloth *c, double cfac);

/* Both below test only candidate pairs, listed by a broadphase for regions around the vertices and
 * kept while the positions asked about stay in them (self_contact.c), in vertex and edge order: the
 * sums do not depend on the list. */

/* The barrier's energy at x (NaN: out of memory); b (NULL: none) gets -cfac times its gradient
 * added, A (NULL: none) cfac^2 times its diagonal blocks. */
double oc_self_contact_eval(self_contact *s, const double *x, double cfac, double *b, bsr *A);

/* The fraction in [0, 1] of the straight motion x0 -> x1 that stops short
 * of the first vertex-triangle or edge-edge touch (all of it when there is
 * none; 0 out of memory). */
double oc_self_contact_max_step(self_contact *s, const double *x0, const double *x1);

self_contact_work oc_self_contact_get_work(const self_contact *s);

#endif
