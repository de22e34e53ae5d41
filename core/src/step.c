/* One time step: backward Euler (paper eq. 15-21) or BDF2 by Newton (newton.c), or explicit /
 * symplectic Euler for comparison; then the plastic update. A failed step leaves the state untouched:
 * everything goes to workspace and is committed at the end. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"
#include "mat3.h"
#include "mpcg.h"
#include "newton.h"
#include "self_contact.h"

int oc_workspace_alloc(cloth *c)
{
    size_t n3 = 3 * (size_t)c->n, nl = 3 * ((size_t)c->n_seq + (size_t)c->n_int);
    /* f b dv z y x_new v_new con_new jac na dvt xt vt sl_x0 ddv dv_saved
     * con_saved x_lever sl_dv (19) + cg (6) vectors of 3n; pre, S of 9n; ut
     * of 3 per link */
    c->work = calloc(31 * n3 + nl, sizeof *c->work);
    if (!c->work) return -1;
    double *w = c->work;
    double **v3[] = {&c->f,       &c->b,        &c->dv,        &c->z,       &c->y,    &c->x_new, &c->v_new,
                     &c->con_new, &c->jac,      &c->na,        &c->dvt,     &c->xt,   &c->vt,    &c->sl_x0,
                     &c->ddv,     &c->dv_saved, &c->con_saved, &c->x_lever, &c->sl_dv};
    for (size_t k = 0; k < sizeof v3 / sizeof *v3; k++, w += n3) *v3[k] = w;
    c->cg = w;
    w += 6 * n3;
    c->pre = w;
    w += 3 * n3;
    c->S = w;
    w += 3 * n3;
    c->ut = w;
    return 0;
}

/* What a step learns of its new state on the way, so its statistics need no second pass over the
 * links: max strain and sequential energy (attempt), then elastic energy and plastic links (commit). */
typedef struct measured {
    double max_strain, elastic;
    int plastic;
} measured;

/* Explicit (forward) Euler: x1 = x0 + h v0, v1 = v0 + h a0. Symplectic
 * (semi-implicit) Euler: v1 = v0 + h a0, x1 = x0 + h v1. Constrained
 * components go to their targets in both, v1 = (target - x0) / h. */
static cloth_failure explicit_step(cloth *c, double h, int symplectic, const double *xs, double frac)
{
    const double *x0 = c->st.x, *v0 = c->st.v;
    oc_forces_eval(c, x0, v0, 1, c->f);
    oc_constraints_build(c, x0, v0, h, xs, frac);
    memset(c->con_new, 0, 3 * (size_t)c->n * sizeof *c->con_new);
    for (int i = 0; i < c->n; i++) {
        const double *Si = c->S + 9 * (size_t)i, *z = c->z + 3 * (size_t)i;
        double dv[3], fdv[3];
        for (int r = 0; r < 3; r++) dv[r] = h * c->f[3 * i + r] / c->mass[i];
        oc_filter_apply(1, Si, dv, fdv);
        for (int r = 0; r < 3; r++) {
            double v1 = v0[3 * i + r] + fdv[r] + z[r];
            c->v_new[3 * i + r] = v1;
            /* the constrained part of the force: M dv / h - f, where the filter acted */
            if (c->con[i].ndof) c->con_new[3 * i + r] = c->mass[i] * (fdv[r] + z[r]) / h - c->f[3 * i + r];
        }
        /* symplectic: x1 = x0 + h v1. explicit: x1 = x0 + h (v0 + z), whose
         * free part moves with v0 and whose constrained part, since
         * z = (I - S)(v_target - v0), lands on (I - S) target. */
        for (int r = 0; r < 3; r++)
            c->x_new[3 * i + r] = x0[3 * i + r] + h * (symplectic ? c->v_new[3 * i + r] : v0[3 * i + r] + z[r]);
    }
    return CLOTH_FAIL_NONE;
}

/* Stats of the current state: as the step computed them (ms), or computed here (ms NULL). */
static void fill_stats(cloth *c, cloth_step_stats *st, const measured *ms)
{
    st->constrained = c->n_con;
    if (ms) {
        st->energy = oc_energies_with_elastic(c, ms->elastic);
        st->max_strain = ms->max_strain;
        st->plastic_links = ms->plastic;
        return;
    }
    st->energy = cloth_energies(c);
    st->max_strain = cloth_max_strain(c);
    int p = 0;
    for (int e = 0; e < c->n_int; e++) p += c->st.plastic[e];
    st->plastic_links = p;
}

/* Wall seconds the bound self-contact has spent since its creation (0: none bound) */
static double self_contact_clock(const cloth *c)
{
    return c->self_contact ? oc_self_contact_get_work(c->self_contact).seconds : 0.0;
}

/* sc0: self_contact_clock when the step began */
static cloth_status finish(cloth *c, cloth_step_stats *st, cloth_step_stats *out, cloth_status s, double sc0)
{
    st->self_contact_seconds = self_contact_clock(c) - sc0;
    c->stats = *st;
    c->warm_set = 0; /* a warm start set for this step only */
    if (out) *out = *st;
    return s;
}

/* One step of h into x_new, v_new, dv, con_new (state untouched; constraints aimed at frac of the way
 * from xs). Adds iterations and corrected links to st; ms gets max strain and sequential energy. last:
 * no smaller substep follows, so with keep_unconverged Newton's unconverged iterate is kept (counted). */
static cloth_failure attempt(cloth *c, double h, const double *xs, double frac, int last, cloth_step_stats *st,
                             measured *ms)
{
    size_t n3 = 3 * (size_t)c->n;
    const cloth_solver *sv = &c->desc.solver;
    int bdf2 = sv->method == CLOTH_BDF2 && c->st.has_prev && fabs(c->st.h_prev - h) <= 1e-12 * h;
    cloth_failure fail;
    int held = 0; /* the limit held by the step itself: no projection */
    switch (sv->method) {
    case CLOTH_EXPLICIT_EULER: fail = explicit_step(c, h, 0, xs, frac); break;
    case CLOTH_SYMPLECTIC_EULER: fail = explicit_step(c, h, 1, xs, frac); break;
    default:
        /* BDF2's first step, or a step after h changed, is backward Euler */
        if (sv->nonlinear == CLOTH_NEWTON) fail = oc_newton_step(c, h, bdf2, xs, frac, st, &held);
        else fail = oc_linearized_step(c, h, bdf2, xs, frac, st);
        if (fail != CLOTH_FAIL_NONE && last && c->self_contact && sv->nonlinear == CLOTH_NEWTON) {
            /* a step the self-contact barrier cannot take, as the smallest substep:
             * taken without it, its pairs left to the pass after the step */
            struct self_contact *sc = c->self_contact;
            c->self_contact = NULL;
            fail = oc_newton_step(c, h, bdf2, xs, frac, st, &held);
            c->self_contact = sc;
            st->self_contact_dropped++;
        }
        if (fail == CLOTH_FAIL_NEWTON && last && sv->keep_unconverged) {
            fail = CLOTH_FAIL_NONE;
            st->unconverged++;
        }
        break;
    }
    if (fail == CLOTH_FAIL_NONE && !(oc_all_finite(c->x_new, n3) && oc_all_finite(c->v_new, n3))) fail = CLOTH_FAIL_NAN;
    memset(c->sl_dv, 0, n3 * sizeof *c->sl_dv);
    if (fail == CLOTH_FAIL_NONE && !held && sv->strain_limit_iterations > 0) {
        memcpy(c->sl_dv, c->v_new, n3 * sizeof *c->sl_dv);
        st->strain_limited += oc_strain_limit(c, c->x_new, c->v_new, c->S, h, sv->strain_limit_iterations);
        for (size_t k = 0; k < n3; k++) c->sl_dv[k] = c->v_new[k] - c->sl_dv[k];
    }
    if (fail == CLOTH_FAIL_NONE && !(oc_all_finite(c->x_new, n3) && oc_all_finite(c->v_new, n3))) fail = CLOTH_FAIL_NAN;
    /* the constraint forces too: A dv - b can overflow while x and v do not */
    if (fail == CLOTH_FAIL_NONE && !oc_all_finite(c->con_new, n3)) fail = CLOTH_FAIL_NAN;
    if (fail == CLOTH_FAIL_NONE) {
        double m = ms->max_strain = oc_max_strain_seq_energy(c, c->x_new, &ms->elastic);
        if (!(m <= sv->strain_fail)) fail = m != m ? CLOTH_FAIL_NAN : CLOTH_FAIL_STRAIN;
    }
    return fail;
}

/* Make the attempt of size h the state; ms gets the elastic energy and plastic links. The projection's
 * dx, with dv = dx / h, keeps x - x_prev - h v and v - v_prev unchanged as v_prev takes dv and x_prev
 * stays, so BDF2 reads no velocity or acceleration from the correction. */
static void commit(cloth *c, double h, measured *ms)
{
    size_t n3 = 3 * (size_t)c->n;
    struct cloth_state *s = &c->st;
    memcpy(s->x_prev, s->x, n3 * sizeof *s->x);
    for (size_t k = 0; k < n3; k++) s->v_prev[k] = s->v[k] + c->sl_dv[k];
    memcpy(s->x, c->x_new, n3 * sizeof *s->x);
    memcpy(s->v, c->v_new, n3 * sizeof *s->v);
    s->h_prev = h;
    s->has_prev = 1;
    cloth_method m = c->desc.solver.method;
    if (m == CLOTH_BACKWARD_EULER || m == CLOTH_BDF2) {
        memcpy(s->dv_prev, c->dv, n3 * sizeof *c->dv);
        memcpy(s->lim_shift, c->lim_shift, (size_t)c->n_seq * sizeof *c->lim_shift);
    }
    ms->plastic = oc_update_plastic_energy(c, h, &ms->elastic); /* cloth_update_plastic */
}

/* Retry after the whole step failed: 2^d substeps of h / 2^d, d = 1..halvings, until a depth takes
 * them all; a failure rolls back to the step's start, since explicit blow-ups show substeps late.
 * On success constraint forces are the substeps' mean; else the state is restored, last failure returned. */
static cloth_failure substep_retry(cloth *c, double h, int halvings, cloth_failure fail, cloth_step_stats *st,
                                   measured *ms)
{
    size_t n3 = 3 * (size_t)c->n;
    struct cloth_state *bk = &c->retry_bk;
    double *xs = c->retry_xs, *fsum = c->retry_fsum, air[3], asum[3], airt[3], atsum[3];
    oc_state_copy(bk, &c->st);
    memcpy(xs, c->st.x, n3 * sizeof *xs);
    long k = 0;
    for (int d = 1; d <= halvings; d++) {
        long parts = 1L << d;
        double hs = h / (double)parts; /* exact: a power of two */
        st->halvings = d;
        st->residual = 0.0; /* of this depth's substeps */
        st->strain_limited = 0;
        memset(fsum, 0, n3 * sizeof *fsum);
        memset(asum, 0, sizeof asum);
        memset(atsum, 0, sizeof atsum);
        /* bodies solved with the cloth: their du carries from substep to
         * substep (bodies.c) */
        oc_bodies_retry_reset(c);
        c->body_retry = 1;
        c->body_hs = hs;
        for (k = 0; k < parts; k++) {
            fail = attempt(c, hs, xs, (double)(k + 1) / (double)parts, d == halvings, st, ms);
            if (fail != CLOTH_FAIL_NONE) break;
            oc_air_step_force(c, hs, air, airt);
            for (int r = 0; r < 3; r++) {
                asum[r] += air[r] / (double)parts;
                atsum[r] += airt[r] / (double)parts;
            }
            commit(c, hs, ms);
            oc_bodies_retry_commit(c, hs);
            for (size_t q = 0; q < n3; q++) fsum[q] += c->con_new[q] / (double)parts;
        }
        c->body_retry = 0;
        if (fail == CLOTH_FAIL_NONE) break;
        st->substeps_failed++;
        oc_state_copy(&c->st, bk);
    }
    st->substeps = fail == CLOTH_FAIL_NONE ? (int)k : (int)k + 1;
    if (fail == CLOTH_FAIL_NONE) {
        memcpy(c->con_force, fsum, n3 * sizeof *fsum);
        memcpy(c->air_force, asum, sizeof asum);
        memcpy(c->air_torque, atsum, sizeof atsum);
        oc_bodies_retry_finish(c);
    }
    return fail;
}

cloth_status cloth_step(cloth *c, double h, cloth_step_stats *out)
{
    if (!c) return CLOTH_EINVAL;
    cloth_step_stats st;
    memset(&st, 0, sizeof st);
    double sc0 = self_contact_clock(c);
    const cloth_solver *sv = &c->desc.solver;
    st.method = sv->method;
    st.substeps = 1;
    if (!(h > 0.0) || !isfinite(h)) {
        st.failure = CLOTH_FAIL_BAD_STEP;
        fill_stats(c, &st, NULL);
        finish(c, &st, out, CLOTH_EINVAL, sc0);
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_step: h = %g must be finite and > 0", h);
    }
    measured ms = {0.0, 0.0, 0};
    oc_contacts_begin(c);
    cloth_failure fail = attempt(c, h, NULL, 1.0, sv->max_substep_halvings == 0, &st, &ms);
    if (fail == CLOTH_FAIL_NONE) {
        oc_air_step_force(c, h, c->air_force, c->air_torque);
        commit(c, h, &ms);
        memcpy(c->con_force, c->con_new, 3 * (size_t)c->n * sizeof *c->con_force);
    } else {
        st.first_failure = fail;
        st.substeps_failed = 1;
        if (sv->max_substep_halvings > 0) fail = substep_retry(c, h, sv->max_substep_halvings, fail, &st, &ms);
    }
    if (fail != CLOTH_FAIL_NONE) {
        oc_contacts_undo(c);
        st.failure = fail;
        fill_stats(c, &st, NULL); /* the unchanged state */
        finish(c, &st, out, CLOTH_ESTEP, sc0);
        if (st.halvings > 0)
            return oc_cloth_fail(c, CLOTH_ESTEP, "cloth_step: %s, also in substeps of h/%ld (state unchanged)",
                                 cloth_failure_string(fail), 1L << st.halvings);
        return oc_cloth_fail(c, CLOTH_ESTEP, "cloth_step: %s (state unchanged)", cloth_failure_string(fail));
    }
    fill_stats(c, &st, &ms); /* the committed positions are x_new */
    return finish(c, &st, out, CLOTH_OK, sc0);
}

const cloth_step_stats *cloth_last_stats(const cloth *c) { return c ? &c->stats : NULL; }
