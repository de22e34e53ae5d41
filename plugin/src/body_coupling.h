/* Body coupling (body_coupling.c): the moving bodies solved with the cloth, and the core's step. */
#ifndef ODECLOTH_BODY_COUPLING_H
#define ODECLOTH_BODY_COUPLING_H

#include "odecloth/dcloth.h"

/* The moving bodies solved with the cloth this step, and the core's view of them */
struct coupled_bodies {
    dBodyID *bodies;
    cloth_body *bdesc;
    int n, cap;
};

/* Hand this pass's moving bodies to the core: an enabled dynamic body a vertex is pinned to, touches or
 * may touch is solved with the cloth (cloth_body), so neither overshoots the other. */
void dcloth_couple_bodies(dClothID c);
/* The core's step of h seconds with this step's solver: one more substep halving for each step held in a
 * row, and Newton's solves to their relative stop while a dynamic body holds the cloth. */
cloth_status dcloth_coupled_step(dClothID c, cloth *core, double h, cloth_step_stats *st);

#endif
