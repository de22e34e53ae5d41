/* The implicit steps' linear solve (linsolve.h). */
#include <math.h>
#include <string.h>
#include "linsolve.h"
#include "mat3.h"
#include "ssor.h"

static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

/* Per-vertex inverse diagonal blocks of the filtered matrix S A_ii S + (I - S): the stopping norm's
 * weight, the block-Jacobi preconditioner and the multigrid smoother (a vertex sliding on a plane
 * gets its own 2x2 free block); also the scalar Jacobi inverse (Baraff-Witkin's choice). */
static void build_preconditioner(cloth *c)
{
    for (int i = 0; i < c->n; i++) {
        const double *Aii = c->A.val + 9 * (size_t)c->A.diag[i], *S = c->S + 9 * (size_t)i;
        double *P = c->pre + 9 * (size_t)i;
        for (int r = 0; r < 3; r++) c->jac[3 * i + r] = Aii[4 * r] > 0.0 ? 1.0 / Aii[4 * r] : 1.0;
        double SA[9], SAS[9];
        mat3mul(S, Aii, SA);
        mat3mul(SA, S, SAS);
        for (int k = 0; k < 9; k++) SAS[k] += I3[k] - S[k];
        double det = mat3inv(SAS, P);
        if (det != 0.0 && isfinite(det)) continue;
        /* singular block (only without the definiteness rule, or zero mass) */
        memset(P, 0, 9 * sizeof *P);
        for (int r = 0; r < 3; r++) P[4 * r] = Aii[4 * r] > 0.0 ? 1.0 / Aii[4 * r] : 1.0;
    }
}

typedef struct jacobi_ctx {
    int n;
    const double *d;
} jacobi_ctx;

static void jacobi_apply(void *ctx, const double *r, double *s)
{
    const jacobi_ctx *j = ctx;
    for (size_t k = 0; k < 3 * (size_t)j->n; k++) s[k] = j->d[k] * r[k];
}

/* The preconditioner the solve uses, CLOTH_PRECOND_AUTO resolved:
 * multigrid for Newton where its levels were made (cloth.c), else block
 * Jacobi. */
static cloth_precond precond_used(const cloth *c)
{
    const cloth_solver *sv = &c->desc.solver;
    if (sv->precond != CLOTH_PRECOND_AUTO) return sv->precond;
    return sv->nonlinear == CLOTH_NEWTON && c->mg.nlev > 0 ? CLOTH_PRECOND_MULTIGRID : CLOTH_PRECOND_BLOCK_JACOBI;
}

mpcg_result oc_linsolve_run(cloth *c, mpcg_problem *P, double *x)
{
    cloth_precond pc = precond_used(c);
    jacobi_ctx j = {c->n, c->jac};
    build_preconditioner(c);
    P->pc = NULL;
    P->ctx = NULL;
    if (pc == CLOTH_PRECOND_MULTIGRID) {
        oc_mg_setup(&c->mg, &c->A, c->S, c->cflag, c->pre);
        P->sym_checked = c->mg.nlev > 1; /* oc_mg_setup checked A->sym */
        P->pc = oc_mg_apply;
        P->ctx = &c->mg;
    } else if (pc == CLOTH_PRECOND_JACOBI) {
        P->pc = jacobi_apply;
        P->ctx = &j;
    }
    mpcg_result r = pc == CLOTH_PRECOND_SSOR ? oc_ssor_run(P, c->cflag, c->Ah, x, c->cg) : oc_mpcg_run(P, x, c->cg);
    P->ctx = NULL;
    P->pc = NULL;
    P->sym_checked = 0;
    return r;
}
