/* The cloth's links against the edges and corners of boxes and trimeshes
 * (edges.c): the contacts that keep a body's edge from passing between two
 * vertices where no triangle test runs. */
#ifndef ODECLOTH_EDGES_H
#define ODECLOTH_EDGES_H

#include "dcloth_internal.h"

/* For the step of h seconds, each sequential link of the cloth whose middle
 * comes nearer geom s->g than both its ends do, within reach (the thickness
 * with the contact margin, plus what the link's ends and the geom close in
 * the step, at least `extra` m), the segment itself clear of the geom, gives
 * both its ends a contact on the plane through the geom's nearest point,
 * facing the link, where deeper than their own (in c->vc_new). Runs on boxes
 * and trimeshes whose triangle tests are off; returns the number of vertex
 * contacts set, or -1 when memory ran out. */
int dcloth_edge_contacts(dClothID c, const struct dcloth_surf *s, double h, double extra);

#endif
