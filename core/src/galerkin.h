/* The Galerkin coarse operator K = W^T F W of a multigrid level (multigrid.c), by a plan made once per
 * grid: each block of K's upper triangle gathers its contributions; the lower triangle is its mirror
 * (F and K are symmetric). */
#ifndef ODECLOTH_GALERKIN_H
#define ODECLOTH_GALERKIN_H

#include <stdint.h>
#include "bsr.h"

typedef struct galerkin_plan {
    int nblk;      /* K's blocks                                                */
    int *start;    /* nblk + 1: each K block's entries (none below the diagonal) */
    int *mid;      /* nblk: the first of its entries that go in transposed      */
    uint32_t *ent; /* F's block << 3 | weight code                             */
} galerkin_plan;

/* The plan from F onto K: par, w the 4 parents (-1 none) and weights of each F node; slot K's block at
 * each of a node's 25 stencil offsets, rc each K node's row and column. 0; -1 on no memory, an F too
 * large, or a weight the plan cannot code (not a product of bilinear weights). */
int oc_galerkin_plan_make(galerkin_plan *g, const bsr *F, const int *par, const double *w, const bsr *K,
                          const int *slot, const int *rc);
void oc_galerkin_plan_free(galerkin_plan *g);

/* K's values from F's: block k of F is filt + 9 fidx[k] where fidx (may be
 * NULL) is >= 0, else val + 9 k. */
void oc_galerkin_apply(const galerkin_plan *g, const double *val, const double *filt, const int *fidx, bsr *K);

#endif
