/* Writing the links' blocks into the step's matrix A (potential.c,
 * linearized.c): where each off-diagonal block is one link's, it is written
 * rather than added, so only the diagonal blocks need zeroing first. */
#ifndef ODECLOTH_ASSEMBLY_H
#define ODECLOTH_ASSEMBLY_H

#include "internal.h"
#include "mat3.h"

/* A's blocks that the assembly adds into set to zero */
static inline void assemble_zero(cloth *c)
{
    if (c->links_own_blocks) oc_bsr_zero_diag(&c->A);
    else oc_bsr_zero(&c->A);
}

/* link (i, j) with blocks bl[0] = (i, j), bl[1] = (j, i): +blk on both
 * diagonal blocks, -blk off the diagonal */
static inline void assemble_link(cloth *c, int i, int j, const int *bl, const double *blk)
{
    double *val = c->A.val;
    mat3_axpy(val + 9 * (size_t)c->A.diag[i], blk, 1.0);
    mat3_axpy(val + 9 * (size_t)c->A.diag[j], blk, 1.0);
    if (c->links_own_blocks) {
        mat3_set_neg(val + 9 * (size_t)bl[0], blk);
        mat3_set_neg(val + 9 * (size_t)bl[1], blk);
    } else {
        mat3_axpy(val + 9 * (size_t)bl[0], blk, -1.0);
        mat3_axpy(val + 9 * (size_t)bl[1], blk, -1.0);
    }
}

/* Fetch, for writing, the blocks assemble_link(c, i, j, bl, ...) will write
 * but row i's diagonal (written by every link of i): a link's blocks lie a
 * grid row or two apart, beyond what the hardware fetches ahead by itself. */
MAT3_INLINE void assemble_prefetch(const cloth *c, int j, const int *bl)
{
#if defined(__GNUC__)
    const double *v = c->A.val, *b0 = v + 9 * (size_t)bl[0], *b1 = v + 9 * (size_t)bl[1];
    const double *d = v + 9 * (size_t)c->A.diag[j];
    __builtin_prefetch(b0, 1);
    __builtin_prefetch(b0 + 8, 1);
    __builtin_prefetch(b1, 1);
    __builtin_prefetch(b1 + 8, 1);
    __builtin_prefetch(d, 1);
    __builtin_prefetch(d + 8, 1);
#else
    (void)c, (void)j, (void)bl;
#endif
}

#endif
