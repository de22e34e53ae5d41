/* Modified preconditioned CG (Baraff-Witkin 1998 sec. 5.3, with Ascher-Boxerman 2003's fixes: warm
 * start in the free directions, convergence judged on the reduced system S A S). Every direction is
 * filtered, so the constrained components stay exactly at z. */
#include <math.h>
#include <string.h>
#include "mat3.h"
#include "mpcg.h"

void oc_filter_apply(int n, const double *S, const double *x, double *y)
{
    for (int i = 0; i < n; i++) {
        const double *B = S + 9 * (size_t)i, *a = x + 3 * (size_t)i;
        double y0 = B[0] * a[0] + B[1] * a[1] + B[2] * a[2];
        double y1 = B[3] * a[0] + B[4] * a[1] + B[5] * a[2];
        double y2 = B[6] * a[0] + B[7] * a[1] + B[8] * a[2];
        y[3 * i] = y0;
        y[3 * i + 1] = y1;
        y[3 * i + 2] = y2;
    }
}

static double dot(const double *a, const double *b, size_t n)
{
    double s = 0.0;
    for (size_t k = 0; k < n; k++) s += a[k] * b[k];
    return s;
}

mpcg_result oc_mpcg_solve(const bsr *A, const double *b, const double *S, const double *z, const double *Pinv,
                          double tol, int max_iter, double *x, double *w)
{
    mpcg_problem P = {A, b, S, z, Pinv, NULL, 0, NULL, NULL, tol, max_iter, NULL, 0.0, 0, 0.0, NULL, 0};
    return oc_mpcg_run(&P, x, w);
}

mpcg_result oc_mpcg_solve_pc(const bsr *A, const double *b, const double *S, const double *z, const double *Dinv,
                             mpcg_precond_fn pc, void *ctx, double tol, int max_iter, double *x, double *w)
{
    mpcg_problem P = {A, b, S, z, Dinv, NULL, 0, pc, ctx, tol, max_iter, NULL, 0.0, 0, 0.0, NULL, 0};
    return oc_mpcg_run(&P, x, w);
}

/* y = S y in place, on the constrained vertices only (all if con is NULL) */
static void filter_inplace(const mpcg_problem *P, double *y)
{
    if (!P->con) {
        oc_filter_apply(P->A->n, P->S, y, y);
        return;
    }
    for (int k = 0; k < P->ncon; k++) {
        int i = P->con[k];
        oc_filter_apply(1, P->S + 9 * (size_t)i, y + 3 * (size_t)i, y + 3 * (size_t)i);
    }
}

/* The fused loops of oc_mpcg_run (no extra unknowns): the separate passes' operations and ascending dot product
 * order, so bitwise the same with fewer passes. `fil` walks the ascending list of constrained vertices
 * (all when P->con is NULL): is vertex i filtered? */
typedef struct con_walk {
    const int *con;
    int ncon, k;
} con_walk;

static inline int con_next(con_walk *w, int i)
{
    if (!w->con) return 1;
    if (w->k < w->ncon && w->con[w->k] == i) {
        w->k++;
        return 1;
    }
    return 0;
}

/* y_i = S_i y_i (oc_filter_apply's arithmetic, which is mat3vec's) */
static inline void filter3(const double *Si, double *y)
{
    double a[3] = {y[0], y[1], y[2]};
    mat3vec(Si, a, y);
}

/* q = S A p; returns p^T q. avx (a constant): the AVX loops (mat3.h), on
 * all rows but the last (whose last block, the matrix's last, they cannot
 * read: they read a double past a block). */
MAT3_INLINE double mul_filter_dot_k(int avx, const mpcg_problem *P, const double *p, double *q)
{
    const bsr *A = P->A;
    con_walk w = {P->con, P->ncon, 0};
    double pq = 0.0;
    for (int i = 0; i < A->n; i++) {
        double acc[3] = {0.0, 0.0, 0.0};
        if (A->sym && A->sym[i])
            row_add_symv(avx && i + 1 < A->n, A->val, A->col, A->row_ptr[i], A->row_ptr[i + 1], p, acc);
        else row_add(A->val, A->col, A->row_ptr[i], A->row_ptr[i + 1], p, acc);
        double *qi = q + 3 * (size_t)i;
        qi[0] = acc[0];
        qi[1] = acc[1];
        qi[2] = acc[2];
        if (con_next(&w, i)) filter3(P->S + 9 * (size_t)i, qi);
        for (int k = 0; k < 3; k++) pq += p[3 * (size_t)i + k] * qi[k];
    }
    return pq;
}

static double mul_filter_dot_plain(const mpcg_problem *P, const double *p, double *q)
{
    return mul_filter_dot_k(0, P, p, q);
}

#if MAT3_HAVE_AVX
MAT3_AVX_FN static double mul_filter_dot_avx(const mpcg_problem *P, const double *p, double *q)
{
    return mul_filter_dot_k(1, P, p, q);
}
#endif

static double mul_filter_dot(const mpcg_problem *P, const double *p, double *q)
{
#if MAT3_HAVE_AVX
    if (mat3_avx()) return mul_filter_dot_avx(P, p, q);
#endif
    return mul_filter_dot_plain(P, p, q);
}

/* x += alpha p, r -= alpha q; block Jacobi: s = S Dinv r and returns
 * r^T s */
static double update_jacobi(const mpcg_problem *P, double alpha, const double *p, const double *q, double *x, double *r,
                            double *s)
{
    con_walk w = {P->con, P->ncon, 0};
    double rs = 0.0;
    for (int i = 0; i < P->A->n; i++) {
        size_t o = 3 * (size_t)i;
        for (size_t k = o; k < o + 3; k++) {
            x[k] += alpha * p[k];
            r[k] -= alpha * q[k];
        }
        mat3vec(P->Dinv + 9 * (size_t)i, r + o, s + o);
        if (con_next(&w, i)) filter3(P->S + 9 * (size_t)i, s + o);
        for (size_t k = o; k < o + 3; k++) rs += r[k] * s[k];
    }
    return rs;
}

/* r^T s, and *rr = r^T Dinv r (u = Dinv r) */
static double dots_pc(const mpcg_problem *P, const double *r, const double *s, double *u, double *rr)
{
    double rs = 0.0, ru = 0.0;
    for (int i = 0; i < P->A->n; i++) {
        size_t o = 3 * (size_t)i;
        mat3vec(P->Dinv + 9 * (size_t)i, r + o, u + o);
        for (size_t k = o; k < o + 3; k++) {
            rs += r[k] * s[k];
            ru += r[k] * u[k];
        }
    }
    *rr = ru;
    return rs;
}

/* is the list of constrained vertices ascending (as the walks need)? */
static int con_sorted(const mpcg_problem *P)
{
    for (int k = 1; P->con && k < P->ncon; k++)
        if (P->con[k] <= P->con[k - 1]) return 0;
    return 1;
}

int oc_mpcg_reference(const mpcg_problem *P, double *x, double *r, double *u, double *ref, mpcg_result *res)
{
    size_t N = 3 * (size_t)P->A->n;
    const mpcg_extra *E = P->extra;
    double free_ref = INFINITY;
    if (P->ref_floor > 0.0) {
        memcpy(r, P->b, N * sizeof *r);
        filter_inplace(P, r);
        oc_filter_apply(P->A->n, P->Dinv, r, u);
        free_ref = fmax(dot(r, u, N), P->ref_floor);
    }
    /* z is zero but at the constrained vertices */
    oc_bsr_mul_cols(P->A, P->z, P->con, P->ncon, u);
    for (size_t k = 0; k < N; k++) r[k] = P->b[k] - u[k];
    double bref = 0.0;
    if (E) {
        /* the extra rows at y = 0: rhs + E^T (b - A z), weighted by G */
        if (E->factor(E->ctx, P)) {
            res->failure = CLOTH_FAIL_CG_INDEFINITE;
            return 1;
        }
        E->reduce(E->ctx, P, r, NULL, 0.0, E->r);
        for (int k = 0; k < E->size; k++) E->r[k] += E->rhs[k];
        E->precondition(E->ctx, E->r, E->s);
        bref = dot(E->r, E->s, (size_t)E->size);
    }
    filter_inplace(P, r);
    oc_filter_apply(P->A->n, P->Dinv, r, u);
    *ref = fmin(dot(r, u, N), free_ref) + bref;
    if (!isfinite(*ref)) {
        res->failure = CLOTH_FAIL_NAN;
        return 1;
    }
    if (*ref < 0.0) {
        /* the norm's weights, the inverse diagonal blocks, are not positive
         * definite: then neither is A */
        res->failure = CLOTH_FAIL_CG_INDEFINITE;
        return 1;
    }
    if (*ref == 0.0) { /* nothing to solve: x = z */
        memcpy(x, P->z, N * sizeof *x);
        return 1;
    }
    return 0;
}

/* Is the error left after the update alpha p within P->abs_err2? Estimated
 * in the mass norm as a geometric tail at the ratio r of this update to the
 * one before (*before, squared, updated): |alpha p|^2 r^2 / (1 - r)^2. */
static int tail_within(const mpcg_problem *P, const double *p, double alpha, double *before)
{
    double last = 0.0;
    for (int i = 0; i < P->A->n; i++) {
        const double *pi = p + 3 * (size_t)i;
        last += P->mass[i] * (pi[0] * pi[0] + pi[1] * pi[1] + pi[2] * pi[2]);
    }
    last *= alpha * alpha;
    double r = sqrt(last / *before), first = !(*before < INFINITY);
    *before = last;
    return !first && r < 1.0 && last * r * r <= P->abs_err2 * (1.0 - r) * (1.0 - r);
}

mpcg_result oc_mpcg_run(const mpcg_problem *P, double *x, double *w)
{
    const bsr *A = P->A;
    const double *b = P->b, *z = P->z, *Dinv = P->Dinv;
    int n = A->n;
    size_t N = 3 * (size_t)n;
    double *r = w, *p = w + N, *q = w + 2 * N, *s = w + 3 * N, *t = w + 4 * N, *u = w + 5 * N;
    mpcg_result res = {0, 0.0, CLOTH_FAIL_NONE};
    double tol = P->tol;
    int max_iter = P->max_iter;
    /* Extra unknowns (P->extra): the vectors' tails E->y, r, p, q, s of
     * length NE; their preconditioner and norm weight is E's G. */
    const mpcg_extra *E = P->extra;
    size_t NE = E ? (size_t)E->size : 0;
    /* s = S M r (the filtered preconditioned residual). With block Jacobi
     * (pc NULL) M = Dinv, and the norm r^T Dinv r is r^T s: no second product. */
#define PRECONDITION()                              \
    do {                                            \
        if (P->pc) P->pc(P->ctx, r, s);             \
        else oc_filter_apply(n, Dinv, r, s);        \
        filter_inplace(P, s);                       \
        if (E) E->precondition(E->ctx, E->r, E->s); \
    } while (0)
#define NORM2() (oc_filter_apply(n, Dinv, r, u), dot(r, u, N) + (E ? dot(E->r, E->s, NE) : 0.0))
#define DOT(a, b) (dot(a, b, N) + (E ? dot(E->a, E->b, NE) : 0.0))

    /* reference: the reduced right-hand side S (b - A z) */
    double ref;
    if (oc_mpcg_reference(P, x, r, t, &ref, &res)) return res;

    /* x = S guess + z (and the extra y = 0) */
    filter_inplace(P, x);
    for (size_t k = 0; k < N; k++) x[k] += z[k];
    oc_bsr_mul(A, x, t);
    if (A->sym && !P->sym_checked) oc_bsr_check_sym(A, A->val, A->sym); /* for oc_bsr_mul_sym below */
    for (size_t k = 0; k < N; k++) r[k] = b[k] - t[k];
    if (E) { /* the extra residual rhs - M y + E^T (b - A x) at y = 0 */
        memset(E->y, 0, NE * sizeof *E->y);
        E->reduce(E->ctx, P, r, NULL, 0.0, E->r);
        for (size_t k = 0; k < NE; k++) E->r[k] += E->rhs[k];
    }
    filter_inplace(P, r);
    PRECONDITION();
    double delta = DOT(r, s), rr = P->pc ? NORM2() : delta;
    memcpy(p, s, N * sizeof *p);
    if (E) memcpy(E->p, E->s, NE * sizeof *E->p);
    double tol2 = tol * tol * ref;
    /* the fused loops: without extra unknowns, with the constrained list ascending */
    int fused = !E && con_sorted(P);

    int it = 0;
    double before = INFINITY; /* the last update's squared mass norm */
    /* |rr| within tol2 has converged: a rounding-level residual can weigh in slightly negative, and
     * only a negative norm beyond tol2 means the matrix is not definite */
    while (rr > tol2 || rr < -tol2) {
        if (!(delta > 0.0) || rr < 0.0) { /* r^T M r <= 0, or a negative norm weight: not definite (mpcg.h) */
            res.failure = !isfinite(delta) ? CLOTH_FAIL_NAN
                          : P->definite    ? CLOTH_FAIL_CG_MAX_ITER
                                           : CLOTH_FAIL_CG_INDEFINITE;
            break;
        }
        if (it >= max_iter) {
            res.failure = CLOTH_FAIL_CG_MAX_ITER;
            break;
        }
        if (E) { /* q = [S; E^T] A (p + E p_y) + (0, M p_y) */
            memcpy(t, p, N * sizeof *t);
            E->expand(E->ctx, P, E->p, t);
            oc_bsr_mul_sym(A, t, q);
            E->reduce(E->ctx, P, q, E->p, 1.0, E->q);
        } else if (!fused) {
            oc_bsr_mul_sym(A, p, q);
        }
        double pq;
        if (fused) {
            pq = mul_filter_dot(P, p, q) + 0.0; /* + 0.0: as DOT adds the (absent) extra part */
        } else {
            filter_inplace(P, q);
            pq = DOT(p, q);
        }
        if (!isfinite(pq)) {
            res.failure = CLOTH_FAIL_NAN;
            break;
        }
        if (pq <= 0.0) { /* non-positive curvature: A is not definite on the free space */
            res.failure = P->definite ? CLOTH_FAIL_CG_MAX_ITER : CLOTH_FAIL_CG_INDEFINITE;
            break;
        }
        double alpha = delta / pq, dnew;
        if (fused && !P->pc) {
            dnew = update_jacobi(P, alpha, p, q, x, r, s) + 0.0;
            rr = dnew;
        } else {
            for (size_t k = 0; k < N; k++) {
                x[k] += alpha * p[k];
                r[k] -= alpha * q[k];
            }
            for (size_t k = 0; k < NE; k++) {
                E->y[k] += alpha * E->p[k];
                E->r[k] -= alpha * E->q[k];
            }
            PRECONDITION();
            if (fused) {
                double ru;
                dnew = dots_pc(P, r, s, u, &ru) + 0.0;
                rr = ru + 0.0;
            } else {
                dnew = DOT(r, s);
                rr = P->pc ? NORM2() : dnew;
            }
        }
        if (P->abs_err2 > 0.0 && !E && tail_within(P, p, alpha, &before)) {
            it++;
            break;
        }
        double beta = dnew / delta;
        for (size_t k = 0; k < N; k++) p[k] = s[k] + beta * p[k];
        for (size_t k = 0; k < NE; k++) E->p[k] = E->s[k] + beta * E->p[k];
        delta = dnew;
        it++;
    }
    if (E) E->expand(E->ctx, P, E->y, x); /* the constrained components follow the extra unknowns */
    res.iterations = it;
    res.residual = sqrt(fmax(rr, 0.0) / ref);
    if (res.failure == CLOTH_FAIL_NONE && !isfinite(rr)) res.failure = CLOTH_FAIL_NAN;
    return res;
#undef PRECONDITION
#undef NORM2
#undef DOT
}
