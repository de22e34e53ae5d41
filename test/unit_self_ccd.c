/* Unit: continuous self-collision (core/src/ccd.c, sweep_grid.c,
 * self_ccd.c), called through their internal headers.
 *
 * 1. Closed forms of the continuous tests: a point falling through a
 *    triangle (t = 1/2, and 6/13 against a rising triangle), an edge passing
 *    an edge (t = 1/2, s = 1/4, u = 1/2), with their weights and normals;
 *    no hit for a point passing beside, a point stopping short, an edge
 *    passing beyond another's end, a point sliding in a triangle's plane
 *    (over it, and along an edge within eta) and an edge sliding along a
 *    parallel edge within eta (none closing); a graze that parts (t = 0.2)
 *    before a crossing (t = 0.7): the hit is at 0.7. The cubic's roots:
 *    three simple, a double, none, vanishing.
 * 2. The grid: every query gives the boxes brute force gives, with a box
 *    blown up to 1e6 m and a NaN box (both in the big list).
 * 3. A sheet thrown through another: it ends above it (each vertex over
 *    the other sheet's surface), no pair left, momentum kept to 1e-12.
 * 4. 20 crumples: a 15 x 15 sheet moved 3 steps from flat by smooth random
 *    fields of 2-8 grid spacings a step; no crossing pair at 8 times through
 *    each step, nothing unresolved, momentum kept to 1e-12. With a row held
 *    (5 more crumples), the count returned is what a fresh sweep finds, and
 *    a step that starts free of crossings and crosses reports pairs.
 *
 * Crossings are counted here by brute force, independently of the code
 * under test: every pair of triangles sharing no vertex whose boxes
 * overlap, an edge of one through the other by signed volumes.
 *
 *   unit_self_ccd              the test
 *   unit_self_ccd --bench N    time calls on an N x N sheet, flat and
 *                              crumpled (CPU ms)
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ccd.h"
#include "check.h"
#include "self_ccd.h"
#include "sweep_grid.h"

#define ETA 1e-3

static rng R;
static double rnd(double a, double b) { return rng_range(&R, a, b); }

/* ------------------------------------------------------- brute force */

static double orient(const double *a, const double *b, const double *c, const double *d)
{
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        w[k] = d[k] - a[k];
    }
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

static int sgn(double v, double tol) { return v > tol ? 1 : (v < -tol ? -1 : 0); }

/* Segment pq strictly through triangle abc (tol: no side). */
static int seg_through(const double *p, const double *q, const double *a, const double *b, const double *c, double tol)
{
    int sp = sgn(orient(a, b, c, p), tol), sq = sgn(orient(a, b, c, q), tol);
    if (sp == 0 || sq == 0 || sp == sq) return 0;
    int s1 = sgn(orient(p, q, a, b), tol), s2 = sgn(orient(p, q, b, c), tol), s3 = sgn(orient(p, q, c, a), tol);
    return s1 != 0 && s1 == s2 && s2 == s3;
}

typedef struct tri_box {
    double lo[3], hi[3];
    int t;
} tri_box;

static int cmp_box(const void *a, const void *b)
{
    double p = ((const tri_box *)a)->lo[0], q = ((const tri_box *)b)->lo[0];
    return (p > q) - (p < q);
}

/* Whether triangles A and B (sharing no vertex) cross: an edge of one
 * strictly through the other. */
static int tri_cross(const double *x, const int *A, const int *B)
{
    double spread = 0.0;
    for (int k = 0; k < 3; k++) {
        double lo = x[3 * A[0] + k], hi = lo;
        for (int a = 0; a < 3; a++) {
            lo = fmin(lo, fmin(x[3 * A[a] + k], x[3 * B[a] + k]));
            hi = fmax(hi, fmax(x[3 * A[a] + k], x[3 * B[a] + k]));
        }
        spread = fmax(spread, hi - lo);
    }
    double tol = 1e-12 * spread * spread * spread;
    for (int e = 0; e < 3; e++)
        if (seg_through(x + 3 * A[e], x + 3 * A[(e + 1) % 3], x + 3 * B[0], x + 3 * B[1], x + 3 * B[2], tol) ||
            seg_through(x + 3 * B[e], x + 3 * B[(e + 1) % 3], x + 3 * A[0], x + 3 * A[1], x + 3 * A[2], tol))
            return 1;
    return 0;
}

/* Pairs of triangles sharing no vertex where an edge of one crosses the
 * other: every pair whose boxes overlap (sorted along x, swept). */
static int crossings(const double *x, int ntri, const int *tri)
{
    tri_box *b = malloc((size_t)ntri * sizeof *b);
    for (int t = 0; t < ntri; t++) {
        b[t].t = t;
        for (int k = 0; k < 3; k++) {
            b[t].lo[k] = b[t].hi[k] = x[3 * tri[3 * t] + k];
            for (int a = 1; a < 3; a++) {
                b[t].lo[k] = fmin(b[t].lo[k], x[3 * tri[3 * t + a] + k]);
                b[t].hi[k] = fmax(b[t].hi[k], x[3 * tri[3 * t + a] + k]);
            }
        }
    }
    qsort(b, (size_t)ntri, sizeof *b, cmp_box);
    int count = 0;
    for (int i = 0; i < ntri; i++)
        for (int j = i + 1; j < ntri && b[j].lo[0] <= b[i].hi[0]; j++) {
            if (b[j].lo[1] > b[i].hi[1] || b[i].lo[1] > b[j].hi[1] || b[j].lo[2] > b[i].hi[2] ||
                b[i].lo[2] > b[j].hi[2])
                continue;
            const int *A = tri + 3 * b[i].t, *B = tri + 3 * b[j].t;
            int shared = 0;
            for (int a = 0; a < 3; a++)
                for (int c = 0; c < 3; c++) shared |= A[a] == B[c];
            if (!shared) count += tri_cross(x, A, B);
        }
    free(b);
    return count;
}

/* The most crossing pairs at any of SAMPLES times through the step
 * (x0 + t (x1 - x0), t = 1/SAMPLES ... 1): a vertex that passes through a
 * triangle and out beyond it is seen at the times its edges are through. */
#define SAMPLES 8
static int crossings_over_step(const double *x0, const double *x1, int nv, int ntri, const int *tri)
{
    double *x = malloc(3 * (size_t)nv * sizeof *x);
    int most = 0;
    for (int k = 1; k <= SAMPLES; k++) {
        double t = (double)k / SAMPLES;
        for (int i = 0; i < 3 * nv; i++) x[i] = k == SAMPLES ? x1[i] : x0[i] + t * (x1[i] - x0[i]);
        int c = crossings(x, ntri, tri);
        most = c > most ? c : most;
    }
    free(x);
    return most;
}

/* --------------------------------------------------------- meshes */

/* An nr x nc grid's triangles (cell split along its (r, k)-(r+1, k+1)
 * diagonal), vertex indices offset by base, into tri; returns their count. */
static int grid_triangles(int nr, int nc, int base, int *tri)
{
    int t = 0;
    for (int r = 0; r + 1 < nr; r++)
        for (int k = 0; k + 1 < nc; k++) {
            int a = base + r * nc + k, b = a + 1, c = a + nc, d = c + 1;
            int v[6] = {a, b, d, a, d, c};
            memcpy(tri + 3 * t, v, sizeof v);
            t += 2;
        }
    return t;
}

static void momentum(const double *x0, const double *x1, const double *inv, int n, double *P, double *scale)
{
    P[0] = P[1] = P[2] = *scale = 0.0;
    for (int i = 0; i < n; i++) {
        if (!(inv[i] > 0.0)) continue;
        double d2 = 0.0;
        for (int k = 0; k < 3; k++) {
            double d = x1[3 * i + k] - x0[3 * i + k];
            P[k] += d / inv[i];
            d2 += d * d;
        }
        *scale += sqrt(d2) / inv[i];
    }
}

/* ------------------------------------------------ 1. closed forms */

static void set4(double *x, const double *a, const double *b, const double *c, const double *d)
{
    memcpy(x, a, 3 * sizeof *x);
    memcpy(x + 3, b, 3 * sizeof *x);
    memcpy(x + 6, c, 3 * sizeof *x);
    memcpy(x + 9, d, 3 * sizeof *x);
}

static void case_point_triangle(void)
{
    double x0[12], x1[12];
    ccd_hit h;
    const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    /* falling through a fixed triangle at (0.2, 0.3) */
    set4(x0, (double[]){0.2, 0.3, 1.0}, a, b, c);
    set4(x1, (double[]){0.2, 0.3, -1.0}, a, b, c);
    CHECK(ccd_point_triangle(x0, x1, ETA, &h), "point through a triangle: hit");
    CHECK_NEAR(h.t, 0.5, 1e-14);
    CHECK_NEAR(h.w[0], 1.0, 1e-14);
    CHECK_NEAR(h.w[1], -0.5, 1e-14);
    CHECK_NEAR(h.w[2], -0.2, 1e-14);
    CHECK_NEAR(h.w[3], -0.3, 1e-14);
    CHECK_NEAR(h.n[2], 1.0, 1e-14);
    CHECK_NEAR(h.dist, 0.0, 1e-14);
    /* against a triangle rising z = -0.2 + 0.6 t: 1 - 2t = -0.2 + 0.6t */
    double r0[3][3] = {{0, 0, -0.2}, {1, 0, -0.2}, {0, 1, -0.2}}, r1[3][3] = {{0, 0, 0.4}, {1, 0, 0.4}, {0, 1, 0.4}};
    set4(x0, (double[]){0.2, 0.3, 1.0}, r0[0], r0[1], r0[2]);
    set4(x1, (double[]){0.2, 0.3, -1.0}, r1[0], r1[1], r1[2]);
    CHECK(ccd_point_triangle(x0, x1, ETA, &h), "point through a rising triangle: hit");
    CHECK_NEAR(h.t, 6.0 / 13.0, 1e-14);
    /* beside: crossing the plane at x = 1.2 */
    set4(x0, (double[]){1.2, 0.3, 1.0}, a, b, c);
    set4(x1, (double[]){1.2, 0.3, -1.0}, a, b, c);
    CHECK(!ccd_point_triangle(x0, x1, ETA, &h), "point beside a triangle: no hit");
    /* stopping 2 eta above */
    set4(x0, (double[]){0.2, 0.3, 1.0}, a, b, c);
    set4(x1, (double[]){0.2, 0.3, 2.0 * ETA}, a, b, c);
    CHECK(!ccd_point_triangle(x0, x1, ETA, &h), "point stopping short: no hit");
    /* sliding in the triangle's plane, over it: touching, never closing */
    set4(x0, (double[]){0.1, 0.2, 0.0}, a, b, c);
    set4(x1, (double[]){0.5, 0.2, 0.0}, a, b, c);
    CHECK(!ccd_point_triangle(x0, x1, ETA, &h), "point sliding in the plane: no hit");
    /* sliding along edge ab in the plane, eta / 2 outside it */
    set4(x0, (double[]){0.1, -0.5 * ETA, 0.0}, a, b, c);
    set4(x1, (double[]){0.9, -0.5 * ETA, 0.0}, a, b, c);
    CHECK(!ccd_point_triangle(x0, x1, ETA, &h), "point sliding along an edge within eta: no hit");
}

/* A graze that parts at t = 0.2 (in the plane just outside edge ab, moving
 * away from it), then a crossing at t = 0.7, the triangle turning about ab. */
static void case_graze_then_cross(void)
{
    double vy = (0.25 + 0.1 * ETA) / 0.5, y0 = -0.1 * ETA - 0.2 * vy;
    double k = -11.0, c0 = 5.0 - 0.2 * k; /* c_z(0.2) = 5, c_z(0.7) = -0.5 */
    double vz = (-0.125 + 0.5 * ETA) / 0.5, z0 = -0.5 * ETA - 0.2 * vz;
    double x0[12] = {0.25, y0, z0, 0, 0, 0, 1, 0, 0, 0, 1, c0};
    double x1[12] = {0.25, y0 + vy, z0 + vz, 0, 0, 0, 1, 0, 0, 0, 1, c0 + k};
    ccd_hit h;
    CHECK(ccd_point_triangle(x0, x1, ETA, &h), "graze then crossing: hit");
    CHECK_NEAR(h.t, 0.7, 1e-12);
    /* the same crossing with the triangle's motion ending at t = 0.5: the
     * graze alone (the point passes the plane outside ab, parting) */
    double x1g[12];
    memcpy(x1g, x1, sizeof x1g);
    x1g[1] = y0 + 0.3 * vy; /* stays outside (y < 0) after the graze */
    x1g[2] = z0 + 0.3 * vz;
    x1g[11] = c0 + 0.3 * k;
    CHECK(!ccd_point_triangle(x0, x1g, ETA, &h) || h.t > 0.25, "the parting graze alone is no hit (t %g)", h.t);
}

static void case_edge_edge(void)
{
    double x0[12], x1[12];
    ccd_hit h;
    const double b0[3] = {0.25, 0, 0}, b1[3] = {0.25, 1, 0};
    set4(x0, (double[]){0, 0.5, 1}, (double[]){1, 0.5, 1}, b0, b1);
    set4(x1, (double[]){0, 0.5, -1}, (double[]){1, 0.5, -1}, b0, b1);
    CHECK(ccd_edge_edge(x0, x1, ETA, &h), "edge through an edge: hit");
    CHECK_NEAR(h.t, 0.5, 1e-14);
    CHECK_NEAR(h.w[0], 0.75, 1e-14);
    CHECK_NEAR(h.w[1], 0.25, 1e-14);
    CHECK_NEAR(h.w[2], -0.5, 1e-14);
    CHECK_NEAR(h.w[3], -0.5, 1e-14);
    CHECK_NEAR(h.n[2], 1.0, 1e-14);
    /* beyond the other's end: b at x = 1.1 */
    const double c0[3] = {1.1, 0, 0}, c1[3] = {1.1, 1, 0};
    set4(x0, (double[]){0, 0.5, 1}, (double[]){1, 0.5, 1}, c0, c1);
    set4(x1, (double[]){0, 0.5, -1}, (double[]){1, 0.5, -1}, c0, c1);
    CHECK(!ccd_edge_edge(x0, x1, ETA, &h), "edge past another's end: no hit");
    /* parallel, eta / 2 apart, sliding along each other */
    const double p0[3] = {0, 0, 0}, p1[3] = {1, 0, 0};
    set4(x0, (double[]){-0.5, 0, 0.5 * ETA}, (double[]){0.5, 0, 0.5 * ETA}, p0, p1);
    set4(x1, (double[]){0.5, 0, 0.5 * ETA}, (double[]){1.5, 0, 0.5 * ETA}, p0, p1);
    CHECK(!ccd_edge_edge(x0, x1, ETA, &h), "parallel slide within eta: no hit");
}

static void case_cubic(void)
{
    double t[3];
    /* (t - 0.2)(t - 0.5)(t - 0.9) */
    double c3[4] = {-0.09, 0.1 + 0.18 + 0.45, -1.6, 1.0};
    int n = ccd_cubic_roots(c3, 1e-15, t);
    CHECK(n == 3, "three roots: %d", n);
    if (n == 3) {
        CHECK_NEAR(t[0], 0.2, 1e-14);
        CHECK_NEAR(t[1], 0.5, 1e-14);
        CHECK_NEAR(t[2], 0.9, 1e-14);
    }
    /* (t - 0.5)^2 (t - 2): a double root in [0, 1] */
    double cd[4] = {-0.5, 0.25 + 2.0, -3.0, 1.0};
    n = ccd_cubic_roots(cd, 1e-14, t);
    CHECK(n == 1 && fabs(t[0] - 0.5) < 1e-7, "double root: %d, %g", n, n ? t[0] : -1.0);
    double cn[4] = {1.0, 0.0, 1.0, 0.0};
    CHECK(ccd_cubic_roots(cn, 1e-14, t) == 0, "no root");
    double cz[4] = {0.0, 0.0, 0.0, 0.0};
    CHECK(ccd_cubic_roots(cz, 1e-14, t) == -1, "vanishing cubic");
}

/* --------------------------------------------------------- 2. grid */

static int cmp_int(const void *a, const void *b) { return *(const int *)a - *(const int *)b; }

static void case_grid(void)
{
    enum { N = 600, Q = 300 };
    static double box[6 * N];
    R = rng_seed(0x5eed);
    for (int i = 0; i < N; i++)
        for (int k = 0; k < 3; k++) {
            double lo = rnd(-1.0, 1.0), s = rnd(0.0, 0.1);
            box[6 * i + k] = lo;
            box[6 * i + 3 + k] = lo + s;
        }
    box[6 * 7 + 3] = 1e6; /* blown up */
    box[6 * 9 + 1] = NAN;
    sweep_grid *g = sweep_grid_create();
    CHECK(g && sweep_grid_build(g, box, N) == 0, "grid built");
    if (!g) return;
    CHECK(sweep_grid_big(g) == 2, "big list: %d boxes (the blown-up and the NaN one)", sweep_grid_big(g));
    int bad = 0, found7 = 0;
    for (int q = 0; q < Q; q++) {
        double qb[6];
        for (int k = 0; k < 3; k++) {
            double lo = rnd(-1.2, 1.2), s = rnd(0.0, q == 0 ? 1e7 : 0.3);
            qb[k] = lo;
            qb[3 + k] = lo + s;
        }
        const int *items;
        int m = sweep_grid_query(g, qb, &items), want[N], nw = 0, got[N];
        memcpy(got, items, (size_t)m * sizeof *got);
        for (int i = 0; i < N; i++) {
            const double *b = box + 6 * i;
            if (b[0] <= qb[3] && qb[0] <= b[3] && b[1] <= qb[4] && qb[1] <= b[4] && b[2] <= qb[5] && qb[2] <= b[5])
                want[nw++] = i;
        }
        qsort(got, (size_t)m, sizeof *got, cmp_int);
        bad += m != nw || memcmp(got, want, (size_t)m * sizeof *got) != 0;
        for (int j = 0; j < m; j++) found7 += got[j] == 7;
    }
    CHECK(bad == 0, "grid queries differing from brute force: %d of %d", bad, Q);
    CHECK(found7 > 0, "the blown-up box is found");
    sweep_grid_destroy(g);
}

/* ------------------------------------------------ 3. sheet through sheet */

static void case_sheets(void)
{
    enum { NA = 11, NB = 7 };
    int n = NA * NA + NB * NB, tri[3 * 2 * (NA * NA + NB * NB)];
    int ntri = grid_triangles(NA, NA, 0, tri);
    ntri += grid_triangles(NB, NB, NA * NA, tri + 3 * ntri);
    double x0[3 * (NA * NA + NB * NB)], x1[3 * (NA * NA + NB * NB)], inv[NA * NA + NB * NB];
    for (int i = 0; i < NA * NA; i++) {
        double p[3] = {0.1 * (i % NA), 0.1 * (i / NA), 0.0}, d[3] = {0.0, 0.0, -0.01};
        for (int k = 0; k < 3; k++) {
            x0[3 * i + k] = p[k];
            x1[3 * i + k] = p[k] + d[k];
        }
        inv[i] = 1.0;
    }
    for (int j = 0; j < NB * NB; j++) {
        int i = NA * NA + j;
        double p[3] = {0.23 + 0.1 * (j % NB), 0.27 + 0.1 * (j / NB), 0.05}, d[3] = {0.02, -0.01, -0.3};
        for (int k = 0; k < 3; k++) {
            x0[3 * i + k] = p[k];
            x1[3 * i + k] = p[k] + d[k];
        }
        inv[i] = 0.5;
    }
    double P0[3], P1[3], sc0, sc1;
    momentum(x0, x1, inv, n, P0, &sc0);
    self_ccd *s = self_ccd_create(n, ntri, tri);
    CHECK(self_ccd_count(s, x0, x1, ETA) > 0, "unresolved, the sheet passes through");
    self_ccd_stats st;
    int left = self_ccd_apply(s, x0, x1, inv, ETA, &st);
    CHECK(left == 0 && st.unresolved == 0, "sheets: %d pairs left", left);
    CHECK(crossings(x1, ntri, tri) == 0, "sheets: %d crossing pairs", crossings(x1, ntri, tri));
    CHECK(self_ccd_count(s, x0, x1, ETA) == 0, "sheets: the sweep finds nothing left");
    /* each vertex of B above A's surface at its (x, y): A's triangle under it
     * by barycentric coordinates in the xy plane */
    int below = 0, over = 0;
    double gap = HUGE_VAL;
    for (int i = NA * NA; i < n; i++)
        for (int t = 0; t < 2 * (NA - 1) * (NA - 1); t++) {
            const double *a = x1 + 3 * tri[3 * t], *b = x1 + 3 * tri[3 * t + 1], *c = x1 + 3 * tri[3 * t + 2];
            const double *p = x1 + 3 * i;
            double den = (b[1] - c[1]) * (a[0] - c[0]) + (c[0] - b[0]) * (a[1] - c[1]);
            double l0 = ((b[1] - c[1]) * (p[0] - c[0]) + (c[0] - b[0]) * (p[1] - c[1])) / den;
            double l1 = ((c[1] - a[1]) * (p[0] - c[0]) + (a[0] - c[0]) * (p[1] - c[1])) / den, l2 = 1.0 - l0 - l1;
            if (l0 < 0.0 || l1 < 0.0 || l2 < 0.0) continue;
            double za = l0 * a[2] + l1 * b[2] + l2 * c[2];
            over++;
            below += p[2] <= za;
            gap = fmin(gap, p[2] - za);
            break;
        }
    CHECK(over == NB * NB && below == 0, "sheet B ends above A: %d of %d vertices over A, %d below", over, NB * NB,
          below);
    momentum(x0, x1, inv, n, P1, &sc1);
    for (int k = 0; k < 3; k++) CHECK_NEAR(P1[k], P0[k], 1e-12 * sc0);
    printf("sheets: %d impulses, %d left to zones, %d zone rounds, %d zones (%d vertices), %d rounds, "
           "stretch %.4f, B above A by %.3g m or more\n",
           st.impulses, st.left, st.zone_rounds, st.zones, st.zone_vertices, st.rounds, st.stretch, gap);
    self_ccd_destroy(s);
}

/* ---------------------------------------------------- 4. crumples */

/* A smooth random displacement field over an n x n sheet (4 modes), scaled
 * so its largest displacement is amp, plus noise of amp / 20. */
static void crumple_field(int n, double amp, double *d)
{
    double a[4][3], f[4][2], ph[4];
    for (int m = 0; m < 4; m++) {
        for (int k = 0; k < 3; k++) a[m][k] = rnd(-1.0, 1.0);
        f[m][0] = rnd(-2.0, 2.0);
        f[m][1] = rnd(-2.0, 2.0);
        ph[m] = rnd(0.0, 6.283185307179586);
    }
    double big = 0.0;
    for (int i = 0; i < n * n; i++) {
        double u = (double)(i % n) / (n - 1), v = (double)(i / n) / (n - 1), l2 = 0.0;
        for (int k = 0; k < 3; k++) {
            d[3 * i + k] = 0.0;
            for (int m = 0; m < 4; m++)
                d[3 * i + k] += a[m][k] * sin(6.283185307179586 * (f[m][0] * u + f[m][1] * v) + ph[m]);
            l2 += d[3 * i + k] * d[3 * i + k];
        }
        big = fmax(big, sqrt(l2));
    }
    for (int i = 0; i < 3 * n * n; i++) d[i] = d[i] * amp / big + rnd(-0.05, 0.05) * amp;
}

typedef struct crumple_result {
    int crossings, unresolved, counted, max_unresolved, impulses, zone_rounds;
    double momentum_err, stretch;
} crumple_result;

/* steps steps from a flat n x n sheet of spacing h; held: the first row
 * is held (inverse mass 0) and moves with the field. */
static crumple_result crumple(int n, int steps, int held, self_ccd *s, const int *tri, int ntri)
{
    double h = 1.0 / (n - 1);
    int nv = n * n;
    double *x0 = malloc(3 * (size_t)nv * sizeof *x0), *x1 = malloc(3 * (size_t)nv * sizeof *x1);
    double *d = malloc(3 * (size_t)nv * sizeof *d), *inv = malloc((size_t)nv * sizeof *inv);
    crumple_result r = {0, 0, 0, 0, 0, 0, 0.0, 1.0};
    for (int i = 0; i < nv; i++) {
        x0[3 * i] = h * (i % n);
        x0[3 * i + 1] = h * (i / n);
        x0[3 * i + 2] = 0.0;
        inv[i] = held && i < n ? 0.0 : 1.0 / rnd(0.5, 2.0);
    }
    for (int step = 0; step < steps; step++) {
        crumple_field(n, h * rnd(2.0, 8.0), d);
        for (int i = 0; i < 3 * nv; i++) x1[i] = x0[i] + d[i];
        double P0[3], P1[3], sc0, sc1;
        momentum(x0, x1, inv, nv, P0, &sc0);
        self_ccd_stats st;
        int left = self_ccd_apply(s, x0, x1, inv, ETA, &st);
        momentum(x0, x1, inv, nv, P1, &sc1);
        for (int k = 0; k < 3; k++) r.momentum_err = fmax(r.momentum_err, fabs(P1[k] - P0[k]) / sc0);
        int c = crossings_over_step(x0, x1, nv, ntri, tri), counted = self_ccd_count(s, x0, x1, ETA);
        int c0 = crossings(x0, ntri, tri);
        r.crossings += c;
        r.unresolved += left;
        r.max_unresolved = left > r.max_unresolved ? left : r.max_unresolved;
        r.impulses += st.impulses;
        r.zone_rounds += st.zone_rounds;
        r.stretch = fmax(r.stretch, st.stretch);
        /* what is reported is what the sweep finds left, and a crossing is
         * never left unreported */
        CHECK(left == counted, "crumple step %d: %d pairs reported, the sweep finds %d", step, left, counted);
        CHECK(c0 > 0 || c == 0 || left > 0, "crumple step %d: %d crossings, none reported", step, c);
        memcpy(x0, x1, 3 * (size_t)nv * sizeof *x0);
    }
    free(x0);
    free(x1);
    free(d);
    free(inv);
    return r;
}

static void case_crumples(void)
{
    enum { N = 15, CRUMPLES = 20, HELD = 5 };
    int tri[3 * 2 * (N - 1) * (N - 1)], ntri = grid_triangles(N, N, 0, tri);
    self_ccd *s = self_ccd_create(N * N, ntri, tri);
    CHECK(s != NULL, "created");
    if (!s) return;
    R = rng_seed(0xc7a5);
    int crossed = 0, unresolved = 0, impulses = 0, zr = 0;
    double merr = 0.0, stretch = 1.0;
    for (int c = 0; c < CRUMPLES; c++) {
        crumple_result r = crumple(N, 3, 0, s, tri, ntri);
        crossed += r.crossings > 0;
        unresolved += r.unresolved;
        impulses += r.impulses;
        zr += r.zone_rounds;
        merr = fmax(merr, r.momentum_err);
        stretch = fmax(stretch, r.stretch);
        if (r.crossings || r.unresolved)
            printf("crumple %d: %d crossing pairs, %d unresolved\n", c, r.crossings, r.unresolved);
    }
    printf("crumples: %d of %d crossed, %d unresolved, %d impulses, %d zone rounds, momentum %.2g, stretch %.4f\n",
           crossed, CRUMPLES, unresolved, impulses, zr, merr, stretch);
    CHECK(crossed == 0, "%d of %d crumples end crossed", crossed, CRUMPLES);
    CHECK(unresolved == 0, "%d pairs unresolved over the crumples", unresolved);
    CHECK(merr <= 1e-12, "momentum kept to %.3g of sum m |dx|", merr);
    int held_left = 0;
    for (int c = 0; c < HELD; c++) {
        crumple_result r = crumple(N, 3, 1, s, tri, ntri);
        held_left += r.unresolved;
        printf("held crumple %d: %d crossing pairs, %d unresolved (at most %d in a step)\n", c, r.crossings,
               r.unresolved, r.max_unresolved);
    }
    printf("held crumples: %d pairs reported unresolved\n", held_left);
    self_ccd_destroy(s);
}

static void case_bad_input(void)
{
    int tri[3] = {0, 1, 2}, bad[3] = {0, 1, 3}, rep[3] = {0, 1, 1};
    CHECK(self_ccd_create(3, 1, bad) == NULL, "an index out of range is refused");
    CHECK(self_ccd_create(3, 1, rep) == NULL, "a repeated corner is refused");
    CHECK(self_ccd_create(0, 0, NULL) == NULL, "no vertices is refused");
    self_ccd *s = self_ccd_create(3, 1, tri);
    double x0[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, x1[9], inv[3] = {1, 1, 1};
    memcpy(x1, x0, sizeof x1);
    CHECK(self_ccd_apply(s, x0, x1, inv, 0.0, NULL) == -1, "eta 0 is refused");
    CHECK(self_ccd_apply(s, x0, x1, inv, NAN, NULL) == -1, "eta NaN is refused");
    x1[4] = NAN;
    CHECK(self_ccd_apply(s, x0, x1, inv, ETA, NULL) == -1, "a NaN position is refused");
    CHECK(isnan(x1[4]), "x1 left untouched");
    x1[4] = 0.0;
    inv[1] = -1.0;
    CHECK(self_ccd_apply(s, x0, x1, inv, ETA, NULL) == -1, "a negative inverse mass is refused");
    inv[1] = 1.0;
    CHECK(self_ccd_apply(s, x0, x1, inv, ETA, NULL) == 0, "a lone triangle: nothing to do");
    self_ccd_destroy(s);
}

/* ------------------------------------------------------- benchmark */

static int bench(int n)
{
    int ntri = 2 * (n - 1) * (n - 1), nv = n * n;
    int *tri = malloc(3 * (size_t)ntri * sizeof *tri);
    double *x0 = malloc(3 * (size_t)nv * sizeof *x0), *x1 = malloc(3 * (size_t)nv * sizeof *x1);
    double *d = malloc(3 * (size_t)nv * sizeof *d), *inv = malloc((size_t)nv * sizeof *inv);
    if (!tri || !x0 || !x1 || !d || !inv) {
        fprintf(stderr, "unit_self_ccd --bench %d: out of memory\n", n);
        return 1;
    }
    grid_triangles(n, n, 0, tri);
    self_ccd *s = self_ccd_create(nv, ntri, tri);
    if (!s) {
        fprintf(stderr, "unit_self_ccd --bench %d: out of memory\n", n);
        return 1;
    }
    double h = 1.0 / (n - 1);
    R = rng_seed(0xbe7c);
    for (int i = 0; i < nv; i++) {
        x0[3 * i] = h * (i % n);
        x0[3 * i + 1] = h * (i / n);
        x0[3 * i + 2] = 0.0;
        inv[i] = 1.0;
    }
    /* phases: a flat sheet moved half a spacing a step (3 calls, timed);
     * crumpled by 6 steps of 2-8 spacings (not timed); 3 more such steps;
     * then 3 steps of half a spacing on the crumpled sheet */
    static const struct {
        const char *name;
        int steps, timed;
        double lo, hi;
    } phase[] = {
        {"flat, 0.5 spacing a step", 3, 1, 0.5, 0.5},
        {"crumpling", 6, 0, 2.0, 8.0},
        {"crumpled, 2-8 spacings a step", 3, 1, 2.0, 8.0},
        {"crumpled, 0.5 spacing a step", 3, 1, 0.5, 0.5},
    };
    for (int ph = 0; ph < 4; ph++) {
        double total = 0.0;
        for (int step = 0; step < phase[ph].steps; step++) {
            crumple_field(n, h * rnd(phase[ph].lo, phase[ph].hi), d);
            for (int i = 0; i < 3 * nv; i++) x1[i] = x0[i] + d[i];
            self_ccd_stats st;
            clock_t c0 = clock();
            int left = self_ccd_apply(s, x0, x1, inv, ETA, &st);
            double ms = 1e3 * (double)(clock() - c0) / CLOCKS_PER_SEC;
            total += ms;
            if (phase[ph].timed)
                printf("%dx%d %s: %.1f ms CPU, %d impulses, %d left to zones, %d zone rounds, %d zones "
                       "(%d vertices), %d rounds, %d unresolved, stretch %.4f\n",
                       n, n, phase[ph].name, ms, st.impulses, st.left, st.zone_rounds, st.zones, st.zone_vertices,
                       st.rounds, left, st.stretch);
            if (ph > 0) memcpy(x0, x1, 3 * (size_t)nv * sizeof *x0); /* the flat phase restarts flat */
        }
        if (phase[ph].timed)
            printf("%dx%d %s: mean %.1f ms CPU a call\n", n, n, phase[ph].name, total / phase[ph].steps);
    }
    self_ccd_destroy(s);
    free(tri);
    free(x0);
    free(x1);
    free(d);
    free(inv);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 1) {
        if (argc != 3 || strcmp(argv[1], "--bench") != 0) {
            fprintf(stderr, "usage: unit_self_ccd [--bench N]  (N: grid side, 3 to 2000)\n");
            return 2;
        }
        char *end = NULL;
        long n = strtol(argv[2], &end, 10);
        if (end == argv[2] || *end || n < 3 || n > 2000) {
            fprintf(stderr, "unit_self_ccd: --bench '%s': the grid side must be a whole number from 3 to 2000\n",
                    argv[2]);
            return 2;
        }
        return bench((int)n);
    }
    case_cubic();
    case_point_triangle();
    case_graze_then_cross();
    case_edge_edge();
    case_grid();
    case_bad_input();
    case_sheets();
    case_crumples();
    return check_summary();
}
