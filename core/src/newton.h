/* The implicit step (backward Euler or BDF2) by Newton's method on its
 * incremental potential (newton.c, potential.h). */
#ifndef ODECLOTH_NEWTON_H
#define ODECLOTH_NEWTON_H

#include "internal.h"

/* One implicit step of h into c->x_new, v_new, dv, con_new (state untouched; constraints aimed at frac
 * of the way from xs; iterations added to st). *limit_held: every sequential link ended within the
 * limit's tolerance. On CLOTH_FAIL_NEWTON the outputs hold the last iterate and its forces. */
cloth_failure oc_newton_step(cloth *c, double h, int bdf2, const double *xs, double frac, cloth_step_stats *st,
                             int *limit_held);

#endif
