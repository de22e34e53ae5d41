/* The cloth's step (step.c): its start, to solve it again from, and its counts. */
#ifndef ODECLOTH_STEP_H
#define ODECLOTH_STEP_H

#include "odecloth/dcloth.h"

/* The step's scratch */
struct step_scratch {
    double *fext;      /* 3n: the user's forces plus sliding friction, handed to the core */
    double *fuser;     /* 3n: the core's own external forces (the user's), put back after each step */
    double *x0;        /* 3n: positions at the step's start */
    double *v0;        /* 3n: velocities at the step's start */
    double *dv;        /* 3n: the last solve's velocity change, the next solve's start */
    cloth_state *save; /* the core's state at the step's start (re-solves) */
    int tri_hits;      /* vertex contacts set by triangle tests this step */
    int edge_hits;     /* vertex contacts set by link tests this step */
    double deepest;    /* m, the deepest point of the cloth inside a geom's thickness shell the contact
                          search measured at the step's start: a vertex's, a triangle's or a link's */
};

#endif
