/* The broadphase (broadphase.c): the geoms near the cloth this step, and their surfaces. */
#ifndef ODECLOTH_BROADPHASE_H
#define ODECLOTH_BROADPHASE_H

#include "odecloth/dcloth.h"

/* A candidate geom's mu and thickness this step (dcloth_surface) */
struct dcloth_surf {
    dGeomID g;
    double mu, thickness;
};

/* The broadphase's scratch: the step's candidate geoms, each one's surface (surf[a] for cand[a]) and
 * a copy of them for a wider run */
struct broadphase_scratch {
    dGeomID box;   /* proxy: the cloth's swept AABB */
    dGeomID *cand; /* candidate geoms of the step */
    int ncand, cand_cap;
    struct dcloth_surf *surf, *surf_old;
    int surf_cap;
};

/* the broadphase alone, reaching `reach` m further: c->broad.cand, c->broad.ncand (and vc_new cleared); the count, or
 * -1 when memory for the candidate list ran out */
int dcloth_find_candidates(dClothID c, double h, double reach);
/* what any vertex may cover in a Newton step beyond its own start velocity (0 for the linearised step) */
double dcloth_newton_reach(dClothID c, double h);
/* the broadphase reaching `extra` m further, and each candidate's surface (dcloth_surface) into c->broad.surf;
 * the count or -1 as above */
int dcloth_find_surfaces(dClothID c, double h, double extra);

#endif
