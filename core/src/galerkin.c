/* The gathered Galerkin product (galerkin.h): each coarse block is summed in registers and stored once,
 * where scattered additions into it in memory would wait on each other's stores. */
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include "galerkin.h"
#include "mat3.h"

#define NSTEN 25

/* The weights a plan can code: products of two nodes' bilinear weights */
static const double WCODE[8] = {1.0, 0.5, 0.25, 0.125, 0.0625, 0.0, 0.0, 0.0};

static int weight_code(double w)
{
    for (int c = 0; c < 5; c++)
        if (w == WCODE[c]) return c;
    return -1;
}

/* K's block (I, J), J within I's 5x5 stencil */
static int kblock(const int *slot, const int *rc, int I, int J)
{
    return slot[(size_t)I * NSTEN + (rc[2 * J] - rc[2 * I] + 2) * 5 + (rc[2 * J + 1] - rc[2 * I + 1] + 2)];
}

/* Each contribution w_I w_J F_ij (j >= i) to K's upper triangle: to (I, J) if I <= J, and as F_ji
 * (transposed) to (J, I) if J <= I and j > i. With ent NULL counted in count[2 t + transposed], else
 * stored at fill[2 t + transposed]++; -1 on an uncodable weight. */
static int visit(const bsr *F, const int *par, const double *w, const int *slot, const int *rc, int *count, int *fill,
                 uint32_t *ent)
{
    for (int i = 0; i < F->n; i++)
        for (int k = F->diag[i]; k < F->row_ptr[i + 1]; k++) {
            int j = F->col[k];
            for (int a = 0; a < 4 && par[4 * i + a] >= 0; a++)
                for (int b = 0; b < 4 && par[4 * j + b] >= 0; b++) {
                    int I = par[4 * i + a], J = par[4 * j + b], code = weight_code(w[4 * i + a] * w[4 * j + b]);
                    if (code < 0) return -1;
                    /* tr 1: as F's (j, i); F's diagonal block has no such twin */
                    for (int tr = 0; tr < 2; tr++) {
                        if ((tr == 0 && J < I) || (tr == 1 && (J > I || j == i))) continue;
                        int t = tr ? kblock(slot, rc, J, I) : kblock(slot, rc, I, J);
                        if (!ent) count[2 * t + tr]++;
                        else ent[fill[2 * t + tr]++] = (uint32_t)k << 3 | (uint32_t)code;
                    }
                }
        }
    return 0;
}

int oc_galerkin_plan_make(galerkin_plan *g, const bsr *F, const int *par, const double *w, const bsr *K,
                          const int *slot, const int *rc)
{
    memset(g, 0, sizeof *g);
    /* a block gives at most 32 entries (16 parent pairs, twice): the counts stay ints */
    if ((size_t)F->nnzb > (size_t)INT_MAX / 32) return -1;
    int nb = K->nnzb;
    g->nblk = nb;
    g->start = malloc(((size_t)nb + 1) * sizeof *g->start);
    g->mid = malloc((size_t)nb * sizeof *g->mid);
    int *cnt = calloc(2 * (size_t)nb, sizeof *cnt);
    if (!g->start || !g->mid || !cnt || visit(F, par, w, slot, rc, cnt, NULL, NULL) != 0) goto fail;
    g->start[0] = 0;
    for (int t = 0; t < nb; t++) {
        g->mid[t] = g->start[t] + cnt[2 * t];
        g->start[t + 1] = g->mid[t] + cnt[2 * t + 1];
        cnt[2 * t] = g->start[t];
        cnt[2 * t + 1] = g->mid[t];
    }
    g->ent = malloc(((size_t)g->start[nb] + 1) * sizeof *g->ent);
    if (!g->ent) goto fail;
    visit(F, par, w, slot, rc, NULL, cnt, g->ent);
    free(cnt);
    return 0;
fail:
    free(cnt);
    oc_galerkin_plan_free(g);
    return -1;
}

void oc_galerkin_plan_free(galerkin_plan *g)
{
    free(g->start);
    free(g->mid);
    free(g->ent);
    memset(g, 0, sizeof *g);
}

/* K's lower blocks from its upper ones: K(I, J) = K(J, I)^T */
static void mirror_lower(bsr *K)
{
    for (int I = 0; I < K->n; I++)
        for (int k = K->row_ptr[I]; k < K->diag[I]; k++) {
            int J = K->col[k], u = -1;
            for (int m = K->diag[J]; m < K->row_ptr[J + 1] && u < 0; m++)
                if (K->col[m] == I) u = m;
            const double *U = K->val + 9 * (size_t)u;
            double *D = K->val + 9 * (size_t)k;
            for (int r = 0; r < 3; r++)
                for (int s = 0; s < 3; s++) D[3 * r + s] = U[3 * s + r];
        }
}

/* acc = the sum of the plan's entries e in [a, z), weighted */
static void gather(const uint32_t *ent, int a, int z, const double *val, const double *filt, const int *fidx,
                   double acc[9])
{
    double s[9] = {0.0};
    for (int e = a; e < z; e++) {
        size_t k = ent[e] >> 3;
        double wt = WCODE[ent[e] & 7];
        const double *B = fidx && fidx[k] >= 0 ? filt + 9 * (size_t)fidx[k] : val + 9 * k;
        for (int r = 0; r < 9; r++) s[r] += wt * B[r];
    }
    memcpy(acc, s, sizeof s);
}

#if MAT3_HAVE_AVX
/* gather with 256-bit vectors, elements 0-3 and 4-7 in a register each: every
 * element's operations as the plain loop's (no FMA), so the same bits */
static inline __attribute__((target("avx"))) void gather_avx(const uint32_t *ent, int a, int z, const double *val,
                                                             const double *filt, const int *fidx, double acc[9])
{
    __m256d lo = _mm256_setzero_pd(), hi = _mm256_setzero_pd();
    double last = 0.0;
    for (int e = a; e < z; e++) {
        size_t k = ent[e] >> 3;
        double wt = WCODE[ent[e] & 7];
        const double *B = fidx && fidx[k] >= 0 ? filt + 9 * (size_t)fidx[k] : val + 9 * k;
        __m256d w = _mm256_set1_pd(wt);
        lo = _mm256_add_pd(lo, _mm256_mul_pd(w, _mm256_loadu_pd(B)));
        hi = _mm256_add_pd(hi, _mm256_mul_pd(w, _mm256_loadu_pd(B + 4)));
        last += wt * B[8];
    }
    _mm256_storeu_pd(acc, lo);
    _mm256_storeu_pd(acc + 4, hi);
    acc[8] = last;
}
#endif

/* The blocks of K's upper triangle, by the AVX gather where avx (a constant) */
MAT3_INLINE void apply_upper(int avx, const galerkin_plan *g, const double *val, const double *filt, const int *fidx,
                             bsr *K)
{
    (void)avx; /* used only where the build has AVX */
    for (int t = 0; t < g->nblk; t++) {
        double an[9], at[9];
#if MAT3_HAVE_AVX
        if (avx) {
            gather_avx(g->ent, g->start[t], g->mid[t], val, filt, fidx, an);
            gather_avx(g->ent, g->mid[t], g->start[t + 1], val, filt, fidx, at);
        } else
#endif
        {
            gather(g->ent, g->start[t], g->mid[t], val, filt, fidx, an);
            gather(g->ent, g->mid[t], g->start[t + 1], val, filt, fidx, at);
        }
        double *D = K->val + 9 * (size_t)t;
        for (int r = 0; r < 3; r++)
            for (int s = 0; s < 3; s++) D[3 * r + s] = an[3 * r + s] + at[3 * s + r];
    }
}

#if MAT3_HAVE_AVX
MAT3_AVX_FN static void apply_upper_avx(const galerkin_plan *g, const double *val, const double *filt, const int *fidx,
                                        bsr *K)
{
    apply_upper(1, g, val, filt, fidx, K);
}
#endif

void oc_galerkin_apply(const galerkin_plan *g, const double *val, const double *filt, const int *fidx, bsr *K)
{
#if MAT3_HAVE_AVX
    if (mat3_avx()) apply_upper_avx(g, val, filt, fidx, K);
    else apply_upper(0, g, val, filt, fidx, K);
#else
    apply_upper(0, g, val, filt, fidx, K);
#endif
    mirror_lower(K);
}
