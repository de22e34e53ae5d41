/* Unit: the continuous tests (core/src/ccd.c) and the swept boxes' grid
 * (sweep_grid.c) that self_contact.c uses, called through their internal
 * headers.
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
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ccd.h"
#include "check.h"
#include "sweep_grid.h"

#define ETA 1e-3

static rng R;
static double rnd(double a, double b) { return rng_range(&R, a, b); }

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
    CHECK(oc_ccd_point_triangle(x0, x1, ETA, &h), "point through a triangle: hit");
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
    CHECK(oc_ccd_point_triangle(x0, x1, ETA, &h), "point through a rising triangle: hit");
    CHECK_NEAR(h.t, 6.0 / 13.0, 1e-14);
    /* beside: crossing the plane at x = 1.2 */
    set4(x0, (double[]){1.2, 0.3, 1.0}, a, b, c);
    set4(x1, (double[]){1.2, 0.3, -1.0}, a, b, c);
    CHECK(!oc_ccd_point_triangle(x0, x1, ETA, &h), "point beside a triangle: no hit");
    /* stopping 2 eta above */
    set4(x0, (double[]){0.2, 0.3, 1.0}, a, b, c);
    set4(x1, (double[]){0.2, 0.3, 2.0 * ETA}, a, b, c);
    CHECK(!oc_ccd_point_triangle(x0, x1, ETA, &h), "point stopping short: no hit");
    /* sliding in the triangle's plane, over it: touching, never closing */
    set4(x0, (double[]){0.1, 0.2, 0.0}, a, b, c);
    set4(x1, (double[]){0.5, 0.2, 0.0}, a, b, c);
    CHECK(!oc_ccd_point_triangle(x0, x1, ETA, &h), "point sliding in the plane: no hit");
    /* sliding along edge ab in the plane, eta / 2 outside it */
    set4(x0, (double[]){0.1, -0.5 * ETA, 0.0}, a, b, c);
    set4(x1, (double[]){0.9, -0.5 * ETA, 0.0}, a, b, c);
    CHECK(!oc_ccd_point_triangle(x0, x1, ETA, &h), "point sliding along an edge within eta: no hit");
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
    CHECK(oc_ccd_point_triangle(x0, x1, ETA, &h), "graze then crossing: hit");
    CHECK_NEAR(h.t, 0.7, 1e-12);
    /* the same crossing with the triangle's motion ending at t = 0.5: the
     * graze alone (the point passes the plane outside ab, parting) */
    double x1g[12];
    memcpy(x1g, x1, sizeof x1g);
    x1g[1] = y0 + 0.3 * vy; /* stays outside (y < 0) after the graze */
    x1g[2] = z0 + 0.3 * vz;
    x1g[11] = c0 + 0.3 * k;
    CHECK(!oc_ccd_point_triangle(x0, x1g, ETA, &h) || h.t > 0.25, "the parting graze alone is no hit (t %g)", h.t);
}

static void case_edge_edge(void)
{
    double x0[12], x1[12];
    ccd_hit h;
    const double b0[3] = {0.25, 0, 0}, b1[3] = {0.25, 1, 0};
    set4(x0, (double[]){0, 0.5, 1}, (double[]){1, 0.5, 1}, b0, b1);
    set4(x1, (double[]){0, 0.5, -1}, (double[]){1, 0.5, -1}, b0, b1);
    CHECK(oc_ccd_edge_edge(x0, x1, ETA, &h), "edge through an edge: hit");
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
    CHECK(!oc_ccd_edge_edge(x0, x1, ETA, &h), "edge past another's end: no hit");
    /* parallel, eta / 2 apart, sliding along each other */
    const double p0[3] = {0, 0, 0}, p1[3] = {1, 0, 0};
    set4(x0, (double[]){-0.5, 0, 0.5 * ETA}, (double[]){0.5, 0, 0.5 * ETA}, p0, p1);
    set4(x1, (double[]){0.5, 0, 0.5 * ETA}, (double[]){1.5, 0, 0.5 * ETA}, p0, p1);
    CHECK(!oc_ccd_edge_edge(x0, x1, ETA, &h), "parallel slide within eta: no hit");
}

static void case_cubic(void)
{
    double t[3];
    /* (t - 0.2)(t - 0.5)(t - 0.9) */
    double c3[4] = {-0.09, 0.1 + 0.18 + 0.45, -1.6, 1.0};
    int n = oc_ccd_cubic_roots(c3, 1e-15, t);
    CHECK(n == 3, "three roots: %d", n);
    if (n == 3) {
        CHECK_NEAR(t[0], 0.2, 1e-14);
        CHECK_NEAR(t[1], 0.5, 1e-14);
        CHECK_NEAR(t[2], 0.9, 1e-14);
    }
    /* (t - 0.5)^2 (t - 2): a double root in [0, 1] */
    double cd[4] = {-0.5, 0.25 + 2.0, -3.0, 1.0};
    n = oc_ccd_cubic_roots(cd, 1e-14, t);
    CHECK(n == 1 && fabs(t[0] - 0.5) < 1e-7, "double root: %d, %g", n, n ? t[0] : -1.0);
    double cn[4] = {1.0, 0.0, 1.0, 0.0};
    CHECK(oc_ccd_cubic_roots(cn, 1e-14, t) == 0, "no root");
    double cz[4] = {0.0, 0.0, 0.0, 0.0};
    CHECK(oc_ccd_cubic_roots(cz, 1e-14, t) == -1, "vanishing cubic");
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
    sweep_grid *g = oc_sweep_grid_create();
    CHECK(g && oc_sweep_grid_build(g, box, N) == 0, "grid built");
    if (!g) return;
    CHECK(oc_sweep_grid_big(g) == 2, "big list: %d boxes (the blown-up and the NaN one)", oc_sweep_grid_big(g));
    int bad = 0, found7 = 0;
    for (int q = 0; q < Q; q++) {
        double qb[6];
        for (int k = 0; k < 3; k++) {
            double lo = rnd(-1.2, 1.2), s = rnd(0.0, q == 0 ? 1e7 : 0.3);
            qb[k] = lo;
            qb[3 + k] = lo + s;
        }
        const int *items;
        int m = oc_sweep_grid_query(g, qb, &items), want[N], nw = 0, got[N];
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
    oc_sweep_grid_destroy(g);
}

int main(void)
{
    case_cubic();
    case_point_triangle();
    case_graze_then_cross();
    case_edge_edge();
    case_grid();
    return check_summary();
}
