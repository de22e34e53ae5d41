/* The Galerkin coarse operator K = W^T F W of a multigrid level
 * (multigrid.c), gathered: each block of K's upper triangle sums its
 * contributions in registers, by a plan made once per grid; the lower
 * triangle is the upper's mirror (F and K are symmetric). */
#ifndef ODECLOTH_GALERKIN_H
#define ODECLOTH_GALERKIN_H

#include <stdint.h>
#include "bsr.h"

typedef struct galerkin_plan {
    int nblk;       /* K's blocks                                                */
    int *start;     /* nblk + 1: each K block's entries (none below the diagonal) */
    int *mid;       /* nblk: the first of its entries that go in transposed      */
    uint32_t *ent;  /* F's block << 3 | weight code                             */
} galerkin_plan;

/* The plan for F (its pattern; par, w: 4 parents and weights per F node, -1
 * none) onto K (its pattern; slot: 25 per node, K's block at each offset of
 * the 5x5 stencil; rc: each K node's row and column). 0, or -1 on no memory
 * or a weight the plan cannot code. */
int galerkin_plan_make(galerkin_plan *g, const bsr *F, const int *par, const double *w, const bsr *K,
                       const int *slot, const int *rc);
void galerkin_plan_free(galerkin_plan *g);

/* K's values from F's: block k of F is filt + 9 fidx[k] where fidx (may be
 * NULL) is >= 0, else val + 9 k. */
void galerkin_apply(const galerkin_plan *g, const double *val, const double *filt, const int *fidx, bsr *K);

#endif
