/* The linearised implicit step (CLOTH_LINEARIZED): backward Euler (paper eq. 15-21) or BDF2
 * linearised about the step's start and solved once by the modified PCG; with rigid bodies,
 * Newton corrections where a link crossed its elongation limit. */
#include <math.h>
#include <string.h>
#include "internal.h"
#include "linsolve.h"
#include "assembly.h"
#include "mat3.h"
#include "mpcg.h"
#include "tuning.h"

/* A = M - beta h df/dv - gamma h^2 df/dx (eq. 21 for beta = gamma = 1), keeping each link's K for
 * the right-hand side, and in the same pass f = the total force at (x, v). */
static void assemble(cloth *c, const double *x, const double *v, double beta_h, double gamma_h2, double *fout)
{
    const cloth_material *m = &c->desc.material;
    int defin = c->desc.solver.definiteness_rule;
    bsr *A = &c->A;
    assemble_zero(c);
    for (int i = 0; i < c->n; i++) {
        double *B = A->val + 9 * (size_t)A->diag[i];
        B[0] = B[4] = B[8] = c->mass[i];
        for (int r = 0; r < 3; r++) fout[3 * i + r] = c->mass[i] * c->desc.gravity[r] + c->f_ext[3 * i + r];
    }
    double f[3], D[9], blk[9];
    for (int t = 0; t < 2; t++) {
        int ne = t ? c->n_int : c->n_seq;
        const link_topo *L = t ? c->lint : c->seq;
        const int *bl = t ? c->int_blk : c->seq_blk;
        double *Ks = t ? c->K_int : c->K_seq;
        double damp = t ? m->c_b : m->c_t;
        for (int e = 0; e < ne; e++) {
            int i = L[e].i, j = L[e].j;
            spring_law s = t ? int_law(m, L[e].rest, c->st.plastic[e], c->st.l1[e])
                             : seq_law(m, L[e].rest, c->st.seq_set[e]);
            if (!t) s.lim -= c->lim_shift[e];
            double *K = Ks + 9 * (size_t)e;
            oc_link_eval(x + 3 * i, x + 3 * j, v + 3 * i, v + 3 * j, s, damp, defin, f, K, D);
            for (int r = 0; r < 3; r++) {
                fout[3 * i + r] += f[r];
                fout[3 * j + r] -= f[r];
            }
            for (int k = 0; k < 9; k++) blk[k] = gamma_h2 * K[k] + beta_h * D[k];
            assemble_link(c, i, j, bl + 2 * e, blk);
        }
    }
    if (oc_crease_law_on(m)) { /* the crease law's hinges (crease_law.c) */
        oc_crease_forces(c, x, x, 1.0, fout);
        oc_crease_matrix(c, x, x, gamma_h2);
    }
    /* air drag: its normals and areas at x, constant over the step (no df/dx) */
    if (oc_air_on(c)) oc_air_eval(c, x, NULL, 0.0, v, 1.0, fout, A, beta_h);
}

/* out += (df/dx) w, link by link: link (i, j) adds K (w_j - w_i) to i and
 * subtracts it from j. */
static void add_Kw(const cloth *c, const double *w, double *out)
{
    for (int t = 0; t < 2; t++) {
        int ne = t ? c->n_int : c->n_seq;
        const link_topo *L = t ? c->lint : c->seq;
        const double *Ks = t ? c->K_int : c->K_seq;
        for (int e = 0; e < ne; e++) {
            const double *K = Ks + 9 * (size_t)e, *wi = w + 3 * L[e].i, *wj = w + 3 * L[e].j;
            double d0 = wj[0] - wi[0], d1 = wj[1] - wi[1], d2 = wj[2] - wi[2];
            double *oi = out + 3 * L[e].i, *oj = out + 3 * L[e].j;
            for (int r = 0; r < 3; r++) {
                double y = K[3 * r] * d0 + K[3 * r + 1] * d1 + K[3 * r + 2] * d2;
                oi[r] += y;
                oj[r] -= y;
            }
        }
    }
}

/* Constraint forces (Baraff-Witkin sec. 5.3): the part of A dv - b the filter removed is the
 * constraints' impulse (beta h) f_c, so con_new = that part / cfac; after a Newton correction,
 * with b the residual at dv1, the same holds for the residual at dv1 + ddv. */
static void constraint_forces(cloth *c, const double *dv, const double *b, double cfac)
{
    size_t n3 = 3 * (size_t)c->n;
    memset(c->con_new, 0, n3 * sizeof *c->con_new);
    if (c->n_con == 0) return;
    oc_bsr_mul_rows(&c->A, dv, c->clist, c->n_con, c->y); /* only the constrained rows are read */
    for (int i = 0; i < c->n; i++) {
        if (c->con[i].ndof == 0) continue;
        const double *Si = c->S + 9 * (size_t)i;
        double e[3];
        for (int r2 = 0; r2 < 3; r2++) e[r2] = (c->y[3 * i + r2] - b[3 * i + r2]) / cfac;
        for (int r2 = 0; r2 < 3; r2++)
            c->con_new[3 * i + r2] = e[r2] - (Si[3 * r2] * e[0] + Si[3 * r2 + 1] * e[1] + Si[3 * r2 + 2] * e[2]);
    }
}

static int crossed_limit(const cloth *c, const double *x0, const double *x1)
{
    double lim = 1.0 + c->desc.material.delta, lim1 = 1.0 + NEWTON_CROSS * c->desc.material.delta;
    for (int e = 0; e < c->n_seq; e++) {
        const link_topo *L = &c->seq[e];
        if (oc_link_held_together(c, L)) continue; /* its length is the targets' */
        double l1 = lim1 * L->rest, d1 = 0.0, d0 = 0.0;
        for (int r = 0; r < 3; r++) {
            double w1 = x1[3 * L->j + r] - x1[3 * L->i + r], w0 = x0[3 * L->j + r] - x0[3 * L->i + r];
            d1 += w1 * w1;
            d0 += w0 * w0;
        }
        if (d1 > l1 * l1 && d0 <= lim * L->rest * lim * L->rest) return 1;
    }
    return 0;
}

/* |S b|: the free components' part of a vector (S the constraint filter) */
static double free_norm(const cloth *c, const double *b)
{
    double s = 0.0;
    for (int i = 0; i < c->n; i++) {
        const double *Si = c->S + 9 * (size_t)i, *bi = b + 3 * (size_t)i;
        for (int r = 0; r < 3; r++) {
            double e = c->con[i].ndof ? Si[3 * r] * bi[0] + Si[3 * r + 1] * bi[1] + Si[3 * r + 2] * bi[2] : bi[r];
            s += e * e;
        }
    }
    return sqrt(s);
}

/* Backward Euler (bdf2 = 0) or BDF2 (Choi-Ko 2002), f linearised about (x0, v0), x_new = a + cfac v_new:
 * BE (M - h D - h^2 K) dv = h f0 + K (h^2 v0), a = x0; BDF2 (M - 2/3 h D - 4/9 h^2 K) dv = 2/3 h f0
 * + 1/3 M (v0 - v_-1) + K (2/9 h (x0 - x_-1) + 4/9 h^2 v0), a = x0 + (x0 - x_-1)/3. */
cloth_failure oc_linearized_step(cloth *c, double h, int bdf2, const double *xs, double frac, cloth_step_stats *st)
{
    const struct cloth_state *S0 = &c->st;
    const double *x0 = S0->x, *v0 = S0->v;
    size_t n3 = 3 * (size_t)c->n;
    double beta = bdf2 ? 2.0 / 3.0 : 1.0, cfac = beta * h;
    double *a = c->x_new, *w = c->y, *b = c->b;

    for (size_t k = 0; k < n3; k++) {
        a[k] = bdf2 ? x0[k] + (x0[k] - S0->x_prev[k]) / 3.0 : x0[k];
        w[k] = bdf2 ? (2.0 / 9.0) * h * (x0[k] - S0->x_prev[k]) + (4.0 / 9.0) * h * h * v0[k] : h * h * v0[k];
    }
    memset(c->lim_shift, 0, (size_t)c->n_seq * sizeof *c->lim_shift);
    oc_limit_multipliers_begin(c); /* its penalties stay 1 (its law has none) */
    assemble(c, x0, v0, beta * h, beta * beta * h * h, c->f);
    for (size_t k = 0; k < n3; k++) b[k] = beta * h * c->f[k];
    if (bdf2)
        for (size_t k = 0; k < n3; k++) b[k] += c->mass[k / 3] * (v0[k] - S0->v_prev[k]) / 3.0;
    add_Kw(c, w, b);
    if (oc_crease_law_on(&c->desc.material)) oc_crease_Kw(c, x0, w, b);

    oc_constraints_build(c, a, v0, cfac, xs, frac);
    const cloth_solver *sv = &c->desc.solver;
    if (sv->warm_start) memcpy(c->dv, S0->dv_prev, n3 * sizeof *c->dv);
    else memset(c->dv, 0, n3 * sizeof *c->dv);
    mpcg_problem P =
        {&c->A, b,   c->S, c->z, c->pre, c->clist, c->n_con, NULL, NULL, sv->cg_tolerance, sv->cg_max_iterations,
         NULL,  0.0, 0,    0.0,  NULL,   0};
    mpcg_bodies bodies;
    P.extra = oc_bodies_prepare(c, h, cfac, &bodies);
    mpcg_result r = oc_linsolve_run(c, &P, c->dv);
    st->iterations += r.iterations;
    if (!(st->residual >= r.residual)) st->residual = r.residual;
    if (r.failure != CLOTH_FAIL_NONE) return r.failure;

    for (size_t k = 0; k < n3; k++) {
        c->v_new[k] = v0[k] + c->dv[k];
        c->x_new[k] = a[k] + cfac * c->v_new[k];
    }
    constraint_forces(c, c->dv, b, cfac);

    /* Newton corrections with rigid bodies: a step linearised about x0 misses the k_delta stiffening of
     * links it carries past the limit, so a body's momentum stretches the cloth; relinearise and correct,
     * holding the limit by its multipliers (limit_multipliers.c) until they settle (docs/solver.md). */
    int newton = P.extra && sv->newton_iterations > 0 && crossed_limit(c, x0, c->x_new);
    double ref = 0.0;
    int saved = 0, pending = 0; /* a converged step saved; corrected since its multipliers changed */
    for (int it = 0; newton; it++) {
        double *ddv = c->ddv;
        /* converged: the free rows' residual within the solver's tolerance of the uncorrected step's; then
         * the limit's multipliers are updated and, if they changed, the step is corrected again (the
         * converged step saved, kept if the budget ends first) */
        int done = 0;
        for (int pass = 0; pass < 2; pass++) {
            assemble(c, c->x_new, c->v_new, beta * h, beta * beta * h * h, c->f);
            for (size_t k = 0; k < n3; k++) {
                double extra = bdf2 ? c->mass[k / 3] * (v0[k] - S0->v_prev[k]) / 3.0 : 0.0;
                b[k] = beta * h * c->f[k] + extra - c->mass[k / 3] * c->dv[k];
            }
            double rn = free_norm(c, b);
            if (it == 0 && pass == 0) ref = rn;
            if (pass == 1 || rn > sv->cg_tolerance * ref) break;
            pending = 0;
            if (it >= sv->newton_iterations) { /* no budget left to correct for new multipliers */
                done = 1;
                break;
            }
            memcpy(c->dv_saved, c->dv, n3 * sizeof *c->dv);
            memcpy(c->con_saved, c->con_new, n3 * sizeof *c->con_new);
            oc_bodies_newton_save(c);
            saved = 1;
            if (oc_limit_multipliers_update(c, c->x_new, 0) <= LIMIT_TOL) {
                done = 1;
                break;
            }
            pending = 1;
        }
        if (done) break;
        if (it >= sv->newton_iterations) break;
        memset(c->z, 0, n3 * sizeof *c->z);
        memset(ddv, 0, n3 * sizeof *ddv);
        oc_bodies_newton_begin(c);
        mpcg_result r2 = oc_linsolve_run(c, &P, ddv);
        oc_bodies_newton_take(c, r2.failure == CLOTH_FAIL_NONE ? 1.0 : 0.0);
        st->iterations += r2.iterations;
        st->newton++;
        /* a correction that fails (CG capped on the stiffer matrix, or
         * indefinite without the definiteness rule) leaves the step as the
         * last one that succeeded; only NaN fails it */
        if (r2.failure == CLOTH_FAIL_NAN) return r2.failure;
        if (r2.failure != CLOTH_FAIL_NONE) break;
        for (size_t k = 0; k < n3; k++) { /* x_new = a + cfac v_new, a as above */
            double ak = bdf2 ? x0[k] + (x0[k] - S0->x_prev[k]) / 3.0 : x0[k];
            c->dv[k] += ddv[k];
            c->v_new[k] = v0[k] + c->dv[k];
            c->x_new[k] = ak + cfac * c->v_new[k];
        }
        constraint_forces(c, ddv, b, cfac);
    }
    if (pending && saved) { /* the corrections for the last multipliers did not converge */
        memcpy(c->dv, c->dv_saved, n3 * sizeof *c->dv);
        memcpy(c->con_new, c->con_saved, n3 * sizeof *c->con_new);
        oc_bodies_newton_restore(c);
        for (size_t k = 0; k < n3; k++) {
            double ak = bdf2 ? x0[k] + (x0[k] - S0->x_prev[k]) / 3.0 : x0[k];
            c->v_new[k] = v0[k] + c->dv[k];
            c->x_new[k] = ak + cfac * c->v_new[k];
        }
    }
    return CLOTH_FAIL_NONE;
}
