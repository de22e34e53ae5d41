/* A hashed uniform grid over boxes: see sweep_grid.h. */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "sweep_grid.h"
#include "tuning.h"

struct sweep_grid {
    const double *box;
    int n, cap;        /* boxes; capacity of the per-box arrays */
    double cell;       /* m */
    double bound[6];   /* the box around every box filed */
    int *big, nbig;    /* boxes over SWEEP_GRID_MAX_CELLS cells */
    int *stamp, query; /* per box: the last query that met it */
    int *out;          /* a query's answer */
    double *side;      /* scratch: the boxes' largest sides */
    size_t nbucket;    /* a power of two */
    size_t bucket_cap;
    size_t *start; /* nbucket + 1: each bucket's first entry */
    int *entry;    /* boxes, bucket by bucket */
    size_t nentry, entry_cap;
};

sweep_grid *oc_sweep_grid_create(void)
{
    sweep_grid *g = calloc(1, sizeof *g);
    if (!g) return NULL;
    for (int a = 0; a < 3; a++) {
        g->bound[a] = HUGE_VAL;
        g->bound[3 + a] = -HUGE_VAL;
    }
    return g;
}

void oc_sweep_grid_destroy(sweep_grid *g)
{
    if (!g) return;
    free(g->big);
    free(g->stamp);
    free(g->out);
    free(g->side);
    free(g->start);
    free(g->entry);
    free(g);
}

int oc_sweep_grid_big(const sweep_grid *g) { return g ? g->nbig : 0; }

const double *oc_sweep_grid_bound(const sweep_grid *g) { return g->bound; }

static int overlap(const double *a, const double *b)
{
    return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] && b[2] <= a[5];
}

/* The cells box spans, into lo and hi; -1 when over the limit or far out. */
static int cell_range(const sweep_grid *g, const double *box, int64_t *lo, int64_t *hi)
{
    double cells = 1.0;
    for (int a = 0; a < 3; a++) {
        double l = floor(box[a] / g->cell), h = floor(box[3 + a] / g->cell);
        if (!(l >= -SWEEP_FAR && h <= SWEEP_FAR && h >= l)) return -1;
        cells *= h - l + 1.0;
        lo[a] = (int64_t)l;
        hi[a] = (int64_t)h;
    }
    return cells > SWEEP_GRID_MAX_CELLS ? -1 : (int)cells;
}

static size_t bucket_of(const sweep_grid *g, int64_t i, int64_t j, int64_t k)
{
    uint64_t h = (uint64_t)i * 0x9E3779B97F4A7C15u + (uint64_t)j * 0xC2B2AE3D27D4EB4Fu +
                 (uint64_t)k * 0x165667B19E3779F9u;
    h ^= h >> 31;
    return (size_t)(h & (g->nbucket - 1));
}

/* The k-th smallest of v[0..m) (0-based), v reordered: quickselect, the pivot a median of three */
static double kth_smallest(double *v, int m, int k)
{
    int lo = 0, hi = m - 1;
    while (lo < hi) {
        double a = v[lo], b = v[lo + (hi - lo) / 2], c = v[hi];
        double p = a < b ? (b < c ? b : a < c ? c : a) : (a < c ? a : b < c ? c : b);
        int i = lo, j = hi;
        while (i <= j) {
            while (v[i] < p) i++;
            while (v[j] > p) j--;
            if (i <= j) {
                double t = v[i];
                v[i++] = v[j];
                v[j--] = t;
            }
        }
        if (k <= j) hi = j;
        else if (k >= i) lo = i;
        else return v[k];
    }
    return v[k];
}

/* The cell: the median of the boxes' largest sides (finite ones); and the
 * boxes' bound. */
static double cell_size(sweep_grid *g)
{
    int m = 0;
    for (int i = 0; i < g->n; i++) {
        const double *b = g->box + 6 * (size_t)i;
        for (int a = 0; a < 3; a++) {
            if (b[a] < g->bound[a]) g->bound[a] = b[a];
            if (b[3 + a] > g->bound[3 + a]) g->bound[3 + a] = b[3 + a];
        }
        double s = fmax(b[3] - b[0], fmax(b[4] - b[1], b[5] - b[2]));
        if (isfinite(s) && s > 0.0) g->side[m++] = s;
    }
    if (m == 0) return 1.0;
    return kth_smallest(g->side, m, m / 2);
}

static int reserve(sweep_grid *g, int n)
{
    if (n <= g->cap) return 0;
    size_t c = (size_t)n + (size_t)n / 2;
    if (c > INT_MAX) c = INT_MAX;
    int *big = realloc(g->big, c * sizeof *big), *stamp, *out;
    if (big) g->big = big;
    stamp = realloc(g->stamp, c * sizeof *stamp);
    if (stamp) g->stamp = stamp;
    out = realloc(g->out, c * sizeof *out);
    if (out) g->out = out;
    double *side = realloc(g->side, c * sizeof *side);
    if (side) g->side = side;
    if (!big || !stamp || !out || !side) return -1;
    g->cap = (int)c;
    return 0;
}

enum { SWEEP_COUNT, SWEEP_TALLY, SWEEP_FILE };

/* One pass over the boxes' cells. COUNT: returns the entries and lists the
 * big boxes; TALLY: counts each bucket's entries at start[b + 2]; FILE:
 * files each entry at start[b + 1], advancing it. */
static size_t file_boxes(sweep_grid *g, int mode)
{
    size_t total = 0;
    if (mode == SWEEP_COUNT) g->nbig = 0;
    for (int i = 0; i < g->n; i++) {
        int64_t lo[3], hi[3];
        if (cell_range(g, g->box + 6 * (size_t)i, lo, hi) < 0) {
            if (mode == SWEEP_COUNT) g->big[g->nbig++] = i;
            continue;
        }
        for (int64_t a = lo[0]; a <= hi[0]; a++)
            for (int64_t b = lo[1]; b <= hi[1]; b++)
                for (int64_t c = lo[2]; c <= hi[2]; c++, total++) {
                    if (mode == SWEEP_COUNT) continue;
                    size_t k = bucket_of(g, a, b, c);
                    if (mode == SWEEP_TALLY) g->start[k + 2]++;
                    else g->entry[g->start[k + 1]++] = i;
                }
    }
    return total;
}

int oc_sweep_grid_build(sweep_grid *g, const double *box, int n)
{
    g->box = box;
    g->n = n < 0 ? 0 : n;
    for (int a = 0; a < 3; a++) {
        g->bound[a] = HUGE_VAL;
        g->bound[3 + a] = -HUGE_VAL;
    }
    g->nbig = 0;
    g->nentry = 0;
    if (g->n == 0) return 0;
    if (reserve(g, n) < 0) {
        g->n = 0;
        return -1;
    }
    g->cell = cell_size(g);
    memset(g->stamp, 0, (size_t)n * sizeof *g->stamp);
    g->query = 0;
    size_t total = file_boxes(g, SWEEP_COUNT), nb = 16;
    while (nb < 2 * total) nb *= 2;
    if (nb > g->bucket_cap) {
        size_t *start = realloc(g->start, (nb + 2) * sizeof *start);
        if (!start) {
            g->n = 0;
            return -1;
        }
        g->start = start;
        g->bucket_cap = nb;
    }
    if (total > g->entry_cap) { /* grown by half again at least: a step's lists rarely reallocate */
        size_t cap = total > g->entry_cap + g->entry_cap / 2 ? total : g->entry_cap + g->entry_cap / 2;
        int *e = realloc(g->entry, cap * sizeof *e);
        if (!e) {
            g->n = 0;
            return -1;
        }
        g->entry = e;
        g->entry_cap = cap;
    }
    g->nbucket = nb;
    /* counting sort: tallies at start[b + 2], summed into each bucket's
     * offset at start[b + 1], which filing advances to the bucket's end */
    memset(g->start, 0, (nb + 2) * sizeof *g->start);
    file_boxes(g, SWEEP_TALLY);
    for (size_t b = 2; b < nb + 2; b++) g->start[b] += g->start[b - 1];
    g->nentry = total;
    file_boxes(g, SWEEP_FILE);
    return 0;
}

int oc_sweep_grid_query(sweep_grid *g, const double *box, const int **items)
{
    int m = 0;
    int64_t lo[3], hi[3];
    *items = g->out;
    if (g->n == 0 || !overlap(g->bound, box)) return 0;
    if (cell_range(g, box, lo, hi) < 0) {
        for (int i = 0; i < g->n; i++)
            if (overlap(g->box + 6 * (size_t)i, box)) g->out[m++] = i;
        return m;
    }
    if (g->query == INT_MAX) {
        memset(g->stamp, 0, (size_t)g->n * sizeof *g->stamp);
        g->query = 0;
    }
    int q = ++g->query;
    for (int64_t a = lo[0]; a <= hi[0]; a++)
        for (int64_t b = lo[1]; b <= hi[1]; b++)
            for (int64_t c = lo[2]; c <= hi[2]; c++) {
                size_t k = bucket_of(g, a, b, c);
                for (size_t e = g->start[k]; e < g->start[k + 1]; e++) {
                    int i = g->entry[e];
                    if (g->stamp[i] == q) continue;
                    g->stamp[i] = q;
                    if (overlap(g->box + 6 * (size_t)i, box)) g->out[m++] = i;
                }
            }
    for (int j = 0; j < g->nbig; j++)
        if (overlap(g->box + 6 * (size_t)g->big[j], box)) g->out[m++] = g->big[j];
    return m;
}
