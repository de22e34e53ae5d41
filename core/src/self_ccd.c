/* Continuous self-collision of a triangle mesh over one step: see
 * self_ccd.h. The sweep (the pairs' broadphase and tests) and the three
 * responses: impulses, rigid impact zones, unstretching. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "ccd.h"
#include "mat3.h"
#include "self_ccd.h"
#include "sweep_grid.h"
#include "vec3.h"
#include "tuning.h"

struct self_ccd {
    int n, ntri, nedge;
    int *tri, *edge; /* 3 ntri, 2 nedge vertex indices */
    /* every vertex's, triangle's and edge's swept box (kept current for
     * the active ones); the active ones' boxes, indices and grid */
    double *all[3];
    sweep_grid *grid[3];
    double *box[3];
    int *id[3], nact[3];
    unsigned char *act;    /* n: active in this sweep */
    unsigned char *mark;   /* n: active in the next (moved, or in a hit) */
    int full;              /* the next sweep tests every pair */
    double *din;           /* 3 n: displacements entering the zones */
    double *mass;          /* n: the zones' fit masses */
    double *lim;           /* nedge: edge length limits */
    int *parent;           /* n: zones (union-find) */
    unsigned char *dirty;  /* n: a zone's root, when the zone grew */
    int *order, *first;    /* n, n + 1: vertices grouped by zone */
    int *pair, npair, cap; /* the colliding pairs' vertices, 4 each */
};

enum { ACT_VERTEX, ACT_TRIANGLE, ACT_EDGE };

enum { SWEEP_RESPOND, SWEEP_RECORD, SWEEP_COUNT };

/* One sweep's inputs; x1w is NULL unless the sweep responds. */
typedef struct sweep_ctx {
    const double *x0, *x1, *inv;
    double *x1w;
    double eta;
    int mode;
    int hits, applied, left;
} sweep_ctx;

static int cmp_edge(const void *a, const void *b)
{
    const int *p = a, *q = b;
    return p[0] != q[0] ? (p[0] > q[0]) - (p[0] < q[0]) : (p[1] > q[1]) - (p[1] < q[1]);
}

/* The mesh's edges, each once (lower index first). */
static int build_edges(self_ccd *s)
{
    size_t m = 3 * (size_t)s->ntri;
    int *e = malloc((m ? m : 1) * 2 * sizeof *e);
    if (!e) return -1;
    for (int t = 0; t < s->ntri; t++)
        for (int k = 0; k < 3; k++) {
            int a = s->tri[3 * t + k], b = s->tri[3 * t + (k + 1) % 3];
            e[2 * (3 * t + k)] = a < b ? a : b;
            e[2 * (3 * t + k) + 1] = a < b ? b : a;
        }
    qsort(e, m, 2 * sizeof *e, cmp_edge);
    size_t u = 0;
    for (size_t k = 0; k < m; k++)
        if (u == 0 || cmp_edge(e + 2 * k, e + 2 * (u - 1)) != 0) {
            e[2 * u] = e[2 * k];
            e[2 * u + 1] = e[2 * k + 1];
            u++;
        }
    s->edge = e;
    s->nedge = (int)u;
    return 0;
}

self_ccd *self_ccd_create(int nvert, int ntri, const int *tri)
{
    if (nvert <= 0 || ntri < 0 || (ntri > 0 && !tri)) return NULL;
    for (int t = 0; t < ntri; t++) {
        const int *v = tri + 3 * t;
        for (int k = 0; k < 3; k++)
            if (v[k] < 0 || v[k] >= nvert) return NULL;
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) return NULL;
    }
    self_ccd *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    size_t n = (size_t)nvert, nt = ntri ? (size_t)ntri : 1;
    s->n = nvert;
    s->ntri = ntri;
    s->tri = malloc(3 * nt * sizeof *s->tri);
    if (s->tri) memcpy(s->tri, tri ? tri : s->tri, 3 * (size_t)ntri * sizeof *s->tri);
    if (!s->tri || build_edges(s) < 0) {
        self_ccd_destroy(s);
        return NULL;
    }
    size_t cap[3] = {n, nt, s->nedge ? (size_t)s->nedge : 1};
    int ok = 1;
    for (int k = 0; k < 3; k++) {
        s->grid[k] = sweep_grid_create();
        s->all[k] = malloc(6 * cap[k] * sizeof *s->all[k]);
        s->box[k] = malloc(6 * cap[k] * sizeof *s->box[k]);
        s->id[k] = malloc(cap[k] * sizeof *s->id[k]);
        ok = ok && s->grid[k] && s->all[k] && s->box[k] && s->id[k];
    }
    s->act = malloc(n);
    s->mark = calloc(n, 1);
    s->dirty = calloc(n, 1);
    s->din = malloc(3 * n * sizeof *s->din);
    s->mass = malloc(n * sizeof *s->mass);
    s->lim = malloc(cap[2] * sizeof *s->lim);
    s->parent = malloc(n * sizeof *s->parent);
    s->order = malloc(n * sizeof *s->order);
    s->first = malloc((n + 1) * sizeof *s->first);
    if (!ok || !s->act || !s->mark || !s->dirty || !s->din || !s->mass || !s->lim || !s->parent || !s->order ||
        !s->first) {
        self_ccd_destroy(s);
        return NULL;
    }
    return s;
}

void self_ccd_destroy(self_ccd *s)
{
    if (!s) return;
    free(s->tri);
    free(s->edge);
    for (int k = 0; k < 3; k++) {
        sweep_grid_destroy(s->grid[k]);
        free(s->all[k]);
        free(s->box[k]);
        free(s->id[k]);
    }
    free(s->act);
    free(s->mark);
    free(s->dirty);
    free(s->din);
    free(s->mass);
    free(s->lim);
    free(s->parent);
    free(s->order);
    free(s->first);
    free(s->pair);
    free(s);
}

/* The box of vertices v[0..k) over the step, widened by pad. */
static void swept_box(const double *x0, const double *x1, const int *v, int k, double pad, double *box)
{
    for (int a = 0; a < 3; a++) {
        box[a] = HUGE_VAL;
        box[3 + a] = -HUGE_VAL;
    }
    for (int j = 0; j < k; j++)
        for (int a = 0; a < 3; a++) {
            double p = x0[3 * v[j] + a], q = x1[3 * v[j] + a], lo = (p < q ? p : q) - pad, hi = (p < q ? q : p) + pad;
            if (lo < box[a]) box[a] = lo;
            if (hi > box[3 + a]) box[3 + a] = hi;
        }
}

/* The inelastic impulse of a hit on the pair v: 1 if applied, 0 if left to
 * the zones (no free vertex, or it would throw a corner). */
static int impulse(sweep_ctx *c, const int *v, const ccd_hit *h)
{
    double vn = 0.0, g0 = 0.0, den = 0.0;
    for (int j = 0; j < 4; j++) {
        const double *p0 = c->x0 + 3 * v[j], *p1 = c->x1 + 3 * v[j];
        double d[3];
        vec3_sub(p1, p0, d);
        vn += h->w[j] * vec3_dot(d, h->n);
        g0 += h->w[j] * vec3_dot(p0, h->n);
        den += h->w[j] * h->w[j] * c->inv[v[j]];
    }
    /* end min(g0, eta / 2) apart; where the first-order end gap is already
     * that, stop the closing */
    double delta = fmin(g0, 0.5 * c->eta) - (g0 + vn);
    if (!(delta > 0.0)) delta = -vn;
    if (!(den > 0.0) || !(delta > 0.0)) return 0;
    double lam = delta / den;
    for (int j = 0; j < 4; j++)
        if (fabs(h->w[j] * c->inv[v[j]] * lam) > SELF_CCD_THROW * delta) return 0;
    for (int j = 0; j < 4; j++) vec3_axpy(c->x1w + 3 * v[j], h->w[j] * c->inv[v[j]] * lam, h->n);
    return 1;
}

/* Test the pair v (a point and a triangle, or two edges) and act on a hit
 * as the sweep's mode says. Returns -1 out of memory. */
static int pair_test(self_ccd *s, sweep_ctx *c, const int *v, int edges)
{
    double p0[12], p1[12];
    ccd_hit h;
    for (int j = 0; j < 4; j++)
        for (int a = 0; a < 3; a++) {
            p0[3 * j + a] = c->x0[3 * v[j] + a];
            p1[3 * j + a] = c->x1[3 * v[j] + a];
        }
    if (!(edges ? ccd_edge_edge(p0, p1, c->eta, &h) : ccd_point_triangle(p0, p1, c->eta, &h))) return 0;
    c->hits++;
    for (int j = 0; j < 4; j++) s->mark[v[j]] = 1;
    if (c->mode == SWEEP_RESPOND) {
        if (impulse(c, v, &h)) c->applied++;
        else c->left++;
    } else if (c->mode == SWEEP_RECORD) {
        if (s->npair == s->cap) {
            int cap = s->cap ? 2 * s->cap : 64;
            int *p = realloc(s->pair, 4 * (size_t)cap * sizeof *p);
            if (!p) return -1;
            s->pair = p;
            s->cap = cap;
        }
        memcpy(s->pair + 4 * s->npair++, v, 4 * sizeof *v);
    }
    return 0;
}

/* Bring the active primitives' boxes of one kind (k: ACT_*) up to date and
 * file them in their grid. */
static int file_active(self_ccd *s, const sweep_ctx *c, int k)
{
    static const int size[3] = {1, 3, 2};
    const int *verts = k == ACT_VERTEX ? NULL : (k == ACT_TRIANGLE ? s->tri : s->edge);
    int count = k == ACT_VERTEX ? s->n : (k == ACT_TRIANGLE ? s->ntri : s->nedge), m = 0;
    double pad = k == ACT_VERTEX ? c->eta : (k == ACT_TRIANGLE ? 0.0 : 0.5 * c->eta);
    for (int i = 0; i < count; i++) {
        const int *v = verts ? verts + size[k] * i : &i;
        int on = 0;
        for (int j = 0; j < size[k]; j++) on |= s->act[v[j]];
        if (!on) continue;
        swept_box(c->x0, c->x1, v, size[k], pad, s->all[k] + 6 * (size_t)i);
        memcpy(s->box[k] + 6 * m, s->all[k] + 6 * (size_t)i, 6 * sizeof *s->box[k]);
        s->id[k][m++] = i;
    }
    s->nact[k] = m;
    return sweep_grid_build(s->grid[k], s->box[k], m);
}

static int box_meets(const double *a, const double *b)
{
    return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] && b[2] <= a[5];
}

static int edge_active(const self_ccd *s, int e) { return s->act[s->edge[2 * e]] | s->act[s->edge[2 * e + 1]]; }

/* Test the pairs with an active vertex whose boxes meet: every triangle
 * against the active vertices, inactive vertices against the active
 * triangles, every edge against the active edges. -1: out of memory. */
static int sweep(self_ccd *s, sweep_ctx *c)
{
    c->hits = c->applied = c->left = 0;
    s->npair = 0;
    for (int i = 0; i < s->n; i++) s->act[i] = s->full || s->mark[i];
    memset(s->mark, 0, (size_t)s->n);
    s->full = 0;
    for (int k = 0; k < 3; k++)
        if (file_active(s, c, k) < 0) return -1;
    const int *cand;
    const double *vb = sweep_grid_bound(s->grid[ACT_VERTEX]), *tb = sweep_grid_bound(s->grid[ACT_TRIANGLE]);
    const double *eb = sweep_grid_bound(s->grid[ACT_EDGE]);
    for (int t = 0; t < s->ntri; t++) {
        const int *tv = s->tri + 3 * t;
        const double *box = s->all[ACT_TRIANGLE] + 6 * (size_t)t;
        int m = box_meets(box, vb) ? sweep_grid_query(s->grid[ACT_VERTEX], box, &cand) : 0;
        for (int k = 0; k < m; k++) {
            int p = s->id[ACT_VERTEX][cand[k]], v[4] = {p, tv[0], tv[1], tv[2]};
            if (p != tv[0] && p != tv[1] && p != tv[2] && pair_test(s, c, v, 0) < 0) return -1;
        }
    }
    for (int p = 0; p < s->n; p++) {
        const double *box = s->all[ACT_VERTEX] + 6 * (size_t)p;
        int m = !s->act[p] && box_meets(box, tb) ? sweep_grid_query(s->grid[ACT_TRIANGLE], box, &cand) : 0;
        for (int k = 0; k < m; k++) {
            const int *tv = s->tri + 3 * s->id[ACT_TRIANGLE][cand[k]];
            int v[4] = {p, tv[0], tv[1], tv[2]};
            if (pair_test(s, c, v, 0) < 0) return -1;
        }
    }
    for (int f = 0; f < s->nedge; f++) {
        const int *fv = s->edge + 2 * f;
        const double *box = s->all[ACT_EDGE] + 6 * (size_t)f;
        int f_on = edge_active(s, f), m = box_meets(box, eb) ? sweep_grid_query(s->grid[ACT_EDGE], box, &cand) : 0;
        for (int k = 0; k < m; k++) {
            int e = s->id[ACT_EDGE][cand[k]];
            const int *ev = s->edge + 2 * e;
            if ((f_on && f >= e) || fv[0] == ev[0] || fv[0] == ev[1] || fv[1] == ev[0] || fv[1] == ev[1]) continue;
            int v[4] = {ev[0], ev[1], fv[0], fv[1]};
            if (pair_test(s, c, v, 1) < 0) return -1;
        }
    }
    return 0;
}

static int zone_root(int *parent, int i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

/* R = the rotation by |w| about w (Rodrigues). */
static void rotation(const double *w, double *R)
{
    double th = vec3_norm(w), k[3] = {0.0, 0.0, 0.0};
    if (th > 0.0)
        for (int a = 0; a < 3; a++) k[a] = w[a] / th;
    double c = cos(th), sn = sin(th), v = 1.0 - c;
    R[0] = c + k[0] * k[0] * v;
    R[1] = k[0] * k[1] * v - k[2] * sn;
    R[2] = k[0] * k[2] * v + k[1] * sn;
    R[3] = k[1] * k[0] * v + k[2] * sn;
    R[4] = c + k[1] * k[1] * v;
    R[5] = k[1] * k[2] * v - k[0] * sn;
    R[6] = k[2] * k[0] * v - k[1] * sn;
    R[7] = k[2] * k[1] * v + k[0] * sn;
    R[8] = c + k[2] * k[2] * v;
}

/* Move the zone of vertices m[0..k) rigidly: the centre of mass and angular
 * momentum of the displacements din about it kept; held vertices keep
 * theirs. */
static void zone_fit(self_ccd *s, const sweep_ctx *c, const int *m, int k)
{
    double M = 0.0, X[3] = {0.0}, V[3] = {0.0}, L[3] = {0.0}, I[9] = {0.0}, Iinv[9] = {0.0}, w[3] = {0.0}, R[9];
    for (int j = 0; j < k; j++) {
        M += s->mass[m[j]];
        vec3_axpy(X, s->mass[m[j]], c->x0 + 3 * m[j]);
        vec3_axpy(V, s->mass[m[j]], s->din + 3 * m[j]);
    }
    for (int a = 0; a < 3; a++) {
        X[a] /= M;
        V[a] /= M;
    }
    for (int j = 0; j < k; j++) {
        double r[3], u[3], ru[3], mj = s->mass[m[j]];
        vec3_sub(c->x0 + 3 * m[j], X, r);
        vec3_sub(s->din + 3 * m[j], V, u);
        vec3_cross(r, u, ru);
        vec3_axpy(L, mj, ru);
        double rr = vec3_dot(r, r);
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) I[3 * a + b] += mj * ((a == b ? rr : 0.0) - r[a] * r[b]);
    }
    /* a line of vertices has no inertia about itself, and no angular
     * momentum about it either: a tiny isotropic term keeps I invertible */
    double tr = I[0] + I[4] + I[8];
    for (int a = 0; a < 3; a++) I[4 * a] += 1e-12 * tr;
    if (tr > 0.0 && mat3inv(I, Iinv) > 0.0) mat3vec(Iinv, L, w);
    rotation(w, R);
    for (int j = 0; j < k; j++) {
        if (!(c->inv[m[j]] > 0.0)) continue;
        double r[3], Rr[3];
        vec3_sub(c->x0 + 3 * m[j], X, r);
        mat3vec(R, r, Rr);
        for (int a = 0; a < 3; a++) c->x1w[3 * m[j] + a] = X[a] + V[a] + Rr[a];
    }
}

/* Group the vertices by zone and move each zone that grew. */
static void zones_move(self_ccd *s, const sweep_ctx *c, self_ccd_stats *st)
{
    int n = s->n;
    memset(s->first, 0, (size_t)(n + 1) * sizeof *s->first);
    for (int i = 0; i < n; i++) {
        s->parent[i] = zone_root(s->parent, i);
        s->first[s->parent[i] + 1]++;
    }
    for (int i = 0; i < n; i++) s->first[i + 1] += s->first[i];
    for (int i = 0; i < n; i++) s->order[s->first[s->parent[i]]++] = i;
    for (int i = n; i > 0; i--) s->first[i] = s->first[i - 1];
    s->first[0] = 0;
    st->zones = st->zone_vertices = 0;
    for (int r = 0; r < n; r++) {
        int k = s->first[r + 1] - s->first[r];
        if (k < 2) continue;
        st->zones++;
        st->zone_vertices += k;
        if (!s->dirty[r]) continue;
        s->dirty[r] = 0;
        zone_fit(s, c, s->order + s->first[r], k);
        for (int j = 0; j < k; j++) s->mark[s->order[s->first[r] + j]] = 1;
    }
}

/* Rigid impact zones until no pair collides or the zones stop growing.
 * Returns the pairs left colliding, or -1 out of memory. */
static int zones(self_ccd *s, sweep_ctx *c, self_ccd_stats *st)
{
    double mean = 0.0;
    int nfree = 0;
    st->zones = st->zone_vertices = 0;
    for (int i = 0; i < s->n; i++) {
        s->parent[i] = i;
        s->dirty[i] = 0;
        for (int a = 0; a < 3; a++) s->din[3 * i + a] = c->x1[3 * i + a] - c->x0[3 * i + a];
        if (c->inv[i] > 0.0) {
            mean += 1.0 / c->inv[i];
            nfree++;
        }
    }
    mean = nfree ? mean / nfree : 1.0;
    for (int i = 0; i < s->n; i++) s->mass[i] = c->inv[i] > 0.0 ? 1.0 / c->inv[i] : SELF_CCD_HELD_MASS * mean;
    c->mode = SWEEP_RECORD;
    for (int round = 0; round < SELF_CCD_ZONE_ROUNDS; round++) {
        if (sweep(s, c) < 0) return -1;
        if (s->npair == 0) return 0;
        int merged = 0;
        for (int p = 0; p < s->npair; p++)
            for (int j = 1; j < 4; j++) {
                int a = zone_root(s->parent, s->pair[4 * p]), b = zone_root(s->parent, s->pair[4 * p + j]);
                if (a == b) continue;
                int lo = a < b ? a : b, hi = a < b ? b : a;
                s->parent[hi] = lo;
                s->dirty[lo] = 1; /* the zone grew: move it */
                s->dirty[hi] = 0;
                merged = 1;
            }
        if (!merged) return s->npair;
        st->zone_rounds++;
        zones_move(s, c, st);
    }
    if (sweep(s, c) < 0) return -1;
    return s->npair;
}

/* Shorten the edges longer than their limits, each end moved by its inverse mass's share.
 * Returns 1 if it shortened any. */
static int unstretch(self_ccd *s, double *x1, const double *inv)
{
    int any = 0;
    for (int it = 0; it < SELF_CCD_UNSTRETCH; it++) {
        int moved = 0;
        for (int e = 0; e < s->nedge; e++) {
            int i = s->edge[2 * e], j = s->edge[2 * e + 1];
            double d[3], wsum = inv[i] + inv[j];
            vec3_sub(x1 + 3 * j, x1 + 3 * i, d);
            double len = vec3_norm(d);
            if (!(len > s->lim[e] * (1.0 + SELF_CCD_SLACK)) || !(wsum > 0.0)) continue;
            double f = (len - s->lim[e]) / (len * wsum);
            vec3_axpy(x1 + 3 * i, f * inv[i], d);
            vec3_axpy(x1 + 3 * j, -f * inv[j], d);
            s->mark[i] = s->mark[j] = 1;
            moved = 1;
        }
        any |= moved;
        if (!moved) break;
    }
    return any;
}

static double edge_len(const double *x, const int *e)
{
    double d[3];
    vec3_sub(x + 3 * e[1], x + 3 * e[0], d);
    return vec3_norm(d);
}

static int bad_input(const self_ccd *s, const double *x0, const double *x1, const double *inv, double eta)
{
    if (!s || !x0 || !x1 || !inv || !(eta > 0.0 && eta < HUGE_VAL)) return 1;
    for (int i = 0; i < 3 * s->n; i++)
        if (!isfinite(x0[i]) || !isfinite(x1[i])) return 1;
    for (int i = 0; i < s->n; i++)
        if (!(inv[i] >= 0.0 && inv[i] < HUGE_VAL)) return 1;
    return 0;
}

int self_ccd_apply(self_ccd *s, const double *x0, double *x1, const double *inv_mass, double eta, self_ccd_stats *stats)
{
    self_ccd_stats st;
    memset(&st, 0, sizeof st);
    if (stats) *stats = st;
    if (bad_input(s, x0, x1, inv_mass, eta)) return -1;
    for (int e = 0; e < s->nedge; e++) s->lim[e] = fmax(edge_len(x0, s->edge + 2 * e), edge_len(x1, s->edge + 2 * e));
    sweep_ctx c = {x0, x1, inv_mass, x1, eta, SWEEP_RESPOND, 0, 0, 0};
    s->full = 1;
    for (int round = 0; round < SELF_CCD_ROUNDS; round++) {
        st.rounds = round + 1;
        c.mode = SWEEP_RESPOND;
        c.hits = 1;
        for (int pass = 0; pass < SELF_CCD_PASSES && c.hits; pass++) {
            if (sweep(s, &c) < 0) return -1;
            st.impulses += c.applied;
            st.left += c.left;
            if (!c.applied) break;
        }
        st.unresolved = c.hits ? zones(s, &c, &st) : 0;
        if (st.unresolved < 0) return -1;
        if (round + 1 == SELF_CCD_ROUNDS || !unstretch(s, x1, inv_mass)) break;
    }
    st.stretch = 1.0;
    for (int e = 0; e < s->nedge; e++)
        if (s->lim[e] > 0.0) st.stretch = fmax(st.stretch, edge_len(x1, s->edge + 2 * e) / s->lim[e]);
    if (stats) *stats = st;
    return st.unresolved;
}

int self_ccd_count(self_ccd *s, const double *x0, const double *x1, double eta)
{
    if (!s || !x0 || !x1 || !(eta > 0.0 && eta < HUGE_VAL)) return -1;
    for (int i = 0; i < 3 * s->n; i++)
        if (!isfinite(x0[i]) || !isfinite(x1[i])) return -1;
    sweep_ctx c = {x0, x1, NULL, NULL, eta, SWEEP_COUNT, 0, 0, 0};
    s->full = 1;
    if (sweep(s, &c) < 0) return -1;
    return c.hits;
}
