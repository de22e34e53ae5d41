/* The crease law (material.k_crease; docs/materials.md, "The crease law"): a link's set fold angle, kept as
 * its chord l1, stays within the yield angle of its fold; a hinge from the middle node to its ends' midpoint,
 * rest length the set's sagitta, resists unfolding along its direction at the step's start. */
#include <math.h>
#include "internal.h"
#include "bsr.h"
#include "mat3.h"
#include "spring_predicted.h"

#define CREASE_PI 3.14159265358979323846

int oc_crease_law_on(const cloth_material *m) { return m->k_crease > 0.0; }

/* the chord of a link of rest length rest folded by phi (clamped to [0, pi]) */
static double chord_of(double rest, double phi)
{
    if (!(phi > 0.0)) return rest;
    return phi < CREASE_PI ? rest * cos(0.5 * phi) : 0.0;
}

double oc_crease_fold_angle(double rest, double d)
{
    double r = d / rest;
    return r >= 1.0 ? 0.0 : r <= 0.0 ? CREASE_PI : 2.0 * acos(r);
}

void oc_crease_rule(double alpha, double rest, double d, int *plastic, double *l1)
{
    if (!(d >= 0.0) || !(rest > 0.0)) return; /* no length: nothing to decide */
    double a = alpha < 0.0 ? 0.0 : alpha > 1.0 ? 1.0 : alpha;
    double yield = 2.0 * acos(a), phi = oc_crease_fold_angle(rest, d);
    /* the set's chord within [chord(phi + yield), chord(phi - yield)]: a deeper fold sets more, an opened one less */
    double longest = chord_of(rest, phi - yield), shortest = chord_of(rest, phi + yield);
    double set = *plastic ? *l1 : rest, kept = set > longest ? longest : set < shortest ? shortest : set;
    if (kept == set) return; /* unchanged, bit for bit */
    *plastic = kept < rest;
    *l1 = kept < rest ? kept : rest;
}

/* the sagitta s = x_m - (x_i + x_j) / 2 of link L at x, m its middle node */
static void sagitta(const double *x, const link_topo *L, int m, double s[3])
{
    for (int r = 0; r < 3; r++) s[r] = x[3 * m + r] - 0.5 * (x[3 * L->i + r] + x[3 * L->j + r]);
}

double oc_crease_hinge(const cloth *c, int e, const double *x, const double *x0, double f_mid[3], double K[9])
{
    const cloth_material *mt = &c->desc.material;
    const link_topo *L = c->lint + e;
    int m = (L->i + L->j) / 2; /* grid indices: the middle node of a link two cells long */
    double half = 0.5 * L->rest, q = 0.5 * c->st.l1[e], sp2 = half * half - q * q;
    spring_law law = {0.0, mt->k_crease, sp2 > 0.0 ? sqrt(sp2) : 0.0, 0.0, HUGE_VAL};
    double s[3], s0[3], u0[3] = {0.0, 0.0, 0.0}, zero[3] = {0.0, 0.0, 0.0};
    sagitta(x, L, m, s);
    sagitta(x0, L, m, s0);
    double n0 = sqrt(s0[0] * s0[0] + s0[1] * s0[1] + s0[2] * s0[2]);
    if (n0 > SPRING_MIN_LENGTH)
        for (int r = 0; r < 3; r++) u0[r] = s0[r] / n0;
    return spring_predicted(zero, s, u0, law, 0.0, f_mid, K, NULL);
}

/* the next link after *e that carries a hinge (the crease law on and the link set): its link and middle node */
static int next_hinge(const cloth *c, int *e, const link_topo **L, int *m)
{
    if (!oc_crease_law_on(&c->desc.material)) return 0;
    while (++*e < c->n_int)
        if (c->st.plastic[*e]) {
            *L = c->lint + *e;
            *m = ((*L)->i + (*L)->j) / 2;
            return 1;
        }
    return 0;
}

double oc_crease_energy(const cloth *c, const double *x, const double *x0)
{
    double E = 0.0;
    const link_topo *L;
    for (int e = -1, m; next_hinge(c, &e, &L, &m);) E += oc_crease_hinge(c, e, x, x0, NULL, NULL);
    return E;
}

void oc_crease_forces(const cloth *c, const double *x, const double *x0, double scale, double *f)
{
    double fm[3];
    const link_topo *L;
    for (int e = -1, m; next_hinge(c, &e, &L, &m);) {
        oc_crease_hinge(c, e, x, x0, fm, NULL);
        for (int r = 0; r < 3; r++) { /* fm acts on the midpoint: half on each end, its reaction on m */
            f[3 * L->i + r] += 0.5 * scale * fm[r];
            f[3 * L->j + r] += 0.5 * scale * fm[r];
            f[3 * m + r] -= scale * fm[r];
        }
    }
}

/* A += w (the pair (a, b)'s link-like block: +K on both diagonals, -K off them) */
static void add_pair(bsr *A, int a, int b, const double K[9], double w)
{
    int ab = oc_bsr_find(A, a, b), ba = oc_bsr_find(A, b, a);
    mat3_axpy(A->val + 9 * (size_t)A->diag[a], K, w);
    mat3_axpy(A->val + 9 * (size_t)A->diag[b], K, w);
    if (ab >= 0) mat3_axpy(A->val + 9 * (size_t)ab, K, -w);
    if (ba >= 0) mat3_axpy(A->val + 9 * (size_t)ba, K, -w);
}

void oc_crease_matrix(cloth *c, const double *x, const double *x0, double scale)
{
    double K[9];
    const link_topo *L;
    for (int e = -1, m; next_hinge(c, &e, &L, &m);) {
        oc_crease_hinge(c, e, x, x0, NULL, K);
        /* B^T K B for s = x_m - (x_i + x_j) / 2: pairs (i, m) and (m, j) at 1/2, (i, j) at -1/4 */
        add_pair(&c->A, L->i, m, K, 0.5 * scale);
        add_pair(&c->A, m, L->j, K, 0.5 * scale);
        add_pair(&c->A, L->i, L->j, K, -0.25 * scale);
    }
}

void oc_crease_Kw(const cloth *c, const double *x, const double *w, double *out)
{
    double K[9];
    const link_topo *L;
    for (int e = -1, m; next_hinge(c, &e, &L, &m);) {
        oc_crease_hinge(c, e, x, x, NULL, K);
        double dw[3], y[3];
        for (int r = 0; r < 3; r++) dw[r] = w[3 * m + r] - 0.5 * (w[3 * L->i + r] + w[3 * L->j + r]);
        for (int r = 0; r < 3; r++) y[r] = K[3 * r] * dw[0] + K[3 * r + 1] * dw[1] + K[3 * r + 2] * dw[2];
        for (int r = 0; r < 3; r++) { /* df_mid/dx_m = K: as a link from the midpoint to m */
            out[3 * L->i + r] += 0.5 * y[r];
            out[3 * L->j + r] += 0.5 * y[r];
            out[3 * m + r] -= y[r];
        }
    }
}

double oc_crease_dissipation(const cloth *c, const double *x0, const double *x)
{
    double D = 0.0, f[3];
    const link_topo *L;
    for (int e = -1, m; next_hinge(c, &e, &L, &m);) {
        double s0[3], s[3];
        sagitta(x0, L, m, s0);
        sagitta(x, L, m, s);
        /* the convex hinge's gap E(x0) - E(x) - f(x) . (s0 - s), its direction x0's */
        D += oc_crease_hinge(c, e, x0, x0, NULL, NULL) - oc_crease_hinge(c, e, x, x0, f, NULL);
        for (int r = 0; r < 3; r++) D -= f[r] * (s0[r] - s[r]);
    }
    return D;
}
