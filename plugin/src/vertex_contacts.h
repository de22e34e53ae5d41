/* Vertex contacts (vertex_contacts.c): each vertex against each candidate geom. */
#ifndef ODECLOTH_VERTEX_CONTACTS_H
#define ODECLOTH_VERTEX_CONTACTS_H

#include "odecloth/dcloth.h"

/* The vertex tests' narrowphase proxies */
struct vertex_proxies {
    dGeomID sphere; /* one vertex */
    dGeomID ray;    /* one vertex over heightfields */
};

/* every vertex's nearest surface among the candidates (c->broad.cand, c->broad.surf) within its reach over the step
 * of h seconds (at least `extra` m), into c->vc_new */
void dcloth_vertex_contacts(dClothID c, double h, double extra);
/* The distance from x to geom g's surface and the outward unit normal there, as the vertex tests see
 * them: 1 where within reach, else 0 */
int dcloth_vertex_distance(dClothID c, dGeomID g, const double *x, double reach, double *dist, double nrm[3]);
/* vertices with no contact this step whose end positions x1 lie deeper in a candidate's shell than `depth`
 * of its thickness get that contact (the shell's plane there, gap from x0); returns how many */
int dcloth_find_late_contacts(dClothID c, const double *x0, const double *x1, double depth);

#endif
