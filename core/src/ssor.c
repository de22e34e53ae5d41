/* Symmetric block Gauss-Seidel (SSOR) preconditioned CG with Eisenstat's trick on the filtered matrix
 * Ah = S A S + (I - S): fewer iterations than block Jacobi at about the same cost per iteration, as
 * the trick folds the product into the sweeps (method and figures: docs/newton.md, "Design notes"). */
#include <math.h>
#include <string.h>
#include "internal.h"
#include "mat3.h"
#include "ssor.h"

/* Ah's blocks from A's: S_i A_ij S_j, and + (I - S_i) on the diagonal; only
 * rows and columns of constrained vertices differ from A. */
static void build_filtered(const bsr *A, const double *S, const unsigned char *cflag, const double *Dinv, double *Ah)
{
    memcpy(Ah, A->val, 9 * (size_t)A->nnzb * sizeof *Ah);
    static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int i = 0; i < A->n; i++)
        for (int k = A->row_ptr[i]; k < A->row_ptr[i + 1]; k++) {
            int j = A->col[k];
            if (!cflag[i] && !cflag[j]) continue;
            double t[9], o[9];
            mat3mul(S + 9 * (size_t)i, A->val + 9 * (size_t)k, t);
            mat3mul(t, S + 9 * (size_t)j, o);
            if (i == j)
                for (int e = 0; e < 9; e++) o[e] += I3[e] - S[9 * (size_t)i + e];
            memcpy(Ah + 9 * (size_t)k, o, sizeof o);
        }
    /* rows of symmetric blocks with a symmetric Dinv_i: the paired loops */
    if (A->sym) {
        unsigned char *fl = A->sym + A->n;
        oc_bsr_check_sym(A, Ah, fl);
        for (int i = 0; i < A->n; i++) fl[i] = fl[i] && mat3_is_sym(Dinv + 9 * (size_t)i);
    }
}

/* y = M x for row i's 3x3 blocks (Dinv_i or the diagonal block): paired on
 * the flagged rows, with the same bits */
MAT3_INLINE void mv_ah(const bsr *A, int i, const double *M, const double *x, double *y)
{
    if (A->sym && A->sym[A->n + i]) mat3vec_sym(M, x, y);
    else mat3vec(M, x, y);
}

/* acc -= sum Ah_ij y_j over the blocks k in [a, z) of row i; rows whose
 * blocks are all symmetric (flags A->sym + n, set by build_filtered) take
 * the paired loop, with the same bits */
MAT3_INLINE void row_sub_ah(int avx, const bsr *A, const double *Ah, int i, int a, int z, const double *y,
                            double acc[3])
{
    if (A->sym && A->sym[A->n + i]) row_sub_symv(avx, Ah, A->col, a, z, y, acc);
    else row_sub(Ah, A->col, a, z, y, acc);
}

/* y = P^-1 v: forward, D_i y_i = v_i - sum_{j<i} Ah_ij y_j */
MAT3_INLINE void forward(int avx, const bsr *A, const double *Ah, const double *Dinv, const double *v, double *y)
{
    for (int i = 0; i < A->n; i++) {
        double acc[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
        row_sub_ah(avx, A, Ah, i, A->row_ptr[i], A->diag[i], y, acc);
        mv_ah(A, i, Dinv + 9 * (size_t)i, acc, y + 3 * i);
    }
}

/* y = Q^-1 v: backward, D_i y_i = v_i - sum_{j>i} Ah_ij y_j */
MAT3_INLINE void backward(int avx, const bsr *A, const double *Ah, const double *Dinv, const double *v, double *y)
{
    for (int i = A->n - 1; i >= 0; i--) {
        double acc[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
        row_sub_ah(avx, A, Ah, i, A->diag[i] + 1, A->row_ptr[i + 1], y, acc);
        mv_ah(A, i, Dinv + 9 * (size_t)i, acc, y + 3 * i);
    }
}

/* One CG iteration's product fused with the vector updates around it (same operations and order, so
 * bitwise the same): p = s + beta p (not on the first), t = Q^-1 p, u = p - D t; forward_pq then
 * gives q = P^-1 u and returns p^T (q + t), the product q + t left as two vectors. */
MAT3_INLINE void backward_p(int avx, const bsr *A, const double *Ah, const double *Dinv, const double *s, double beta,
                            int first, double *p, double *t, double *u)
{
    for (int i = A->n - 1; i >= 0; i--) {
        double *pi = p + 3 * i;
        if (!first) {
            pi[0] = s[3 * i] + beta * pi[0];
            pi[1] = s[3 * i + 1] + beta * pi[1];
            pi[2] = s[3 * i + 2] + beta * pi[2];
        }
        double acc[3] = {pi[0], pi[1], pi[2]}, dt[3];
        row_sub_ah(avx, A, Ah, i, A->diag[i] + 1, A->row_ptr[i + 1], t, acc);
        double *ti = t + 3 * i;
        mv_ah(A, i, Dinv + 9 * (size_t)i, acc, ti);
        mv_ah(A, i, Ah + 9 * (size_t)A->diag[i], ti, dt);
        u[3 * i] = pi[0] - dt[0];
        u[3 * i + 1] = pi[1] - dt[1];
        u[3 * i + 2] = pi[2] - dt[2];
    }
}

MAT3_INLINE double forward_pq(int avx, const bsr *A, const double *Ah, const double *Dinv, const double *u,
                              const double *t, const double *p, double *q)
{
    double pq = 0.0;
    for (int i = 0; i < A->n; i++) {
        double acc[3] = {u[3 * i], u[3 * i + 1], u[3 * i + 2]};
        row_sub_ah(avx, A, Ah, i, A->row_ptr[i], A->diag[i], q, acc);
        double *qi = q + 3 * i;
        mv_ah(A, i, Dinv + 9 * (size_t)i, acc, qi);
        for (int k = 3 * i; k < 3 * i + 3; k++) pq += p[k] * (q[k] + t[k]);
    }
    return pq;
}

/* y = P v (lower triangle with the diagonal) or Q v (upper) */
MAT3_INLINE void tri_mul(int avx, const bsr *A, const double *Ah, int upper, const double *v, double *y)
{
    for (int i = 0; i < A->n; i++) {
        double acc[3] = {0.0, 0.0, 0.0};
        int lo = upper ? A->diag[i] : A->row_ptr[i], hi = upper ? A->row_ptr[i + 1] : A->diag[i] + 1;
        /* (the AVX loop reads a double past a block: not at Ah's last one,
         * the last row's diagonal) */
        if (A->sym && A->sym[A->n + i]) row_add_symv(avx && i + 1 < A->n, Ah, A->col, lo, hi, v, acc);
        else row_add(Ah, A->col, lo, hi, v, acc);
        y[3 * i] = acc[0], y[3 * i + 1] = acc[1], y[3 * i + 2] = acc[2];
    }
}

/* v^T Dinv-weighted norm^2 of v: sum v_i^T Dinv_i v_i; and D-weighted */
static double wnorm2(int n, const double *W, const double *v)
{
    double s = 0.0, t[3];
    for (int i = 0; i < n; i++) {
        mat3vec(W + 9 * (size_t)i, v + 3 * i, t);
        s += v[3 * i] * t[0] + v[3 * i + 1] * t[1] + v[3 * i + 2] * t[2];
    }
    return s;
}

static double dot(const double *a, const double *b, size_t n)
{
    double s = 0.0;
    for (size_t k = 0; k < n; k++) s += a[k] * b[k];
    return s;
}

/* oc_ssor_run's body; avx (a constant): the AVX loops (mat3.h) */
MAT3_INLINE mpcg_result ssor_run_k(int avx, const mpcg_problem *P, const unsigned char *cflag, double *Ah, double *x,
                                   double *w)
{
    const bsr *A = P->A;
    int n = A->n;
    size_t N = 3 * (size_t)n;
    const double *Dinv = P->Dinv;
    double *r = w, *p = w + N, *q = w + 2 * N, *s = w + 3 * N, *t = w + 4 * N, *u = w + 5 * N;
    mpcg_result res = {0, 0.0, CLOTH_FAIL_NONE};
    /* bodies solved with the cloth: the plain modified CG (block Jacobi)
     * carries their unknowns; this one does not */
    if (P->extra) return oc_mpcg_run(P, x, w);
    build_filtered(A, P->S, cflag, Dinv, Ah);
    /* u = rh0 = S (b - A z); ref, the stopping norm's reference */
    double ref;
    if (oc_mpcg_reference(P, x, u, t, &ref, &res)) return res;
    /* warm start xh0 = S x: y0 = Q xh0, r~0 = P^-1 (rh0 - Ah xh0) */
    oc_filter_apply(n, P->S, x, x);
    tri_mul(avx, A, Ah, 1, x, p); /* p = Q xh0 = y0 */
    tri_mul(avx, A, Ah, 0, x, q); /* q = P xh0 */
    /* Ah xh0 = P xh0 + Q xh0 - D xh0 */
    for (int i = 0; i < n; i++) {
        const double *Dii = Ah + 9 * (size_t)A->diag[i];
        double dx[3];
        mat3vec(Dii, x + 3 * i, dx);
        for (int k = 0; k < 3; k++) t[3 * i + k] = q[3 * i + k] + p[3 * i + k] - dx[k];
    }
    for (size_t k = 0; k < N; k++) u[k] -= t[k]; /* u = rh = rh0 - Ah xh0 */
    double *y = x;                               /* y lives in x until the end */
    memcpy(y, p, N * sizeof *y);
    forward(avx, A, Ah, Dinv, u, r); /* r = r~ */
    double tol2 = P->tol * P->tol * ref;
    double true2 = wnorm2(n, Dinv, u);
    /* preconditioner D: s = D r~ */
#define APPLY_D(in, out) \
    for (int i = 0; i < n; i++) mat3vec(Ah + 9 * (size_t)A->diag[i], (in) + 3 * i, (out) + 3 * i)
    APPLY_D(r, s);
    double delta = dot(r, s, N);
    memcpy(p, s, N * sizeof *p);
    /* the true norm over the cheap one at the last check: the true residual
     * is computed (half a pass) only when the cheap one, scaled by it,
     * predicts convergence, or every 16 iterations */
    double ratio = delta > 0.0 ? true2 / delta : 1.0, beta = 0.0;
    int it = 0;
    while (true2 > tol2) {
        if (!(delta > 0.0)) { /* mpcg.h: P->definite */
            res.failure = !isfinite(delta) ? CLOTH_FAIL_NAN
                          : P->definite    ? CLOTH_FAIL_CG_MAX_ITER
                                           : CLOTH_FAIL_CG_INDEFINITE;
            break;
        }
        if (it >= P->max_iter) {
            res.failure = CLOTH_FAIL_CG_MAX_ITER;
            break;
        }
        /* p = s + beta p (from the second iteration on); then
         * P^-1 Ah Q^-1 p = t + P^-1 (p - D t), t = Q^-1 p: q + t */
        backward_p(avx, A, Ah, Dinv, s, beta, it == 0, p, t, u);
        double pq = forward_pq(avx, A, Ah, Dinv, u, t, p, q);
        if (!isfinite(pq)) {
            res.failure = CLOTH_FAIL_NAN;
            break;
        }
        if (pq <= 0.0) { /* mpcg.h: P->definite */
            res.failure = P->definite ? CLOTH_FAIL_CG_MAX_ITER : CLOTH_FAIL_CG_INDEFINITE;
            break;
        }
        double alpha = delta / pq, dnew = 0.0;
        for (int i = 0; i < n; i++) {
            for (int k = 3 * i; k < 3 * i + 3; k++) {
                y[k] += alpha * p[k];
                r[k] -= alpha * (q[k] + t[k]);
            }
            mv_ah(A, i, Ah + 9 * (size_t)A->diag[i], r + 3 * i, s + 3 * i); /* s = D r~ */
            for (int k = 3 * i; k < 3 * i + 3; k++) dnew += r[k] * s[k];
        }
        it++;
        /* the true filtered residual is P r~ */
        if (dnew * ratio <= 1.5 * tol2 || it % 16 == 0) {
            tri_mul(avx, A, Ah, 0, r, u);
            true2 = wnorm2(n, Dinv, u);
            if (dnew > 0.0) ratio = true2 / dnew;
        }
        beta = dnew / delta; /* p = s + beta p: in the next iteration's sweep */
        delta = dnew;
    }
#undef APPLY_D
    /* xh = Q^-1 y; x = z + xh */
    backward(avx, A, Ah, Dinv, y, t);
    for (size_t k = 0; k < N; k++) x[k] = P->z[k] + t[k];
    res.iterations = it;
    res.residual = sqrt(fmax(true2, 0.0) / ref);
    if (res.failure == CLOTH_FAIL_NONE && !isfinite(true2)) res.failure = CLOTH_FAIL_NAN;
    return res;
}

static mpcg_result ssor_run_plain(const mpcg_problem *P, const unsigned char *cflag, double *Ah, double *x, double *w)
{
    return ssor_run_k(0, P, cflag, Ah, x, w);
}

#if MAT3_HAVE_AVX
MAT3_AVX_FN static mpcg_result ssor_run_avx(const mpcg_problem *P, const unsigned char *cflag, double *Ah, double *x,
                                            double *w)
{
    return ssor_run_k(1, P, cflag, Ah, x, w);
}
#endif

mpcg_result oc_ssor_run(const mpcg_problem *P, const unsigned char *cflag, double *Ah, double *x, double *w)
{
#if MAT3_HAVE_AVX
    if (mat3_avx()) return ssor_run_avx(P, cflag, Ah, x, w);
#endif
    return ssor_run_plain(P, cflag, Ah, x, w);
}
