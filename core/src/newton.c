/* Newton's method on the implicit step's potential (potential.h): each iteration solves the
 * positive-definite Newton matrix by the modified PCG, constraints held, and a backtracking line
 * search keeps it a descent. The elongation limit is an augmented Lagrangian on the same potential. */
#include <math.h>
#include <string.h>
#include "newton.h"
#include "linsolve.h"
#include "potential.h"
#include "mat3.h"
#include "mpcg.h"
#include "self_contact.h"
#include "tuning.h"

/* Solve the Newton matrix in c->A for ddv (cold start), rhs P->b, the
 * constrained components held at P->z. */
static mpcg_result linear_solve(cloth *c, mpcg_problem *P, double *ddv)
{
    memset(ddv, 0, 3 * (size_t)c->n * sizeof *ddv);
    if (P->extra) oc_bodies_newton_begin(c);
    return oc_linsolve_run(c, P, ddv);
}

/* The free part of vertex i's residual, S_i b_i (b_i where unconstrained) */
static void free_part(const cloth *c, int i, const double *b, double e[3])
{
    const double *Si = c->S + 9 * (size_t)i, *bi = b + 3 * (size_t)i;
    for (int r = 0; r < 3; r++)
        e[r] = c->con[i].ndof ? Si[3 * r] * bi[0] + Si[3 * r + 1] * bi[1] + Si[3 * r + 2] * bi[2] : bi[r];
}

/* The residual's size: sqrt((|S R|^2_{M^-1} + the bodies' |R_g|^2_{M_g^-1})
 * / mt), an RMS velocity (m/s); b = -R, mt the cloth's mass. */
static double residual_norm(const cloth *c, const mpcg_problem *P, const double *b, double mt)
{
    double s = 0.0;
    for (int i = 0; i < c->n; i++) {
        double e[3];
        free_part(c, i, b, e);
        s += (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) / c->mass[i];
    }
    if (P->extra) s += oc_bodies_residual_energy(P, b);
    return sqrt(s / mt);
}

/* Backtracking (Armijo) along ddv from dv, from t = tmax; returns the t taken and sets *phi to its
 * potential (phi0, slope: potential and derivative at dv, bodies included). The full step's residual
 * lands in c->b; *ready says whether the full step was taken, so the next iteration reuses it. */
static double line_search(cloth *c, const step_eq *q, const double *dv, const double *ddv, int bodies, double tmax,
                          double phi0, double slope, double *phi, int *ready)
{
    size_t n3 = 3 * (size_t)c->n;
    double t = tmax;
    *ready = 0;
    for (int k = 0; k < LINE_SEARCH_HALVINGS; k++, t *= 0.5) {
        for (size_t j = 0; j < n3; j++) c->dvt[j] = dv[j] + t * ddv[j];
        if (k == 0) {
            oc_potential_state(c, q, c->dvt);
            *phi = oc_potential_residual(c, q, c->dvt, c->b);
        } else {
            *phi = oc_potential_value(c, q, c->dvt, c->xt, c->vt);
        }
        *phi += bodies ? oc_bodies_newton_energy(c, t) : 0.0;
        *ready = k == 0;
        if (!(slope < 0.0)) break; /* not a descent direction (CG cut short): the full step */
        if (*phi <= phi0 + LINE_SEARCH_ARMIJO * t * slope) break;
        /* the change is within the potential's rounding: nothing to decide */
        if (fabs(t * slope) <= 1e-13 * (fabs(phi0) + fabs(*phi))) break;
    }
    if (t < 1.0) *ready = 0;
    return t;
}

/* Constraint forces at the iterate, R = -b (assembled there): the
 * constrained components of R are the impulse the constraints applied,
 * cfac f_c. */
static void constraint_forces(cloth *c, const double *b, double cfac)
{
    for (int i = 0; i < c->n; i++) {
        double *f = c->con_new + 3 * (size_t)i, R[3];
        f[0] = f[1] = f[2] = 0.0;
        if (c->con[i].ndof == 0) continue;
        const double *Si = c->S + 9 * (size_t)i;
        for (int r = 0; r < 3; r++) R[r] = -b[3 * i + r];
        for (int r = 0; r < 3; r++)
            f[r] = (R[r] - (Si[3 * r] * R[0] + Si[3 * r + 1] * R[1] + Si[3 * r + 2] * R[2])) / cfac;
    }
}

/* A free cloth's converged step keeps linear momentum exactly: the sum of
 * the residual the solves leave goes by one rigid velocity change (no link
 * feels it); not with constraints or air drag. */
static void balance_momentum(cloth *c, const step_eq *q, double *dv)
{
    double W[3], mt = 0.0;
    if (c->n_con || oc_air_on(c)) return;
    oc_potential_momentum_residual(c, q, dv, W);
    for (int i = 0; i < c->n; i++) mt += c->mass[i];
    if (!(mt > 0.0)) return;
    for (size_t k = 0; k < 3 * (size_t)c->n; k++) dv[k] -= W[k % 3] / mt;
    oc_potential_state(c, q, dv); /* x_new, v_new, which the step commits */
}

/* Component j of the dv whose positions go share of the way from x0 to those of dv = 0 */
static double start_share(const cloth *c, const step_eq *q, size_t j, double share)
{
    double x = c->st.x[j] + share * (q->a[j] + q->cfac * c->st.v[j] - c->st.x[j]);
    return (x - q->a[j]) / q->cfac - c->st.v[j];
}

/* The start: of no change, rest (v = 0) and, with warm_start, the last step's dv, whichever has the
 * lowest potential (with self-contact, among those reachable from x0 without a touch); z what the
 * first iteration adds to land the constraints. Returns 1 if that is nothing. */
static int newton_start(cloth *c, const step_eq *q, double *dv)
{
    size_t n3 = 3 * (size_t)c->n;
    double best = INFINITY;
    memset(dv, 0, n3 * sizeof *dv);
    /* k: no change, the last step's dv, rest, and with self-contact the share of the way
     * from x0 to no change's positions that stops short of a touch */
    double share = 1.0;
    if (c->self_contact) {
        for (size_t j = 0; j < n3; j++) c->vt[j] = q->a[j] + q->cfac * c->st.v[j];
        share = oc_self_contact_max_step(c->self_contact, c->st.x, c->vt);
    }
    const double *warm = c->warm_set ? c->warm_dv : c->st.dv_prev;
    for (int k = -1; k < 3; k++) {
        if ((k == 0 && !c->desc.solver.warm_start) || (k == 2 && !c->self_contact)) continue;
        for (size_t j = 0; j < n3; j++)
            c->dvt[j] = k < 0 ? 0.0 : k == 0 ? warm[j] : k == 1 ? -c->st.v[j] : start_share(c, q, j, share);
        double phi = oc_potential_value(c, q, c->dvt, c->xt, c->vt);
        if (c->self_contact && oc_self_contact_max_step(c->self_contact, c->st.x, c->xt) < 1.0) continue;
        if (phi < best || k < 0) {
            best = phi;
            memcpy(dv, c->dvt, n3 * sizeof *dv);
        }
    }
    int none = 1;
    for (int i = 0; i < c->n; i++) {
        if (!c->con[i].ndof) continue;
        double *d = dv + 3 * (size_t)i, *z = c->z + 3 * (size_t)i, s[3];
        mat3vec(c->S + 9 * (size_t)i, d, s);
        for (int r = 0; r < 3; r++) {
            z[r] -= d[r] - s[r];
            none = none && z[r] == 0.0;
        }
    }
    return none;
}

/* The velocity change dv's size, |dv|_M / sqrt(mt) (m/s, RMS; mt the
 * cloth's mass). */
static double dv_size(const cloth *c, const double *dv, double mt)
{
    double s = 0.0;
    for (int i = 0; i < c->n; i++) {
        const double *d = dv + 3 * (size_t)i;
        s += c->mass[i] * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    return sqrt(s / mt);
}

/* What the warm start dv must come within to be kept without a solve:
 * newton_tolerance and newton_rtol of its own velocity change (free fall's
 * is exact); by the absolute tolerance alone a weak force would never act. */
static double warm_goal(const cloth *c, const double *dv, double mt)
{
    return fmin(c->desc.solver.newton_tolerance, c->desc.solver.newton_rtol * dv_size(c, dv, mt));
}

/* The Newton step's size, sqrt(ddv^T M ddv (+ the bodies') / cloth mass):
 * the velocity correction the residual calls for (m/s, RMS). */
static double step_norm(const cloth *c, const mpcg_problem *P, const double *ddv)
{
    double s = 0.0, mt = 0.0;
    for (int i = 0; i < c->n; i++) {
        const double *d = ddv + 3 * (size_t)i;
        mt += c->mass[i];
        s += c->mass[i] * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    if (P->extra) s += oc_bodies_step_energy(c);
    return sqrt(s / mt);
}

/* The work the momentum the solve leaves over (the free residual's sum, an
 * impulse) can do on the bodies: shared among the constraints by the size of
 * their forces, as the plugin gives it, each moving at its held velocity. */
static double leftover_work(const cloth *c, const double *b)
{
    double F[3] = {0.0, 0.0, 0.0}, fsum = 0.0, fv = 0.0;
    for (int i = 0; i < c->n; i++) {
        const double *vi = c->v_new + 3 * (size_t)i, *bi = b + 3 * (size_t)i;
        double e[3], vf[3], f2 = 0.0, v2 = 0.0;
        free_part(c, i, b, e);
        for (int r = 0; r < 3; r++) F[r] += e[r];
        if (!c->con[i].ndof) continue;
        free_part(c, i, vi, vf);
        for (int r = 0; r < 3; r++) {
            f2 += (bi[r] - e[r]) * (bi[r] - e[r]);
            v2 += (vi[r] - vf[r]) * (vi[r] - vf[r]);
        }
        fsum += sqrt(f2);
        fv += sqrt(f2 * v2);
    }
    return fsum > 0.0 ? sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2]) * fv / fsum : 0.0;
}

/* Whether the iterate dv (b = -R there, assembled) can have made no more
 * energy than NEWTON_GAIN_SHARE of what the exact step dissipates: the work of
 * R's free part at v_new, each held body's at its velocity, the leftover's. */
static int energy_bounded(cloth *c, const step_eq *q, const mpcg_problem *P, const double *b, const double *dv,
                          double mt)
{
    double work = 0.0, diss = 0.0, tol = NEWTON_REL_FLOOR * c->desc.solver.newton_tolerance;
    for (int i = 0; i < c->n; i++) {
        const double *vi = c->v_new + 3 * (size_t)i, *d = dv + 3 * (size_t)i;
        double e[3];
        free_part(c, i, b, e);
        work += vi[0] * e[0] + vi[1] * e[1] + vi[2] * e[2];
        diss += 0.5 * c->mass[i] * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    if (P->extra) {
        work += oc_bodies_residual_work(c, P, b);
        diss += 0.5 * oc_bodies_step_energy(c);
    }
    double gain = leftover_work(c, b) - work;
    diss += oc_potential_step_dissipation(c, q);
    return gain <= NEWTON_GAIN_SHARE * diss + 0.5 * mt * tol * tol;
}

/* The share of the update ddv from dv that self-contact lets an iterate take (1 without it):
 * short of the first touch on the way (vertex-triangle or edge-edge). */
static double contact_free_share(cloth *c, const step_eq *q, const double *dv, const double *ddv)
{
    if (!c->self_contact) return 1.0;
    for (size_t k = 0; k < 3 * (size_t)c->n; k++) {
        c->xt[k] = q->a[k] + q->cfac * (c->st.v[k] + dv[k]);
        c->vt[k] = c->xt[k] + q->cfac * ddv[k];
    }
    return oc_self_contact_max_step(c->self_contact, c->xt, c->vt);
}

/* One Newton iteration from dv: solve, search (not on the first, which lands the constraints), take
 * (*taken: the update's share). *size gets the full step's size, *ready whether b is assembled at the
 * new dv; returns the CG's failure (NONE, or a cut-short solve's). */
static cloth_failure newton_iteration(cloth *c, const step_eq *q, mpcg_problem *P, double *dv, double *phi, int first,
                                      int matrix, double *size, int *ready, double *taken, cloth_step_stats *st)
{
    size_t n3 = 3 * (size_t)c->n;
    double *ddv = c->ddv;
    if (!matrix) oc_potential_matrix(c, q, 1); /* at dv: c->x_new, c->v_new are its */
    mpcg_result r = linear_solve(c, P, ddv);
    *ready = 0;
    st->iterations += r.iterations;
    if (!(st->residual >= r.residual)) st->residual = r.residual;
    if (r.failure == CLOTH_FAIL_NAN || r.failure == CLOTH_FAIL_CG_INDEFINITE || !oc_all_finite(ddv, n3)) {
        if (P->extra) oc_bodies_newton_take(c, 0.0);
        return r.failure == CLOTH_FAIL_NONE ? CLOTH_FAIL_NAN : r.failure;
    }
    *size = step_norm(c, P, ddv);
    double t = contact_free_share(c, q, dv, ddv);
    if (!first) {
        double slope = 0.0, phi1;
        for (size_t k = 0; k < n3; k++) slope -= c->b[k] * ddv[k];
        if (P->extra) slope += oc_bodies_newton_slope(c);
        t = line_search(c, q, dv, ddv, P->extra != NULL, t, *phi, slope, &phi1, ready);
        if (t < 1.0) st->line_search_cuts++;
        *phi = phi1;
    } else {
        *phi = NAN;
    }
    for (size_t k = 0; k < n3; k++) dv[k] += t * ddv[k];
    if (P->extra) oc_bodies_newton_take(c, t);
    *taken = t;
    return r.failure;
}

/* The constraints again after the contacts changed (contacts.c): the
 * filter and targets. */
static void contacts_changed(cloth *c, const step_eq *q, mpcg_problem *P, const double *xs, double frac, int n,
                             cloth_step_stats *st)
{
    st->contacts_decided += n;
    oc_constraints_build(c, q->a, c->st.v, q->cfac, xs, frac);
    P->ncon = c->n_con;
}

/* Contact candidates the iterate dv (in c->x_new) puts behind their
 * surface, beyond what the tolerance leaves open (cfac newton_tolerance),
 * become planes landed by the next iteration; returns how many. */
static int decide_contacts(cloth *c, const step_eq *q, mpcg_problem *P, const double *dv, const double *xs, double frac,
                           cloth_step_stats *st)
{
    int added = oc_contacts_decide(c, c->x_new, q->cfac * c->desc.solver.newton_tolerance);
    if (!added) return 0;
    contacts_changed(c, q, P, xs, frac, added, st);
    oc_contacts_land(c, dv);
    return added;
}

/* The constraints again after n contacts were loosened at the converged
 * iterate (let slide or let go): their normal components are on target. */
static int loosened(cloth *c, const step_eq *q, mpcg_problem *P, const double *xs, double frac, int n,
                    cloth_step_stats *st)
{
    if (!n) return 0;
    contacts_changed(c, q, P, xs, frac, n, st);
    memset(c->z, 0, 3 * (size_t)c->n * sizeof *c->z);
    return n;
}

cloth_failure oc_newton_step(cloth *c, double h, int bdf2, const double *xs, double frac, cloth_step_stats *st,
                             int *limit_held)
{
    const cloth_solver *sv = &c->desc.solver;
    step_eq q;
    oc_potential_begin(c, h, bdf2, &q);
    oc_constraints_build(c, q.a, c->st.v, q.cfac, xs, frac);
    double *dv = c->dv, *b = c->b;
    memcpy(c->lim_shift, c->st.lim_shift, (size_t)c->n_seq * sizeof *c->lim_shift);
    oc_limit_multipliers_begin(c);
    int landed = newton_start(c, &q, dv);
    mpcg_problem P =
        {&c->A, b,   c->S, c->z, c->pre, c->clist, c->n_con, NULL, NULL, sv->newton_cg_tolerance, sv->cg_max_iterations,
         NULL,  0.0, 1,    0.0,  NULL,   0};
    mpcg_bodies bodies;
    P.extra = oc_bodies_prepare(c, h, q.cfac, &bodies);
    double mt = 0.0;
    for (int i = 0; i < c->n; i++) mt += c->mass[i];
    /* a landing's solve is judged against the residual before it where that is smaller (inexact
     * Newton's forcing), down to newton_tolerance's */
    P.ref_floor = mt * pow(sv->newton_tolerance / sv->newton_cg_tolerance, 2);
    P.mass = c->mass;
    int it = 0, limit_rounds = 0, assembled = 0, landing = 1; /* limit_rounds: the multipliers' updates so far */
    int ready = 0;                                            /* b already at dv (the line search's full step) */
    int matrix = 0;                                           /* the Newton matrix already at dv */
    int since = 0;                                            /* iterations since the contacts or multipliers changed */
    double phi = NAN, size = INFINITY, rn = INFINITY, goal = sv->newton_tolerance;
    int conv = 0, pending = !landed; /* pending: constraints the iterate has not landed */
    *limit_held = 0;
    for (;;) {
        if (!assembled) { /* the residual at dv, and whether it is small enough */
            if (!ready) {
                /* with constraints to land no iterate converges: the matrix comes in the same pass */
                matrix = pending && since < sv->newton_iterations;
                oc_potential_state(c, &q, dv);
                double at = matrix ? oc_potential_assemble(c, &q, dv, b, 1) : oc_potential_residual(c, &q, dv, b);
                if (phi != phi) phi = at + (P.extra ? oc_bodies_energy(c) : 0.0);
            }
            ready = 0;
            assembled = 1;
            rn = residual_norm(c, &P, b, mt);
            goal = it == 0 && landed ? warm_goal(c, dv, mt) : sv->newton_tolerance;
            if (it == 0) size = rn; /* no step taken yet: the residual bounds it */
            conv = !pending && fmin(size, rn) <= goal && energy_bounded(c, &q, &P, b, dv, mt);
        }
        if (rn != rn) return CLOTH_FAIL_NAN;
        if (conv) {
            /* every change the converged iterate calls for, at once: contacts
             * on a link past the limit slide or (pulling) let go, others pulling
             * past their own limit let go, candidates behind their surface hold */
            int loose = oc_contacts_slide(c, c->x_new);
            loose += oc_contacts_release(c, c->x_new, b, q.cfac);
            int changed = loosened(c, &q, &P, xs, frac, loose, st);
            int added = decide_contacts(c, &q, &P, dv, xs, frac, st);
            if (added) {
                landing = pending = 1;
                landed = 0; /* the residual no longer bounds the step */
            }
            changed += added;
            /* contact rounds end by themselves (a contact changes at most
             * twice a step); the multipliers' rounds have a budget */
            if (changed) {
                since = 0;
            } else if (limit_rounds++ >= sv->newton_iterations) {
                break; /* the limit left to the projection */
            } else if (oc_limit_multipliers_update(c, c->x_new, 1) <= sv->limit_tolerance) {
                *limit_held = 1;
                break;
            } else {
                st->limit_updates++;
                since = 0; /* each round its own budget */
            }
            phi = NAN; /* the potential changed with the multipliers or contacts */
            assembled = 0;
            size = INFINITY;
            continue;
        }
        if (since >= sv->newton_iterations) break;
        if (it > 0 && !landing && decide_contacts(c, &q, &P, dv, xs, frac, st)) {
            landing = pending = 1;
            phi = NAN;
            since = 0;
        }
        if (phi != phi && it > 0)
            phi = oc_potential_value(c, &q, dv, c->xt, c->vt) + (P.extra ? oc_bodies_energy(c) : 0.0);
        double taken = 1.0;
        /* the share serves the size test; iterations after it is met are
         * for the energy bound, whose residual only a full solve reduces */
        P.abs_err2 = size > goal ? mt * pow(sv->newton_cg_share * goal, 2) : 0.0;
        cloth_failure f = newton_iteration(c, &q, &P, dv, &phi, landing, matrix, &size, &ready, &taken, st);
        matrix = 0;
        /* the constraints landed, or the share taken of the way (self-contact): the next lands the rest */
        int rest = 0; /* constrained components still to land */
        for (size_t k = 0; landing && k < 3 * (size_t)c->n; k++) {
            c->z[k] = taken < 1.0 ? c->z[k] * (1.0 - taken) : 0.0;
            rest = rest || c->z[k] != 0.0;
        }
        landing = pending = rest;
        it++;
        since++;
        assembled = 0;
        if (f == CLOTH_FAIL_NAN || f == CLOTH_FAIL_CG_INDEFINITE) return f;
    }
    st->newton += it;
    st->newton_residual = fmin(size, rn);
    st->newton_goal = goal;
    if (!conv) { /* b is assembled at the last iterate: every exit follows an assembly */
        constraint_forces(c, b, q.cfac);
        return CLOTH_FAIL_NEWTON;
    }
    balance_momentum(c, &q, dv);
    constraint_forces(c, b, q.cfac);
    return CLOTH_FAIL_NONE;
}
