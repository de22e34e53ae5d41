/* Unit: the count of intersecting triangle pairs (examples/common/intersections.h).
 *
 *   - the grid's triangles: two per cell, split along the (r, k)-(r+1, k+1)
 *     diagonal, counter-clockwise seen from +z, covering the sheet;
 *   - closed form: an N x N node grid (spacing 1, plane z = 0) crossed by a
 *     two-triangle rectangle standing in the plane x = k + f. The plane cuts
 *     both triangles of the N - 1 cells of column k: 2 (N - 1) pairs with
 *     the rectangle's triangle on their side of its diagonal, and one more
 *     where the diagonal passes through a cut triangle: 2N - 1 pairs; the
 *     vertices are columns k and k + 1 (2N) and the rectangle's 4: 2N + 4.
 *     The same after a rigid motion;
 *   - no crossing: a flat sheet, the sheet moved rigidly far from the
 *     origin, folded flat in three (touching layers) and moved rigidly,
 *     wrapped on a cylinder, rolled into a spiral, waved;
 *   - crumpled grids: the grid search gives the pairs and the marked
 *     vertices of testing every pair (brute force);
 *   - bad input (an index out of range, a NaN) is refused.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "intersections.h"
#include "check.h"

#define MAXN 41

static double xs[3 * (MAXN * MAXN + 4)];
static int tris[3 * (2 * (MAXN - 1) * (MAXN - 1) + 2)];
static unsigned char mark[MAXN * MAXN + 4], mark_b[MAXN * MAXN + 4];

/* An n x n grid at spacing s in the plane z = 0; returns its triangles. */
static int flat_grid(int n, double s)
{
    for (int r = 0; r < n; r++)
        for (int k = 0; k < n; k++) {
            double *p = xs + 3 * (r * n + k);
            p[0] = k * s, p[1] = r * s, p[2] = 0.0;
        }
    return intersections_grid_triangles(n, n, tris);
}

/* x -> Q x + t with Q a rotation about a random unit axis by angle a. */
static void rigid_motion(rng *g, int nv, double a, const double t[3])
{
    double u[3];
    rng_unit_vector(g, u);
    double c = cos(a), s = sin(a), Q[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) Q[i][j] = (i == j ? c : 0.0) + (1.0 - c) * u[i] * u[j];
    Q[0][1] -= s * u[2], Q[0][2] += s * u[1], Q[1][0] += s * u[2];
    Q[1][2] -= s * u[0], Q[2][0] -= s * u[1], Q[2][1] += s * u[0];
    for (int v = 0; v < nv; v++) {
        double *p = xs + 3 * v, q[3];
        for (int i = 0; i < 3; i++) q[i] = Q[i][0] * p[0] + Q[i][1] * p[1] + Q[i][2] * p[2] + t[i];
        memcpy(p, q, sizeof q);
    }
}

static void check_grid_triangles(void)
{
    int n = 7, nt = flat_grid(n, 1.0);
    double area = 0.0;
    CHECK(nt == 2 * (n - 1) * (n - 1), "%d triangles", nt);
    for (int t = 0; t < nt; t++) {
        const int *p = tris + 3 * t, cell = t / 2, a = (cell / (n - 1)) * n + cell % (n - 1);
        const double *x0 = xs + 3 * p[0], *x1 = xs + 3 * p[1], *x2 = xs + 3 * p[2];
        double cz = (x1[0] - x0[0]) * (x2[1] - x0[1]) - (x1[1] - x0[1]) * (x2[0] - x0[0]);
        int has_a = 0, has_d = 0;
        for (int i = 0; i < 3; i++) has_a |= p[i] == a, has_d |= p[i] == a + n + 1;
        CHECK(has_a && has_d && cz > 0.0, "triangle %d (%d %d %d): diagonal or orientation", t, p[0], p[1], p[2]);
        area += 0.5 * cz;
    }
    CHECK_NEAR(area, (n - 1.0) * (n - 1.0), 1e-12);
}

/* The closed form: an n-node grid crossed at x = k + f by a rectangle from
 * y = -1 to n, its diagonal from z = -1 to z = z1. */
static void check_rectangle(int n, int k, double f, double z1, rng *g)
{
    int nt = flat_grid(n, 1.0), nv = n * n;
    double c = k + f, ys = -1.0 + (n + 1.0) / (1.0 + z1); /* where the diagonal meets z = 0 */
    double rect[4][3] = {{c, -1.0, -1.0}, {c, n, -1.0}, {c, n, z1}, {c, -1.0, z1}};
    double frac = ys - floor(ys);
    /* generic: the diagonal meets no cut triangle's edge */
    CHECK(fabs(frac) > 1e-3 && fabs(frac - f) > 1e-3 && fabs(frac - 1.0) > 1e-3 && ys > 0.0 && ys < n - 1.0,
          "n %d f %g: diagonal at y %g is not generic", n, f, ys);
    memcpy(xs + 3 * nv, rect, sizeof rect);
    int *r = tris + 3 * nt;
    r[0] = nv, r[1] = nv + 1, r[2] = nv + 2, r[3] = nv, r[4] = nv + 2, r[5] = nv + 3;
    for (int moved = 0; moved < 2; moved++) {
        if (moved) rigid_motion(g, nv + 4, rng_range(g, 0.1, 3.0), (double[3]){3.0, -40.0, 7.0});
        intersections is;
        CHECK(intersections_count(xs, nv + 4, tris, nt + 2, &is, mark) == 0, "count failed");
        CHECK(is.pairs == 2 * n - 1 && is.vertices == 2 * n + 4,
              "n %d k %d f %g moved %d: %ld pairs, %d vertices; expected %d, %d", n, k, f, moved, is.pairs, is.vertices,
              2 * n - 1, 2 * n + 4);
        int wrong = 0;
        for (int v = 0; v < nv + 4; v++) wrong += mark[v] != (v >= nv || v % n == k || v % n == k + 1);
        CHECK(wrong == 0, "n %d k %d: %d vertices marked wrongly", n, k, wrong);
    }
}

static long count_pairs(int nv, int nt)
{
    intersections is;
    if (intersections_count(xs, nv, tris, nt, &is, mark)) return -1;
    return is.pairs;
}

/* A sheet folded in three (accordion, layers `gap` apart), then every vertex
 * moved by up to `noise` on each axis. */
static void crumple(rng *g, int n, double gap, double noise)
{
    flat_grid(n, 1.0 / (n - 1));
    for (int v = 0; v < n * n; v++) {
        double *p = xs + 3 * v, u = 3.0 * p[0];
        int layer = u < 1.0 ? 0 : u < 2.0 ? 1 : 2;
        double w = layer == 1 ? 2.0 - u : u - layer; /* back and forth */
        p[0] = w / 3.0, p[2] = layer * gap;
        for (int a = 0; a < 3; a++) p[a] += rng_range(g, -noise, noise);
    }
}

static void check_no_crossing(rng *g)
{
    int n = MAXN, nv = n * n, nt = flat_grid(n, 0.025);
    CHECK(count_pairs(nv, nt) == 0, "flat sheet crosses itself");
    for (int i = 0; i < 20; i++) {
        double t[3] = {rng_range(g, -100, 100), rng_range(g, -100, 100), rng_range(g, -100, 100)};
        flat_grid(n, 0.025);
        rigid_motion(g, nv, rng_range(g, 0.0, 3.14), t);
        long p = count_pairs(nv, nt);
        CHECK(p == 0, "flat sheet moved rigidly (%d, offset %.0f %.0f %.0f) crosses itself: %ld pairs", i, t[0], t[1],
              t[2], p);
    }
    /* folded flat in three (layers touching, none crossing), moved rigidly:
     * rounding alone puts the layers' points either side of each other */
    for (int i = 0; i < 5; i++) {
        double t[3] = {rng_range(g, -10, 10), rng_range(g, -10, 10), rng_range(g, -10, 10)};
        crumple(g, n, 0.0, 0.0);
        rigid_motion(g, nv, rng_range(g, 0.1, 3.0), t);
        long p = count_pairs(nv, nt);
        CHECK(p == 0, "sheet folded flat, moved rigidly (%d) crosses itself: %ld pairs", i, p);
    }
    /* the 1 m sheet wrapped 0.95 times round a cylinder, its ends 5 cm apart */
    flat_grid(n, 0.025);
    double rc = 1.0 / (0.95 * 2.0 * M_PI);
    for (int v = 0; v < nv; v++) {
        double *p = xs + 3 * v, a = p[0] / rc;
        p[0] = rc * sin(a), p[2] = rc * (1.0 - cos(a));
    }
    CHECK(count_pairs(nv, nt) == 0, "cylinder crosses itself");
    /* a spiral r = 0.05 + 0.02 theta / (2 pi): turns 2 cm apart, spacing 2.5 cm along it */
    flat_grid(n, 0.025);
    for (int v = 0; v < nv; v++) {
        double *p = xs + 3 * v, s = p[0], th = 0.0;
        /* arc length to angle, by small steps */
        for (double l = 0.0; l < s; th += 1e-3) l += 1e-3 * hypot(0.05 + 0.02 * th / (2 * M_PI), 0.02 / (2 * M_PI));
        double rad = 0.05 + 0.02 * th / (2 * M_PI);
        p[0] = rad * cos(th), p[2] = rad * sin(th);
    }
    CHECK(count_pairs(nv, nt) == 0, "spiral crosses itself");
    flat_grid(n, 0.025);
    for (int v = 0; v < nv; v++) xs[3 * v + 2] = 0.05 * sin(9.0 * xs[3 * v]) * cos(13.0 * xs[3 * v + 1]);
    CHECK(count_pairs(nv, nt) == 0, "waved sheet crosses itself");
}

static void check_against_brute_force(rng *g)
{
    static const struct {
        int n;
        double gap, noise;
    } cases[] = {{21, 0.02, 0.0125}, {21, 0.01, 0.012}, {21, 0.002, 0.03}, {41, 0.01, 0.008}, {41, 0.0, 0.02}};
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        int n = cases[c].n, nv = n * n, nt = 2 * (n - 1) * (n - 1);
        crumple(g, n, cases[c].gap, cases[c].noise);
        intersections is;
        CHECK(intersections_count(xs, nv, tris, nt, &is, mark) == 0, "count failed");
        long brute = 0;
        memset(mark_b, 0, (size_t)nv);
        for (int a = 0; a < nt; a++)
            for (int b = a + 1; b < nt; b++)
                if (intersections_pair(xs, tris + 3 * a, tris + 3 * b)) {
                    brute++;
                    for (int k = 0; k < 3; k++) mark_b[tris[3 * a + k]] = mark_b[tris[3 * b + k]] = 1;
                }
        printf("crumple %zu (%dx%d, gap %g, noise %g): %ld pairs (every pair: %ld), %d vertices\n", c, n, n,
               cases[c].gap, cases[c].noise, is.pairs, brute, is.vertices);
        CHECK(brute > 0, "crumple %zu: no crossing to compare", c);
        CHECK(is.pairs == brute, "crumple %zu: grid %ld pairs, every pair %ld", c, is.pairs, brute);
        CHECK(memcmp(mark, mark_b, (size_t)nv) == 0, "crumple %zu: marked vertices differ", c);
    }
}

static void check_bad_input(void)
{
    int nt = flat_grid(3, 1.0);
    intersections is = {5, 5};
    tris[4] = 9;
    CHECK(intersections_count(xs, 9, tris, nt, &is, mark) == -1 && is.pairs == 0, "index 9 of 9 accepted");
    tris[4] = -1;
    CHECK(intersections_count(xs, 9, tris, nt, &is, NULL) == -1, "index -1 accepted");
    flat_grid(3, 1.0);
    xs[7] = NAN;
    CHECK(intersections_count(xs, 9, tris, nt, &is, mark) == -1, "NaN accepted");
    flat_grid(3, 1.0);
    CHECK(intersections_count(xs, 9, tris, 0, &is, mark) == 0 && is.pairs == 0 && is.vertices == 0, "no triangles");
    int shared[6] = {0, 1, 4, 4, 2, 8};
    CHECK(!intersections_pair(xs, shared, shared + 3), "pair sharing a vertex counted");
}

int main(void)
{
    rng g = rng_seed(19);
    check_grid_triangles();
    check_rectangle(10, 4, 0.3, 1.5, &g);
    check_rectangle(11, 4, 0.3, 1.5, &g);
    check_rectangle(3, 0, 0.71, 0.9, &g);
    check_rectangle(25, 23, 0.55, 2.2, &g);
    check_no_crossing(&g);
    check_against_brute_force(&g);
    check_bad_input();
    return check_summary();
}
