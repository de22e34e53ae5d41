/* The cloth's angular momentum that no force explains, and the turn that takes it out (momentum.c). */
#ifndef ODECLOTH_MOMENTUM_H
#define ODECLOTH_MOMENTUM_H

#include "odecloth/dcloth.h"

/* The turn's workspace */
struct turn_scratch {
    dBodyID *bodies; /* n: the moving bodies the turn moves */
    double *dv;      /* 3n: the turn's velocity change */
};

/* after a solved step, the torque (N m) the cloth's angular momentum change calls for
 * beyond its forces and the constraints' shares of the leftover force F */
void dcloth_leftover_torque(dClothID c, double h, const double F[3], double wsum, double T[3]);
/* change the angular momentum of the cloth and its moving holders by dL (N m s), the rigid
 * turn of least energy their joints and the cloth's other constraints allow (docs/contacts.md); done:
 * the change made; -1 (nothing done) if a body's journal ran out of memory */
int dcloth_turn(dClothID c, const double dL[3], double done[3]);

#endif
