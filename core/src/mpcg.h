/* Baraff and Witkin's modified preconditioned conjugate gradient (mpcg.c). */
#ifndef ODECLOTH_MPCG_H
#define ODECLOTH_MPCG_H

#include "odecloth/cloth.h"
#include "bsr.h"

typedef struct mpcg_result {
    int iterations;
    double residual;       /* final |S r|_P / |S (b - A z)|_P */
    cloth_failure failure; /* NONE, CG_MAX_ITER, CG_INDEFINITE or NAN */
} mpcg_result;

/* Solve A x = b for the free components, the constrained ones held at z (S, Pinv: 9n per-vertex filter
 * and preconditioner blocks; x 3n in: warm start, out: solution with (I - S) x = z; w 6 * 3n scratch).
 * Stops when |S r|_P <= tol |S (b - A z)|_P, |y|_P^2 = y^T Pinv y (see oc_mpcg_solve_pc). */
mpcg_result oc_mpcg_solve(const bsr *A, const double *b, const double *S, const double *z, const double *Pinv,
                          double tol, int max_iter, double *x, double *w);

/* A preconditioner: s = M r for a symmetric positive definite M (on the free
 * directions; the solver filters s afterwards). */
typedef void (*mpcg_precond_fn)(void *ctx, const double *r, double *s);

struct mpcg_problem;

/* Extra unknowns solved with the cloth's (the rigid bodies', bodies.c): the cloth's unknowns gain E y
 * in their constrained components, and the CG runs on (x, y) with the operator [S; E^T] A [S, E] +
 * diag(0, M), symmetric and definite when A is. The operators get ctx and the problem. */
typedef struct mpcg_extra {
    int size;              /* the extra unknowns' count */
    const double *rhs;     /* size: their right-hand side, besides E^T (b - A x) */
    double *y;             /* size: out, the solution */
    double *r, *p, *q, *s; /* size each: CG scratch */
    const void *ctx;       /* the operators' own */
    /* out += E y, on the constrained vertices */
    void (*expand)(const void *ctx, const struct mpcg_problem *P, const double *y, double *out);
    /* out = s_m M y + E^T t (y may be NULL: 0) */
    void (*reduce)(const void *ctx, const struct mpcg_problem *P, const double *t, const double *y, double s_m,
                   double *out);
    /* make G = (M + E^T diag(A) E)^-1 per body (diag(A): A's vertex blocks), the preconditioner and norm
     * weight; -1 when a block is not positive definite (then neither is the system), else 0 */
    int (*factor)(const void *ctx, const struct mpcg_problem *P);
    /* out = G r */
    void (*precondition)(const void *ctx, const double *r, double *out);
} mpcg_extra;

/* The general form used by the step. */
typedef struct mpcg_problem {
    const bsr *A;
    const double *b, *S, *z;
    /* per-vertex blocks weighting the stopping norm |y|_D^2 = y^T Dinv y, so
     * a tolerance means the same whatever the preconditioner */
    const double *Dinv;
    /* the vertices whose filter is not the identity (NULL: treat all as
     * constrained); filtering costs only these */
    const int *con;
    int ncon;
    mpcg_precond_fn pc; /* NULL: block Jacobi with Dinv itself */
    void *ctx;
    double tol;
    int max_iter;
    const mpcg_extra *extra; /* extra unknowns: the rigid bodies solved with the cloth (NULL: none) */
    /* > 0: the reference is no more than |S b|_D^2 (the residual before the
     * constrained components move to z), nor less than this */
    double ref_floor;
    /* 1: A is positive definite by construction (Newton's matrix), so a
     * non-positive curvature or residual weight is a stalled recurrence's
     * rounding: the solve stops there, cut short (CLOTH_FAIL_CG_MAX_ITER) */
    int definite;
    /* > 0 (no extra unknowns): also stop once the error's estimate from the last two
     * updates, in the norm weighted by mass (n values), is within abs_err2's
     * root (Newton's share of its goal) */
    double abs_err2;
    const double *mass;
    int sym_checked; /* 1: A->sym is current for A->val (oc_bsr_check_sym done by the caller) */
} mpcg_problem;

/* The start of a solve: r = S (b - A z) and *ref its Dinv-weighted squared norm (u: 3n scratch).
 * Returns 1 when the solve ends here (NaN, A not definite, or nothing to solve: x = z); res says which. */
int oc_mpcg_reference(const mpcg_problem *P, double *x, double *r, double *u, double *ref, mpcg_result *res);

/* x: in, the warm-start guess; out, the solution. w: 6 * 3n doubles. */
mpcg_result oc_mpcg_run(const mpcg_problem *P, double *x, double *w);

/* As oc_mpcg_solve with any preconditioner pc; the norm is weighted by Dinv.
 * w: 6 * 3n doubles. */
mpcg_result oc_mpcg_solve_pc(const bsr *A, const double *b, const double *S, const double *z, const double *Dinv,
                             mpcg_precond_fn pc, void *ctx, double tol, int max_iter, double *x, double *w);

/* y = S_i x_i per vertex (may alias). */
void oc_filter_apply(int n, const double *S, const double *x, double *y);

#endif
