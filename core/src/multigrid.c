/* Geometric multigrid V-cycle preconditioner for the modified PCG: keeps the CG's iteration count
 * nearly flat in the grid's width, where diagonal preconditioners let it grow. Design (coarsening,
 * Galerkin operators, constraint filtering, smoothers, storage): docs/newton.md, "Design notes". */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "mat3.h"
#include "multigrid.h"
#include "tuning.h"

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

void oc_mg_free(multigrid *mg)
{
    for (int l = 0; l < MG_MAX_LEVELS; l++) {
        mg_level *L = &mg->lev[l];
        oc_bsr_free(&L->M);
        if (l > 0) free(L->Dinv);
        free(L->x);
        free(L->b);
        free(L->par);
        free(L->w);
        free(L->slot);
        free(L->rc);
        free(L->symrow);
        oc_galerkin_plan_free(&L->gp);
        free(L->fidx);
        free(L->fbuf);
    }
    free(mg->dense);
    memset(mg, 0, sizeof *mg);
}

/* The coarsest level's node count for an R x C grid (the levels of
 * oc_mg_create, without allocating). */
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

static int on_grid(const mg_level *L, int i, int k, int *j)
{
    int r2 = L->rc[2 * i] + k / 5 - 2, c2 = L->rc[2 * i + 1] + k % 5 - 2;
    *j = r2 * L->C + c2;
    return r2 >= 0 && r2 < L->R && c2 >= 0 && c2 < L->C;
}

/* A coarse level's block-CSR pattern: the 5x5 stencil's neighbours on the
 * grid, in stencil order (= ascending column); slot maps stencil offsets to
 * blocks. 0, or -1 on no memory. */
static int level_pattern(mg_level *L)
{
    bsr *M = &L->M;
    int nnzb = 0, j;
    for (int i = 0; i < L->n; i++)
        for (int k = 0; k < NSTEN; k++) nnzb += on_grid(L, i, k, &j);
    M->n = L->n;
    M->nnzb = nnzb;
    M->row_ptr = malloc(((size_t)L->n + 1) * sizeof *M->row_ptr);
    M->col = malloc((size_t)nnzb * sizeof *M->col);
    M->diag = malloc((size_t)L->n * sizeof *M->diag);
    M->val = calloc(9 * (size_t)nnzb + 1, sizeof *M->val); /* + the AVX rows' padding double (mat3.h) */
    L->slot = malloc(NSTEN * (size_t)L->n * sizeof *L->slot);
    if (!M->row_ptr || !M->col || !M->diag || !M->val || !L->slot) return -1;
    int b = 0;
    for (int i = 0; i < L->n; i++) {
        M->row_ptr[i] = b;
        for (int k = 0; k < NSTEN; k++) {
            if (!on_grid(L, i, k, &j)) {
                L->slot[NSTEN * i + k] = -1;
                continue;
            }
            if (k == CENTER) M->diag[i] = b;
            L->slot[NSTEN * i + k] = b;
            M->col[b++] = j;
        }
    }
    M->row_ptr[L->n] = b;
    return 0;
}

int oc_mg_create(multigrid *mg, int R, int C, const bsr *A0)
{
    memset(mg, 0, sizeof *mg);
    /* the coarsest level is solved densely: a grid that does not coarsen
     * (a side under 5 nodes) is refused, as its dense matrix can be huge */
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
        K->Dinv = malloc(9 * (size_t)K->n * sizeof *K->Dinv);
        if (!F->par || !F->w || !K->Dinv) goto fail;
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
        L->rc = malloc(2 * (size_t)L->n * sizeof *L->rc);
        L->symrow = calloc((size_t)L->n, 1);
        if (!L->x || !L->b || !L->rc || !L->symrow) goto fail;
        for (int i = 0; i < L->n; i++) {
            L->rc[2 * i] = i / L->C;
            L->rc[2 * i + 1] = i % L->C;
        }
        if (l > 0 && level_pattern(L) != 0) goto fail;
    }
    for (l = 0; l + 1 < mg->nlev; l++) {
        mg_level *F = &mg->lev[l], *K = &mg->lev[l + 1];
        if (oc_galerkin_plan_make(&F->gp, l ? &F->M : A0, F->par, F->w, &K->M, K->slot, K->rc) != 0) goto fail;
    }
    if (mg->nlev > 1) {
        mg->lev[0].fidx = malloc((size_t)A0->nnzb * sizeof *mg->lev[0].fidx);
        mg->lev[0].fbuf = malloc(9 * (size_t)A0->nnzb * sizeof *mg->lev[0].fbuf);
        if (!mg->lev[0].fidx || !mg->lev[0].fbuf) goto fail;
    }
    mg->nc = 3 * mg->lev[mg->nlev - 1].n;
    mg->dense = malloc((size_t)mg->nc * mg->nc * sizeof *mg->dense);
    if (!mg->dense) goto fail;
    return 0;
fail:
    oc_mg_free(mg);
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

/* Inverse of a symmetric block regularised by 1e-10 of its trace, so a coarse node whose support is
 * wholly or partly constrained stays finite; the residual in those directions is zero. */
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

/* In-place (lower) Cholesky of the coarsest level's dense matrix; a non-positive pivot is replaced so
 * the V-cycle stays defined, and CG, seeing the true matrix, reports the curvature itself. */
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

/* row i's blocks and its inverse diagonal block all exactly symmetric */
static int row_symmetric(const bsr *A, const double *Dinv, int i)
{
    int sym = mat3_is_sym(Dinv + 9 * (size_t)i);
    for (int k = A->row_ptr[i]; k < A->row_ptr[i + 1]; k++) sym = sym && mat3_is_sym(A->val + 9 * (size_t)k);
    return sym;
}

void oc_mg_setup(multigrid *mg, const bsr *A, const double *S, const unsigned char *constrained, double *Dinv0)
{
    mg->A0 = A;
    mg->S0 = S;
    mg->constrained = constrained;
    mg->lev[0].Dinv = Dinv0;
    double B[9];
    /* level 0 -> 1 from the BSR matrix, its blocks at constraints filtered */
    if (mg->nlev > 1) {
        mg_level *F = &mg->lev[0];
        int nf = 0;
        if (A->sym) oc_bsr_check_sym(A, A->val, A->sym);
        for (int i = 0; i < F->n; i++) {
            F->symrow[i] = (unsigned char)(A->sym ? A->sym[i] && mat3_is_sym(Dinv0 + 9 * (size_t)i)
                                                  : row_symmetric(A, Dinv0, i));
            for (int k = A->diag[i]; k < A->row_ptr[i + 1]; k++) {
                int j = A->col[k];
                F->fidx[k] = constrained[i] || constrained[j] ? nf : -1;
                if (F->fidx[k] < 0) continue;
                filter_block(S + 9 * (size_t)i, A->val + 9 * (size_t)k, S + 9 * (size_t)j, F->fbuf + 9 * (size_t)nf);
                nf++;
            }
        }
        oc_galerkin_apply(&F->gp, A->val, F->fbuf, F->fidx, &mg->lev[1].M);
    }
    for (int l = 1; l < mg->nlev; l++) {
        mg_level *L = &mg->lev[l];
        const bsr *M = &L->M;
        for (int i = 0; i < L->n; i++) inv_reg(M->val + 9 * (size_t)M->diag[i], L->Dinv + 9 * (size_t)i);
        if (l + 1 == mg->nlev) break;
        for (int i = 0; i < L->n; i++) L->symrow[i] = (unsigned char)row_symmetric(M, L->Dinv, i);
        oc_galerkin_apply(&L->gp, M->val, NULL, NULL, &mg->lev[l + 1].M);
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
        const bsr *M = &L->M;
        for (int i = 0; i < L->n; i++)
            for (int k = M->row_ptr[i]; k < M->row_ptr[i + 1]; k++)
                dense_put(mg->dense, n3, i, M->col[k], M->val + 9 * (size_t)k);
    }
    cholesky(mg->dense, n3);
}

/* ------------------------------------------------------------- smoothing */

/* acc -= sum A_ij x_j over row i's blocks k in [a, z), each block summed as mat3vec does (mat3.h),
 * symmetric rows by the paired loop with the same bits. */
MAT3_INLINE void level_row_sub(int avx, const bsr *A, const unsigned char *symrow, int i, int a, int z, const double *x,
                               double acc[3])
{
    if (symrow[i]) row_sub_symv(avx, A->val, A->col, a, z, x, acc);
    else row_sub(A->val, A->col, a, z, x, acc);
}

/* acc = S_i acc on level 0's constrained vertices. The sweeps filter D_i^-1's
 * output too: it maps S_i's range into itself only up to rounding, which the
 * block's condition amplifies, and CG stalls on what leaks. */
static inline void filter_row(const multigrid *mg, int l, int i, double acc[3])
{
    if (l == 0 && mg->constrained[i]) {
        double t[3];
        mat3vec(mg->S0 + 9 * (size_t)i, acc, t);
        memcpy(acc, t, sizeof t);
    }
}

static inline const bsr *level_matrix(const multigrid *mg, int l) { return l ? &mg->lev[l].M : mg->A0; }

/* Fetch row i's blocks and inverse diagonal block into the cache */
MAT3_INLINE void prefetch_row(const bsr *A, const double *Dinv, int i)
{
#if defined(__GNUC__)
    const char *p = (const char *)(A->val + 9 * (size_t)A->row_ptr[i]);
    const char *end = (const char *)(A->val + 9 * (size_t)A->row_ptr[i + 1]);
    for (; p < end; p += 64) __builtin_prefetch(p);
    __builtin_prefetch(Dinv + 9 * (size_t)i);
#else
    (void)A, (void)Dinv, (void)i;
#endif
}

/* Backward block Gauss-Seidel, D_i x_i = b_i - sum_{j != i} A_ij x_j, i descending, filtered on
 * level 0. It never reads a diagonal block in the row loops, so never the last block the AVX loop
 * could not read past. */
MAT3_INLINE void backward_sweep_k(int avx, const multigrid *mg, int l, double *x, const double *b)
{
    const bsr *A = level_matrix(mg, l);
    const double *Dinv = mg->lev[l].Dinv;
    const unsigned char *sym = mg->lev[l].symrow;
    for (int i = A->n - 1; i >= 0; i--) {
        if (i >= SWEEP_PREFETCH_ROWS) prefetch_row(A, Dinv, i - SWEEP_PREFETCH_ROWS);
        double acc[3] = {b[3 * i], b[3 * i + 1], b[3 * i + 2]};
        level_row_sub(avx, A, sym, i, A->row_ptr[i], A->diag[i], x, acc);
        level_row_sub(avx, A, sym, i, A->diag[i] + 1, A->row_ptr[i + 1], x, acc);
        filter_row(mg, l, i, acc);
        if (sym[i]) mat3vec_sym(Dinv + 9 * (size_t)i, acc, x + 3 * i);
        else mat3vec(Dinv + 9 * (size_t)i, acc, x + 3 * i);
        filter_row(mg, l, i, x + 3 * i);
    }
}

/* Forward block Gauss-Seidel from x = 0, fused with restricting its residual (bc = W^T r): what
 * remains is r_i = -sum_{j>i} A_ij x_j, taken a band behind the sweep while its blocks are in cache,
 * so one pass over the matrix; residuals reach parents in ascending order, as a separate pass would. */
MAT3_INLINE void forward_sweep_restrict_k(int avx, const multigrid *mg, int l, double *x, const double *b, double *bc)
{
    const mg_level *L = &mg->lev[l];
    const bsr *A = level_matrix(mg, l);
    const double *Dinv = L->Dinv;
    const unsigned char *sym = L->symrow;
    const int *row_ptr = A->row_ptr, *diag = A->diag, *col = A->col;
    memset(bc, 0, 3 * (size_t)mg->lev[l + 1].n * sizeof *bc);
    int p = 0; /* the next row whose residual is pending */
    for (int i = 0; i <= A->n; i++) {
        if (i + SWEEP_PREFETCH_ROWS < A->n) prefetch_row(A, Dinv, i + SWEEP_PREFETCH_ROWS);
        if (i < A->n) {
            double acc[3] = {b[3 * i], b[3 * i + 1], b[3 * i + 2]};
            level_row_sub(avx, A, sym, i, row_ptr[i], diag[i], x, acc);
            filter_row(mg, l, i, acc);
            if (sym[i]) mat3vec_sym(Dinv + 9 * (size_t)i, acc, x + 3 * i);
            else mat3vec(Dinv + 9 * (size_t)i, acc, x + 3 * i);
            filter_row(mg, l, i, x + 3 * i);
        }
        /* rows whose neighbours are all updated (all rows at the end) */
        for (; p <= i && p < A->n && (i == A->n || col[row_ptr[p + 1] - 1] <= i); p++) {
            double r[3] = {0.0, 0.0, 0.0};
            level_row_sub(avx, A, sym, p, diag[p] + 1, row_ptr[p + 1], x, r);
            filter_row(mg, l, p, r);
            for (int a = 0; a < 4 && L->par[4 * p + a] >= 0; a++) {
                double w = L->w[4 * p + a];
                double *bi = bc + 3 * L->par[4 * p + a];
                bi[0] += w * r[0];
                bi[1] += w * r[1];
                bi[2] += w * r[2];
            }
        }
    }
}

/* the sweeps with the plain and the AVX loops (mat3.h) */
static void backward_sweep_plain(const multigrid *mg, int l, double *x, const double *b)
{
    backward_sweep_k(0, mg, l, x, b);
}

static void forward_sweep_restrict_plain(const multigrid *mg, int l, double *x, const double *b, double *bc)
{
    forward_sweep_restrict_k(0, mg, l, x, b, bc);
}

#if MAT3_HAVE_AVX
MAT3_AVX_FN static void backward_sweep_avx(const multigrid *mg, int l, double *x, const double *b)
{
    backward_sweep_k(1, mg, l, x, b);
}

MAT3_AVX_FN static void forward_sweep_restrict_avx(const multigrid *mg, int l, double *x, const double *b, double *bc)
{
    forward_sweep_restrict_k(1, mg, l, x, b, bc);
}
#endif

static void backward_sweep(int avx, const multigrid *mg, int l, double *x, const double *b)
{
#if MAT3_HAVE_AVX
    if (avx) {
        backward_sweep_avx(mg, l, x, b);
        return;
    }
#endif
    (void)avx;
    backward_sweep_plain(mg, l, x, b);
}

static void forward_sweep_restrict(int avx, const multigrid *mg, int l, double *x, const double *b, double *bc)
{
#if MAT3_HAVE_AVX
    if (avx) {
        forward_sweep_restrict_avx(mg, l, x, b, bc);
        return;
    }
#endif
    (void)avx;
    forward_sweep_restrict_plain(mg, l, x, b, bc);
}

/* avx: mat3_avx() */
static void vcycle(int avx, const multigrid *mg, int l, double *x, const double *b)
{
    const mg_level *L = &mg->lev[l];
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
    const mg_level *K = &mg->lev[l + 1];
    forward_sweep_restrict(avx, mg, l, x, b, K->b);
    vcycle(avx, mg, l + 1, K->x, K->b);
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
    backward_sweep(avx, mg, l, x, b);
}

void oc_mg_apply(void *ctx, const double *r, double *s) { vcycle(mat3_avx(), (const multigrid *)ctx, 0, s, r); }
