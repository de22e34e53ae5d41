/* The implicit steps' linear solve (linsolve.c): the preconditioner the
 * solver descriptor names, set up on c->A and the constraint filter, and
 * the modified PCG (or SSOR-preconditioned CG) run on P. */
#ifndef ODECLOTH_LINSOLVE_H
#define ODECLOTH_LINSOLVE_H

#include "internal.h"
#include "mpcg.h"

/* x: in, the guess for the free components; out, the solution. The
 * multigrid's coarse levels are built anew from c->A for every solve. */
mpcg_result oc_linsolve_run(cloth *c, mpcg_problem *P, double *x);

#endif
