/* Plugin: a cloth's link cannot pass a body's edge.
 *
 * A 9 x 9 cloth, 0.4 m (spacing S = 5 cm), thickness T = 5 mm, is dropped
 * flat from 3 cm above a static bar (1 m along x, BAR = 2 cm square, its top
 * at z = 0) lying across its middle between two rows, which are S / 2 either
 * side of the bar's axis: the bar with its shell (BAR / 2 + T = 1.5 cm) fits
 * between them, so vertex contacts alone let both rows fall past it and the
 * link joining them through it. The bar's triangle tests are off, so only
 * the links' tests against its edges (plugin/src/edges.c) can hold it; as
 * ODE's box geom, the same box in 12 triangles and as a convex (its points
 * handed over); the default (linearised) step and Newton's. Stepped at
 * 1/60 s for 1.5 s.
 *
 * Pinned (Newton, box geom and mesh): the cloth lies at the thickness
 * under a kinematic bar W = 4 cm wide, its first row pinned to the bar under
 * its axis, the rest reaching out past its edge, the cloth's gravity pointing
 * up. The link from the pinned row starts level, as far from the bar's lower
 * edge as from its underside (a tie), and must not swing up through the edge
 * as the free cloth rises beside the bar.
 *
 * Asserted, every step: the step succeeds and no sequential link, both its
 * ends outside the bar, has its segment through the bar (a slab test in the
 * bar's frame). At the end the cloth hangs on the bar: its highest vertex is
 * above the bar's bottom (falling free from 3 cm for 1.5 s would put it 11 m
 * below); pinned, it has risen above the bar's underside beside the bar. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define N 9
#define SIDE 0.4
#define BAR 0.02
#define BAR_LEN 1.0
#define DROP 0.03
#define STEPS 90
#define W 0.04
#define T 0.005

typedef struct result {
    int failed_step;
    int crossings;  /* link-steps through the bar */
    int first_step; /* the first step with one, -1 if none */
    double top;     /* the highest vertex at the end */
    long newton;    /* Newton iterations over the run */
} result;

/* Whether segment [a, b] passes through the box of half sides e centred at
 * the origin (axis-aligned), neither end inside it. */
static int through_box(const double *a, const double *b, const double e[3])
{
    int ina = 1, inb = 1;
    for (int k = 0; k < 3; k++) {
        ina = ina && fabs(a[k]) < e[k];
        inb = inb && fabs(b[k]) < e[k];
    }
    if (ina || inb) return 0;
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < 3; k++) {
        double d = b[k] - a[k];
        if (d == 0.0) {
            if (fabs(a[k]) >= e[k]) return 0;
            continue;
        }
        double u0 = (-e[k] - a[k]) / d, u1 = (e[k] - a[k]) / d;
        if (u0 > u1) {
            double t = u0;
            u0 = u1, u1 = t;
        }
        t0 = fmax(t0, u0), t1 = fmin(t1, u1);
        if (t0 > t1) return 0;
    }
    return 1;
}

/* The bar as a convex (ODE's dConvex, half sides e): its points (handed to
 * the cloth), planes and faces */
static dReal cvx_points[24], cvx_planes[24];
static const unsigned int cvx_polys[30] = {4, 1, 3, 7, 5, 4, 0, 4, 6, 2, 4, 2, 6, 7, 3,
                                           4, 0, 1, 5, 4, 4, 4, 5, 7, 6, 4, 0, 2, 3, 1};

static dGeomID convex_bar(dSpaceID sp, const double e[3])
{
    for (int i = 0; i < 8; i++)
        for (int k = 0; k < 3; k++) cvx_points[3 * i + k] = (i >> k & 1) ? e[k] : -e[k];
    for (int f = 0; f < 6; f++) {
        int k = f / 2;
        for (int r = 0; r < 3; r++) cvx_planes[4 * f + r] = r == k ? (f & 1 ? -1.0 : 1.0) : 0.0;
        cvx_planes[4 * f + 3] = e[k];
    }
    return dCreateConvex(sp, cvx_planes, 6, cvx_points, 8, cvx_polys);
}

/* The pinned scene's cloth: its gravity up, the row under the bar's axis
 * pinned to the bar's kinematic body */
static void pin_under(dWorldID w, dClothID c, dGeomID bar, double centre_z)
{
    dBodyID body = dBodyCreate(w);
    dBodySetKinematic(body);
    dGeomSetBody(bar, body);
    dBodySetPosition(body, 0, 0, centre_z);
    const double up[3] = {0, 0, 9.81};
    CHECK(cloth_set_gravity(dClothGetCore(c), up) == CLOTH_OK, "cloth_set_gravity");
    const dReal *x = dClothGetPositions(c);
    for (int i = 0; i < N * N; i++) {
        if (fabs(x[3 * i + 1]) > 1e-9) continue;
        const dReal local[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2] - centre_z};
        CHECK(dClothPinToBody(c, i, body, local) == CLOTH_OK, "dClothPinToBody: %s", dClothGetLastError(c));
    }
}

/* kind: 0 box geom, 1 box mesh, 2 convex; pinned: the scene under the bar */
static result run(int kind, int newton, int pinned)
{
    result r = {-1, 0, -1, -INFINITY, 0};
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    const double side = pinned ? W : BAR, centre_z = pinned ? 0.5 * W : -0.5 * BAR;
    const double e[3] = {0.5 * BAR_LEN, 0.5 * side, 0.5 * side};
    static dReal bv[24];
    static dTriIndex bt[36];
    dTriMeshDataID md = 0;
    dGeomID bar = kind == 2 ? convex_bar(sp, e) : box_geom(sp, e, kind, bv, bt, &md);
    dGeomSetPosition(bar, 0, 0, centre_z);
    const double u[3] = {1, 0, 0}, v[3] = {0, 1, 0}, spacing = SIDE / (N - 1);
    /* the bar between the middle rows, or over the first */
    const double centre[3] = {0, pinned ? 0.5 * SIDE : 0.5 * spacing, pinned ? -T : DROP};
    dClothID c = flat_cloth(w, sp, N, SIDE, centre, u, v, 0.3, T);
    if (!c) return r;
    if (pinned) pin_under(w, c, bar, centre_z);
    CHECK(dClothSetTriangleTests(c, bar, 0) == CLOTH_OK, "dClothSetTriangleTests: %s", dClothGetLastError(c));
    if (kind == 2)
        CHECK(dClothSetConvexPoints(c, bar, cvx_points, 8) == CLOTH_OK, "dClothSetConvexPoints: %s",
              dClothGetLastError(c));
    cloth_solver sv = cloth_get_desc(dClothGetCore(c)).solver;
    sv.nonlinear = newton ? CLOTH_NEWTON : CLOTH_LINEARIZED;
    CHECK(cloth_set_solver(dClothGetCore(c), &sv) == CLOTH_OK, "cloth_set_solver");
    const double h = 1.0 / 60.0;
    const int nl = cloth_link_count(dClothGetCore(c), CLOTH_SEQUENTIAL);
    for (int s = 0; s < STEPS; s++) {
        if (dClothWorldStep(w, &c, 1, h, 0) != CLOTH_OK) {
            r.failed_step = s;
            printf("    step %d: %s\n", s, dClothGetLastError(c));
            break;
        }
        r.newton += dClothGetStats(c)->newton_all;
        const dReal *x = dClothGetPositions(c);
        for (int k = 0; k < nl; k++) {
            cloth_link L;
            cloth_get_link(dClothGetCore(c), CLOTH_SEQUENTIAL, k, &L);
            double a[3] = {x[3 * L.i], x[3 * L.i + 1], x[3 * L.i + 2] - centre_z};
            double b[3] = {x[3 * L.j], x[3 * L.j + 1], x[3 * L.j + 2] - centre_z};
            if (!through_box(a, b, e)) continue;
            r.crossings++;
            if (r.first_step < 0) r.first_step = s;
        }
    }
    const dReal *x = dClothGetPositions(c);
    for (int i = 0; i < N * N; i++) r.top = fmax(r.top, x[3 * i + 2]);
    dClothDestroy(c);
    dSpaceDestroy(sp);
    if (md) dGeomTriMeshDataDestroy(md);
    dWorldDestroy(w);
    return r;
}

int main(void)
{
    dInitODE2(0);
    for (int newton = 0; newton < 2; newton++)
        for (int kind = 0; kind < 3; kind++) {
            const char *what[3] = {"box geom", "box mesh", "convex"};
            char name[64];
            snprintf(name, sizeof name, "%s, %s", what[kind], newton ? "Newton" : "linearised");
            result r = run(kind, newton, 0);
            printf("%-22s: %d link-steps through the bar (first at step %d); highest vertex at the end %+.1f mm%s\n",
                   name, r.crossings, r.first_step, 1e3 * r.top, r.failed_step >= 0 ? "; a step failed" : "");
            CHECK(r.failed_step < 0, "%s: step %d failed", name, r.failed_step);
            CHECK((r.newton > 0) == newton, "%s: %ld Newton iterations", name, r.newton);
            CHECK(r.crossings == 0, "%s: %d link-steps through the bar, the first at step %d", name, r.crossings,
                  r.first_step);
            CHECK(r.top > -BAR, "%s: the cloth fell off or through the bar (highest vertex %.3f m)", name, r.top);
        }
    for (int kind = 0; kind < 2; kind++) {
        const char *name = kind ? "pinned, box mesh" : "pinned, box geom";
        result r = run(kind, 1, 1);
        printf("%-22s: %d link-steps through the bar (first at step %d); highest vertex at the end %+.1f mm%s\n", name,
               r.crossings, r.first_step, 1e3 * r.top, r.failed_step >= 0 ? "; a step failed" : "");
        CHECK(r.failed_step < 0, "%s: step %d failed", name, r.failed_step);
        CHECK(r.crossings == 0, "%s: %d link-steps through the bar, the first at step %d", name, r.crossings,
              r.first_step);
        CHECK(r.top > 0.0, "%s: the cloth did not rise beside the bar (highest vertex %.3f m)", name, r.top);
    }
    return check_summary();
}
