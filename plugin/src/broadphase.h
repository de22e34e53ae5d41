/* The broadphase (broadphase.c): the geoms near the cloth this step, and their surfaces. */
#ifndef ODECLOTH_BROADPHASE_H
#define ODECLOTH_BROADPHASE_H

#include "dcloth_internal.h"

/* the broadphase alone, reaching `reach` m further: c->cand, c->ncand (and vc_new cleared); the count, or
 * -1 when memory for the candidate list ran out */
int dcloth_find_candidates(dClothID c, double h, double reach);
/* what any vertex may cover in a Newton step beyond its own start velocity (0 for the linearised step) */
double dcloth_newton_reach(dClothID c, double h);
/* the broadphase reaching `extra` m further, and each candidate's surface (dcloth_surface) into c->surf;
 * the count or -1 as above */
int dcloth_find_surfaces(dClothID c, double h, double extra);

#endif
