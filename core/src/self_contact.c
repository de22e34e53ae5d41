/* Self-contact inside the Newton step: see self_contact.h. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "self_contact.h"
#include "ccd.h"
#include "vec3.h"

/* A touch is a pair within this share of the thickness when coplanar (ccd.h);
 * an update stops at this share of the way to its first. */
#define SELF_CONTACT_TOUCH 1e-3
#define SELF_CONTACT_STOP 0.5

/* Primitives of one kind (triangles or edges) filed in a hashed grid */
typedef struct prim_set {
    int k, count;            /* corners per primitive, primitives */
    const int *idx;          /* k count corners */
    int *head;               /* nbucket: first entry, -1 none */
    int *ent, *next;         /* 8 count entries: primitive and next in its bucket */
    int *big, nbig;          /* boxes over a cell wide: every query meets them */
    double *box;             /* 6 count: the boxes filed */
} prim_set;

struct self_contact {
    int n, nbucket;
    double D, cell, kappa;
    prim_set tri, edge;
    int *edges;              /* 2 per edge of the triangles */
    int *stamp, visit;       /* per primitive: the last query that met it */
    int *cand, ncand;        /* a query's primitives */
    cloth *owner;            /* the cloth whose steps feel it, or NULL */
};

static int set_alloc(prim_set *p, int k, int count, const int *idx, int nbucket)
{
    p->k = k;
    p->count = count;
    p->idx = idx;
    p->head = malloc((size_t)nbucket * sizeof *p->head);
    p->ent = malloc(8 * (size_t)count * sizeof *p->ent);
    p->next = malloc(8 * (size_t)count * sizeof *p->next);
    p->big = malloc((size_t)count * sizeof *p->big);
    p->box = malloc(6 * (size_t)count * sizeof *p->box);
    return p->head && p->ent && p->next && p->big && p->box;
}

static void set_free(prim_set *p)
{
    free(p->head);
    free(p->ent);
    free(p->next);
    free(p->big);
    free(p->box);
}

static int cmp_edge(const void *a, const void *b)
{
    const int *x = a, *y = b;
    return x[0] != y[0] ? (x[0] > y[0]) - (x[0] < y[0]) : (x[1] > y[1]) - (x[1] < y[1]);
}

/* The triangles' edges, each once (ends ascending), into *out; their number, -1 out of memory */
static int edges_of(int ntri, const int *tri, int **out)
{
    int *e = malloc(6 * (size_t)ntri * sizeof *e), m = 0;
    if (!e) return -1;
    for (int t = 0; t < 3 * ntri; t++) {
        int a = tri[t], b = tri[t % 3 == 2 ? t - 2 : t + 1];
        e[2 * t] = a < b ? a : b;
        e[2 * t + 1] = a < b ? b : a;
    }
    qsort(e, 3 * (size_t)ntri, 2 * sizeof *e, cmp_edge);
    for (int t = 0; t < 3 * ntri; t++)
        if (m == 0 || e[2 * t] != e[2 * m - 2] || e[2 * t + 1] != e[2 * m - 1]) {
            e[2 * m] = e[2 * t];
            e[2 * m + 1] = e[2 * t + 1];
            m++;
        }
    *out = e;
    return m;
}

self_contact *self_contact_create(int n, int ntri, const int *tri, double thickness, double cell)
{
    self_contact *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->n = n;
    s->D = thickness;
    s->cell = cell;
    s->nbucket = 4 * ntri + 1;
    int ne = tri ? edges_of(ntri, tri, &s->edges) : -1;
    int most = ne > ntri ? ne : ntri;
    s->stamp = malloc((size_t)(most > 0 ? most : 1) * sizeof *s->stamp);
    s->cand = malloc((size_t)(most > 0 ? most : 1) * sizeof *s->cand);
    if (ne < 0 || !s->stamp || !s->cand || !set_alloc(&s->tri, 3, ntri, tri, s->nbucket) ||
        !set_alloc(&s->edge, 2, ne, s->edges, s->nbucket)) {
        self_contact_destroy(s);
        return NULL;
    }
    for (int t = 0; t < most; t++) s->stamp[t] = -1;
    return s;
}

void self_contact_destroy(self_contact *s)
{
    if (!s) return;
    if (s->owner) s->owner->self_contact = NULL;
    set_free(&s->tri);
    set_free(&s->edge);
    free(s->edges);
    free(s->stamp);
    free(s->cand);
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

/* b''(D / 2), the same for every D: 2 ln 2 + 4 + 1 */
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

/* The box over primitive j's corners at x0 and x1 (x1 NULL: x0 only) into bx */
static void prim_box(const prim_set *p, int j, const double *x0, const double *x1, double *bx)
{
    for (int a = 0; a < 3; a++) {
        bx[a] = HUGE_VAL;
        bx[3 + a] = -HUGE_VAL;
    }
    for (int k = 0; k < p->k; k++)
        for (int f = 0; f < (x1 ? 2 : 1); f++) {
            const double *q = (f ? x1 : x0) + 3 * p->idx[p->k * j + k];
            for (int a = 0; a < 3; a++) {
                bx[a] = q[a] < bx[a] ? q[a] : bx[a];
                bx[3 + a] = q[a] > bx[3 + a] ? q[a] : bx[3 + a];
            }
        }
}

/* File every primitive of p by its box over x0 and x1, widened by pad: into
 * the cells it overlaps, or the big list. */
static void file_set(const self_contact *s, prim_set *p, const double *x0, const double *x1, double pad)
{
    for (int b = 0; b < s->nbucket; b++) p->head[b] = -1;
    int nent = 0;
    p->nbig = 0;
    for (int j = 0; j < p->count; j++) {
        double *bx = p->box + 6 * (size_t)j;
        prim_box(p, j, x0, x1, bx);
        int wide = 0;
        for (int a = 0; a < 3; a++) {
            bx[a] -= pad;
            bx[3 + a] += pad;
            wide = wide || !(bx[3 + a] - bx[a] <= s->cell);
        }
        if (wide) {
            p->big[p->nbig++] = j;
            continue;
        }
        for (long i = cell_index(s, bx[0]); i <= cell_index(s, bx[3]); i++)
            for (long k = cell_index(s, bx[1]); k <= cell_index(s, bx[4]); k++)
                for (long l = cell_index(s, bx[2]); l <= cell_index(s, bx[5]); l++) {
                    int b = bucket(s, i, k, l);
                    p->ent[nent] = j;
                    p->next[nent] = p->head[b];
                    p->head[b] = nent++;
                }
    }
}

static int overlaps(const double *a, const double *b)
{
    return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] && b[2] <= a[5];
}

static void take(self_contact *s, const prim_set *p, int j, const double *q, int from)
{
    if (j <= from || s->stamp[j] == s->visit || !overlaps(p->box + 6 * (size_t)j, q)) return;
    s->stamp[j] = s->visit;
    s->cand[s->ncand++] = j;
}

/* The primitives of p filed whose box overlaps box q (6), above index from and
 * with neither u nor v as a corner, into s->cand; returns their number. */
static int gather(self_contact *s, const prim_set *p, const double *q, int from, int u, int v)
{
    s->ncand = 0;
    if (++s->visit == INT32_MAX) {
        int most = s->tri.count > s->edge.count ? s->tri.count : s->edge.count;
        for (int t = 0; t < most; t++) s->stamp[t] = -1;
        s->visit = 0;
    }
    for (int e = 0; e < p->nbig; e++) take(s, p, p->big[e], q, from);
    if (!(q[3] - q[0] <= s->cell && q[4] - q[1] <= s->cell && q[5] - q[2] <= s->cell)) {
        for (int t = 0; t < p->count; t++) take(s, p, t, q, from);
    } else {
        for (long i = cell_index(s, q[0]); i <= cell_index(s, q[3]); i++)
            for (long j = cell_index(s, q[1]); j <= cell_index(s, q[4]); j++)
                for (long k = cell_index(s, q[2]); k <= cell_index(s, q[5]); k++)
                    for (int e = p->head[bucket(s, i, j, k)]; e >= 0; e = p->next[e]) take(s, p, p->ent[e], q, from);
    }
    int m = 0;
    for (int c = 0; c < s->ncand; c++) {
        const int *tv = p->idx + p->k * s->cand[c];
        int shared = 0;
        for (int k = 0; k < p->k; k++) shared = shared || tv[k] == u || tv[k] == v;
        if (!shared) s->cand[m++] = s->cand[c];
    }
    return s->ncand = m;
}

/* Add h n n^T to A's diagonal block of vertex i */
static void add_diag(bsr *A, int i, double h, const double *n)
{
    double *B = A->val + 9 * (size_t)A->diag[i];
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) B[3 * r + k] += h * n[r] * n[k];
}

/* A pair of vertices v (4) whose closest points differ by sum_k c_k x_k = d n
 * (n unit, sum |c_k| = 2): the barrier's energy at d, its share of b and A
 * if d < D; 0 otherwise. */
static double pair_terms(const self_contact *s, const int *v, const double *c, const double *x, double cfac,
                         double *b, bsr *A)
{
    double n[3] = {0.0, 0.0, 0.0}, D = s->D;
    for (int k = 0; k < 4; k++) vec3_axpy(n, c[k], x + 3 * v[k]);
    double d = vec3_norm(n);
    /* on the other primitive to rounding: no direction; the updates never
     * take a pair there (self_contact_max_step) */
    if (!(d < D) || !(d > 1e-9 * D)) return 0.0;
    for (int r = 0; r < 3; r++) n[r] /= d;
    double lr = log(d / D), g = d - D;
    double e = -g * g * lr, d1 = -2.0 * g * lr - g * g / d, d2 = -2.0 * lr - 4.0 * g / d + g * g / (d * d);
    /* (sum c_k a_k)^2 <= (sum |c_k|) sum |c_k| a_k^2: blocks that bound the pair's
     * Gauss-Newton Hessian, so an update cannot overshoot it */
    double hh = 2.0 * cfac * cfac * s->kappa * d2;
    for (int k = 0; k < 4; k++) {
        if (b) vec3_axpy(b + 3 * v[k], -cfac * s->kappa * d1 * c[k], n);
        if (A) add_diag(A, v[k], hh * fabs(c[k]), n);
    }
    return s->kappa * e;
}

/* Pair v (4 vertices: a point and a triangle, or with edge_edge two edges) at x */
static double pair_at(const self_contact *s, const int *v, int edge_edge, const double *x, double cfac, double *b,
                      bsr *A)
{
    double y[12], c[4];
    for (int k = 0; k < 4; k++)
        for (int r = 0; r < 3; r++) y[3 * k + r] = x[3 * v[k] + r];
    ccd_pair_weights(edge_edge, y, c);
    return pair_terms(s, v, c, x, cfac, b, A);
}

static double vertex_triangle(self_contact *s, const double *x, double cfac, double *b, bsr *A)
{
    double E = 0.0;
    for (int p = 0; p < s->n; p++) {
        const double *xp = x + 3 * p;
        double q[6] = {xp[0], xp[1], xp[2], xp[0], xp[1], xp[2]};
        int m = gather(s, &s->tri, q, -1, p, p);
        for (int k = 0; k < m; k++) {
            const int *tv = s->tri.idx + 3 * s->cand[k], v[4] = {p, tv[0], tv[1], tv[2]};
            E += pair_at(s, v, 0, x, cfac, b, A);
        }
    }
    return E;
}

static double edge_edge(self_contact *s, const double *x, double cfac, double *b, bsr *A)
{
    double E = 0.0;
    for (int e = 0; e < s->edge.count; e++) {
        const int *ev = s->edges + 2 * e;
        double q[6];
        prim_box(&s->edge, e, x, NULL, q);
        int m = gather(s, &s->edge, q, e, ev[0], ev[1]);
        for (int k = 0; k < m; k++) {
            const int *fv = s->edges + 2 * s->cand[k], v[4] = {ev[0], ev[1], fv[0], fv[1]};
            E += pair_at(s, v, 1, x, cfac, b, A);
        }
    }
    return E;
}

double self_contact_eval(self_contact *s, const double *x, double cfac, double *b, bsr *A)
{
    file_set(s, &s->tri, x, NULL, s->D);
    file_set(s, &s->edge, x, NULL, s->D);
    return vertex_triangle(s, x, cfac, b, A) + edge_edge(s, x, cfac, b, A);
}

/* The first touch's time over x0 -> x1 of the four vertices v, a point and
 * a triangle (pt) or two edges; HUGE_VAL if none */
static double touch(const double *x0, const double *x1, const int *v, int pt, double eta)
{
    double y0[12], y1[12];
    for (int k = 0; k < 4; k++)
        for (int r = 0; r < 3; r++) {
            y0[3 * k + r] = x0[3 * v[k] + r];
            y1[3 * k + r] = x1[3 * v[k] + r];
        }
    ccd_hit hit;
    int h = pt ? ccd_point_triangle(y0, y1, eta, &hit) : ccd_edge_edge(y0, y1, eta, &hit);
    return h ? hit.t : HUGE_VAL;
}

double self_contact_max_step(self_contact *s, const double *x0, const double *x1)
{
    double eta = SELF_CONTACT_TOUCH * s->D, first = HUGE_VAL, q[6];
    file_set(s, &s->tri, x0, x1, eta);
    file_set(s, &s->edge, x0, x1, eta);
    for (int p = 0; p < s->n; p++) {
        for (int r = 0; r < 3; r++) {
            q[r] = fmin(x0[3 * p + r], x1[3 * p + r]);
            q[3 + r] = fmax(x0[3 * p + r], x1[3 * p + r]);
        }
        int m = gather(s, &s->tri, q, -1, p, p);
        for (int k = 0; k < m; k++) {
            const int *tv = s->tri.idx + 3 * s->cand[k], v[4] = {p, tv[0], tv[1], tv[2]};
            first = fmin(first, touch(x0, x1, v, 1, eta));
        }
    }
    for (int e = 0; e < s->edge.count; e++) {
        const int *ev = s->edges + 2 * e;
        prim_box(&s->edge, e, x0, x1, q);
        int m = gather(s, &s->edge, q, e, ev[0], ev[1]);
        for (int k = 0; k < m; k++) {
            const int *fv = s->edges + 2 * s->cand[k], v[4] = {ev[0], ev[1], fv[0], fv[1]};
            first = fmin(first, touch(x0, x1, v, 0, eta));
        }
    }
    return first <= 1.0 ? SELF_CONTACT_STOP * first : 1.0;
}
