/* Plugin: a cloth triangle against a box by separating axes (plugin/src/polytope.c), the geometry of
 * dClothSetExactTriangleTests. Triangles of 1-6 cm placed at random (fixed seed) within 2 cm of a 60 x 40 x
 * 20 cm box, grown by r = 2 cm. For each the query answers, asserted:
 *   - n is a unit vector; the triangle moved by depth along n touches: by 1e-9 m more it is apart, by 1e-6
 *     m less it overlaps by 1e-6 m (to 1e-12);
 *   - apart from the box, its distance r - depth equals the least over a barycentric grid of M steps of each
 *     point's distance to the box (closed form), d_grid: d_grid - D / M <= r - depth <= d_grid + 1e-12, D the
 *     triangle's diameter (the distance is 1-Lipschitz);
 *   - the mirror image (x and y swapped, of a box with equal x and y sides) gives the mirror image: depth to
 *     1e-15 m, n to 1e-12;
 *   - the same box turned and moved (a random rotation R and offset o) answers R v + o alike: the same
 *     depth and R n, to 1e-12 m and 1e-9.
 * And the queries that leave the answer to EPA (0) are fewer than a tenth. The tie merging of the exact tests
 * (dcloth_merge_tie): three triangles' contacts tying at a vertex weigh alike (the mean of their normals,
 * points, gaps and body velocities), the heaviest point's triangle carries it; a tie on another geom, a
 * vertex's own contact or a query left to EPA are not merged. */
#include <math.h>
#include <stdlib.h>

#include <string.h>

#include "check.h"
#include "polytope.h"
#include "triangle_query.h"

#define M 120

static const double HB[3] = {0.3, 0.2, 0.1}, SQ[3] = {0.3, 0.3, 0.1};

static double rnd(unsigned long long *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* distance from p to the box of half sides h at the origin */
static double box_distance(const double h[3], const double p[3])
{
    double s = 0.0;
    for (int k = 0; k < 3; k++) {
        double e = fabs(p[k]) - h[k];
        if (e > 0.0) s += e * e;
    }
    return sqrt(s);
}

static int query(const dcloth_polytope *P, double v[3][3], double r, double *depth, double n[3])
{
    const double *t[3] = {v[0], v[1], v[2]};
    double pos[3];
    return dcloth_polytope_query(P, t, r, depth, n, pos);
}

/* A random rotation (ODE's 3x4 rows) from a unit quaternion */
static void rotation(unsigned long long *seed, double R[12])
{
    double q[4], m = 0.0;
    for (int k = 0; k < 4; k++) {
        q[k] = 2 * rnd(seed) - 1;
        m += q[k] * q[k];
    }
    for (int k = 0; k < 4; k++) q[k] /= sqrt(m);
    double w = q[0], x = q[1], y = q[2], z = q[3];
    const double T[12] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),     0,
                          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),     0,
                          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y), 0};
    for (int k = 0; k < 12; k++) R[k] = T[k];
}

/* the turned and moved box's answer for v (in the box's frame) against depth and n there */
static void check_turned(const dcloth_polytope *T, const double R[12], const double o[3], double v[3][3], double r,
                         double depth, const double n[3], int it, double *worst)
{
    double w[3][3], dt, nt[3];
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < 3; k++)
            w[a][k] = o[k] + R[4 * k] * v[a][0] + R[4 * k + 1] * v[a][1] + R[4 * k + 2] * v[a][2];
    if (!CHECK(query(T, w, r, &dt, nt) == 1, "triangle %d: the turned box's query not answered alike", it)) return;
    double e = 0.0;
    for (int k = 0; k < 3; k++) e += fabs(nt[k] - (R[4 * k] * n[0] + R[4 * k + 1] * n[1] + R[4 * k + 2] * n[2]));
    *worst = fmax(*worst, e);
    CHECK(fabs(dt - depth) <= 1e-12 && e <= 1e-9, "triangle %d: turned box depth %.17g against %.17g, n off by %.3g",
          it, dt, depth, e);
}

static void moved(double v[3][3], const double n[3], double s, double o[3][3])
{
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < 3; k++) o[a][k] = v[a][k] + s * n[k];
}

/* Three contacts tying at one vertex, from triangles 4, 5, 6 (queries 11, 12, 13) on one exact box */
static void check_merge_tie(const dcloth_polytope *box)
{
    struct dxCloth cl;
    memset(&cl, 0, sizeof cl);
    int g1, g2; /* two geoms: only their addresses are compared */
    struct dcloth_surf surf = {(dGeomID)&g1, 0.5, 0.01};
    convex_query q = {.g = (dGeomID)&g1, .surf = &surf, .poly = box}, other = q;
    other.g = (dGeomID)&g2;
    const double n[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, gap[3] = {-1e-3, -1e-3 + 3e-9, -1e-3 - 3e-9};
    const double pt[3][3] = {{3, 0, 0}, {0, 3, 0}, {0, 0, 3}}, vb[3][3] = {{0, 0, 6}, {0, 6, 0}, {6, 0, 0}};
    const double w[3] = {0.3, 0.5, 0.4};
    vcontact vc =
        {.geom = (dGeomID)&g1, .gap = gap[0], .from_triangle = 1, .tri = 4, .query = 11, .weight = w[0], .ties = 1};
    memcpy(vc.normal, n[0], sizeof vc.normal);
    memcpy(vc.tie_sum, n[0], sizeof vc.tie_sum);
    memcpy(vc.point, pt[0], sizeof vc.point);
    memcpy(vc.vbody, vb[0], sizeof vc.vbody);
    vcontact before = vc;
    cl.triangles.query = 12;
    CHECK(!dcloth_merge_tie(&cl, &other, &vc, 5, n[1], gap[1], pt[1], vb[1], w[1]) && !memcmp(&vc, &before, sizeof vc),
          "a tie on another geom merged");
    q.poly = NULL;
    CHECK(!dcloth_merge_tie(&cl, &q, &vc, 5, n[1], gap[1], pt[1], vb[1], w[1]), "a tie left to EPA merged");
    q.poly = box;
    vc.from_triangle = 0;
    CHECK(!dcloth_merge_tie(&cl, &q, &vc, 5, n[1], gap[1], pt[1], vb[1], w[1]), "a vertex's own contact merged");
    vc.from_triangle = 1;
    for (int k = 1; k < 3; k++) {
        cl.triangles.query = 11 + k;
        CHECK(dcloth_merge_tie(&cl, &q, &vc, 4 + k, n[k], gap[k], pt[k], vb[k], w[k]), "tie %d not merged", k);
    }
    double e = 0.0, s = 1.0 / sqrt(3.0);
    for (int r = 0; r < 3; r++)
        e = fmax(e, fmax(fabs(vc.normal[r] - s), fmax(fabs(vc.point[r] - 1.0), fabs(vc.vbody[r] - 2.0))));
    printf("three tied contacts merged: the mean's normal, point and velocity to %.2e, gap %.17g\n", e, vc.gap);
    CHECK(e <= 1e-15, "three ties merged unevenly: normal (%.6f %.6f %.6f), point (%.6f %.6f %.6f)", vc.normal[0],
          vc.normal[1], vc.normal[2], vc.point[0], vc.point[1], vc.point[2]);
    CHECK(fabs(vc.gap + 1e-3) <= 1e-18, "the merged gap %.17g, not the ties' mean -1e-3", vc.gap);
    CHECK(vc.tri == 5 && vc.query == 12 && vc.weight == w[1], "carried by triangle %d (query %u), not 5 (12)", vc.tri,
          vc.query);
}

int main(void)
{
    const double R[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, o[3] = {0, 0, 0}, r = 0.02;
    dcloth_polytope box, sq, turned;
    dcloth_polytope_box(&box, o, R, HB);
    dcloth_polytope_box(&sq, o, R, SQ);
    unsigned long long seed = 18;
    double Rt[12], ot[3] = {0.3, -0.7, 1.1}, worst_turned = 0.0;
    rotation(&seed, Rt);
    dcloth_polytope_box(&turned, ot, Rt, HB);
    int answered = 0, undecided = 0, apart = 0, distances = 0;
    double worst_touch = 0.0, worst_mirror = 0.0;
    for (int it = 0; it < 3000; it++) {
        double v[3][3], c[3], s = 0.01 + 0.05 * rnd(&seed);
        int face = (int)(3 * rnd(&seed)), sign = rnd(&seed) < 0.5 ? -1 : 1;
        const double *h = it % 2 ? SQ : HB;
        for (int k = 0; k < 3; k++) c[k] = (2 * rnd(&seed) - 1) * (h[k] + 0.02);
        c[face] = sign * (h[face] + 0.02 * (2 * rnd(&seed) - 1));
        for (int a = 0; a < 3; a++)
            for (int k = 0; k < 3; k++) v[a][k] = c[k] + s * (2 * rnd(&seed) - 1);
        const dcloth_polytope *P = it % 2 ? &sq : &box;
        double depth, n[3];
        int q = query(P, v, r, &depth, n);
        if (q < 0) {
            apart++;
            continue;
        }
        if (q == 0) {
            undecided++;
            continue;
        }
        answered++;
        if (P == &box) check_turned(&turned, Rt, ot, v, r, depth, n, it, &worst_turned);
        CHECK(fabs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1.0) < 1e-12, "triangle %d: |n| = %.17g", it,
              sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]));
        double w[3][3], d2, n2[3];
        moved(v, n, depth + 1e-9, w);
        int q2 = query(P, w, r, &d2, n2);
        CHECK(q2 < 0 || (q2 == 0) || d2 <= 1e-12, "triangle %d: moved by depth + 1e-9 it still overlaps by %.3g", it,
              d2);
        moved(v, n, depth - 1e-6, w);
        if (query(P, w, r, &d2, n2) > 0) worst_touch = fmax(worst_touch, fabs(d2 - 1e-6));
        if (depth < r) { /* apart: the distance against the grid's */
            double best = INFINITY, diam = 0.0;
            for (int a = 0; a < 3; a++) {
                double e[3] = {v[(a + 1) % 3][0] - v[a][0], v[(a + 1) % 3][1] - v[a][1], v[(a + 1) % 3][2] - v[a][2]};
                diam = fmax(diam, sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]));
            }
            for (int i = 0; i <= M; i++)
                for (int j = 0; i + j <= M; j++) {
                    double p[3];
                    for (int k = 0; k < 3; k++)
                        p[k] = v[0][k] + i * (v[1][k] - v[0][k]) / M + j * (v[2][k] - v[0][k]) / M;
                    best = fmin(best, box_distance(h, p));
                }
            if (best > 0.0) {
                distances++;
                double dist = r - depth;
                CHECK(dist <= best + 1e-12 && dist >= best - diam / M,
                      "triangle %d: distance %.9g, the grid's %.9g (spacing %.3g)", it, dist, best, diam / M);
            }
        }
        if (P == &sq) { /* the mirror image x <-> y */
            double m[3][3], dm, nm[3];
            for (int a = 0; a < 3; a++) m[a][0] = v[a][1], m[a][1] = v[a][0], m[a][2] = v[a][2];
            if (CHECK(query(P, m, r, &dm, nm) == 1, "triangle %d: its mirror image not answered alike", it)) {
                CHECK(fabs(dm - depth) <= 1e-15, "triangle %d: mirror depth %.17g, %.17g", it, dm, depth);
                double e = fabs(nm[0] - n[1]) + fabs(nm[1] - n[0]) + fabs(nm[2] - n[2]);
                worst_mirror = fmax(worst_mirror, e);
                CHECK(e <= 1e-12, "triangle %d: mirror normal off by %.3g", it, e);
            }
        }
    }
    printf("3000 triangles: %d answered (%d distances against the grid), %d apart, %d left to EPA; moved by depth "
           "- 1e-6 m the overlap is 1e-6 m to %.2e; mirror normals to %.2e\n",
           answered, distances, apart, undecided, worst_touch, worst_mirror);
    printf("turned box: normals to %.2e\n", worst_turned);
    check_merge_tie(&box);
    CHECK(worst_touch <= 1e-12, "the overlap after moving by depth - 1e-6 m is off by %.3g", worst_touch);
    CHECK(undecided * 10 < answered, "%d of %d left to EPA", undecided, answered + undecided);
    CHECK(distances > 100, "only %d distances checked", distances);
    return check_summary();
}
