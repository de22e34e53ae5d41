/* Geometric multigrid preconditioner for the modified PCG.
 *
 * Why: with a diagonal or block-diagonal preconditioner the CG iteration
 * count grows with the grid's width (the stiff springs spread information one
 * node per iteration); a multigrid V-cycle keeps it nearly flat.
 * How (as measured on the prototype in DESIGN.md):
 *  - coarsen by two in each grid direction (node 2I of a level is node I of
 *    the next), bilinear prolongation W, restriction W^T;
 *  - Galerkin coarse operators W^T A W rebuilt every step (springs rotate, so
 *    reusing them across steps costs iterations);
 *  - constraints removed before coarsening: the fine operator coarsened is
 *    S A S (Tamstorf, Jones, McCormick 2015), and the fine smoother works on
 *    S A S + (I - S), so the coarse levels never fight a constraint;
 *  - block Gauss-Seidel, forward before and backward after the coarse
 *    correction, and an exact (Cholesky) solve on the coarsest level: the
 *    V-cycle is then a symmetric positive definite operator, as CG needs.
 * Coarse levels store a full 5x5 stencil per node: with interlaced links the
 * fine stencil reaches two nodes, and so does every Galerkin coarse one. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "mat3.h"
#include "multigrid.h"

#define NSTEN 25
#define CENTER 12

static int coarse_dim(int R) { return (R - 1) / 2 + 1; }

/* Parents of fine index r on a coarse axis of length Rc: up to 2 (index, weight). */
static int axis_parents(int r, int Rc, int idx[2], double w[2])
{
    if (r % 2 == 0) {
        idx[0] = r / 2;
        w[0] = 1.0;
        return 1;
    }
    idx[0] = (r - 1) / 2;
    idx[1] = (r + 1) / 2;
    if (idx[1] >= Rc) { /* even-sized grid: the last node hangs off one parent */
        w[0] = 1.0;
        return 1;
    }
    w[0] = w[1] = 0.5;
    return 2;
}

void mg_free(multigrid *mg)
{
    for (int l = 0; l < MG_MAX_LEVELS; l++) {
        mg_level *L = &mg->lev[l];
        free(L->A);
        if (l > 0) free(L->Dinv);
        free(L->x);
        free(L->b);
        free(L->r);
        free(L->par);
        free(L->w);
        free(L->nb);
        free(L->rc);
    }
    free(mg->dense);
    memset(mg, 0, sizeof *mg);
}

/* The coarsest level's node count for an R x C grid (the levels of
 * mg_create, without allocating). */
static long coarsest_nodes(int R, int C)
{
    long n = (long)R * C;
    for (int l = 0; n > 64 && R >= 5 && C >= 5 && l + 1 < MG_MAX_LEVELS; l++) {
        R = coarse_dim(R);
        C = coarse_dim(C);
        n = (long)R * C;
    }
    return n;
}

int mg_create(multigrid *mg, int R, int C)
{
    memset(mg, 0, sizeof *mg);
    /* the coarsest level is solved densely: a grid that does not coarsen
     * (a side under 5 nodes: 3 x 100000 asked for 6.5 TB) is refused */
    if (3 * coarsest_nodes(R, C) > MG_DENSE_MAX) return -2;
    int l = 0;
    mg->lev[0].R = R;
    mg->lev[0].C = C;
    mg->lev[0].n = R * C;
    while (mg->lev[l].n > 64 && mg->lev[l].R >= 5 && mg->lev[l].C >= 5 && l + 1 < MG_MAX_LEVELS) {
        mg_level *F = &mg->lev[l], *K = &mg->lev[l + 1];
        K->R = coarse_dim(F->R);
        K->C = coarse_dim(F->C);
        K->n = K->R * K->C;
        F->par = malloc(4 * (size_t)F->n * sizeof *F->par);
        F->w = malloc(4 * (size_t)F->n * sizeof *F->w);
        K->A = malloc(NSTEN * 9 * (size_t)K->n * sizeof *K->A);
        K->Dinv = malloc(9 * (size_t)K->n * sizeof *K->Dinv);
        if (!F->par || !F->w || !K->A || !K->Dinv) goto fail;
        for (int r = 0; r < F->R; r++)
            for (int c = 0; c < F->C; c++) {
                int ri[2], ci[2];
                double rw[2], cw[2];
                int nr = axis_parents(r, K->R, ri, rw), nc = axis_parents(c, K->C, ci, cw);
                int i = r * F->C + c, m = 0;
                for (int a = 0; a < nr; a++)
                    for (int b = 0; b < nc; b++, m++) {
                        F->par[4 * i + m] = ri[a] * K->C + ci[b];
                        F->w[4 * i + m] = rw[a] * cw[b];
                    }
                for (; m < 4; m++) {
                    F->par[4 * i + m] = -1;
                    F->w[4 * i + m] = 0.0;
                }
            }
        l++;
    }
    mg->nlev = l + 1;
    for (l = 0; l < mg->nlev; l++) {
        mg_level *L = &mg->lev[l];
        L->x = calloc(3 * (size_t)L->n, sizeof(double));
        L->b = calloc(3 * (size_t)L->n, sizeof(double));
        L->r = calloc(3 * (size_t)L->n, sizeof(double));
        L->rc = malloc(2 * (size_t)L->n * sizeof *L->rc);
        L->nb = l > 0 ? malloc(NSTEN * (size_t)L->n * sizeof *L->nb) : NULL;
        if (!L->x || !L->b || !L->r || !L->rc || (l > 0 && !L->nb)) goto fail;
        for (int i = 0; i < L->n; i++) {
            int r = i / L->C, c = i % L->C;
            L->rc[2 * i] = r;
            L->rc[2 * i + 1] = c;
            for (int k = 0; l > 0 && k < NSTEN; k++) {
                int r2 = r + k / 5 - 2, c2 = c + k % 5 - 2;
                L->nb[NSTEN * i + k] = (r2 < 0 || r2 >= L->R || c2 < 0 || c2 >= L->C) ? -1 : r2 * L->C + c2;
            }
        }
    }
    mg->nc = 3 * mg->lev[mg->nlev - 1].n;
    mg->dense = malloc((size_t)mg->nc * mg->nc * sizeof *mg->dense);
    if (!mg->dense) goto fail;
    return 0;
fail:
    mg_free(mg);
    return -1;
}

/* ---------------------------------------------------------- 3x3 helpers */

/* S_i B S_j */
static void filter_block(const double *Si, const double *B, const double *Sj, double *out)
{
    double t[9];
    mat3mul(Si, B, t);
    mat3mul(t, Sj, out);
}

/* Inverse of a symmetric block, regularised by 1e-10 of its trace so that a
 * coarse node whose fine support is entirely constrained (a zero block) or
 * constrained along a common direction (a singular block) stays finite; the
 * residual in those directions is zero. */
static void inv_reg(const double *B, double *o)
{
    double m[9];
    memcpy(m, B, sizeof m);
    double tr = m[0] + m[4] + m[8], eps = 1e-10 * (tr > 0.0 ? tr : 0.0);
    m[0] += eps;
    m[4] += eps;
    m[8] += eps;
    double det = mat3inv(m, o);
    if (!(det > 0.0) || !isfinite(det)) {
        memset(o, 0, 9 * sizeof *o);
        for (int k = 0; k < 3; k++) o[4 * k] = m[4 * k] > 0.0 ? 1.0 / m[4 * k] : 0.0;
    }
}

/* Add w_I w_J B to coarse block (I, J) for every parent I of fine node i and
 * J of fine node j. */
static void galerkin_block(const mg_level *F, mg_level *K, int i, int j, const double *B)
{
    for (int a = 0; a < 4 && F->par[4 * i + a] >= 0; a++) {
        int I = F->par[4 * i + a];
        double wi = F->w[4 * i + a];
        const int *rcI = K->rc + 2 * I;
        for (int b = 0; b < 4 && F->par[4 * j + b] >= 0; b++) {
            const int *rcJ = K->rc + 2 * F->par[4 * j + b];
            double w = wi * F->w[4 * j + b];
            double *D = K->A + 9 * ((size_t)I * NSTEN + (size_t)((rcJ[0] - rcI[0] + 2) * 5 + (rcJ[1] - rcI[1] + 2)));
            for (int k = 0; k < 9; k++) D[k] += w * B[k];
        }
    }
}

/* neighbour of node i at stencil offset k on level L (>= 1), or -1 */
static inline int stencil_nb(const mg_level *L, int i, int k) { return L->nb[NSTEN * i + k]; }

/* Cholesky of the coarsest level's dense matrix, in place (lower). A pivot
 * that is not positive (an indefinite matrix, e.g. without the definiteness
 * rule) is replaced so the V-cycle stays defined; CG then sees the true
 * matrix and reports the non-positive curvature itself. */
static void cholesky(double *a, int n)
{
    double dmax = 0.0;
    for (int i = 0; i < n; i++) dmax = fmax(dmax, a[(size_t)i * n + i]);
    if (!(dmax > 0.0)) dmax = 1.0;
    for (int j = 0; j < n; j++) {
        double d = a[(size_t)j * n + j] + 1e-12 * dmax;
        for (int k = 0; k < j; k++) d -= a[(size_t)j * n + k] * a[(size_t)j * n + k];
        d = d > 1e-12 * dmax ? sqrt(d) : sqrt(dmax);
        a[(size_t)j * n + j] = d;
        for (int i = j + 1; i < n; i++) {
            double s = a[(size_t)i * n + j];
            for (int k = 0; k < j; k++) s -= a[(size_t)i * n + k] * a[(size_t)j * n + k];
            a[(size_t)i * n + j] = s / d;
        }
    }
}

static void cholesky_solve(const double *a, int n, const double *b, double *x)
{
    for (int i = 0; i < n; i++) {
        double s = b[i];
        for (int k = 0; k < i; k++) s -= a[(size_t)i * n + k] * x[k];
        x[i] = s / a[(size_t)i * n + i];
    }
    for (int i = n - 1; i >= 0; i--) {
        double s = x[i];
        for (int k = i + 1; k < n; k++) s -= a[(size_t)k * n + i] * x[k];
        x[i] = s / a[(size_t)i * n + i];
    }
}

static void dense_put(double *D, int n3, int i, int j, const double *B)
{
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) D[(size_t)(3 * i + a) * n3 + 3 * j + b] = B[3 * a + b];
}

static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

void mg_setup(multigrid *mg, const bsr *A, const double *S, const unsigned char *constrained, double *Dinv0)
{
    mg->A0 = A;
    mg->S0 = S;
    mg->constrained = constrained;
    mg->lev[0].Dinv = Dinv0;
    double B[9];
    /* level 0 -> 1 from the BSR matrix, filtered */
    if (mg->nlev > 1) {
        mg_level *F = &mg->lev[0], *K = &mg->lev[1];
        memset(K->A, 0, NSTEN * 9 * (size_t)K->n * sizeof *K->A);
        for (int i = 0; i < F->n; i++)
            for (int k = A->row_ptr[i]; k < A->row_ptr[i + 1]; k++) {
                int j = A->col[k];
                const double *Bk = A->val + 9 * (size_t)k;
                if (constrained[i] || constrained[j]) {
                    filter_block(S + 9 * (size_t)i, Bk, S + 9 * (size_t)j, B);
                    Bk = B;
                }
                galerkin_block(F, K, i, j, Bk);
            }
    }
    for (int l = 1; l < mg->nlev; l++) {
        mg_level *L = &mg->lev[l];
        for (int i = 0; i < L->n; i++) inv_reg(L->A + 9 * ((size_t)i * NSTEN + CENTER), L->Dinv + 9 * (size_t)i);
        if (l + 1 == mg->nlev) break;
        mg_level *K = &mg->lev[l + 1];
        memset(K->A, 0, NSTEN * 9 * (size_t)K->n * sizeof *K->A);
        for (int i = 0; i < L->n; i++)
            for (int k = 0; k < NSTEN; k++) {
                int j = stencil_nb(L, i, k);
                if (j >= 0) galerkin_block(L, K, i, j, L->A + 9 * ((size_t)i * NSTEN + k));
            }
    }
    /* coarsest level: dense, factored */
    mg_level *L = &mg->lev[mg->nlev - 1];
    int n3 = mg->nc;
    memset(mg->dense, 0, (size_t)n3 * n3 * sizeof *mg->dense);
    if (mg->nlev == 1) {
        for (int i = 0; i < L->n; i++)
            for (int k = A->row_ptr[i]; k < A->row_ptr[i + 1]; k++) {
                int j = A->col[k];
                filter_block(S + 9 * (size_t)i, A->val + 9 * (size_t)k, S + 9 * (size_t)j, B);
                if (i == j)
                    for (int e = 0; e < 9; e++) B[e] += I3[e] - S[9 * (size_t)i + e];
                dense_put(mg->dense, n3, i, j, B);
            }
    } else {
        for (int i = 0; i < L->n; i++)
            for (int k = 0; k < NSTEN; k++) {
                int j = stencil_nb(L, i, k);
                if (j >= 0) dense_put(mg->dense, n3, i, j, L->A + 9 * ((size_t)i * NSTEN + k));
            }
    }
    cholesky(mg->dense, n3);
}

/* ------------------------------------------------------------- smoothing */

/* acc = b_i - sum A_ij x_j over the row's blocks of one triangle or both
 * (part < 0: j < i only; part > 0: j > i only; 0: all j != i), filtered on
 * level 0. */
static void row_residual(const multigrid *mg, int l, int i, const double *x, const double *b, int part,
                         double acc[3])
{
    const mg_level *L = &mg->lev[l];
    acc[0] = b ? b[3 * i] : 0.0;
    acc[1] = b ? b[3 * i + 1] : 0.0;
    acc[2] = b ? b[3 * i + 2] : 0.0;
    double t[3];
    int lo, hi, mid;
    const double *val;
    const int *col = NULL;
    if (l == 0) {
        const bsr *A = mg->A0;
        lo = A->row_ptr[i];
        hi = A->row_ptr[i + 1];
        mid = A->diag[i];
        val = A->val;
        col = A->col;
    } else {
        lo = (int)((size_t)i * NSTEN);
        hi = lo + NSTEN;
        mid = lo + CENTER;
        val = L->A;
    }
    int a = part > 0 ? mid + 1 : lo, z = part < 0 ? mid : hi;
    for (int k = a; k < z; k++) {
        if (k == mid) continue;
        int j = col ? col[k] : L->nb[k];
        if (j < 0) continue;
        mat3vec(val + 9 * (size_t)k, x + 3 * j, t);
        acc[0] -= t[0];
        acc[1] -= t[1];
        acc[2] -= t[2];
    }
    if (l == 0 && mg->constrained[i]) {
        mat3vec(mg->S0 + 9 * (size_t)i, acc, t);
        memcpy(acc, t, sizeof t);
    }
}

/* One block Gauss-Seidel update of node i; part as in row_residual (a
 * forward sweep from x = 0 needs only j < i: the rest of x is still zero). */
static void gs_node(const multigrid *mg, int l, int i, double *x, const double *b, int part)
{
    double acc[3];
    row_residual(mg, l, i, x, b, part, acc);
    mat3vec(mg->lev[l].Dinv + 9 * (size_t)i, acc, x + 3 * i);
}

/* The residual r = b - A x right after a forward Gauss-Seidel sweep that
 * started from x = 0. Each node's update solved its own row exactly against
 * the nodes before it, D_i x_i = b_i - sum_{j<i} A_ij x_j, so what remains is
 * r_i = -sum_{j>i} A_ij x_j: only the strictly upper triangle, half a sweep.
 * (On level 0 D_i is S A_ii S + (I - S) and x_i lies in the free directions,
 * so the same holds for the filtered rows.) */
static void residual_after_forward_sweep(const multigrid *mg, int l, const double *x, double *r)
{
    for (int i = 0; i < mg->lev[l].n; i++) row_residual(mg, l, i, x, NULL, 1, r + 3 * i);
}

static void vcycle(const multigrid *mg, int l, double *x, const double *b)
{
    const mg_level *L = &mg->lev[l];
    size_t n3 = 3 * (size_t)L->n;
    if (l == mg->nlev - 1) {
        cholesky_solve(mg->dense, mg->nc, b, x);
        if (l == 0)
            for (int i = 0; i < L->n; i++)
                if (mg->constrained[i]) {
                    double t[3];
                    mat3vec(mg->S0 + 9 * (size_t)i, x + 3 * i, t);
                    memcpy(x + 3 * i, t, sizeof t);
                }
        return;
    }
    memset(x, 0, n3 * sizeof *x);
    for (int i = 0; i < L->n; i++) gs_node(mg, l, i, x, b, -1);
    residual_after_forward_sweep(mg, l, x, L->r);
    const mg_level *K = &mg->lev[l + 1];
    memset(K->b, 0, 3 * (size_t)K->n * sizeof *K->b);
    for (int i = 0; i < L->n; i++)
        for (int a = 0; a < 4 && L->par[4 * i + a] >= 0; a++) {
            double w = L->w[4 * i + a];
            double *bc = K->b + 3 * L->par[4 * i + a];
            bc[0] += w * L->r[3 * i];
            bc[1] += w * L->r[3 * i + 1];
            bc[2] += w * L->r[3 * i + 2];
        }
    vcycle(mg, l + 1, K->x, K->b);
    for (int i = 0; i < L->n; i++) {
        double e[3] = {0.0, 0.0, 0.0};
        for (int a = 0; a < 4 && L->par[4 * i + a] >= 0; a++) {
            double w = L->w[4 * i + a];
            const double *xc = K->x + 3 * L->par[4 * i + a];
            e[0] += w * xc[0];
            e[1] += w * xc[1];
            e[2] += w * xc[2];
        }
        if (l == 0 && mg->constrained[i]) {
            double t[3];
            mat3vec(mg->S0 + 9 * (size_t)i, e, t);
            memcpy(e, t, sizeof e);
        }
        x[3 * i] += e[0];
        x[3 * i + 1] += e[1];
        x[3 * i + 2] += e[2];
    }
    for (int i = L->n - 1; i >= 0; i--) gs_node(mg, l, i, x, b, 0);
}

void mg_apply(void *ctx, const double *r, double *s)
{
    vcycle((const multigrid *)ctx, 0, s, r);
}
