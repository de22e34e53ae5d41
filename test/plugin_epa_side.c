/* Plugin: a cloth triangle grown by its radius just touching a geom (the origin within rounding of the
 * Minkowski difference's face), where EPA's direction can point through the far side of the geom (a
 * triangle lying on a cylinder's top cap answered along -z). dcloth_triangle_penetration must answer
 * the near side or apart, asserted:
 *   - a triangle lying on a turned cylinder's cap (bench_drape's pile scene): apart, or a direction
 *     within 8 degrees of +z no deeper than 1e-6 m;
 *   - triangles at random (fixed seed) over a cylinder's and a box's top (EPA's), grown to touch it within
 *     1e-9 m: every answer apart, or within 8 degrees of +z no deeper than 1e-6 m, where libccd alone
 *     answers some along -z, through the far side (counted, more than none, lest the test test nothing);
 *   - links grown by a radius over a cylinder's and a convex box's top, the same through the edge tests'
 *     own query (dcloth_link_distance). */
#include <math.h>
#include <string.h>

#include "check.h"
#include "edges.h"
#include "geom_support.h"
#include "triangle_query.h"

/* the triangle queries' tight libccd for thickness t */
static ccd_t tight(double t)
{
    ccd_t loose, fine;
    dcloth_triangle_ccd(t, &loose, &fine);
    return fine;
}

/* half: a box's half sides; a cylinder's radius and half length */
static convex_query query_of(dcloth_geom_shape *gs, dGeomID g, const double half[3])
{
    memset(gs, 0, sizeof *gs);
    gs->g = g;
    gs->cls = dGeomGetClass(g);
    memcpy(gs->half, half, sizeof gs->half);
    convex_query q = {.shape = gs, .support = dcloth_geom_support, .center = dcloth_geom_center, .g = g};
    q.cls = gs->cls;
    return q;
}

/* the pile's cylinder and the triangle lying on its cap, 6.375 mm grown (bench_drape --grid 161) */
static void recorded(void)
{
    static const double R[12] = {0.99999996183555884,    -0.00027624861706831885, -3.9474550215327135e-06, 0,
                                 0.00027624860437398758, 0.99999996183818218,     -3.2160101681339615e-06, 0,
                                 3.9483432892520785e-06, 3.214919566456203e-06,   0.99999999998703737,     0};
    static const double v0[3] = {0.17102822139725968, 0.34256683879539152, 0.25652572090211612},
                        v1[3] = {0.17726754589926391, 0.34289116362161731, 0.25671205171573092},
                        v2[3] = {0.17693064373887202, 0.34912512591685985, 0.25637133373386289};
    dGeomID g = dCreateCylinder(0, 0.08, 0.25);
    dGeomSetPosition(g, 0.14997664717076781, 0.28001317125651431, 0.12499599532695142);
    dGeomSetRotation(g, R);
    dcloth_geom_shape gs;
    convex_query q = query_of(&gs, g, (const double[3]){0.08, 0.125, 0.0});
    ccd_t ccd = tight(0.005);
    const double *v[3] = {v0, v1, v2};
    double depth, n[3], pos[3];
    int r = dcloth_triangle_penetration(&q, v, 0.00625 + 0.00012500385384646255, &ccd, &depth, n, pos);
    CHECK(r == -1 || (n[2] >= 0.99 && depth <= 1e-6), "recorded: %d, depth %.3g along (%.3g %.3g %.3g)", r, depth, n[0],
          n[1], n[2]);
    dGeomDestroy(g);
}

static double rnd(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* Random triangles over the top of g (its top at height top, within reach of its axis), grown to touch */
static void touching(dGeomID g, const double half[3], double top, double reach, int trials, uint64_t seed)
{
    dcloth_geom_shape gs;
    convex_query q = query_of(&gs, g, half);
    ccd_t ccd = tight(0.005);
    int far_raw = 0, bad = 0;
    for (int k = 0; k < trials; k++) {
        double p[3][3];
        double cx = (2.0 * rnd(&seed) - 1.0) * reach, cy = (2.0 * rnd(&seed) - 1.0) * reach;
        double z = top + 0.001 + 0.01 * rnd(&seed), lo = INFINITY;
        for (int a = 0; a < 3; a++) {
            p[a][0] = cx + 0.00625 * (2.0 * rnd(&seed) - 1.0);
            p[a][1] = cy + 0.00625 * (2.0 * rnd(&seed) - 1.0);
            p[a][2] = z + 0.0003 * (2.0 * rnd(&seed) - 1.0);
            lo = fmin(lo, p[a][2]);
        }
        const double *v[3] = {p[0], p[1], p[2]};
        double rad = lo - top + 1e-9 * (2.0 * rnd(&seed) - 1.0), depth, n[3], pos[3];
        struct {
            const double *v[3];
            double radius;
        } ts = {{p[0], p[1], p[2]}, rad};
        ccd_real_t d0;
        ccd_vec3_t n0, p0;
        if (ccdGJKPenetration(q.shape, &ts, &ccd, &d0, &n0, &p0) == 0 && n0.v[2] < -0.99) far_raw++;
        if (dcloth_triangle_penetration(&q, v, rad, &ccd, &depth, n, pos) != 0) continue;
        if (n[2] >= 0.99 && depth <= 1e-6) continue;
        if (!bad++) fprintf(stderr, "trial %d: depth %.3g along (%.3g %.3g %.3g)\n", k, depth, n[0], n[1], n[2]);
    }
    printf("class %d: %d of %d through the far side by libccd alone, %d by the query\n", dGeomGetClass(g), far_raw,
           trials, bad);
    CHECK(bad == 0, "class %d: %d answers not up within 8 degrees, at most 1e-6 m deep", dGeomGetClass(g), bad);
    CHECK(far_raw > 0, "class %d: libccd alone answered none through the far side", dGeomGetClass(g));
}

/* Random links over the top of g (at height top, within reach of its axis), grown to touch it */
static void links_touching(dGeomID g, const double half[3], const double *pts, double top, double reach, int trials,
                           uint64_t seed)
{
    dcloth_geom_shape gs;
    convex_query q = query_of(&gs, g, half);
    if (pts) {
        gs.pts = pts;
        gs.npts = 8;
    }
    ccd_t ccd;
    dcloth_link_ccd(0.005, &ccd);
    int far_raw = 0, bad = 0;
    for (int k = 0; k < trials; k++) {
        double a[3], b[3], cx = (2.0 * rnd(&seed) - 1.0) * reach, cy = (2.0 * rnd(&seed) - 1.0) * reach;
        double z = top + 0.001 + 0.01 * rnd(&seed);
        for (int r = 0; r < 2; r++) {
            a[r] = (r ? cy : cx) + 0.00625 * (2.0 * rnd(&seed) - 1.0);
            b[r] = (r ? cy : cx) + 0.00625 * (2.0 * rnd(&seed) - 1.0);
        }
        a[2] = z + 0.0003 * (2.0 * rnd(&seed) - 1.0);
        b[2] = z + 0.0003 * (2.0 * rnd(&seed) - 1.0);
        dcloth_seg_shape sg = {a, b, fmin(a[2], b[2]) - top + 1e-9 * (2.0 * rnd(&seed) - 1.0)};
        ccd_real_t depth;
        ccd_vec3_t n0, p0;
        if (ccdGJKPenetration(q.shape, &sg, &ccd, &depth, &n0, &p0) == 0)
            far_raw += n0.v[2] < -0.99 * sqrt(n0.v[0] * n0.v[0] + n0.v[1] * n0.v[1] + n0.v[2] * n0.v[2]);
        double n[3], d = dcloth_link_distance(&gs, a, b, sg.r, &ccd, n);
        if (d == INFINITY || (n[2] >= 0.99 && sg.r - d <= 1e-6)) continue;
        if (!bad++) fprintf(stderr, "link %d: depth %.3g along (%.3g %.3g %.3g)\n", k, sg.r - d, n[0], n[1], n[2]);
    }
    printf("links, class %d: %d of %d through the far side by libccd alone, %d by the link query\n", dGeomGetClass(g),
           far_raw, trials, bad);
    CHECK(bad == 0, "links, class %d: %d answers not up within 8 degrees, at most 1e-6 m deep", dGeomGetClass(g), bad);
    CHECK(far_raw > 0, "links, class %d: libccd alone answered none through the far side", dGeomGetClass(g));
}

int main(void)
{
    dInitODE2(0);
    recorded();
    dGeomID cyl = dCreateCylinder(0, 0.08, 0.25), box = dCreateBox(0, 0.3, 0.2, 0.15);
    dGeomSetPosition(cyl, 0.0, 0.0, 0.125);
    dGeomSetPosition(box, 0.0, 0.0, 0.075);
    touching(cyl, (const double[3]){0.08, 0.125, 0.0}, 0.25, 0.05, 20000, 7);
    touching(box, (const double[3]){0.15, 0.1, 0.075}, 0.15, 0.08, 20000, 11);
    links_touching(cyl, (const double[3]){0.08, 0.125, 0.0}, NULL, 0.25, 0.05, 20000, 13);
    /* the edge tests' own libccd path: a convex, the box's corners (ODE keeps the arrays) */
    static const dReal planes[24] = {1, 0,  0, 0.15, -1, 0, 0, 0.15,  0, 1, 0,  0.1,
                                     0, -1, 0, 0.1,  0,  0, 1, 0.075, 0, 0, -1, 0.075};
    static dReal pts[24];
    static const unsigned polys[30] = {4, 0, 2, 6, 4, 4, 1, 5, 7, 3, 4, 0, 4, 5, 1,
                                       4, 2, 3, 7, 6, 4, 0, 1, 3, 2, 4, 4, 6, 7, 5};
    for (int k = 0; k < 8; k++) {
        pts[3 * k] = k & 4 ? 0.15 : -0.15;
        pts[3 * k + 1] = k & 2 ? 0.1 : -0.1;
        pts[3 * k + 2] = k & 1 ? 0.075 : -0.075;
    }
    dGeomID cvx = dCreateConvex(0, planes, 6, pts, 8, polys);
    dGeomSetPosition(cvx, 0.0, 0.0, 0.075);
    links_touching(cvx, (const double[3]){0, 0, 0}, pts, 0.15, 0.08, 20000, 17);
    dGeomDestroy(cvx);
    dGeomDestroy(cyl);
    dGeomDestroy(box);
    dCloseODE();
    return check_summary();
}
