/* Plugin: contact parameters per geom (dClothSetSurfaceCallback): each
 * geom's friction and contact distance (thickness) from the user's
 * callback, the cloth's own where it gives none or an invalid one.
 *
 * Scenes (gravity -9.81 z, h = 1/60 s, cloth 21 x 21 nodes, 1 m, cotton,
 * thickness 5 mm, mu 0.3, unless said):
 *
 * 1. Unchanged: a cloth dropped 5 cm onto a turned box and a sphere (vertex
 *    and triangle contacts) for 1.5 s. Its positions are bitwise those of
 *    the same run with a callback that leaves the surface as given, and
 *    with one that answers only invalid values (mu NaN, -1; thickness NaN,
 *    -0.01, 1e-9, 1e3).
 * 2. Thickness per geom: two boxes side by side, tops at z = 0, a 10 cm
 *    gap between them; the callback gives box A 0.02 m and box B 0.005 m.
 *    After 2 s, every vertex in contact with a box and more than 15 cm from
 *    the gap rests at that box's thickness above its top within 10% of it:
 *    a resting vertex is held on its shell, left free only while it is
 *    predicted within DCLOTH_CONTACT_SLOP (0.1) of the thickness of it, and
 *    held again when it ends deeper than RESOLVE_DEPTH (0.1) inside.
 * 3. Friction per geom: the cloth at rest on a plane tilted 20 degrees
 *    (tan = 0.36), its own mu 0.3. The plane's mu 1 from the callback: it
 *    stays put (under 1 mm in 1 s); mu 0: it slides as frictionless,
 *    g sin(theta) t (t + h) / 2 (backward Euler) within 1%. dClothSetFrictionCallback alone
 *    still holds it (mu 1); setting the surface callback after it clears it
 *    (then the cloth's 0.3: slides).
 * 4. Field by field: the callback's mu NaN and thickness 0.02 on the slope,
 *    the cloth's mu 1: stays put (mu kept) and rests 0.02 above the plane
 *    (thickness taken); then the callback NULL: the cloth settles back to
 *    0.005 within 1 s.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define G 9.81
#define H (1.0 / 60.0)
#define N 21
#define THICK 0.005

static dClothID make_cloth(dWorldID w, dSpaceID s, double L, const double centre[3], const double u[3],
                           const double v[3], double mu)
{
    return flat_cloth(w, s, N, L, centre, u, v, mu, THICK);
}

static int run(dWorldID w, dClothID c, double seconds, const char *what)
{
    int steps = (int)(seconds / H + 0.5);
    for (int k = 0; k < steps; k++)
        if (!CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "%s: step %d failed: %s", what, k,
                   dClothGetLastError(c)))
            return 0;
    return 1;
}

/* ---------------------------------------------------------- callbacks */

/* leaves the surface as given */
static void same(void *data, dClothID c, dGeomID g, dClothSurface *s) { (void)data, (void)c, (void)g, (void)s; }

/* only invalid values, a different pair at each call */
static void invalid(void *data, dClothID c, dGeomID g, dClothSurface *s)
{
    static const double mu[] = {NAN, -1.0, -INFINITY, INFINITY};
    static const double t[] = {NAN, -0.01, 1e-9, 1e3, 0.0};
    int *k = data;
    (void)c, (void)g;
    s->mu = mu[*k % 4];
    s->thickness = t[*k % 5];
    ++*k;
}

/* per geom: a's surface for geom a, b's for the others */
typedef struct two_surfaces {
    dGeomID a;
    dClothSurface sa, sb;
} two_surfaces;
static void per_geom(void *data, dClothID c, dGeomID g, dClothSurface *s)
{
    const two_surfaces *t = data;
    (void)c;
    *s = g == t->a ? t->sa : t->sb;
}

static void mu_only(void *data, dClothID c, dGeomID g, dReal *mu)
{
    (void)c, (void)g;
    *mu = *(const double *)data;
}

/* ------------------------------------------------------------ 1. same */

/* the drop onto a box and a sphere: positions into x (3 N N) */
static int drop(dClothSurfaceFn *fn, void *data, double *x)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -G);
    dSpaceID s = dHashSpaceCreate(0);
    dGeomID box = dCreateBox(s, 0.4, 0.4, 0.2);
    dGeomSetPosition(box, -0.2, 0, -0.1);
    dMatrix3 R;
    dRFromAxisAndAngle(R, 0, 0, 1, 0.3);
    dGeomSetRotation(box, R);
    dGeomID ball = dCreateSphere(s, 0.15);
    dGeomSetPosition(ball, 0.25, 0, -0.12);
    double centre[3] = {0, 0, 0.05}, u[3] = {1, 0, 0}, v[3] = {0, 1, 0};
    dClothID c = make_cloth(w, s, 1.0, centre, u, v, 0.3);
    int ok = 0;
    if (c) {
        if (fn) dClothSetSurfaceCallback(c, fn, data);
        ok = run(w, c, 1.5, "drop");
        memcpy(x, dClothGetPositions(c), 3 * N * N * sizeof *x);
        ok = ok && CHECK(dClothGetStats(c)->contacts > 0, "drop: no contacts at the end");
        dClothDestroy(c);
    }
    dSpaceDestroy(s);
    dWorldDestroy(w);
    return ok;
}

static void unchanged(void)
{
    static double x0[3 * N * N], x1[3 * N * N], x2[3 * N * N];
    int calls = 0;
    int ok = drop(NULL, NULL, x0) && drop(same, NULL, x1) && drop(invalid, &calls, x2);
    printf("unchanged: no callback vs one leaving the surface: %s; vs invalid answers only (%d calls): %s\n",
           memcmp(x0, x1, sizeof x0) ? "differ" : "bitwise equal", calls,
           memcmp(x0, x2, sizeof x0) ? "differ" : "bitwise equal");
    CHECK(ok, "unchanged: a run failed");
    CHECK(memcmp(x0, x1, sizeof x0) == 0, "a callback leaving the surface changed the run");
    CHECK(calls > 0 && memcmp(x0, x2, sizeof x0) == 0, "invalid answers changed the run (%d calls)", calls);
}

/* ------------------------------------------------------- 2. thickness */

static void thickness_per_geom(void)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -G);
    dSpaceID s = dHashSpaceCreate(0);
    dGeomID a = dCreateBox(s, 0.5, 1.2, 0.2), b = dCreateBox(s, 0.5, 1.2, 0.2);
    dGeomSetPosition(a, -0.3, 0, -0.1);
    dGeomSetPosition(b, 0.3, 0, -0.1);
    two_surfaces ts = {a, {0.3, 0.02}, {0.3, 0.005}};
    double centre[3] = {0, 0, 0.03}, u[3] = {1, 0, 0}, v[3] = {0, 1, 0};
    dClothID c = make_cloth(w, s, 1.0, centre, u, v, 0.3);
    if (c) {
        dClothSetSurfaceCallback(c, per_geom, &ts);
        if (run(w, c, 2.0, "two boxes")) {
            const dReal *x = dClothGetPositions(c);
            double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
            int count[2] = {0, 0};
            for (int i = 0; i < N * N; i++) {
                dGeomID g;
                dClothGetVertexContact(c, i, &g, NULL, NULL);
                int k = g == a ? 0 : g == b ? 1 : -1;
                if (k < 0 || fabs(x[3 * i]) < 0.2) continue;
                lo[k] = fmin(lo[k], x[3 * i + 2]);
                hi[k] = fmax(hi[k], x[3 * i + 2]);
                count[k]++;
            }
            double want[2] = {ts.sa.thickness, ts.sb.thickness};
            for (int k = 0; k < 2; k++) {
                printf("thickness %.3f m: %d vertices at %.5f .. %.5f m above the top\n", want[k], count[k], lo[k],
                       hi[k]);
                CHECK(count[k] >= 50, "box %c: only %d vertices in contact", 'A' + k, count[k]);
                CHECK(fabs(lo[k] - want[k]) <= 0.1 * want[k] && fabs(hi[k] - want[k]) <= 0.1 * want[k],
                      "box %c: vertices at %.5f .. %.5f m, want %.3f within 10%%", 'A' + k, lo[k], hi[k], want[k]);
            }
        }
        dClothDestroy(c);
    }
    dSpaceDestroy(s);
    dWorldDestroy(w);
}

/* ------------------------------------------------------------ 3. slope */

#define THETA (20.0 * 3.14159265358979323846 / 180.0)

/* The cloth (mu) at rest on a plane tilted by THETA about y for T seconds,
 * with the callbacks set by `setup`; how far it moved down the slope, and
 * its least and largest height above the plane in *lo, *hi */
typedef void setup_fn(dClothID c, dGeomID plane, void *data);
static double slope(double mu, double T, setup_fn *setup, void *data, double *lo, double *hi)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -G);
    dSpaceID s = dSimpleSpaceCreate(0);
    double n[3] = {sin(THETA), 0, cos(THETA)}, down[3] = {cos(THETA), 0, -sin(THETA)}, across[3] = {0, 1, 0};
    dGeomID plane = dCreatePlane(s, n[0], n[1], n[2], 0);
    double centre[3] = {THICK * n[0], THICK * n[1], THICK * n[2]};
    dClothID c = make_cloth(w, s, 0.5, centre, down, across, mu);
    double moved = NAN;
    if (c) {
        const dReal *x = dClothGetPositions(c);
        double x0 = x[3 * (N * N / 2)] * down[0] + x[3 * (N * N / 2) + 2] * down[2];
        if (setup) setup(c, plane, data);
        if (run(w, c, T, "slope")) {
            x = dClothGetPositions(c);
            moved = x[3 * (N * N / 2)] * down[0] + x[3 * (N * N / 2) + 2] * down[2] - x0;
            *lo = INFINITY, *hi = -INFINITY;
            for (int i = 0; i < N * N; i++) {
                double d = x[3 * i] * n[0] + x[3 * i + 2] * n[2];
                *lo = fmin(*lo, d);
                *hi = fmax(*hi, d);
            }
        }
        dClothDestroy(c);
    }
    dSpaceDestroy(s);
    dWorldDestroy(w);
    return moved;
}

static void set_surface(dClothID c, dGeomID plane, void *data)
{
    two_surfaces *t = data;
    t->a = plane;
    dClothSetSurfaceCallback(c, per_geom, t);
}
static void set_friction(dClothID c, dGeomID plane, void *data)
{
    (void)plane;
    dClothSetFrictionCallback(c, mu_only, data);
}
static void set_friction_then_surface(dClothID c, dGeomID plane, void *data)
{
    static double one = 1.0;
    set_friction(c, plane, &one);
    set_surface(c, plane, data);
}

static void friction_per_geom(void)
{
    /* frictionless over 1 s of backward Euler steps: a h^2 n (n + 1) / 2 */
    double lo, hi, free_fall = 0.5 * G * sin(THETA) * 1.0 * (1.0 + H);
    two_surfaces grip = {0, {1.0, THICK}, {0.3, THICK}}, ice = {0, {0.0, THICK}, {0.3, THICK}};
    two_surfaces same_surface = {0, {0.3, THICK}, {0.3, THICK}};
    double one = 1.0;
    double m_grip = slope(0.3, 1.0, set_surface, &grip, &lo, &hi);
    double m_ice = slope(0.3, 1.0, set_surface, &ice, &lo, &hi);
    double m_fric = slope(0.3, 1.0, set_friction, &one, &lo, &hi);
    double m_clear = slope(0.3, 1.0, set_friction_then_surface, &same_surface, &lo, &hi);
    printf("slope %.0f deg, 1 s: plane mu 1 moved %.3g m, mu 0 %.4f m (frictionless %.4f); friction callback "
           "mu 1 %.3g m; it cleared by the surface callback (cloth mu 0.3) %.4f m\n",
           THETA * 180 / 3.14159265358979323846, m_grip, m_ice, free_fall, m_fric, m_clear);
    CHECK(fabs(m_grip) < 1e-3, "plane mu 1: moved %.3g m", m_grip);
    CHECK(fabs(m_ice - free_fall) <= 0.01 * free_fall, "plane mu 0: moved %.4f m, want %.4f", m_ice, free_fall);
    CHECK(fabs(m_fric) < 1e-3, "friction callback mu 1: moved %.3g m", m_fric);
    CHECK(m_clear > 0.05, "the surface callback did not clear the friction callback: moved %.3g m", m_clear);
}

/* ------------------------------------------------------ 4. field by field */

static void set_then_clear(dClothID c, dGeomID plane, void *data)
{
    (void)plane;
    dClothSetSurfaceCallback(c, per_geom, data);
}

static void field_by_field(void)
{
    double lo, hi;
    two_surfaces nan_mu = {0, {NAN, 0.02}, {NAN, 0.02}};
    double moved = slope(1.0, 1.5, set_then_clear, &nan_mu, &lo, &hi);
    printf("mu NaN, thickness 0.02 (cloth mu 1): moved %.3g m, %.5f .. %.5f m above the plane\n", moved, lo, hi);
    CHECK(fabs(moved) < 1e-3, "a NaN mu was not ignored: moved %.3g m", moved);
    CHECK(fabs(lo - 0.02) <= 0.002 && fabs(hi - 0.02) <= 0.002, "thickness 0.02 not taken: %.5f .. %.5f m", lo, hi);

    /* the same, then the callback NULL: back to the cloth's 5 mm */
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -G);
    dSpaceID s = dSimpleSpaceCreate(0);
    dCreatePlane(s, 0, 0, 1, 0);
    double centre[3] = {0, 0, THICK}, u[3] = {1, 0, 0}, v[3] = {0, 1, 0};
    dClothID c = make_cloth(w, s, 0.5, centre, u, v, 0.3);
    if (c) {
        dClothSetSurfaceCallback(c, per_geom, &nan_mu);
        double z1 = NAN, z2 = NAN;
        if (run(w, c, 1.0, "thick")) z1 = dClothGetPositions(c)[3 * (N * N / 2) + 2];
        CHECK(dClothSetSurfaceCallback(c, NULL, NULL) == CLOTH_OK, "clearing the callback");
        if (run(w, c, 1.0, "cleared")) z2 = dClothGetPositions(c)[3 * (N * N / 2) + 2];
        printf("on a level plane: %.5f m with the callback, %.5f m after it is cleared\n", z1, z2);
        CHECK(fabs(z1 - 0.02) <= 0.002, "with thickness 0.02: %.5f m", z1);
        CHECK(fabs(z2 - THICK) <= 0.1 * THICK, "cleared: %.5f m, want %.3f", z2, THICK);
        dClothDestroy(c);
    }
    dSpaceDestroy(s);
    dWorldDestroy(w);
    CHECK(dClothSetSurfaceCallback(NULL, same, NULL) == CLOTH_EINVAL, "NULL cloth accepted");
}

int main(void)
{
    dInitODE2(0);
    unchanged();
    thickness_per_geom();
    friction_per_geom();
    field_by_field();
    dCloseODE();
    return check_summary();
}
