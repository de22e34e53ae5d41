/* Self-contact inside the Newton step: see self_contact.h. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "self_contact.h"
#include "ccd.h"
#include "vec3.h"

/* A touch is a vertex within this share of the thickness of a triangle's
 * plane inside it; an update stops at this share of the way to its first. */
#define SELF_CONTACT_TOUCH 1e-3
#define SELF_CONTACT_STOP 0.5

struct self_contact {
    int n, ntri;
    const int *tri;       /* 3 ntri corners */
    double D, cell, kappa;
    int nbucket;
    int *head;            /* nbucket: first entry, -1 none */
    int *ent_tri, *ent_next; /* 8 ntri entries */
    int *big, nbig;       /* triangles whose box is over a cell wide: every query meets them */
    int *stamp, visit;    /* ntri: the last query that met each triangle */
    int *cand, ncand;     /* ntri: a query's triangles */
    double *box;          /* 6 ntri: the boxes filed */
    cloth *owner;         /* the cloth whose steps feel it, or NULL */
};

self_contact *self_contact_create(int n, int ntri, const int *tri, double thickness, double cell)
{
    self_contact *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->n = n;
    s->ntri = ntri;
    s->tri = tri;
    s->D = thickness;
    s->cell = cell;
    s->nbucket = 4 * ntri + 1;
    s->head = malloc((size_t)s->nbucket * sizeof *s->head);
    s->ent_tri = malloc(8 * (size_t)ntri * sizeof *s->ent_tri);
    s->ent_next = malloc(8 * (size_t)ntri * sizeof *s->ent_next);
    s->big = malloc((size_t)ntri * sizeof *s->big);
    s->stamp = malloc((size_t)ntri * sizeof *s->stamp);
    s->cand = malloc((size_t)ntri * sizeof *s->cand);
    s->box = malloc(6 * (size_t)ntri * sizeof *s->box);
    if (!s->head || !s->ent_tri || !s->ent_next || !s->big || !s->stamp || !s->cand || !s->box) {
        self_contact_destroy(s);
        return NULL;
    }
    for (int t = 0; t < ntri; t++) s->stamp[t] = -1;
    return s;
}

void self_contact_destroy(self_contact *s)
{
    if (!s) return;
    if (s->owner) s->owner->self_contact = NULL;
    free(s->head);
    free(s->ent_tri);
    free(s->ent_next);
    free(s->big);
    free(s->stamp);
    free(s->cand);
    free(s->box);
    free(s);
}

void self_contact_bind(self_contact *s, cloth *c)
{
    if (s->owner == c) return;
    if (s->owner) s->owner->self_contact = NULL;
    if (c->self_contact) c->self_contact->owner = NULL;
    s->owner = c;
    c->self_contact = s;
}

void self_contact_unbind_cloth(cloth *c)
{
    if (c->self_contact) c->self_contact->owner = NULL;
    c->self_contact = NULL;
}

/* b(d) / D^2's derivatives' scale: b''(D / 2) */
static double curvature_at_half(void) { return 2.0 * log(2.0) + 4.0 + 1.0; }

void self_contact_begin(self_contact *s, const cloth *c, double cfac)
{
    /* IPC's scale: the barrier's curvature at half the thickness is the
     * mean vertex's mass in Newton's matrix (cfac^2 kappa b'') */
    double mt = 0.0;
    for (int i = 0; i < c->n; i++) mt += c->mass[i];
    s->kappa = mt / c->n / (cfac * cfac * curvature_at_half());
}

static long cell_index(const self_contact *s, double u) { return (long)floor(u / s->cell); }

static int bucket(const self_contact *s, long i, long j, long k)
{
    uint64_t h = (uint64_t)i * 73856093u ^ (uint64_t)j * 19349663u ^ (uint64_t)k * 83492791u;
    return (int)(h % (uint64_t)s->nbucket);
}

/* File every triangle by its box over its corners at x0 and x1 (x1 NULL:
 * x0 only), widened by pad: into the cells it overlaps, or the big list. */
static void file_triangles(self_contact *s, const double *x0, const double *x1, double pad)
{
    for (int b = 0; b < s->nbucket; b++) s->head[b] = -1;
    int nent = 0;
    s->nbig = 0;
    for (int t = 0; t < s->ntri; t++) {
        double *bx = s->box + 6 * (size_t)t;
        int wide = 0;
        for (int a = 0; a < 3; a++) {
            bx[a] = HUGE_VAL;
            bx[3 + a] = -HUGE_VAL;
            for (int k = 0; k < 3; k++) {
                const double *p = x0 + 3 * s->tri[3 * t + k];
                bx[a] = fmin(bx[a], p[a]);
                bx[3 + a] = fmax(bx[3 + a], p[a]);
                if (x1) {
                    p = x1 + 3 * s->tri[3 * t + k];
                    bx[a] = fmin(bx[a], p[a]);
                    bx[3 + a] = fmax(bx[3 + a], p[a]);
                }
            }
            bx[a] -= pad;
            bx[3 + a] += pad;
            wide = wide || !(bx[3 + a] - bx[a] <= s->cell);
        }
        if (wide) {
            s->big[s->nbig++] = t;
            continue;
        }
        for (long i = cell_index(s, bx[0]); i <= cell_index(s, bx[3]); i++)
            for (long j = cell_index(s, bx[1]); j <= cell_index(s, bx[4]); j++)
                for (long k = cell_index(s, bx[2]); k <= cell_index(s, bx[5]); k++) {
                    int b = bucket(s, i, j, k);
                    s->ent_tri[nent] = t;
                    s->ent_next[nent] = s->head[b];
                    s->head[b] = nent++;
                }
    }
}

static int overlaps(const double *a, const double *b)
{
    return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] && b[2] <= a[5];
}

static void take(self_contact *s, int t, const double *q)
{
    if (s->stamp[t] == s->visit || !overlaps(s->box + 6 * (size_t)t, q)) return;
    s->stamp[t] = s->visit;
    s->cand[s->ncand++] = t;
}

/* The triangles filed whose box overlaps box q (6), not having p as a
 * corner, into s->cand; returns their number. */
static int gather(self_contact *s, int p, const double *q)
{
    s->ncand = 0;
    if (++s->visit == INT32_MAX) {
        for (int t = 0; t < s->ntri; t++) s->stamp[t] = -1;
        s->visit = 0;
    }
    for (int e = 0; e < s->nbig; e++) take(s, s->big[e], q);
    if (!(q[3] - q[0] <= s->cell && q[4] - q[1] <= s->cell && q[5] - q[2] <= s->cell)) {
        for (int t = 0; t < s->ntri; t++) take(s, t, q);
    } else {
        for (long i = cell_index(s, q[0]); i <= cell_index(s, q[3]); i++)
            for (long j = cell_index(s, q[1]); j <= cell_index(s, q[4]); j++)
                for (long k = cell_index(s, q[2]); k <= cell_index(s, q[5]); k++)
                    for (int e = s->head[bucket(s, i, j, k)]; e >= 0; e = s->ent_next[e]) take(s, s->ent_tri[e], q);
    }
    int m = 0;
    for (int k = 0; k < s->ncand; k++) {
        const int *tv = s->tri + 3 * s->cand[k];
        if (tv[0] != p && tv[1] != p && tv[2] != p) s->cand[m++] = s->cand[k];
    }
    return s->ncand = m;
}

/* The point of triangle (a, b, c) closest to p as weights w on its corners
 * (Ericson, Real-Time Collision Detection, 5.1.5). */
static void closest_weights(const double *p, const double *a, const double *b, const double *c, double *w)
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    vec3_sub(b, a, ab);
    vec3_sub(c, a, ac);
    vec3_sub(p, a, ap);
    double d1 = vec3_dot(ab, ap), d2 = vec3_dot(ac, ap);
    w[0] = 1.0;
    w[1] = w[2] = 0.0;
    if (d1 <= 0.0 && d2 <= 0.0) return;
    vec3_sub(p, b, bp);
    double d3 = vec3_dot(ab, bp), d4 = vec3_dot(ac, bp);
    w[0] = 0.0;
    w[1] = 1.0;
    if (d3 >= 0.0 && d4 <= d3) return;
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        double v = d1 / (d1 - d3);
        w[0] = 1.0 - v, w[1] = v, w[2] = 0.0;
        return;
    }
    vec3_sub(p, c, cp);
    double d5 = vec3_dot(ab, cp), d6 = vec3_dot(ac, cp);
    w[0] = w[1] = 0.0;
    w[2] = 1.0;
    if (d6 >= 0.0 && d5 <= d6) return;
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        double v = d2 / (d2 - d6);
        w[0] = 1.0 - v, w[1] = 0.0, w[2] = v;
        return;
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        double v = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        w[0] = 0.0, w[1] = 1.0 - v, w[2] = v;
        return;
    }
    double den = 1.0 / (va + vb + vc);
    w[1] = vb * den;
    w[2] = vc * den;
    w[0] = 1.0 - w[1] - w[2];
}

/* Add h n n^T to A's diagonal block of vertex i */
static void add_diag(bsr *A, int i, double h, const double *n)
{
    double *B = A->val + 9 * (size_t)A->diag[i];
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) B[3 * r + k] += h * n[r] * n[k];
}

/* Pair (p, t) at distance d along unit n (from the triangle to p), the
 * closest point's weights w: its energy, its share of b and A. */
static double pair_terms(const self_contact *s, int p, const int *tv, double d, const double *n, const double *w,
                         double cfac, double *b, bsr *A)
{
    double D = s->D, lr = log(d / D), g = d - D;
    double e = -g * g * lr, d1 = -2.0 * g * lr - g * g / d, d2 = -2.0 * lr - 4.0 * g / d + g * g / (d * d);
    if (b) {
        double f = -cfac * s->kappa * d1; /* along n on p, -w_k of it on corner k */
        vec3_axpy(b + 3 * p, f, n);
        for (int k = 0; k < 3; k++) vec3_axpy(b + 3 * tv[k], -f * w[k], n);
    }
    if (A) {
        /* (a - sum w_k b_k)^2 <= 2 (a^2 + sum w_k b_k^2), the weights summing to 1: blocks
         * that bound the pair's Gauss-Newton Hessian, so an update cannot overshoot it */
        double hh = 2.0 * cfac * cfac * s->kappa * d2;
        add_diag(A, p, hh, n);
        for (int k = 0; k < 3; k++) add_diag(A, tv[k], hh * w[k], n);
    }
    return s->kappa * e;
}

double self_contact_eval(self_contact *s, const double *x, double cfac, double *b, bsr *A)
{
    double E = 0.0, D = s->D;
    file_triangles(s, x, NULL, D);
    for (int p = 0; p < s->n; p++) {
        const double *xp = x + 3 * p;
        double q[6] = {xp[0], xp[1], xp[2], xp[0], xp[1], xp[2]};
        int m = gather(s, p, q);
        for (int k = 0; k < m; k++) {
            const int *tv = s->tri + 3 * s->cand[k];
            const double *a = x + 3 * tv[0], *bb = x + 3 * tv[1], *c = x + 3 * tv[2];
            double w[3], n[3];
            closest_weights(xp, a, bb, c, w);
            for (int r = 0; r < 3; r++) n[r] = xp[r] - (w[0] * a[r] + w[1] * bb[r] + w[2] * c[r]);
            double d = vec3_norm(n);
            /* a vertex on the triangle to rounding has no direction: the
             * updates never take it there (self_contact_max_step) */
            if (!(d < D) || !(d > 1e-9 * D)) continue;
            for (int r = 0; r < 3; r++) n[r] /= d;
            E += pair_terms(s, p, tv, d, n, w, cfac, b, A);
        }
    }
    return E;
}

double self_contact_max_step(self_contact *s, const double *x0, const double *x1)
{
    double eta = SELF_CONTACT_TOUCH * s->D, first = HUGE_VAL;
    file_triangles(s, x0, x1, eta);
    for (int p = 0; p < s->n; p++) {
        const double *a0 = x0 + 3 * p, *a1 = x1 + 3 * p;
        double q[6];
        for (int r = 0; r < 3; r++) {
            q[r] = fmin(a0[r], a1[r]);
            q[3 + r] = fmax(a0[r], a1[r]);
        }
        int m = gather(s, p, q);
        for (int k = 0; k < m; k++) {
            const int *tv = s->tri + 3 * s->cand[k];
            double y0[12], y1[12];
            for (int r = 0; r < 3; r++) {
                y0[r] = a0[r];
                y1[r] = a1[r];
                for (int j = 0; j < 3; j++) {
                    y0[3 + 3 * j + r] = x0[3 * tv[j] + r];
                    y1[3 + 3 * j + r] = x1[3 * tv[j] + r];
                }
            }
            ccd_hit hit;
            if (ccd_point_triangle(y0, y1, eta, &hit) && hit.t < first) first = hit.t;
        }
    }
    return first <= 1.0 ? SELF_CONTACT_STOP * first : 1.0;
}
