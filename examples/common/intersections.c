/* A triangle mesh's intersecting pairs (intersections.h): a uniform grid of
 * bounding boxes, then an exact-sign test of each edge against the other
 * triangle with a tolerance relative to the pair's size. */
#include "intersections.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Six times the signed volume of tetrahedron (a, b, c, d). */
static double orient(const double *a, const double *b, const double *c, const double *d)
{
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        w[k] = d[k] - a[k];
    }
    return u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

static int side(double v, double tol) { return v > tol ? 1 : v < -tol ? -1 : 0; }

/* Segment pq passes strictly through triangle abc: p and q on opposite
 * sides of its plane, and line pq strictly inside its three edges. */
static int edge_crosses(const double *p, const double *q, const double *a, const double *b, const double *c, double tol)
{
    if (side(orient(a, b, c, p), tol) * side(orient(a, b, c, q), tol) != -1) return 0;
    int s0 = side(orient(p, q, a, b), tol), s1 = side(orient(p, q, b, c), tol), s2 = side(orient(p, q, c, a), tol);
    return s0 != 0 && s0 == s1 && s1 == s2;
}

int intersections_pair(const double *x, const int *ta, const int *tb)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (ta[i] == tb[j]) return 0;
    const double *p[6];
    for (int i = 0; i < 3; i++) {
        p[i] = x + 3 * (size_t)ta[i];
        p[3 + i] = x + 3 * (size_t)tb[i];
    }
    double spread = 0.0;
    for (int k = 0; k < 3; k++) {
        double lo = p[0][k], hi = p[0][k];
        for (int i = 1; i < 6; i++) lo = fmin(lo, p[i][k]), hi = fmax(hi, p[i][k]);
        spread = fmax(spread, hi - lo);
    }
    double tol = INTERSECTIONS_FLAT * spread * spread * spread;
    for (int s = 0; s < 2; s++) {
        const double *const *e = p + 3 * s, *const *t = p + 3 * (1 - s); /* e's edges against t */
        for (int i = 0; i < 3; i++)
            if (edge_crosses(e[i], e[(i + 1) % 3], t[0], t[1], t[2], tol)) return 1;
    }
    return 0;
}

int intersections_grid_triangles(int rows, int cols, int *tri)
{
    int t = 0;
    for (int r = 0; r + 1 < rows; r++)
        for (int k = 0; k + 1 < cols; k++) {
            int a = r * cols + k, d = a + cols + 1;
            int *p = tri + 3 * t;
            p[0] = a, p[1] = a + 1, p[2] = d;
            p[3] = a, p[4] = d, p[5] = a + cols;
            t += 2;
        }
    return t;
}

/* The grid: cubic cells of side `side` from corner lo, dim cells a side. */
typedef struct grid {
    double lo[3], side;
    long long dim[3];
} grid;

typedef struct entry {
    long long key; /* the cell */
    int tri;
} entry;

/* The cell holding coordinate v along axis a; monotonic in v, so a point
 * inside a box lies in one of the cells the box's corners bound. */
static long long cell_of(const grid *g, int a, double v)
{
    double i = floor((v - g->lo[a]) / g->side);
    return i < 0.0 ? 0 : i >= (double)g->dim[a] ? g->dim[a] - 1 : (long long)i;
}

static long long cell_key(const grid *g, const long long i[3]) { return i[0] + g->dim[0] * (i[1] + g->dim[1] * i[2]); }

/* How many cells box b (lo, hi per axis) overlaps. */
static long long box_cells(const grid *g, const double *b)
{
    long long n = 1;
    for (int a = 0; a < 3; a++) n *= cell_of(g, a, b[2 * a + 1]) - cell_of(g, a, b[2 * a]) + 1;
    return n;
}

/* Each triangle's box (6 doubles: lo, hi per axis); -1 on a bad index or a
 * coordinate that is not finite. */
static int boxes(const double *x, int nv, const int *tri, int nt, double *box)
{
    for (int t = 0; t < nt; t++) {
        const int *p = tri + 3 * t;
        for (int i = 0; i < 3; i++)
            if (p[i] < 0 || p[i] >= nv) return -1;
        double *b = box + 6 * t;
        for (int a = 0; a < 3; a++) {
            double u = x[3 * (size_t)p[0] + a], v = x[3 * (size_t)p[1] + a], w = x[3 * (size_t)p[2] + a];
            if (!isfinite(u) || !isfinite(v) || !isfinite(w)) return -1;
            b[2 * a] = fmin(u, fmin(v, w));
            b[2 * a + 1] = fmax(u, fmax(v, w));
        }
    }
    return 0;
}

/* Cells about the mean triangle's size, doubled while the boxes would fill
 * more than CELLS_PER_TRI cells each on average (a few large triangles), and
 * at most 1e6 a side. Returns the number of (cell, triangle) entries. */
#define CELLS_PER_TRI 16
static long long grid_fit(grid *g, const double *box, int nt)
{
    double hi[3], mean = 0.0, span = 0.0;
    long long limit = (long long)CELLS_PER_TRI * nt;
    for (int a = 0; a < 3; a++) g->lo[a] = INFINITY, hi[a] = -INFINITY;
    for (int t = 0; t < nt; t++) {
        const double *b = box + 6 * t;
        double ext = 0.0;
        for (int a = 0; a < 3; a++) {
            g->lo[a] = fmin(g->lo[a], b[2 * a]);
            hi[a] = fmax(hi[a], b[2 * a + 1]);
            ext = fmax(ext, b[2 * a + 1] - b[2 * a]);
        }
        mean += ext / nt;
    }
    for (int a = 0; a < 3; a++) span = fmax(span, hi[a] - g->lo[a]);
    g->side = fmax(mean, span * 1e-6);
    if (!(g->side > 0.0)) g->side = 1.0; /* every point the same */
    for (;;) {
        long long total = 0;
        for (int a = 0; a < 3; a++) g->dim[a] = (long long)((hi[a] - g->lo[a]) / g->side) + 1;
        for (int t = 0; t < nt && total <= limit; t++) total += box_cells(g, box + 6 * t);
        if (total <= limit || g->side > span) return total;
        g->side *= 2.0;
    }
}

static int entry_order(const void *pa, const void *pb)
{
    const entry *a = pa, *b = pb;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return (a->tri > b->tri) - (a->tri < b->tri);
}

static void fill(const grid *g, const double *box, int nt, entry *e)
{
    size_t n = 0;
    for (int t = 0; t < nt; t++) {
        const double *b = box + 6 * t;
        long long i0[3], i1[3], i[3];
        for (int a = 0; a < 3; a++) i0[a] = cell_of(g, a, b[2 * a]), i1[a] = cell_of(g, a, b[2 * a + 1]);
        for (i[2] = i0[2]; i[2] <= i1[2]; i[2]++)
            for (i[1] = i0[1]; i[1] <= i1[1]; i[1]++)
                for (i[0] = i0[0]; i[0] <= i1[0]; i[0]++) e[n++] = (entry){cell_key(g, i), t};
    }
}

/* Whether cell `key` is the one that tests triangles s and t: their boxes
 * overlap, and the overlap's minimum corner lies in it. */
static int owns(const grid *g, long long key, const double *bs, const double *bt)
{
    long long i[3];
    for (int a = 0; a < 3; a++) {
        double lo = fmax(bs[2 * a], bt[2 * a]);
        if (lo > fmin(bs[2 * a + 1], bt[2 * a + 1])) return 0;
        i[a] = cell_of(g, a, lo);
    }
    return cell_key(g, i) == key;
}

/* The pairs within each run of entries sharing a cell. */
static long scan(const grid *g, const entry *e, size_t n, const double *x, const int *tri, const double *box,
                 unsigned char *mark)
{
    long pairs = 0;
    for (size_t s = 0, end; s < n; s = end) {
        for (end = s + 1; end < n && e[end].key == e[s].key; end++) {
        }
        for (size_t i = s; i < end; i++)
            for (size_t j = i + 1; j < end; j++) {
                int a = e[i].tri, b = e[j].tri;
                if (!owns(g, e[s].key, box + 6 * a, box + 6 * b)) continue;
                if (!intersections_pair(x, tri + 3 * a, tri + 3 * b)) continue;
                pairs++;
                for (int k = 0; k < 3; k++) mark[tri[3 * a + k]] = mark[tri[3 * b + k]] = 1;
            }
    }
    return pairs;
}

int intersections_count(const double *x, int nv, const int *tri, int nt, intersections *out, unsigned char *mark)
{
    out->pairs = 0;
    out->vertices = 0;
    if (nv < 0 || nt < 0) return -1;
    unsigned char *m = mark ? mark : malloc((size_t)nv + 1);
    double *box = malloc(6 * (size_t)nt * sizeof *box + 1);
    int rc = -1;
    if (m) memset(m, 0, (size_t)nv);
    if (!m || !box || boxes(x, nv, tri, nt, box)) goto done;
    if (nt > 1) {
        grid g;
        long long total = grid_fit(&g, box, nt);
        entry *e = malloc((size_t)total * sizeof *e);
        if (!e) goto done;
        fill(&g, box, nt, e);
        qsort(e, (size_t)total, sizeof *e, entry_order);
        out->pairs = scan(&g, e, (size_t)total, x, tri, box, m);
        free(e);
    }
    for (int i = 0; i < nv; i++) out->vertices += m[i];
    rc = 0;
done:
    if (m != mark) free(m);
    free(box);
    return rc;
}
