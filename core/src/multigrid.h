/* Geometric multigrid V-cycle on the cloth grid, used as the preconditioner
 * of the modified PCG (multigrid.c). */
#ifndef ODECLOTH_MULTIGRID_H
#define ODECLOTH_MULTIGRID_H

#include "bsr.h"
#include "galerkin.h"
#include "tuning.h"

#define MG_MAX_LEVELS 16

typedef struct mg_level {
    int R, C, n; /* grid of this level                                     */
    /* levels >= 1: the 5x5-offset stencil matrix in block-CSR form, one block
     * per stencil neighbour on the grid (rows sorted, so in stencil order) */
    bsr M;
    int *slot;             /* levels >= 1: 25n, block of M at each stencil offset
                          * (-1 = off the grid)                                    */
    double *Dinv;          /* 9n inverse diagonal blocks (level 0: the cloth's)      */
    unsigned char *symrow; /* n: row i's blocks and Dinv_i all exactly symmetric (oc_mg_setup;
                            * the smoother's paired loop, same bits)             */
    double *x, *b;         /* 3n                                                     */
    int *rc;               /* 2n: row and column of each node                        */
    /* prolongation from the next coarser level: up to 4 parents per node */
    int *par;         /* 4n coarse node indices (-1 = none)                     */
    double *w;        /* 4n bilinear weights                                    */
    galerkin_plan gp; /* the next level's matrix from this one's                */
    /* level 0: the filtered blocks S_i A_ij S_j of the upper triangle's blocks
     * that touch a constraint (fidx[k] >= 0: at fbuf + 9 fidx[k]) */
    int *fidx;
    double *fbuf;
} mg_level;

typedef struct multigrid {
    int nlev;
    mg_level lev[MG_MAX_LEVELS];
    int nc;        /* unknowns of the coarsest level (3 n)                   */
    double *dense; /* nc x nc Cholesky factor of the coarsest level          */
    /* level 0 (the cloth's own matrix), set before each use */
    const bsr *A0;
    const double *S0;                 /* 9n filters                                             */
    const unsigned char *constrained; /* n flags: filter needed                    */
} multigrid;

/* Levels for an R x C grid of A0's pattern, coarsened by two while a level has over 64 nodes. 0; -1 on
 * no memory (or a grid too large to plan); -2 when the coarsest level would have more than
 * MG_DENSE_MAX unknowns (a grid with a side under 5 nodes does not coarsen). */
int oc_mg_create(multigrid *mg, int R, int C, const bsr *A0);
void oc_mg_free(multigrid *mg);

/* Per step: Galerkin coarse operators W^T A_l W from the filtered S A S (constraints removed before
 * coarsening), their diagonal inverses and the coarsest level's Cholesky factor. Dinv0: the fine
 * level's inverse diagonal blocks of S A S + (I - S). With several levels, A->sym is checked here. */
void oc_mg_setup(multigrid *mg, const bsr *A, const double *S, const unsigned char *constrained, double *Dinv0);

/* s = V(r): one V(1,1)-cycle, forward block Gauss-Seidel before and backward
 * after the coarse correction, so the operator is symmetric and positive
 * definite (a valid CG preconditioner). ctx is the multigrid. */
void oc_mg_apply(void *ctx, const double *r, double *s);

#endif
