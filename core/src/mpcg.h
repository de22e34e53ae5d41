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
 * Stops when |S r|_P <= tol |S (b - A z)|_P, |y|_P^2 = y^T Pinv y (see mpcg_solve_pc). */
mpcg_result mpcg_solve(const bsr *A, const double *b, const double *S, const double *z, const double *Pinv, double tol,
                       int max_iter, double *x, double *w);

/* A preconditioner: s = M r for a symmetric positive definite M (on the free
 * directions; the solver filters s afterwards). */
typedef void (*mpcg_precond_fn)(void *ctx, const double *r, double *s);

/* Rigid bodies solved with the cloth (bodies.c): vertex i held by body g has dv_i = S_i w_i + z_i +
 * (I - S_i) J_i u_g, and the CG runs on (w, u) with the operator [S; J^T P] A [S, P J] + diag(0, M),
 * symmetric and definite when A is. */
typedef struct mpcg_bodies {
    int nb;
    const int *vbody;      /* n: body of each vertex, -1 none (constrained only) */
    const double *x;       /* 3n: positions at the step's start (lever arms) */
    const double *com;     /* 3 nb */
    const double *M;       /* 36 nb: 6x6 mass matrices, scaled as the cloth's rows */
    const double *rhs;     /* 6 nb: impulse from everything but the cloth, likewise */
    double *ginv;          /* 36 nb: out of bodies_precond */
    double *u;             /* 6 nb: out, the velocity changes */
    double *r, *p, *q, *s; /* 6 nb each: CG scratch */
} mpcg_bodies;

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
    const mpcg_bodies *bodies; /* NULL: none */
    /* > 0: the reference is no more than |S b|_D^2 (the residual before the
     * constrained components move to z), nor less than this */
    double ref_floor;
    /* 1: A is positive definite by construction (Newton's matrix), so a
     * non-positive curvature or residual weight is a stalled recurrence's
     * rounding: the solve stops there, cut short (CLOTH_FAIL_CG_MAX_ITER) */
    int definite;
    /* > 0 (no bodies): also stop once the error's estimate from the last two
     * updates, in the norm weighted by mass (n values), is within abs_err2's
     * root (Newton's share of its goal) */
    double abs_err2;
    const double *mass;
    int sym_checked; /* 1: A->sym is current for A->val (bsr_check_sym done by the caller) */
} mpcg_problem;

/* bodies.c, the solver's body operations (P->bodies not NULL):
 * out += sum over held vertices of (I - S_i) J_i u */
void bodies_expand(const mpcg_problem *P, const double *u, double *out);
/* out (6 nb) = s_m M u + sum_i J_i^T (I - S_i) t_i (u may be NULL: 0) */
void bodies_reduce(const mpcg_problem *P, const double *t, const double *u, double s_m, double *out);
/* ginv = (M + sum J^T (I - S) A_ii (I - S) J)^-1 per body; -1 when a block
 * is not positive definite (then neither is the system), else 0. */
int bodies_precond(const mpcg_problem *P);
/* out = ginv r (6 nb) */
void bodies_apply_ginv(const mpcg_bodies *B, const double *r, double *out);

/* The start of a solve: r = S (b - A z) and *ref its Dinv-weighted squared norm (u: 3n scratch).
 * Returns 1 when the solve ends here (NaN, A not definite, or nothing to solve: x = z); res says which. */
int mpcg_reference(const mpcg_problem *P, double *x, double *r, double *u, double *ref, mpcg_result *res);

/* x: in, the warm-start guess; out, the solution. w: 6 * 3n doubles. */
mpcg_result mpcg_run(const mpcg_problem *P, double *x, double *w);

/* As mpcg_solve with any preconditioner pc; the norm is weighted by Dinv.
 * w: 6 * 3n doubles. */
mpcg_result mpcg_solve_pc(const bsr *A, const double *b, const double *S, const double *z, const double *Dinv,
                          mpcg_precond_fn pc, void *ctx, double tol, int max_iter, double *x, double *w);

/* y = S_i x_i per vertex (may alias). */
void filter_apply(int n, const double *S, const double *x, double *y);

#endif
