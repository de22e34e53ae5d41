/* Block matrices of the cloth's grid pattern for the multigrid's unit tests
 * (header-only, static). */
#ifndef ODECLOTH_TEST_GRID_MATRIX_H
#define ODECLOTH_TEST_GRID_MATRIX_H

#include <stdlib.h>

#include "bsr.h"
#include "check.h"

/* the cloth's links on an R x C grid: step 1 (sequential) and 2 (interlaced) */
static inline int grid_links(int R, int C, int *ei, int *ej)
{
    static const int off[4][2] = {{0, 1}, {1, 0}, {1, 1}, {1, -1}};
    int m = 0;
    for (int s = 1; s <= 2; s++)
        for (int r = 0; r < R; r++)
            for (int c = 0; c < C; c++)
                for (int k = 0; k < 4; k++) {
                    int r2 = r + s * off[k][0], c2 = c + s * off[k][1];
                    if (r2 >= R || c2 < 0 || c2 >= C) continue;
                    ei[m] = r * C + c;
                    ej[m++] = r2 * C + c2;
                }
    return m;
}

/* A's blocks random, A_ji = A_ij^T; a diagonal block symmetric, and every
 * block if sym */
static inline void random_symmetric(bsr *A, rng *g, int sym)
{
    for (int i = 0; i < A->n; i++)
        for (int k = A->row_ptr[i]; k < A->row_ptr[i + 1]; k++) {
            int j = A->col[k];
            if (j < i) continue;
            double *B = A->val + 9 * (size_t)k;
            for (int e = 0; e < 9; e++) B[e] = rng_range(g, -1.0, 1.0);
            if (j == i || sym) {
                for (int r = 0; r < 3; r++)
                    for (int s = 0; s < r; s++) B[3 * r + s] = B[3 * s + r];
                if (j == i) continue;
            }
            double *T = A->val + 9 * (size_t)oc_bsr_find(A, j, i);
            for (int r = 0; r < 3; r++)
                for (int s = 0; s < 3; s++) T[3 * r + s] = B[3 * s + r];
        }
}

/* A: the R x C grid's link pattern as a block matrix (values zero); 0, or -1 */
static inline int grid_matrix(int R, int C, bsr *A)
{
    int n = R * C, ne_max = 8 * n;
    int *ei = malloc(sizeof *ei * (size_t)ne_max), *ej = malloc(sizeof *ej * (size_t)ne_max);
    int *blk = malloc(2 * sizeof *blk * (size_t)ne_max);
    int ok = ei && ej && blk && oc_bsr_build(A, n, grid_links(R, C, ei, ej), ei, ej, blk) == 0;
    free(ei);
    free(ej);
    free(blk);
    return ok ? 0 : -1;
}

#endif
