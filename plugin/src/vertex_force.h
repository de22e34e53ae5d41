/* The force each constrained vertex puts on its body, and which body takes it (vertex_force.c). */
#ifndef ODECLOTH_VERTEX_FORCE_H
#define ODECLOTH_VERTEX_FORCE_H

#include "dcloth_internal.h"

/* the force (N) vertex i's constraint puts on its body, with its share by force size of
 * the leftover force F (the share returned: 0 unless that body moves) */
double dcloth_vertex_force(dClothID c, int i, const double F[3], double wsum, double f[3]);
/* the body that takes vertex i's force f: its pin's or contact's, or when pinched and
 * pushed toward that contact's body, the opposite one; 0 for none */
dBodyID dcloth_force_body(dClothID c, int i, const double f[3]);
/* vertex i's contact force (N) without its second plane's (a static or kinematic geom) */
void dcloth_first_force(cloth *core, int i, double f[3]);
/* 1 + the index of the body solved with the cloth holding vertex i's constraint, or 0 */
int dcloth_held_by_coupled(dClothID c, int i);

#endif
