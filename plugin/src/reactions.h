/* Reactions (reactions.c): the cloth's forces back onto its bodies after a solved step. */
#ifndef ODECLOTH_REACTIONS_H
#define ODECLOTH_REACTIONS_H

#include "odecloth/dcloth.h"

/* The reactions' scratch (reactions.c, read by momentum.c) */
struct reactions_scratch {
    double *vfix;    /* 3n: velocities after the step's contact fix-up */
    dBodyID *holder; /* n: the body that takes each vertex's force, or 0 */
};

/* After the step of h seconds is solved: the contact fix-up of the velocities, each body's force and
 * torque from the constraints holding the cloth, the turn (st's turned and couple), the held contacts'
 * forces for the next step (c->vc_new) */
void dcloth_reactions(dClothID c, double h, dClothStepStats *st);

#endif
