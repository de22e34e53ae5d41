/* Self-contact inside the Newton step: see self_contact.h. */
#include <limits.h>
#include <math.h>
#include <string.h>
#include <stdlib.h>
#include <time.h>
#include "self_contact.h"
#include "ccd.h"
#include "pair_apart.h"
#include "sweep_grid.h"
#include "vec3.h"
#include "tuning.h"

/* A growable list of index pairs */
typedef struct pair_list {
    int *v, n, cap;
} pair_list;

/* Close pairs of a reference */
typedef struct ref_set {
    pair_list close; /* (kind, candidate) of the close pairs, in list order */
    double *xref;    /* 3 n: their reference positions */
    long close_at;   /* the lists they are of (version then); -1: none */
    long used;       /* the clock when last used */
} ref_set;

struct self_contact {
    int n, ntri, nedge;
    double D, kappa;
    const int *tri;                    /* 3 ntri corners, kept by pointer */
    int *edges;                        /* 2 per edge of the triangles */
    sweep_grid *grid;                  /* the broadphase of a rebuild */
    double *box;                       /* 6 per triangle or edge: boxes */
    double *frame;                     /* 12 per triangle: its frame at the evaluation (pair_apart.h) */
    double *vbox;                      /* 6 per vertex: the box of its path in a sweep */
    double *lo, *hi;                   /* 3 n each: the vertices' regions (boxes) the candidates cover */
    int listed;                        /* whether the candidates are listed */
    long version;                      /* counts the lists' changes */
    double *xstart;                    /* 3 n: the step's start positions (oc_self_contact_begin) */
    int *out;                          /* n: the vertices outside their regions */
    unsigned char *mark;               /* n: zero but while their pairs are found */
    int has_start;                     /* whether xstart is set */
    pair_list vt, ee;                  /* candidates: (vertex, triangle), (edge, later edge) */
    pair_list swept;                   /* a direct sweep's pairs of one query */
    pair_list near;                    /* (kind, candidate) of the pairs the last evaluation did not prove apart */
    ref_set ref;                       /* the close pairs of the last evaluation or sweep */
    ref_set spare[SELF_CONTACT_SPARE]; /* those of earlier references, kept for evaluations that return there */
    long clock;                        /* counts the close pairs' uses */
    double *xnear;                     /* 3 n: its positions */
    long near_at;                      /* the lists it used (version then) */
    int near_ok;                       /* whether near holds them all */
    self_contact_work work;
    cloth *owner; /* the cloth whose steps feel it, or NULL */
};

static int pair_reserve(pair_list *l, int more)
{
    if (l->n + more <= l->cap) return 0;
    int cap = l->cap ? l->cap : 64;
    while (cap < l->n + more) {
        if (cap > INT_MAX / 4) return -1;
        cap *= 2;
    }
    int *v = realloc(l->v, 2 * (size_t)cap * sizeof *v);
    if (!v) return -1;
    l->v = v;
    l->cap = cap;
    return 0;
}

static int cmp_edge(const void *a, const void *b)
{
    const int *x = a, *y = b;
    return x[0] != y[0] ? (x[0] > y[0]) - (x[0] < y[0]) : (x[1] > y[1]) - (x[1] < y[1]);
}

/* The triangles' edges, each once (ends ascending), into *out; their number, -1 out of memory */
static int edges_of(int ntri, const int *tri, int **out)
{
    int *e = malloc(6 * (size_t)ntri * sizeof *e + 1), m = 0;
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

self_contact *oc_self_contact_create(int n, int ntri, const int *tri, double thickness)
{
    self_contact *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->n = n;
    s->ntri = ntri;
    s->tri = tri;
    s->D = thickness;
    s->nedge = tri ? edges_of(ntri, tri, &s->edges) : -1;
    int most = s->nedge > ntri ? s->nedge : ntri;
    s->box = malloc(6 * (size_t)(most > 0 ? most : 1) * sizeof *s->box);
    s->lo = malloc(3 * (size_t)(n > 0 ? n : 1) * sizeof *s->lo);
    s->hi = malloc(3 * (size_t)(n > 0 ? n : 1) * sizeof *s->hi);
    s->xnear = malloc(3 * (size_t)(n > 0 ? n : 1) * sizeof *s->xnear);
    int refs_ok = 1;
    for (int k = 0; k <= SELF_CONTACT_SPARE; k++) {
        ref_set *r = k ? &s->spare[k - 1] : &s->ref;
        r->xref = malloc(3 * (size_t)(n > 0 ? n : 1) * sizeof *r->xref);
        r->close_at = -1;
        refs_ok = refs_ok && r->xref;
    }
    s->xstart = malloc(3 * (size_t)(n > 0 ? n : 1) * sizeof *s->xstart);
    s->out = malloc((size_t)(n > 0 ? n : 1) * sizeof *s->out);
    s->mark = calloc((size_t)(n > 0 ? n : 1), 1);
    s->frame = malloc(12 * (size_t)(ntri > 0 ? ntri : 1) * sizeof *s->frame);
    s->vbox = malloc(6 * (size_t)(n > 0 ? n : 1) * sizeof *s->vbox);
    s->grid = oc_sweep_grid_create();
    /* room for a crumpled sheet's candidates, so that steps seldom allocate */
    int ok = s->nedge >= 0 && s->box && s->lo && s->hi && s->xnear && refs_ok && s->xstart && s->out && s->mark &&
             s->frame && s->vbox && s->grid;
    if (!ok || pair_reserve(&s->vt, 8 * n) || pair_reserve(&s->ee, 8 * n)) {
        oc_self_contact_destroy(s);
        return NULL;
    }
    return s;
}

void oc_self_contact_destroy(self_contact *s)
{
    if (!s) return;
    if (s->owner) s->owner->self_contact = NULL;
    oc_sweep_grid_destroy(s->grid);
    free(s->edges);
    free(s->box);
    free(s->lo);
    free(s->hi);
    free(s->frame);
    free(s->vbox);
    free(s->vt.v);
    free(s->ee.v);
    free(s->swept.v);
    free(s->near.v);
    for (int k = 0; k <= SELF_CONTACT_SPARE; k++) {
        free(k ? s->spare[k - 1].close.v : s->ref.close.v);
        free(k ? s->spare[k - 1].xref : s->ref.xref);
    }
    free(s->xnear);
    free(s->xstart);
    free(s->out);
    free(s->mark);
    free(s);
}

void oc_self_contact_bind(self_contact *s, cloth *c)
{
    if (s->owner == c) return;
    if (s->owner) s->owner->self_contact = NULL;
    if (c->self_contact) c->self_contact->owner = NULL;
    s->owner = c;
    c->self_contact = s;
}

void oc_self_contact_unbind_cloth(cloth *c)
{
    if (c->self_contact) c->self_contact->owner = NULL;
    c->self_contact = NULL;
}

self_contact_work oc_self_contact_get_work(const self_contact *s) { return s->work; }

/* b''(D / 2), the same for every D: 2 ln 2 + 4 + 1 */
static double curvature_at_half(void) { return 2.0 * log(2.0) + 4.0 + 1.0; }

void oc_self_contact_begin(self_contact *s, const cloth *c, double cfac)
{
    /* IPC's scale: the barrier's curvature at half the thickness is the
     * mean vertex's mass in Newton's matrix (cfac^2 kappa b'') */
    double mt = 0.0;
    for (int i = 0; i < c->n; i++) mt += c->mass[i];
    s->kappa = mt / c->n / (cfac * cfac * curvature_at_half());
    memcpy(s->xstart, c->st.x, 3 * (size_t)s->n * sizeof *s->xstart);
    s->has_start = 1;
}

/* The box over the k corners idx at x0 and x1 (x1 NULL: x0 only), widened by pad, into bx */
static void corners_box(const int *idx, int k, const double *x0, const double *x1, double pad, double *bx)
{
    for (int a = 0; a < 3; a++) {
        bx[a] = HUGE_VAL;
        bx[3 + a] = -HUGE_VAL;
    }
    for (int j = 0; j < k; j++)
        for (int f = 0; f < (x1 ? 2 : 1); f++) {
            const double *q = (f ? x1 : x0) + 3 * idx[j];
            for (int a = 0; a < 3; a++) {
                bx[a] = q[a] < bx[a] ? q[a] : bx[a];
                bx[3 + a] = q[a] > bx[3 + a] ? q[a] : bx[3 + a];
            }
        }
    for (int a = 0; a < 3; a++) {
        bx[a] -= pad;
        bx[3 + a] += pad;
    }
}

/* Boxes a and b within pad of each other on every axis */
static inline int near_boxes(const double *a, const double *b, double pad)
{
    return a[0] - pad <= b[3] && b[0] - pad <= a[3] && a[1] - pad <= b[4] && b[1] - pad <= a[4] && a[2] - pad <= b[5] &&
           b[2] - pad <= a[5];
}

/* The widest gap between boxes a and b along an axis (0 when they overlap): a lower bound on the
 * distance between what they hold */
static inline double box_gap(const double *a, const double *b)
{
    double g = 0.0;
    for (int k = 0; k < 3; k++) {
        double lo = a[k] - b[3 + k], hi = b[k] - a[3 + k];
        g = lo > g ? lo : g;
        g = hi > g ? hi : g;
    }
    return g;
}

/* Appends (a, b) for the m primitives b of cand above from with none of their kb corners
 * among the ku corners u, b ascending; -1 out of memory */
static int append(pair_list *l, int a, const int *cand, int m, const int *idx, int kb, const int *u, int ku, int from)
{
    if (pair_reserve(l, m) < 0) return -1;
    int first = l->n;
    for (int c = 0; c < m; c++) {
        const int *bv = idx + kb * cand[c];
        int shared = cand[c] <= from;
        for (int i = 0; i < kb; i++)
            for (int j = 0; j < ku; j++) shared = shared || bv[i] == u[j];
        if (shared) continue;
        int j = l->n++;
        for (; j > first && l->v[2 * j - 1] > cand[c]; j--) {
            l->v[2 * j] = a;
            l->v[2 * j + 1] = l->v[2 * j - 1];
        }
        l->v[2 * j] = a;
        l->v[2 * j + 1] = cand[c];
    }
    return 0;
}

static double touch(const double *x0, const double *x1, const int *v, int pt, double eta);

/* The four vertices of pair i of list l (vertex-triangle, or with ee edge-edge) into v */
static void pair_vertices(const self_contact *s, const pair_list *l, int ee, int i, int *v)
{
    int a = l->v[2 * i], t = l->v[2 * i + 1];
    const int *bv = (ee ? s->edges : s->tri) + (ee ? 2 : 3) * t;
    v[0] = ee ? s->edges[2 * a] : a;
    v[1] = ee ? s->edges[2 * a + 1] : bv[0];
    v[2] = bv[ee ? 0 : 1];
    v[3] = bv[ee ? 1 : 2];
}

/* The pairs of the vertices and triangles (ee 0) or of the edges and later edges (ee 1)
 * whose boxes over x0 and x1 (x1 NULL: x0 only) come within pad: listed; with first, each
 * query's swept from x0 to x1 for the first touch within pad (into *first) and dropped */
static int list_pairs(self_contact *s, int ee, const double *x0, const double *x1, double pad, double *first)
{
    const int *idx = ee ? s->edges : s->tri;
    int k = ee ? 2 : 3, nf = ee ? s->nedge : s->ntri;
    pair_list *l = first ? &s->swept : ee ? &s->ee : &s->vt;
    for (int t = 0; t < nf; t++) corners_box(idx + k * t, k, x0, x1, pad, s->box + 6 * (size_t)t);
    if (oc_sweep_grid_build(s->grid, s->box, nf) < 0) return -1;
    for (int a = 0; a < (ee ? s->nedge : s->n); a++) {
        const int *cand, *u = ee ? idx + 2 * a : &a;
        double q[6];
        corners_box(u, ee ? 2 : 1, x0, x1, 0.0, q);
        int m = oc_sweep_grid_query(s->grid, q, &cand);
        if (append(l, a, cand, m, idx, k, u, ee ? 2 : 1, ee ? a : -1) < 0) return -1;
        for (int i = 0; first && i < l->n; i++) {
            int v[4];
            pair_vertices(s, l, ee, i, v);
            *first = fmin(*first, touch(x0, x1, v, !ee, pad));
        }
        if (first) l->n = 0;
    }
    return 0;
}

/* Whether vertex i of x is in its region */
static int in_region(const self_contact *s, const double *x, int i)
{
    for (int k = 3 * i; k < 3 * i + 3; k++)
        if (!(s->lo[k] <= x[k] && x[k] <= s->hi[k])) return 0;
    return 1;
}

/* Whether every vertex of x is in its region, the regions shifted by one translation (found per axis as
 * the meet of the vertices' intervals): pairs' distances and touches do not change under it */
static int in_regions(const self_contact *s, const double *x)
{
    double lo[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, hi[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
    for (int k = 0; k < 3 * s->n; k++) {
        double a = x[k] - s->hi[k], b = x[k] - s->lo[k];
        if (!(a <= b)) return 0; /* not finite */
        lo[k % 3] = a > lo[k % 3] ? a : lo[k % 3];
        hi[k % 3] = b < hi[k % 3] ? b : hi[k % 3];
    }
    return lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2];
}

/* Merges the pairs of add (any order, repeats allowed) into l (ascending, each once), keeping it so */
static int merge_pairs(pair_list *l, pair_list *add)
{
    qsort(add->v, (size_t)add->n, 2 * sizeof *add->v, cmp_edge);
    if (pair_reserve(l, add->n) < 0) return -1;
    int i = l->n - 1, j = add->n - 1, w = l->n + add->n;
    while (j >= 0) {
        const int *p = add->v + 2 * j;
        int c = i < 0 ? -1 : cmp_edge(l->v + 2 * i, p);
        const int *from = c >= 0 ? l->v + 2 * i : p;
        w--;
        l->v[2 * w] = from[0];
        l->v[2 * w + 1] = from[1];
        i -= c >= 0;
        j -= c <= 0;
        while (j >= 0 && c <= 0 && !cmp_edge(add->v + 2 * j, p)) j--; /* repeats in add */
    }
    if (w > i + 1) memmove(l->v + 2 * (i + 1), l->v + 2 * w, 2 * (size_t)(l->n + add->n - w) * sizeof *l->v);
    l->n = i + 1 + (l->n + add->n - w);
    return 0;
}

/* Appends (a, b) or (b, a), the smaller first with order, when their boxes ba and bb come within D and
 * the primitives (corners ia, ka of them; ib, kb) share no vertex; -1 out of memory */
static int pair_if_near(self_contact *s, pair_list *l, int a, const int *ia, int ka, const double *ba, int b,
                        const int *ib, int kb, const double *bb, int order)
{
    if (!near_boxes(ba, bb, s->D)) return 0;
    for (int p = 0; p < ka; p++)
        for (int q = 0; q < kb; q++)
            if (ia[p] == ib[q]) return 0;
    if (pair_reserve(l, 1) < 0) return -1;
    int swap = order && b < a;
    l->v[2 * l->n] = swap ? b : a;
    l->v[2 * l->n++ + 1] = swap ? a : b;
    return 0;
}

/* The box of vertex i's region */
static const double *region_box(const self_contact *s, int i, double *bx)
{
    for (int a = 0; a < 3; a++) {
        bx[a] = s->lo[3 * i + a];
        bx[3 + a] = s->hi[3 * i + a];
    }
    return bx;
}

/* The pairs that the regions of the vertices flagged in s->mark bring within D: vertex against triangle
 * (ee 0: a marked vertex, or a triangle with a marked corner) or edge against edge (ee 1), into add */
static int pairs_of_marked(self_contact *s, int ee, pair_list *add)
{
    int nf = ee ? s->nedge : s->ntri, k = ee ? 2 : 3, na = ee ? s->nedge : s->n;
    const int *idx = ee ? s->edges : s->tri;
    double qa[6], qf[6];
    add->n = 0;
    for (int f = 0; f < nf; f++) corners_box(idx + k * f, k, s->lo, s->hi, 0.0, s->box + 6 * (size_t)f);
    for (int f = 0; f < nf; f++) {
        const int *fv = idx + k * f;
        const double *bf = s->box + 6 * (size_t)f;
        int hit = 0;
        for (int j = 0; j < k; j++) hit |= s->mark[fv[j]];
        for (int a = 0; hit && a < na; a++) {
            const int *av = ee ? idx + 2 * a : &a;
            const double *ba = ee ? s->box + 6 * (size_t)a : region_box(s, a, qa);
            if (pair_if_near(s, add, a, av, ee ? 2 : 1, ba, f, fv, k, bf, ee) < 0) return -1;
        }
    }
    for (int a = 0; !ee && a < s->n; a++)
        for (int f = 0; s->mark[a] && f < nf; f++)
            if (pair_if_near(s, add, a, &a, 1, region_box(s, a, qf), f, idx + 3 * f, 3, s->box + 6 * (size_t)f, 0))
                return -1;
    return 0;
}

/* The regions of the few vertices outside them grown to also hold the path x0 -> y widened by the skin,
 * and the pairs that brings within D merged into the lists. 1: too many outside (nothing changed); 0:
 * done; -1 out of memory (the lists are then cleared). */
static int extend(self_contact *s, const double *x0, const double *y, double skin)
{
    int k = 0, limit = 1 + s->n / SELF_CONTACT_FEW;
    if (limit > SELF_CONTACT_FEW_MAX) limit = SELF_CONTACT_FEW_MAX;
    for (int i = 0; i < s->n; i++)
        if (!in_region(s, x0, i) || !in_region(s, y, i)) {
            if (k == limit) return 1;
            s->out[k++] = i;
        }
    for (int j = 0; j < k; j++) {
        int i = s->out[j];
        s->mark[i] = 1;
        for (int a = 3 * i; a < 3 * i + 3; a++) {
            s->lo[a] = fmin(s->lo[a], fmin(x0[a], y[a]) - skin);
            s->hi[a] = fmax(s->hi[a], fmax(x0[a], y[a]) + skin);
        }
    }
    int ok = pairs_of_marked(s, 0, &s->swept) == 0 && merge_pairs(&s->vt, &s->swept) == 0 &&
             pairs_of_marked(s, 1, &s->swept) == 0 && merge_pairs(&s->ee, &s->swept) == 0;
    for (int j = 0; j < k; j++) s->mark[s->out[j]] = 0;
    s->version++;
    s->work.extended++;
    s->work.candidates = s->vt.n + s->ee.n;
    if (!ok) s->listed = 0, s->vt.n = s->ee.n = 0;
    return ok ? 0 : -1;
}

/* Candidates covering x0 and x1 (x1 NULL: x0 only): kept while both lie in the regions, else listed for
 * the motion x0 -> x1 and from the step's start (a few vertices outside: their regions grown). Returns
 * 0; 1 when the motion exceeds SELF_CONTACT_LONG (none listed: sweep it); -1 out of memory. */
static int candidates(self_contact *s, const double *x0, const double *x1)
{
    if (s->listed && in_regions(s, x0) && (!x1 || in_regions(s, x1))) return 0;
    const double *y = x1 ? x1 : x0;
    double skin = SELF_CONTACT_SKIN * s->D, most = 0.0, from = 0.0;
    for (int k = 0; k < 3 * s->n; k++) {
        double d = fabs(y[k] - x0[k]), e = s->has_start ? fabs(s->xstart[k] - x0[k]) : 0.0;
        if (!(d <= most)) most = d == d ? d : HUGE_VAL;
        if (!(e <= from)) from = e == e ? e : HUGE_VAL;
    }
    if (most > SELF_CONTACT_LONG * s->D) return 1;
    int how = s->listed ? extend(s, x0, y, skin) : 1;
    if (how <= 0) return how;
    /* the step's start too, unless far: the step's sweeps start there */
    int start = s->has_start && from + most <= SELF_CONTACT_LONG * s->D;
    for (int k = 0; k < 3 * s->n; k++) {
        s->lo[k] = fmin(x0[k], y[k]) - skin;
        s->hi[k] = fmax(x0[k], y[k]) + skin;
        if (start) {
            s->lo[k] = fmin(s->lo[k], s->xstart[k] - skin);
            s->hi[k] = fmax(s->hi[k], s->xstart[k] + skin);
        }
    }
    s->vt.n = s->ee.n = 0;
    s->work.rebuilds++;
    s->version++;
    s->listed = list_pairs(s, 0, s->lo, s->hi, s->D, NULL) == 0 && list_pairs(s, 1, s->lo, s->hi, s->D, NULL) == 0;
    if (!s->listed) {
        s->vt.n = s->ee.n = 0;
        return -1;
    }
    s->work.candidates = s->vt.n + s->ee.n;
    return 0;
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
static double pair_terms(const self_contact *s, const int *v, const double *c, const double *x, double cfac, double *b,
                         bsr *A)
{
    double n[3] = {0.0, 0.0, 0.0}, D = s->D;
    for (int k = 0; k < 4; k++) vec3_axpy(n, c[k], x + 3 * v[k]);
    double d = vec3_norm(n);
    /* on the other primitive to rounding: no direction; the updates never
     * take a pair there (oc_self_contact_max_step) */
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
    oc_ccd_pair_weights(edge_edge, y, c);
    return pair_terms(s, v, c, x, cfac, b, A);
}

/* A lower bound on candidate i's distance at x (vertex-triangle, or with ee edge-edge), its four
 * vertices into v; the boxes at x are in s->box, the triangles' frames in s->frame. A box gap of
 * at least enough is returned without the separating axes. */
static double pair_gap(const self_contact *s, int ee, int i, const double *x, double enough, int *v)
{
    const pair_list *l = ee ? &s->ee : &s->vt;
    int a = l->v[2 * i], t = l->v[2 * i + 1];
    double g;
    if (ee) {
        const int *e = s->edges + 2 * a, *f = s->edges + 2 * t;
        v[0] = e[0], v[1] = e[1], v[2] = f[0], v[3] = f[1];
        g = box_gap(s->box + 6 * (size_t)a, s->box + 6 * (size_t)t);
        if (g >= enough) return g;
        double sep = oc_pair_apart_edges_gap(x + 3 * v[0], x + 3 * v[1], x + 3 * v[2], x + 3 * v[3], enough);
        return sep > g ? sep : g;
    }
    const int *tv = s->tri + 3 * t;
    const double *p = x + 3 * a, pt[6] = {p[0], p[1], p[2], p[0], p[1], p[2]};
    v[0] = a, v[1] = tv[0], v[2] = tv[1], v[3] = tv[2];
    g = box_gap(pt, s->box + 6 * (size_t)t);
    if (g >= enough) return g;
    double sep = oc_pair_apart_point_triangle_gap(p, x + 3 * v[1], x + 3 * v[2], x + 3 * v[3],
                                                  s->frame + 12 * (size_t)t, enough);
    return sep > g ? sep : g;
}

/* Primitive f's box over x0 and x1 (x1 NULL: x0 only; a triangle, or with ee an edge), with frame
 * the triangle's frame at x0 too */
static void prim_box(self_contact *s, int ee, int f, const double *x0, const double *x1, int frame)
{
    const int *idx = ee ? s->edges + 2 * f : s->tri + 3 * f;
    corners_box(idx, ee ? 2 : 3, x0, x1, 0.0, s->box + 6 * (size_t)f);
    if (frame) oc_pair_apart_frame(x0 + 3 * idx[0], x0 + 3 * idx[1], x0 + 3 * idx[2], s->frame + 12 * (size_t)f);
}

/* What pair_gap (x1 NULL) or first_touch reads for the vertex-triangle (ee 0) or edge-edge pairs: the
 * boxes (and frames, vertex boxes) of every primitive, or with close only of the close pairs' */
static void boxes_for(self_contact *s, int ee, int close, const double *x0, const double *x1)
{
    const pair_list *cl = &s->ref.close, *l = ee ? &s->ee : &s->vt;
    if (!close) {
        for (int f = 0; f < (ee ? s->nedge : s->ntri); f++) prim_box(s, ee, f, x0, x1, !ee && !x1);
        for (int i = 0; !ee && x1 && i < s->n; i++) corners_box(&i, 1, x0, x1, 0.0, s->vbox + 6 * (size_t)i);
        return;
    }
    for (int j = 0; j < cl->n; j++) {
        if (cl->v[2 * j] != ee) continue;
        int i = cl->v[2 * j + 1], a = l->v[2 * i], f = l->v[2 * i + 1];
        prim_box(s, ee, f, x0, x1, !ee && !x1);
        if (ee) prim_box(s, 1, a, x0, x1, 0);
        else if (x1) corners_box(&a, 1, x0, x1, 0.0, s->vbox + 6 * (size_t)a);
    }
}

/* Appends (kind, i) to l, or marks *ok 0 when out of memory */
static void note(pair_list *l, int *ok, int kind, int i)
{
    if (*ok) *ok = pair_reserve(l, 1) == 0;
    if (!*ok) return;
    l->v[2 * l->n] = kind;
    l->v[2 * l->n++ + 1] = i;
}

/* The terms of the candidate pairs (vertex-triangle, or with ee edge-edge) within D at x: every
 * candidate when listing the close pairs (into s->ref, *ok 0 out of memory), else the close ones */
static double pairs_at(self_contact *s, int ee, const double *x, double cfac, double *b, bsr *A, int listing, int *ok)
{
    double E = 0.0, apart = s->D * PAIR_APART_MARGIN, keep = apart + 2.0 * SELF_CONTACT_SLACK * s->D;
    const pair_list *cl = &s->ref.close;
    int v[4], np = listing ? (ee ? s->ee.n : s->vt.n) : cl->n;
    for (int j = 0; j < np; j++) {
        int i = j;
        if (!listing) {
            if (cl->v[2 * j] != ee) continue;
            i = cl->v[2 * j + 1];
        }
        double g = pair_gap(s, ee, i, x, listing ? keep : apart, v);
        if (listing && g < keep) note(&s->ref.close, ok, ee, i);
        if (g >= apart) continue;
        note(&s->near, &s->near_ok, ee, i);
        double e = pair_at(s, v, ee, x, cfac, b, A);
        s->work.tested++;
        s->work.active += e > 0.0;
        E += e;
    }
    return E;
}

/* The largest distance of a vertex of x from its reference position in r shifted by a common
 * translation (the middle of the displacements' box): pair distances do not change under one */
static double moved(const self_contact *s, const ref_set *r, const double *x)
{
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, t[3], m = 0.0;
    for (int k = 0; k < 3 * s->n; k++) {
        double d = x[k] - r->xref[k];
        lo[k % 3] = d < lo[k % 3] ? d : lo[k % 3];
        hi[k % 3] = d > hi[k % 3] ? d : hi[k % 3];
    }
    for (int a = 0; a < 3; a++) t[a] = 0.5 * (lo[a] + hi[a]);
    for (int i = 0; i < s->n; i++) {
        double d[3];
        vec3_sub(x + 3 * i, r->xref + 3 * i, d);
        vec3_sub(d, t, d);
        double d2 = vec3_dot(d, d);
        if (!(d2 <= m)) m = d2 == d2 ? d2 : INFINITY; /* a NaN position: moved past any slack */
    }
    return sqrt(m);
}

/* Whether r's close pairs hold every candidate that can come within D at x, or with x1 (not NULL) every
 * one that can touch on the path x -> x1: a pair's distance shrinks by at most twice the most a vertex
 * moved from the shifted reference, and a touch needs it under eta, not D */
static int holds(const self_contact *s, const ref_set *r, const double *x, const double *x1)
{
    double slack = SELF_CONTACT_SLACK * s->D;
    if (x1) slack += 0.5 * s->D * (1.0 - 2.0 * SELF_CONTACT_TOUCH);
    return r->close_at == s->version && moved(s, r, x) <= slack && (!x1 || moved(s, r, x1) <= slack);
}

static void swap_refs(ref_set *a, ref_set *b)
{
    ref_set t = *a;
    *a = *b;
    *b = t;
}

/* Whether the close pairs of a reference hold x (and x1 unless NULL): the current one, else a spare made
 * current */
static int close_holds(self_contact *s, const double *x, const double *x1)
{
    int k = -1;
    if (!holds(s, &s->ref, x, x1))
        for (k = 0; k < SELF_CONTACT_SPARE && !holds(s, &s->spare[k], x, x1); k++) continue;
    if (k == SELF_CONTACT_SPARE) return 0;
    if (k >= 0) swap_refs(&s->ref, &s->spare[k]);
    s->ref.used = ++s->clock;
    return 1;
}

/* Before the close pairs are listed again: the current ones kept as a spare, in place of the least
 * recently used */
static void retire_ref(self_contact *s)
{
    int k = 0;
    long oldest = LONG_MAX;
    for (int j = 0; j < SELF_CONTACT_SPARE; j++) {
        long u = s->spare[j].close_at == s->version ? s->spare[j].used : -1;
        if (u < oldest) oldest = u, k = j;
    }
    if (s->ref.close_at == s->version) swap_refs(&s->ref, &s->spare[k]);
}

/* The terms of the pairs the last evaluation found near, at the same positions */
static double near_again(self_contact *s, const double *x, double cfac, double *b, bsr *A)
{
    double E[2] = {0.0, 0.0};
    for (int k = 0; k < s->near.n; k++) {
        int ee = s->near.v[2 * k], v[4];
        pair_vertices(s, ee ? &s->ee : &s->vt, ee, s->near.v[2 * k + 1], v);
        E[ee] += pair_at(s, v, ee, x, cfac, b, A);
    }
    return E[0] + E[1];
}

/* Wall seconds (C11's timespec_get: the core links libm only) */
static double wall_now(void)
{
    struct timespec ts;
    return timespec_get(&ts, TIME_UTC) ? (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec : 0.0;
}

static double eval_untimed(self_contact *s, const double *x, double cfac, double *b, bsr *A)
{
    size_t n3 = 3 * (size_t)s->n;
    if (candidates(s, x, NULL) < 0) return NAN;
    /* the matrix follows the residual at the same positions: their pairs again */
    if (s->near_ok && s->near_at == s->version && !memcmp(x, s->xnear, n3 * sizeof *x))
        return near_again(s, x, cfac, b, A);
    s->work.tested = s->work.active = 0;
    s->near.n = 0;
    s->near_ok = 1;
    int listing = !close_holds(s, x, NULL), ok = 1;
    if (listing) {
        retire_ref(s);
        s->ref.close.n = 0;
        s->ref.close_at = -1;
    }
    boxes_for(s, 0, !listing, x, NULL);
    double E = pairs_at(s, 0, x, cfac, b, A, listing, &ok);
    boxes_for(s, 1, !listing, x, NULL);
    E += pairs_at(s, 1, x, cfac, b, A, listing, &ok);
    if (listing && ok) {
        memcpy(s->ref.xref, x, n3 * sizeof *x);
        s->ref.close_at = s->version;
        s->ref.used = ++s->clock;
        s->work.relisted++;
    }
    memcpy(s->xnear, x, n3 * sizeof *x);
    s->near_at = s->version;
    return E;
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
    int h = pt ? oc_ccd_point_triangle(y0, y1, eta, &hit) : oc_ccd_edge_edge(y0, y1, eta, &hit);
    return h ? hit.t : HUGE_VAL;
}

/* The first touch over x0 -> x1 of the candidate pairs (vertex-triangle, or with ee edge-edge;
 * with close, only the close ones) whose swept boxes in box come within eta */
static double first_touch(self_contact *s, int ee, int close, const double *x0, const double *x1, double eta)
{
    const pair_list *l = ee ? &s->ee : &s->vt;
    double first = HUGE_VAL;
    const pair_list *cl = &s->ref.close;
    int np = close ? cl->n : l->n;
    for (int j = 0; j < np; j++) {
        int i = j, v[4];
        if (close) {
            if (cl->v[2 * j] != ee) continue;
            i = cl->v[2 * j + 1];
        }
        int a = l->v[2 * i], t = l->v[2 * i + 1];
        if (ee) {
            if (!near_boxes(s->box + 6 * (size_t)a, s->box + 6 * (size_t)t, eta)) continue;
        } else if (!near_boxes(s->vbox + 6 * (size_t)a, s->box + 6 * (size_t)t, eta)) {
            continue;
        }
        pair_vertices(s, l, ee, i, v);
        first = fmin(first, touch(x0, x1, v, !ee, eta));
    }
    return first;
}

/* The first touch over x0 -> x1, the pairs found by their swept boxes alone (no list kept) */
static double sweep_direct(self_contact *s, const double *x0, const double *x1, double eta)
{
    double first = HUGE_VAL;
    s->swept.n = 0;
    if (list_pairs(s, 0, x0, x1, eta, &first) < 0 || list_pairs(s, 1, x0, x1, eta, &first) < 0) return -1.0;
    return first;
}

static double max_step_untimed(self_contact *s, const double *x0, const double *x1)
{
    double eta = SELF_CONTACT_TOUCH * s->D, first;
    int how = candidates(s, x0, x1);
    if (how < 0) return 0.0;
    if (how > 0) {
        first = sweep_direct(s, x0, x1, eta);
        if (first < 0.0) return 0.0;
    } else {
        /* a path between two points within the slack of the references stays within it */
        int close = close_holds(s, x0, x1);
        boxes_for(s, 0, close, x0, x1);
        first = first_touch(s, 0, close, x0, x1, eta);
        boxes_for(s, 1, close, x0, x1);
        first = fmin(first, first_touch(s, 1, close, x0, x1, eta));
    }
    return first <= 1.0 ? SELF_CONTACT_STOP * first : 1.0;
}

double oc_self_contact_eval(self_contact *s, const double *x, double cfac, double *b, bsr *A)
{
    double t0 = wall_now(), E = eval_untimed(s, x, cfac, b, A);
    s->work.seconds += wall_now() - t0;
    return E;
}

double oc_self_contact_max_step(self_contact *s, const double *x0, const double *x1)
{
    double t0 = wall_now(), f = max_step_untimed(s, x0, x1);
    s->work.seconds += wall_now() - t0;
    return f;
}
