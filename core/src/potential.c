/* The implicit step's incremental potential (potential.h): its value, its
 * gradient (the residual) and the positive-definite Newton matrix. */
#include <math.h>
#include <string.h>
#include "potential.h"
#include "assembly.h"
#include "mat3.h"
#include "spring_predicted.h"
#include "self_contact.h"
#include "tuning.h"

void oc_potential_begin(cloth *c, double h, int bdf2, step_eq *q)
{
    const struct cloth_state *s = &c->st;
    size_t n3 = 3 * (size_t)c->n;
    q->h = h;
    q->bdf2 = bdf2;
    q->beta = bdf2 ? 2.0 / 3.0 : 1.0;
    q->cfac = q->beta * h;
    for (size_t k = 0; k < n3; k++) c->na[k] = bdf2 ? s->x[k] + (s->x[k] - s->x_prev[k]) / 3.0 : s->x[k];
    q->a = c->na;
    if (c->self_contact) oc_self_contact_begin(c->self_contact, c, q->cfac);
    memset(c->slack_age, 0, (size_t)c->n_seq * sizeof *c->slack_age);
    /* the links' directions, damping's and compression's: backward Euler's at
     * x0, where the step's energy equals the springs' and elsewhere bounds it
     * (no exact step gains energy); BDF2's at x0 + h v0, for its order */
    double hd = bdf2 ? h : 0.0;
    for (int t = 0; t < 2; t++) {
        int ne = t ? c->n_int : c->n_seq;
        const link_topo *L = t ? c->lint : c->seq;
        double *ut = c->ut + (t ? 3 * (size_t)c->n_seq : 0);
        for (int e = 0; e < ne; e++) {
            const double *xi = s->x + 3 * L[e].i, *xj = s->x + 3 * L[e].j;
            const double *vi = s->v + 3 * L[e].i, *vj = s->v + 3 * L[e].j;
            double w[3], d2 = 0.0;
            for (int r = 0; r < 3; r++) {
                w[r] = xj[r] - xi[r] + hd * (vj[r] - vi[r]);
                d2 += w[r] * w[r];
            }
            double inv = d2 > 1e-24 ? 1.0 / sqrt(d2) : 0.0;
            for (int r = 0; r < 3; r++) ut[3 * e + r] = w[r] * inv;
        }
    }
    c->diss_e0 = NAN;
}

void oc_potential_state(cloth *c, const step_eq *q, const double *dv)
{
    const double *v0 = c->st.v;
    for (size_t k = 0; k < 3 * (size_t)c->n; k++) {
        c->v_new[k] = v0[k] + dv[k];
        c->x_new[k] = q->a[k] + q->cfac * c->v_new[k];
    }
}

/* BDF2's constant term e_k = m (v0 - v_-1) / 3 */
static double bdf2_extra(const cloth *c, const step_eq *q, size_t k)
{
    return q->bdf2 ? c->mass[k / 3] * (c->st.v[k] - c->st.v_prev[k]) / 3.0 : 0.0;
}

/* the law of link e of type t as the step uses it (the limit shifted by
 * its multiplier) */
MAT3_INLINE spring_law law_of(const cloth *c, int t, int e)
{
    const cloth_material *m = &c->desc.material;
    if (t) return int_law(m, c->lint[e].rest, c->st.plastic[e], c->st.l1[e]);
    spring_law s = seq_law(m, c->seq[e].rest, c->st.seq_set[e]);
    double rho = c->lim_rho[e], shift = c->lim_shift[e];
    s.k_lim *= rho;
    if (shift != 0.0) s.lim -= shift / rho;
    return s;
}

/* the law of link e of type t without the elongation limit */
MAT3_INLINE spring_law base_law(const cloth *c, int t, int e)
{
    spring_law s = t ? int_law(&c->desc.material, c->lint[e].rest, c->st.plastic[e], c->st.l1[e])
                     : seq_law(&c->desc.material, c->seq[e].rest, c->st.seq_set[e]);
    s.k_lim = 0.0;
    return s;
}

/* The links in node-major order, both types merged (each type's array is
 * node-major), so the matrix's rows are written in one pass: the next link
 * into *t, *e; returns 0 when none is left. */
MAT3_INLINE int next_link(const cloth *c, int *es, int *ei, int *t, int *e)
{
    if (*es < c->n_seq && (*ei >= c->n_int || c->seq[*es].i <= c->lint[*ei].i)) {
        *t = 0;
        *e = (*es)++;
        return 1;
    }
    if (*ei >= c->n_int) return 0;
    *t = 1;
    *e = (*ei)++;
    return 1;
}

/* link e of type t: its endpoints and its frozen direction */
MAT3_INLINE const double *link_ends(const cloth *c, int t, int e, int *i, int *j)
{
    const link_topo *L = (t ? c->lint : c->seq) + e;
    *i = L->i;
    *j = L->j;
    return c->ut + 3 * (t ? (size_t)c->n_seq + (size_t)e : (size_t)e);
}

/* The rate of link (i, j) along u at velocities v */
MAT3_INLINE double link_rate(const double *v, int i, int j, const double *u)
{
    return (v[3 * j] - v[3 * i]) * u[0] + (v[3 * j + 1] - v[3 * i + 1]) * u[1] + (v[3 * j + 2] - v[3 * i + 2]) * u[2];
}

/* The links' energy at x0 without the elongation limit, along the step's directions */
static double energy_at_start(const cloth *c)
{
    const double *x0 = c->st.x;
    double E = 0.0;
    for (int es = 0, ei = 0, t, e; next_link(c, &es, &ei, &t, &e);) {
        int i, j;
        const double *u = link_ends(c, t, e, &i, &j);
        E += spring_predicted(x0 + 3 * i, x0 + 3 * j, u, base_law(c, t, e), 0.0, NULL, NULL, NULL);
    }
    return E;
}

/* The vertices' terms of R and Phi into b (inertia, gravity, external forces, BDF2's e) */
static double inertia_terms(const cloth *c, const step_eq *q, const double *dv, double *b)
{
    const double *v = c->v_new;
    double cf = q->cfac, P = 0.0;
    for (int i = 0; i < c->n; i++)
        for (int r = 0; r < 3; r++) {
            size_t k = 3 * (size_t)i + (size_t)r;
            double fc = c->mass[i] * c->desc.gravity[r] + c->f_ext[k], e = bdf2_extra(c, q, k);
            b[k] = cf * fc + e - c->mass[i] * dv[k];
            P += (0.5 * c->mass[i] * dv[k] - e) * dv[k] - cf * fc * v[k];
        }
    return P;
}

/* Link (i, j)'s Bregman gap and damper work in backward Euler's dissipation, less its
 * energy at x0 (oc_potential_begin's e0): its force f (limit share lim) and energy E at x. */
MAT3_INLINE double link_dissipation(const cloth *c, int i, int j, double E, const double f[3], const double lim[2],
                                    double damp_vu2)
{
    const double *x0 = c->st.x, *x = c->x_new;
    double gap = lim[0] - E;
    for (int r = 0; r < 3; r++) {
        double w = x[3 * j + r] - x[3 * i + r];
        gap -= (f[r] - lim[1] * w) * ((x0[3 * j + r] - x0[3 * i + r]) - w);
    }
    return gap + damp_vu2;
}

/* One pass over the links at c->x_new, c->v_new (node-major): with b, their impulses into b, their
 * share of Phi added to P (returned) and BE's dissipation less their x0 energy into c->diss_links;
 * with mat, their Newton blocks into c->A (stiffen: oc_potential_matrix's). */
MAT3_INLINE double links_pass(cloth *c, const step_eq *q, double P, double *b, int mat, int stiffen)
{
    const cloth_material *m = &c->desc.material;
    const double *x = c->x_new, *v = c->v_new;
    double cf = q->cfac, cf2 = cf * cf, D = 0.0, f[3], K[9], blk[9], lim[2];
    int diss = b && !q->bdf2;
    for (int es = 0, ei = 0, t, e; next_link(c, &es, &ei, &t, &e);) {
        int i, j, slack, ahead = e + ASSEMBLY_PREFETCH_LINKS;
        if (mat && ahead < (t ? c->n_int : c->n_seq))
            assemble_prefetch(c, (t ? c->lint : c->seq)[ahead].j, (t ? c->int_blk : c->seq_blk) + 2 * ahead);
        const double *u = link_ends(c, t, e, &i, &j);
        unsigned char *age = !mat || t || !stiffen ? NULL : c->slack_age + e;
        double damp = t ? m->c_b : m->c_t, w = age ? ldexp(SLACK_SHARE, -*age) : 0.0;
        double E = spring_predicted_lim(x + 3 * i, x + 3 * j, u, law_of(c, t, e), w, b ? f : NULL, mat ? K : NULL,
                                        &slack, diss ? lim : NULL);
        if (age) *age = slack ? (unsigned char)(*age < SLACK_AGE_MAX ? *age + 1 : *age) : 0;
        if (mat) {
            for (int r = 0; r < 3; r++)
                for (int s = 0; s < 3; s++) blk[3 * r + s] = cf2 * K[3 * r + s] + cf * damp * u[r] * u[s];
            assemble_link(c, i, j, (t ? c->int_blk : c->seq_blk) + 2 * e, blk);
        }
        if (!b) continue;
        double vu = link_rate(v, i, j, u), rate = damp * vu;
        P += E + 0.5 * cf * damp * vu * vu;
        for (int r = 0; r < 3; r++) {
            double fr = cf * (f[r] + rate * u[r]);
            b[3 * i + r] += fr;
            b[3 * j + r] -= fr;
        }
        if (diss) D += link_dissipation(c, i, j, E, f, lim, cf * damp * vu * vu);
    }
    if (b) c->diss_links = diss ? D : 0.0;
    return P;
}

/* The matrix's diagonal blocks set to the masses (and the rest zeroed where links add) */
static void matrix_begin(cloth *c)
{
    bsr *A = &c->A;
    if (!c->links_own_blocks) oc_bsr_zero(A);
    for (int i = 0; i < c->n; i++) {
        double *B = A->val + 9 * (size_t)A->diag[i];
        memset(B, 0, 9 * sizeof *B);
        B[0] = B[4] = B[8] = c->mass[i];
    }
}

/* The crease hinges', air's and self-contact's terms at c->x_new, c->v_new: into b and added to P
 * (with b), into c->A (with mat) */
static double other_terms(cloth *c, const step_eq *q, double P, double *b, int mat)
{
    double cf = q->cfac;
    const double *x = c->x_new, *v = c->v_new;
    if (oc_crease_law_on(&c->desc.material)) { /* the crease law's hinges (crease_law.c), pushing as at the start */
        if (b) {
            P += oc_crease_energy(c, x, c->st.x);
            oc_crease_forces(c, x, c->st.x, cf, b);
        }
        if (mat) oc_crease_matrix(c, x, c->st.x, cf * cf);
    }
    /* air drag, a damper with its normals and areas at x~ */
    if (b && oc_air_on(c)) P += cf * oc_air_eval(c, c->st.x, c->st.v, q->h, v, cf, b, NULL, 0.0);
    if (b && c->self_contact) P += oc_self_contact_eval(c->self_contact, x, cf, b, NULL);
    if (mat && oc_air_on(c)) oc_air_eval(c, c->st.x, c->st.v, q->h, v, 0.0, NULL, &c->A, cf);
    if (mat && c->self_contact) oc_self_contact_eval(c->self_contact, x, cf, NULL, &c->A);
    return P;
}

double oc_potential_residual(cloth *c, const step_eq *q, const double *dv, double *b)
{
    double P = links_pass(c, q, inertia_terms(c, q, dv, b), b, 0, 0);
    return other_terms(c, q, P, b, 0);
}

void oc_potential_matrix(cloth *c, const step_eq *q, int stiffen)
{
    matrix_begin(c);
    links_pass(c, q, 0.0, NULL, 1, stiffen);
    other_terms(c, q, 0.0, NULL, 1);
}

double oc_potential_assemble(cloth *c, const step_eq *q, const double *dv, double *b, int stiffen)
{
    double P = inertia_terms(c, q, dv, b);
    matrix_begin(c);
    P = links_pass(c, q, P, b, 1, stiffen);
    return other_terms(c, q, P, b, 1);
}

double oc_potential_step_dissipation(cloth *c, const step_eq *q)
{
    if (q->bdf2) return 0.0;
    if (c->diss_e0 != c->diss_e0) c->diss_e0 = energy_at_start(c);
    double D = c->diss_e0 + c->diss_links;
    return oc_crease_law_on(&c->desc.material) ? D + oc_crease_dissipation(c, c->st.x, c->x_new) : D;
}

void oc_potential_momentum_residual(const cloth *c, const step_eq *q, const double *dv, double out[3])
{
    out[0] = out[1] = out[2] = 0.0;
    for (int i = 0; i < c->n; i++)
        for (int r = 0; r < 3; r++) {
            size_t k = 3 * (size_t)i + (size_t)r;
            double fc = c->mass[i] * c->desc.gravity[r] + c->f_ext[k];
            out[r] += c->mass[i] * dv[k] - bdf2_extra(c, q, k) - q->cfac * fc;
        }
}

double oc_potential_value(const cloth *c, const step_eq *q, const double *dv, double *x, double *v)
{
    const cloth_material *m = &c->desc.material;
    double cf = q->cfac, P = 0.0;
    for (int i = 0; i < c->n; i++)
        for (int r = 0; r < 3; r++) {
            size_t k = 3 * (size_t)i + (size_t)r;
            v[k] = c->st.v[k] + dv[k];
            x[k] = q->a[k] + cf * v[k];
            double fc = c->mass[i] * c->desc.gravity[r] + c->f_ext[k];
            P += (0.5 * c->mass[i] * dv[k] - bdf2_extra(c, q, k)) * dv[k] - cf * fc * v[k];
        }
    for (int es = 0, ei = 0, t, e; next_link(c, &es, &ei, &t, &e);) {
        int i, j;
        const double *u = link_ends(c, t, e, &i, &j);
        double damp = t ? m->c_b : m->c_t, vu = link_rate(v, i, j, u);
        P += spring_predicted(x + 3 * i, x + 3 * j, u, law_of(c, t, e), 0.0, NULL, NULL, NULL) +
             0.5 * cf * damp * vu * vu;
    }
    if (oc_crease_law_on(m)) P += oc_crease_energy(c, x, c->st.x);
    if (oc_air_on(c)) P += cf * oc_air_eval(c, c->st.x, c->st.v, q->h, v, 0.0, NULL, NULL, 0.0);
    if (c->self_contact) P += oc_self_contact_eval(c->self_contact, x, cf, NULL, NULL);
    return P;
}

double oc_potential_dissipation(const cloth *c, const step_eq *q)
{
    if (q->bdf2) return 0.0;
    const cloth_material *m = &c->desc.material;
    const double *x0 = c->st.x, *x = c->x_new, *v = c->v_new;
    double D = 0.0, f[3];
    for (int t = 0; t < 2; t++) {
        int ne = t ? c->n_int : c->n_seq;
        const link_topo *L = t ? c->lint : c->seq;
        const double *ut = c->ut + (t ? 3 * (size_t)c->n_seq : 0);
        double damp = q->cfac * (t ? m->c_b : m->c_t);
        for (int e = 0; e < ne; e++) {
            int i = L[e].i, j = L[e].j;
            const double *u = ut + 3 * (size_t)e;
            spring_law s = law_of(c, t, e);
            s.k_lim = 0.0;
            double gap = spring_predicted(x0 + 3 * i, x0 + 3 * j, u, s, 0.0, NULL, NULL, NULL) -
                         spring_predicted(x + 3 * i, x + 3 * j, u, s, 0.0, f, NULL, NULL),
                   rate = 0.0;
            for (int r = 0; r < 3; r++) {
                gap -= f[r] * ((x0[3 * j + r] - x0[3 * i + r]) - (x[3 * j + r] - x[3 * i + r]));
                rate += (v[3 * j + r] - v[3 * i + r]) * u[r];
            }
            D += gap + damp * rate * rate;
        }
    }
    if (oc_crease_law_on(m)) D += oc_crease_dissipation(c, x0, x);
    return D;
}
