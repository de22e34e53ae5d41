/* Rigid bodies solved with the cloth (cloth_body, cloth.h): each body's six velocity unknowns join
 * the modified CG (mpcg.c), a held vertex moving with the body's point velocity J_i u = u_lin +
 * u_ang x r_i in its constrained directions. API, per-step set-up and the solver's body operations. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

/* workspace per body, in doubles: M ginv (36 each), rhs u r p q s (6 each),
 * com (3), then for the elongation limit minv (36), F and D (6 each) */
enum {
    WS_PER_BODY = 2 * 36 + 6 * 6 + 3 + 36 + 12 + 6 + 6 + 6
}; /* + U (6): the substep retry's sum of du;
                                                                    + the Newton iterations' first du (6);
                                                                    + their saved du (6) */

/* P_i = I - S_i applied to a 3-vector */
static void con_project(const double *S, const double *a, double *o)
{
    for (int r = 0; r < 3; r++) o[r] = a[r] - (S[3 * r] * a[0] + S[3 * r + 1] * a[1] + S[3 * r + 2] * a[2]);
}

/* P J as a 3 x 6 matrix (row-major), J = [I, -[r]x]: J u = u_lin + u_ang x r */
static void pj_matrix(const double *S, const double r[3], double PJ[18])
{
    const double J[18] = {1, 0, 0, 0, r[2], -r[1], 0, 1, 0, -r[2], 0, r[0], 0, 0, 1, r[1], -r[0], 0};
    for (int col = 0; col < 6; col++) {
        double a[3] = {J[col], J[6 + col], J[12 + col]}, pa[3];
        con_project(S, a, pa);
        for (int row = 0; row < 3; row++) PJ[6 * row + col] = pa[row];
    }
}

static int spd6_inverse(const double *A, double *out);

static int body_valid(const cloth_body *b, char *why, size_t len, int k)
{
    if (!(b->mass > 0.0) || !isfinite(b->mass)) {
        snprintf(why, len, "body %d: mass %g must be finite and > 0", k, b->mass);
        return 0;
    }
    for (int a = 0; a < 9; a++)
        if (!isfinite(b->inertia[a])) {
            snprintf(why, len, "body %d: inertia must be finite", k);
            return 0;
        }
    for (int r = 0; r < 3; r++)
        for (int s = r + 1; s < 3; s++)
            if (fabs(b->inertia[3 * r + s] - b->inertia[3 * s + r]) >
                1e-9 * (fabs(b->inertia[3 * r + s]) + fabs(b->inertia[3 * s + r])) + 1e-300) {
                snprintf(why, len, "body %d: inertia must be symmetric", k);
                return 0;
            }
    double M[36] = {0}, Mi[36];
    for (int r = 0; r < 3; r++) {
        M[7 * r] = b->mass;
        for (int s = 0; s < 3; s++) M[6 * (r + 3) + s + 3] = b->inertia[3 * r + s];
    }
    if (spd6_inverse(M, Mi)) {
        snprintf(why, len, "body %d: inertia must be positive definite", k);
        return 0;
    }
    if (!finite3(b->com) || !finite3(b->force) || !finite3(b->torque) || !finite3(b->velocity) ||
        !finite3(b->velocity + 3)) {
        snprintf(why, len, "body %d: com, force, torque and velocity must be finite", k);
        return 0;
    }
    return 1;
}

cloth_status cloth_set_bodies(cloth *c, const cloth_body *bodies, int count)
{
    if (!c) return CLOTH_EINVAL;
    if (count < 0) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_bodies: count %d must be >= 0", count);
    if (count > 0 && !bodies) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_bodies: bodies is NULL");
    if (count > (1 << 20)) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_bodies: count %d is too large", count);
    char why[160];
    for (int k = 0; k < count; k++)
        if (!body_valid(&bodies[k], why, sizeof why, k))
            return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_set_bodies: %s", why);
    if (c->vbody)
        for (int i = 0; i < c->n; i++)
            if (c->vbody[i] >= count)
                return oc_cloth_fail(c, CLOTH_EINVAL,
                                     "cloth_set_bodies: vertex %d is held by body %d of %d; release it first", i,
                                     c->vbody[i], count);
    if (count > c->nbody || !c->vbody) {
        cloth_body *nb = malloc((size_t)(count > 0 ? count : 1) * sizeof *nb);
        double *ws = calloc((size_t)(count > 0 ? count : 1) * WS_PER_BODY, sizeof *ws);
        int *vb = c->vbody ? c->vbody : malloc((size_t)c->n * sizeof *vb);
        double *dev = c->body_dev ? c->body_dev : calloc(3 * (size_t)c->n, sizeof *dev);
        if (!nb || !ws || !vb || !dev) {
            free(nb);
            free(ws);
            if (vb != c->vbody) free(vb);
            if (dev != c->body_dev) free(dev);
            return oc_cloth_fail(c, CLOTH_ENOMEM, "cloth_set_bodies: out of memory for %d bodies", count);
        }
        c->body_dev = dev;
        if (vb != c->vbody)
            for (int i = 0; i < c->n; i++) vb[i] = -1;
        free(c->body);
        free(c->body_ws);
        c->body = nb;
        c->body_ws = ws;
        c->vbody = vb;
    } else {
        memset(c->body_ws, 0, (size_t)(count > 0 ? count : 1) * WS_PER_BODY * sizeof *c->body_ws);
    }
    if (count > 0) memcpy(c->body, bodies, (size_t)count * sizeof *bodies);
    c->nbody = count;
    return CLOTH_OK;
}

int cloth_body_count(const cloth *c) { return c ? c->nbody : 0; }

cloth_status cloth_hold_by_body(cloth *c, int vertex, int index)
{
    if (!c) return CLOTH_EINVAL;
    if (vertex < 0 || vertex >= c->n)
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_hold_by_body: vertex %d out of range [0, %d)", vertex, c->n);
    if (index < -1 || index >= c->nbody)
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_hold_by_body: body %d must be -1 (none) or in [0, %d)", index,
                             c->nbody);
    if (index >= 0 && !c->con[vertex].ndof && c->cand_on[vertex] != 1)
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_hold_by_body: vertex %d has no constraint or contact to hold",
                             vertex);
    if (c->vbody) c->vbody[vertex] = index;
    return CLOTH_OK;
}

cloth_status cloth_body_velocity_change(const cloth *c, int index, double dv[6])
{
    if (!c || !dv) return CLOTH_EINVAL;
    if (index < 0 || index >= c->nbody)
        return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_body_velocity_change: body %d out of range [0, %d)",
                             index, c->nbody);
    memcpy(dv, c->body_ws + 2 * 36 * (size_t)c->nbody + 6 * ((size_t)c->nbody + index), 6 * sizeof *dv);
    return CLOTH_OK;
}

static void bodies_expand(const void *ctx, const mpcg_problem *P, const double *u, double *out);
static void bodies_reduce(const void *ctx, const mpcg_problem *P, const double *t, const double *u, double s_m,
                          double *out);
static int bodies_precond(const void *ctx, const mpcg_problem *P);
static void bodies_apply_ginv(const void *ctx, const double *r, double *out);

const mpcg_extra *oc_bodies_prepare(cloth *c, double h, double cfac, mpcg_bodies *B)
{
    c->body_held = 0;
    if (c->nbody == 0) return NULL;
    int held = 0;
    for (int i = 0; i < c->n; i++) held += c->vbody[i] >= 0 && (c->con[i].ndof || c->cand_on[i] == 1);
    size_t nb = (size_t)c->nbody;
    double *w = c->body_ws, *M = w, *ginv = w + 36 * nb, *rhs = w + 72 * nb;
    B->nb = c->nbody;
    B->vbody = c->vbody;
    B->x = c->x_lever; /* the cloth feels the forces there: no torque created */
    B->M = M;
    B->ginv = ginv;
    B->ex = (mpcg_extra){.size = 6 * c->nbody,
                         .rhs = rhs,
                         .y = rhs + 6 * nb,
                         .r = rhs + 12 * nb,
                         .p = rhs + 18 * nb,
                         .q = rhs + 24 * nb,
                         .s = rhs + 30 * nb,
                         .ctx = B,
                         .expand = bodies_expand,
                         .reduce = bodies_reduce,
                         .factor = bodies_precond,
                         .precondition = bodies_apply_ginv};
    double *com = rhs + 36 * nb;
    B->com = com;
    memset(B->ex.y, 0, 6 * nb * sizeof *B->ex.y);
    c->body_held = held;
    if (!held) return NULL;
    /* the cloth's rows are scaled by cfac (A dv - b = cfac f_c); the body's
     * row M du = h (F - f_c) likewise */
    double s = cfac / h;
    for (size_t g = 0; g < nb; g++) {
        const cloth_body *b = &c->body[g];
        double *Mg = M + 36 * g;
        memset(Mg, 0, 36 * sizeof *Mg);
        for (int r = 0; r < 3; r++) {
            Mg[7 * r] = s * b->mass;
            for (int q = 0; q < 3; q++) Mg[6 * (r + 3) + q + 3] = s * b->inertia[3 * r + q];
            rhs[6 * g + r] = cfac * b->force[r];
            rhs[6 * g + 3 + r] = cfac * b->torque[r];
            com[3 * g + r] = b->com[r];
        }
    }
    /* for the elongation limit (levers from the step's start; its
     * projection sets them again from the positions it works on) */
    oc_body_limit_begin(c);
    memset(com + 3 * nb + 36 * nb, 0, 12 * nb * sizeof *com);
    return &B->ex;
}

/* ----------------------------------------- the elongation limit's share */

/* The limit's projection (strain_limit.c) moves a held vertex's constrained
 * components with its body: the body, of inverse mass Minv, takes the
 * correction's impulse J^T P f and moves by D = Minv sum J^T P f. */
static double *bw(const cloth *c, int part) /* 0 com, 1 minv, 2 F, 3 D */
{
    size_t nb = (size_t)c->nbody;
    double *com = c->body_ws + 108 * nb;
    return part == 0 ? com : part == 1 ? com + 3 * nb : part == 2 ? com + 39 * nb : com + 45 * nb;
}

static void lever_of(const cloth *c, int i, double r[3])
{
    const double *com = bw(c, 0) + 3 * c->vbody[i], *x = c->sl_x ? c->sl_x : c->st.x;
    for (int a = 0; a < 3; a++) r[a] = x[3 * i + a] - com[a];
}

int oc_body_holds(const cloth *c, int i) { return c->body_held && c->vbody[i] >= 0 && c->con[i].ndof; }

/* The inverse of each body's mass with its held vertices' (which move with
 * it), M + sum m_i J_i^T P_i J_i, at the levers lever_of gives. */
void oc_body_limit_begin(cloth *c)
{
    size_t nb = (size_t)c->nbody;
    double *minv = bw(c, 1);
    for (size_t g = 0; g < nb; g++) {
        const cloth_body *b = &c->body[g];
        double *Mg = minv + 36 * g;
        memset(Mg, 0, 36 * sizeof *Mg);
        for (int r = 0; r < 3; r++) {
            Mg[7 * r] = b->mass;
            for (int q = 0; q < 3; q++) Mg[6 * (r + 3) + q + 3] = b->inertia[3 * r + q];
        }
    }
    for (int i = 0; i < c->n; i++) {
        if (c->vbody[i] < 0 || !c->con[i].ndof) continue;
        double *Mg = minv + 36 * (size_t)c->vbody[i], r[3], PJ[18];
        lever_of(c, i, r);
        pj_matrix(c->S + 9 * (size_t)i, r, PJ);
        for (int a = 0; a < 6; a++)
            for (int e = 0; e < 6; e++)
                Mg[6 * a + e] += c->mass[i] * (PJ[a] * PJ[e] + PJ[6 + a] * PJ[6 + e] + PJ[12 + a] * PJ[12 + e]);
    }
    for (size_t g = 0; g < nb; g++) {
        double inv[36];
        if (spd6_inverse(minv + 36 * g, inv) == 0) memcpy(minv + 36 * g, inv, sizeof inv);
    }
}

/* J^T P f for held vertex i */
static void jtp(const cloth *c, const double *S, int i, const double f[3], double o[6])
{
    double r[3], pf[3];
    lever_of(c, i, r);
    con_project(S + 9 * (size_t)i, f, pf);
    o[0] = pf[0];
    o[1] = pf[1];
    o[2] = pf[2];
    o[3] = r[1] * pf[2] - r[2] * pf[1];
    o[4] = r[2] * pf[0] - r[0] * pf[2];
    o[5] = r[0] * pf[1] - r[1] * pf[0];
}

double oc_body_wnorm(const cloth *c, const double *S, int i, const double u[3])
{
    double j[6], w = 0.0;
    jtp(c, S, i, u, j);
    const double *Mi = bw(c, 1) + 36 * c->vbody[i];
    for (int a = 0; a < 6; a++)
        for (int b = 0; b < 6; b++) w += j[a] * Mi[6 * a + b] * j[b];
    return w;
}

void oc_body_push(cloth *c, const double *S, int i, const double u[3], double s)
{
    double j[6], *F = bw(c, 2) + 6 * c->vbody[i];
    jtp(c, S, i, u, j);
    for (int a = 0; a < 6; a++) F[a] += s * j[a];
}

void oc_body_solve(cloth *c)
{
    double *F = bw(c, 2), *D = bw(c, 3);
    const double *Mi = bw(c, 1);
    for (int g = 0; g < c->nbody; g++) {
        for (int a = 0; a < 6; a++) {
            double s = 0.0;
            for (int b = 0; b < 6; b++) s += Mi[36 * g + 6 * a + b] * F[6 * g + b];
            D[6 * g + a] = s;
        }
        memset(F + 6 * g, 0, 6 * sizeof *F);
    }
}

/* v = U_lin + U_ang x r: a rigid body's velocity U (6) at lever r */
static void rigid_vel(const double *U, const double r[3], double v[3])
{
    v[0] = U[0] + U[4] * r[2] - U[5] * r[1];
    v[1] = U[1] + U[5] * r[0] - U[3] * r[2];
    v[2] = U[2] + U[3] * r[1] - U[4] * r[0];
}

void oc_body_move(const cloth *c, const double *S, int i, double s, double *q)
{
    const double *D = bw(c, 3) + 6 * c->vbody[i];
    double r[3], v[3], pv[3];
    lever_of(c, i, r);
    rigid_vel(D, r, v);
    con_project(S + 9 * (size_t)i, v, pv);
    for (int a = 0; a < 3; a++) q[3 * i + a] += s * pv[a];
}

void oc_body_kept(cloth *c, double s)
{
    size_t nb = (size_t)c->nbody;
    double *u = c->body_ws + 72 * nb + 6 * nb;
    const double *D = bw(c, 3);
    for (size_t k = 0; k < 6 * nb; k++) u[k] += s * D[k];
}


/* Loop over the held vertices (the constrained ones with a body of B). */
#define FOR_HELD(P, B, i, g)                                               \
    for (int k_ = 0, n_ = (P)->con ? (P)->ncon : (P)->A->n; k_ < n_; k_++) \
        for (int i = (P)->con ? (P)->con[k_] : k_, g = (B)->vbody[i]; g >= 0; g = -1)

static void lever(const mpcg_bodies *B, int i, int g, double r[3])
{
    for (int a = 0; a < 3; a++) r[a] = B->x[3 * i + a] - B->com[3 * g + a];
}

/* ex.expand: out += sum over held vertices of (I - S_i) J_i u */
static void bodies_expand(const void *ctx, const mpcg_problem *P, const double *u, double *out)
{
    const mpcg_bodies *B = ctx;
    FOR_HELD(P, B, i, g)
    {
        const double *ug = u + 6 * g;
        double r[3], v[3], pv[3];
        lever(B, i, g, r);
        rigid_vel(ug, r, v);
        con_project(P->S + 9 * (size_t)i, v, pv);
        for (int a = 0; a < 3; a++) out[3 * i + a] += pv[a];
    }
}

/* ex.reduce: out (6 nb) = s_m M u + sum_i J_i^T (I - S_i) t_i (u may be NULL: 0) */
static void bodies_reduce(const void *ctx, const mpcg_problem *P, const double *t, const double *u, double s_m,
                          double *out)
{
    const mpcg_bodies *B = ctx;
    for (int g = 0; g < B->nb; g++) {
        double *o = out + 6 * g;
        for (int a = 0; a < 6; a++) {
            double m = 0.0;
            if (u)
                for (int b = 0; b < 6; b++) m += B->M[36 * g + 6 * a + b] * u[6 * g + b];
            o[a] = s_m * m;
        }
    }
    FOR_HELD(P, B, i, g)
    {
        double r[3], f[3];
        lever(B, i, g, r);
        con_project(P->S + 9 * (size_t)i, t + 3 * i, f);
        double *o = out + 6 * g;
        o[0] += f[0];
        o[1] += f[1];
        o[2] += f[2];
        o[3] += r[1] * f[2] - r[2] * f[1];
        o[4] += r[2] * f[0] - r[0] * f[2];
        o[5] += r[0] * f[1] - r[1] * f[0];
    }
}

/* Inverse of a symmetric positive definite 6x6 matrix by Cholesky; -1 (out
 * untouched) when it is not positive definite. */
static int spd6_inverse(const double *A, double *out)
{
    double L[36] = {0};
    for (int j = 0; j < 6; j++) {
        double d = A[7 * j];
        for (int k = 0; k < j; k++) d -= L[6 * j + k] * L[6 * j + k];
        if (!(d > 0.0) || !isfinite(d)) return -1;
        L[7 * j] = sqrt(d);
        for (int i = j + 1; i < 6; i++) {
            double s = A[6 * i + j];
            for (int k = 0; k < j; k++) s -= L[6 * i + k] * L[6 * j + k];
            L[6 * i + j] = s / L[7 * j];
        }
    }
    /* columns of A^-1: solve L L^T x = e_c */
    for (int c = 0; c < 6; c++) {
        double y[6];
        for (int i = 0; i < 6; i++) {
            double s = i == c;
            for (int k = 0; k < i; k++) s -= L[6 * i + k] * y[k];
            y[i] = s / L[7 * i];
        }
        for (int i = 5; i >= 0; i--) {
            double s = y[i];
            for (int k = i + 1; k < 6; k++) s -= L[6 * k + i] * y[k];
            y[i] = s / L[7 * i];
        }
        for (int i = 0; i < 6; i++) out[6 * i + c] = y[i];
    }
    return 0;
}

/* ex.factor: ginv = (M + sum J^T (I - S) A_ii (I - S) J)^-1 per body; -1 when a block is not
 * positive definite, else 0 */
static int bodies_precond(const void *ctx, const mpcg_problem *P)
{
    const mpcg_bodies *B = ctx;
    int nb = B->nb;
    /* accumulate into ginv, then invert each block in place */
    memcpy(B->ginv, B->M, 36 * (size_t)nb * sizeof *B->ginv);
    FOR_HELD(P, B, i, g)
    {
        const double *S = P->S + 9 * (size_t)i, *Aii = P->A->val + 9 * (size_t)P->A->diag[i];
        double r[3], PJ[18], APJ[18];
        lever(B, i, g, r);
        pj_matrix(S, r, PJ);
        for (int row = 0; row < 3; row++)
            for (int col = 0; col < 6; col++)
                APJ[6 * row + col] = Aii[3 * row] * PJ[col] + Aii[3 * row + 1] * PJ[6 + col] +
                                     Aii[3 * row + 2] * PJ[12 + col];
        double *G = B->ginv + 36 * g;
        for (int a = 0; a < 6; a++)
            for (int b = 0; b < 6; b++)
                G[6 * a + b] += PJ[a] * APJ[b] + PJ[6 + a] * APJ[6 + b] + PJ[12 + a] * APJ[12 + b];
    }
    for (int g = 0; g < nb; g++) {
        double inv[36];
        if (spd6_inverse(B->ginv + 36 * g, inv)) return -1;
        memcpy(B->ginv + 36 * g, inv, sizeof inv);
    }
    return 0;
}

/* ex.precondition: out = ginv r (6 nb) */
static void bodies_apply_ginv(const void *ctx, const double *r, double *out)
{
    const mpcg_bodies *B = ctx;
    for (int g = 0; g < B->nb; g++)
        for (int a = 0; a < 6; a++) {
            double s = 0.0;
            for (int b = 0; b < 6; b++) s += B->ginv[36 * g + 6 * a + b] * r[6 * g + b];
            out[6 * g + a] = s;
        }
}

/* ------------------------------------------------- the substep retry */

/* Substep retry (step.c): a held vertex moves with its body's velocity at the step's start plus the
 * substeps' sum of du so far (U), which moves vertex i by D_i. */
static double *body_U(const cloth *c) { return bw(c, 0) + 51 * (size_t)c->nbody; }

void oc_bodies_retry_reset(cloth *c)
{
    if (!c->nbody || !c->body_dev) return;
    memset(body_U(c), 0, 6 * (size_t)c->nbody * sizeof(double));
    memset(c->body_dev, 0, 3 * (size_t)c->n * sizeof *c->body_dev);
}

static void body_point_vel(const cloth *c, int i, const double *U, double v[3])
{
    double r[3];
    lever_of(c, i, r);
    rigid_vel(U, r, v);
}

void oc_bodies_retry_target(const cloth *c, int i, double hs, double tg[3])
{
    if (!c->nbody || !c->body_dev || c->vbody[i] < 0) return;
    double v[3];
    body_point_vel(c, i, body_U(c) + 6 * c->vbody[i], v);
    for (int a = 0; a < 3; a++) tg[a] += c->body_dev[3 * i + a] + hs * v[a];
}

void oc_bodies_retry_commit(cloth *c, double hs)
{
    if (!c->nbody || !c->body_dev || !c->body_held) return;
    size_t nb = (size_t)c->nbody;
    double *U = body_U(c);
    const double *u = c->body_ws + 78 * nb;
    for (size_t k = 0; k < 6 * nb; k++) U[k] += u[k];
    for (int i = 0; i < c->n; i++) {
        if (c->vbody[i] < 0 || !c->con[i].ndof) continue;
        double v[3];
        body_point_vel(c, i, U + 6 * c->vbody[i], v);
        for (int a = 0; a < 3; a++) c->body_dev[3 * i + a] += hs * v[a];
    }
}

void oc_bodies_retry_finish(cloth *c)
{
    if (!c->nbody || !c->body_dev) return;
    size_t nb = (size_t)c->nbody;
    memcpy(c->body_ws + 78 * nb, body_U(c), 6 * nb * sizeof(double));
}

/* ------------------------------------------------- Newton iterations */

/* A Newton iteration solves the bodies' rows on their residual, M ddu = rhs - M du1 - sum J^T P
 * (A ddv - b); oc_bodies_newton_take then sets du = du1 + t ddu. */
static double *body_u1(const cloth *c) { return bw(c, 0) + 57 * (size_t)c->nbody; }

/* rhs_g += s M_g v_g for every body */
static void add_mass_times(cloth *c, const double *v, double s)
{
    size_t nb = (size_t)c->nbody;
    const double *M = c->body_ws;
    double *rhs = c->body_ws + 72 * nb;
    for (size_t g = 0; g < nb; g++)
        for (int a = 0; a < 6; a++) {
            double t = 0.0;
            for (int b = 0; b < 6; b++) t += M[36 * g + 6 * a + b] * v[6 * g + b];
            rhs[6 * g + a] += s * t;
        }
}

void oc_bodies_newton_begin(cloth *c)
{
    size_t nb = (size_t)c->nbody;
    double *u = c->body_ws + 78 * nb, *u1 = body_u1(c);
    add_mass_times(c, u, -1.0);
    memcpy(u1, u, 6 * nb * sizeof *u1);
    memset(u, 0, 6 * nb * sizeof *u);
}

/* ---------------------------------- the bodies' share of the potential */

/* 1/2 w^T M w - rhs^T w for body g's rows, w = u1 + t du, rhs = rhs_mod + M u1 */
static double body_quad(const double *M, const double *rhs, const double *u1, const double *du, double t)
{
    double w[6], E = 0.0;
    for (int a = 0; a < 6; a++) w[a] = u1[a] + t * du[a];
    for (int a = 0; a < 6; a++) {
        double Mw = 0.0, Mu1 = 0.0;
        for (int b = 0; b < 6; b++) {
            Mw += M[6 * a + b] * w[b];
            Mu1 += M[6 * a + b] * u1[b];
        }
        E += 0.5 * w[a] * Mw - (rhs[a] + Mu1) * w[a];
    }
    return E;
}

double oc_bodies_newton_energy(const cloth *c, double t)
{
    size_t nb = (size_t)c->nbody;
    const double *M = c->body_ws, *rhs = c->body_ws + 72 * nb, *du = c->body_ws + 78 * nb, *u1 = body_u1(c);
    double E = 0.0;
    for (size_t g = 0; g < nb; g++) E += body_quad(M + 36 * g, rhs + 6 * g, u1 + 6 * g, du + 6 * g, t);
    return E;
}

double oc_bodies_energy(const cloth *c)
{
    size_t nb = (size_t)c->nbody;
    const double *M = c->body_ws, *rhs = c->body_ws + 72 * nb, *u = c->body_ws + 78 * nb;
    static const double zero[6] = {0, 0, 0, 0, 0, 0};
    double E = 0.0;
    for (size_t g = 0; g < nb; g++) E += body_quad(M + 36 * g, rhs + 6 * g, zero, u + 6 * g, 1.0); /* rhs unshifted */
    return E;
}

double oc_bodies_newton_slope(const cloth *c)
{
    size_t nb = (size_t)c->nbody;
    const double *rhs = c->body_ws + 72 * nb, *du = c->body_ws + 78 * nb;
    double s = 0.0;
    for (size_t k = 0; k < 6 * nb; k++) s -= rhs[k] * du[k];
    return s;
}

void oc_bodies_newton_take(cloth *c, double t)
{
    size_t nb = (size_t)c->nbody;
    double *u = c->body_ws + 78 * nb, *u1 = body_u1(c);
    add_mass_times(c, u1, 1.0);
    for (size_t k = 0; k < 6 * nb; k++) u[k] = u1[k] + t * u[k];
}

/* Body g's residual r = rhs - M u + sum J^T P b, after bodies_reduce has
 * put -M u + sum J^T P b in B->ex.r */
static void body_residual(const mpcg_bodies *B, int g, double r[6])
{
    for (int a = 0; a < 6; a++) r[a] = B->ex.r[6 * g + a] + B->ex.rhs[6 * g + a];
}

double oc_bodies_residual_work(const cloth *c, const mpcg_problem *P, const double *b)
{
    const mpcg_bodies *B = P->extra->ctx;
    bodies_reduce(B, P, b, B->ex.y, -1.0, B->ex.r);
    double w = 0.0;
    for (int g = 0; g < B->nb; g++) {
        double r[6];
        body_residual(B, g, r);
        for (int a = 0; a < 6; a++) w += (c->body[g].velocity[a] + B->ex.y[6 * g + a]) * r[a];
    }
    return w;
}

double oc_bodies_residual_energy(const mpcg_problem *P, const double *b)
{
    const mpcg_bodies *B = P->extra->ctx;
    bodies_reduce(B, P, b, B->ex.y, -1.0, B->ex.r);
    double s = 0.0;
    for (int g = 0; g < B->nb; g++) {
        double r[6], Mi[36];
        body_residual(B, g, r);
        if (spd6_inverse(B->M + 36 * (size_t)g, Mi)) continue;
        for (int a = 0; a < 6; a++)
            for (int k = 0; k < 6; k++) s += r[a] * Mi[6 * a + k] * r[k];
    }
    return s;
}

void oc_bodies_held_motion(const cloth *c, int i, double out[3])
{
    out[0] = out[1] = out[2] = 0.0;
    if (!c->body_held || !c->vbody || c->vbody[i] < 0) return;
    size_t nb = (size_t)c->nbody, g = (size_t)c->vbody[i];
    const double *U = c->body_ws + 78 * nb + 6 * g, *com = bw(c, 0) + 3 * g, *x = c->x_lever + 3 * (size_t)i;
    double r[3] = {x[0] - com[0], x[1] - com[1], x[2] - com[2]};
    rigid_vel(U, r, out);
}

double oc_bodies_step_energy(const cloth *c)
{
    size_t nb = (size_t)c->nbody;
    const double *M = c->body_ws, *du = c->body_ws + 78 * nb;
    double s = 0.0;
    for (size_t g = 0; g < nb; g++)
        for (int a = 0; a < 6; a++)
            for (int b = 0; b < 6; b++) s += du[6 * g + a] * M[36 * g + 6 * a + b] * du[6 * g + b];
    return s;
}
/* The step's du at the last converged Newton corrections, kept by linearized.c if the elongation
 * limit's later corrections do not converge within the budget. */
static double *body_saved(const cloth *c) { return bw(c, 0) + 63 * (size_t)c->nbody; }

void oc_bodies_newton_save(cloth *c)
{
    size_t nb = (size_t)c->nbody;
    memcpy(body_saved(c), c->body_ws + 78 * nb, 6 * nb * sizeof(double));
}

void oc_bodies_newton_restore(cloth *c)
{
    size_t nb = (size_t)c->nbody;
    memcpy(c->body_ws + 78 * nb, body_saved(c), 6 * nb * sizeof(double));
}
