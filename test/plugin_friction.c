/* Plugin: Coulomb friction between a cloth and ODE geoms (dcloth.h, step 2:
 * a contact sticks, moving with the body, while last step's tangential
 * constraint force is within mu N; it slides otherwise, under a friction
 * force of mu N against the slip).
 *
 * 1. Threshold angle on a slope. A small cloth (11 x 11 nodes, 0.3 m,
 *    cotton) lies flat on a static plane tilted by theta, at the contact
 *    distance (the thickness, 5 mm), at rest; gravity -9.81 z; h = 1/100 s.
 *    "Stays put": its centre of mass moves less than 1 mm down the slope in
 *    2 s; "slides": more than 5 cm. For mu = 0.4 and 0.8, a sweep of theta
 *    over 0.70, 0.72, ..., 1.30 atan(mu) finds the first angle at which the
 *    cloth does not stay put; it must slide at every larger angle of the
 *    sweep (one clean transition: no early creep, no stick coming back),
 *    and bisection between that angle and the one before gives the
 *    threshold, which must be within 5% of atan(mu). Separately, the cloth
 *    must stay put at 0.95 atan(mu) and slide at 1.05 atan(mu).
 *    Why atan(mu) for a cloth, not only a point mass: lying flat in its rest
 *    shape the cloth has no internal force, and each vertex's weight is
 *    proportional to its mass, so every contact carries the same ratio of
 *    tangential to normal force, tan(theta): all vertices reach the cone
 *    together and in-plane stiffness plays no part (it would only matter if
 *    some vertices slipped before others). The 1 mm / 2 s criterion moves
 *    the measured threshold above atan(mu) by about 2 mm / (g T^2) ~ 5e-5
 *    rad (the acceleration just past it is g (cos + mu sin) dtheta), far
 *    inside 5%.
 *    While sliding, the acceleration down the slope (from the centre of
 *    mass's velocity between 0.5 s and 2 s, so one-off start-up effects
 *    cancel) must be g (sin theta - mu cos theta) within 3% at
 *    theta = 1.2 atan(mu): a sliding contact's friction is mu N, N being the
 *    normal constraint force, m g cos theta per vertex. The 3% covers the CG
 *    tolerance (1e-3) in N and rounding; the rate is exact otherwise
 *    (constant forces, a uniform cloth that does not deform).
 *
 * 2. Sliding friction on a horizontal plane. The same cloth lies on the
 *    static plane z = 0 at the contact distance, mu = 0.3, and gets a
 *    horizontal velocity v0 = 2 m/s on every vertex, in two ways: (a) from
 *    the start (its contacts are new in the first step), (b) after resting
 *    on the plane for 0.2 s (its contacts are established and sticking).
 *    It must decelerate at mu g (measured from the centre of mass's
 *    velocity at 0.05 s and 0.35 s after the kick, while still sliding;
 *    within 5%) and stop after v0^2 / (2 mu g) = 0.680 m, within 10%.
 *    Why 10%: the friction force is explicit (last step's N, constant over
 *    the step) and backward Euler advances x with the end-of-step velocity,
 *    so the discrete distance is short by about v0 h / 2 (1.5%); a one-step
 *    lag at the onset of slip (a contact must see one step of force before
 *    it slides) costs up to v0 h = 2 cm (3%) per step of lag; the final
 *    step's capped friction stops the slip exactly. That is ~5% at most for
 *    an implementation that does what dcloth.h says; 10% leaves a margin
 *    and still fails any model whose friction is off by a factor (a cloth
 *    that stops at once, or mu applied to half the weight).
 *
 * 3. A kinematic sphere drags a draped cloth. A cloth (15 x 15, 0.5 m)
 *    settles for 2 s, mu = 1, on a kinematic sphere (radius 0.2 m) at rest;
 *    then mu is set to the value under test and the sphere moves at a
 *    constant 0.5 m/s along x (dBodySetLinearVel) for 3 s.
 *    mu = 1: the cloth's centre of mass moves with the sphere: its mean
 *    horizontal velocity over the last 1 s within 3% of the sphere's, its
 *    x within 2 cm of the sphere's centre at the end, still in contact.
 *    mu = 0: no tangential force, so the cloth keeps (relative to the
 *    sphere) the backward motion it had when the sphere started, and a
 *    frictionless drape over a sphere is unstable: it slides off the back.
 *    Asserted: its mean horizontal velocity over the 3 s is below half the
 *    sphere's, and at the end it has no contact and lags the sphere by more
 *    than the sphere's radius.
 *
 * 4. Per-geom friction (dClothSetFrictionCallback): at 1.2 atan(0.3) the
 *    plane's mu from the callback decides, not the cloth's: 0.8 stays put,
 *    0.3 slides at g (sin - 0.3 cos) within 3%; a NaN from it is ignored.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "plugin_cloth.h"

#define G 9.81
#define PI 3.14159265358979323846
#define THICK 0.005
#define H 0.01

static void cloth_com(dClothID c, double x[3], double v[3])
{
    const cloth *core = dClothGetCore(c);
    const double *p = cloth_positions(core), *u = cloth_velocities(core), *m = cloth_masses(core);
    double M = 0;
    for (int k = 0; k < 3; k++) x[k] = v[k] = 0;
    for (int i = 0; i < cloth_vertex_count(core); i++) {
        M += m[i];
        for (int k = 0; k < 3; k++) {
            x[k] += m[i] * p[3 * i + k];
            v[k] += m[i] * u[3 * i + k];
        }
    }
    for (int k = 0; k < 3; k++) {
        x[k] /= M;
        v[k] /= M;
    }
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* A flat square cloth of n x n nodes and side L centred at `centre`, its
 * columns along u and rows along v. NULL (and a failed check) on error. */
static dClothID make_cloth(dWorldID w, dSpaceID s, int n, double L, const double centre[3], const double u[3],
                           const double v[3], double mu)
{
    return flat_cloth(w, s, n, L, centre, u, v, mu, THICK);
}

/* One step of cloth and world; a failure is a failed check. */
static int step(dWorldID w, dClothID c, const char *what)
{
    return CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "%s: step failed: %s", what, dClothGetLastError(c));
}

/* ----------------------------------------------------------------- slope */

#define SLOPE_T 2.0
#define STAY 1e-3  /* m: "stays put" below this */
#define SLIDE 0.05 /* m: "slides" above this    */

typedef struct slope_result {
    double moved; /* m, centre of mass down the slope after SLOPE_T */
    double accel; /* m/s^2, down the slope, from the velocity at 0.5 s and SLOPE_T */
    int ok;       /* every step succeeded */
} slope_result;

/* per-geom friction: the plane's mu from the test (dClothSetFrictionCallback) */
static void plane_mu(void *data, dClothID c, dGeomID g, dReal *mu)
{
    (void)c, (void)g;
    *mu = *(const double *)data;
}

/* The cloth at rest on a plane through the origin tilted by theta about y
 * (downhill is +x), for SLOPE_T seconds; geom_mu not NaN: the plane's mu
 * given by a friction callback, the cloth's own being mu. */
static slope_result slope_run_solver(double mu, double theta, double geom_mu, cloth_nonlinear nl)
{
    slope_result r = {0, 0, 0};
    dWorldID w = dWorldCreate();
    dSpaceID s = dSimpleSpaceCreate(0);
    double n[3] = {sin(theta), 0, cos(theta)}, down[3] = {cos(theta), 0, -sin(theta)}, across[3] = {0, 1, 0};
    dCreatePlane(s, n[0], n[1], n[2], 0);
    double centre[3] = {THICK * n[0], THICK * n[1], THICK * n[2]};
    dClothID c = make_cloth(w, s, 11, 0.3, centre, down, across, mu);
    if (c && geom_mu == geom_mu) dClothSetFrictionCallback(c, plane_mu, &geom_mu);
    if (c) {
        cloth_solver sv = cloth_get_desc(dClothGetCore(c)).solver;
        sv.nonlinear = nl;
        CHECK(cloth_set_solver(dClothGetCore(c), &sv) == CLOTH_OK, "cloth_set_solver");
    }
    if (c) {
        double x0[3], x[3], v[3], v_half = 0;
        cloth_com(c, x0, v);
        int steps = (int)(SLOPE_T / H + 0.5), half = (int)(0.5 / H + 0.5);
        r.ok = 1;
        for (int k = 1; k <= steps && r.ok; k++) {
            r.ok = step(w, c, "slope");
            if (k == half) {
                cloth_com(c, x, v);
                v_half = dot3(v, down);
            }
        }
        cloth_com(c, x, v);
        double dx[3] = {x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]};
        r.moved = dot3(dx, down);
        r.accel = (dot3(v, down) - v_half) / (SLOPE_T - half * H);
        dClothDestroy(c);
    }
    dSpaceDestroy(s);
    dWorldDestroy(w);
    return r;
}

static slope_result slope_run_geom(double mu, double theta, double geom_mu)
{
    return slope_run_solver(mu, theta, geom_mu, cloth_default_desc().solver.nonlinear);
}

static slope_result slope_run(double mu, double theta) { return slope_run_geom(mu, theta, NAN); }

/* The callback's mu decides: at 1.2 atan(0.3) a cloth of mu 0.3 slides and
 * one of mu 0.8 stays; swapped by the plane's mu from the callback, they
 * must swap, the sliding one at g (sin - 0.3 cos) within 3%; a NaN from the
 * callback is ignored (the cloth's mu 0.8: stays). */
static void per_geom_friction(void)
{
    double theta = 1.2 * atan(0.3), want = G * (sin(theta) - 0.3 * cos(theta));
    slope_result stays = slope_run_geom(0.3, theta, 0.8), slides = slope_run_geom(0.8, theta, 0.3),
                 ignored = slope_run_geom(0.8, theta, -NAN);
    printf("per-geom friction at %.2f deg: plane mu 0.8 (cloth 0.3) moved %.3g m; plane mu 0.3 (cloth 0.8) "
           "moved %.3g m, acceleration %.4f (want %.4f); a NaN mu ignored: moved %.3g m\n",
           theta * 180 / PI, stays.moved, slides.moved, slides.accel, want, ignored.moved);
    CHECK(stays.ok && fabs(stays.moved) < STAY, "plane mu 0.8 from the callback: moved %.3g m", stays.moved);
    CHECK(slides.ok && slides.moved > SLIDE && fabs(slides.accel - want) <= 0.03 * want,
          "plane mu 0.3 from the callback: moved %.3g m, acceleration %.4f, want %.4f", slides.moved, slides.accel,
          want);
    CHECK(ignored.ok && fabs(ignored.moved) < STAY, "a NaN mu was not ignored: moved %.3g m", ignored.moved);
    CHECK(dClothSetFrictionCallback(NULL, plane_mu, NULL) == CLOTH_EINVAL, "NULL cloth accepted");
}

static void slope_tests(double mu)
{
    double t0 = atan(mu);
    printf("slope, mu = %.2f: atan(mu) = %.4f deg\n", mu, t0 * 180 / PI);

    /* independent of the bisection: 5% either side */
    slope_result below = slope_run(mu, 0.95 * t0), above = slope_run(mu, 1.05 * t0);
    printf("  at 0.95 atan(mu) = %.3f deg: moved %.3g m in %.0f s\n", 0.95 * t0 * 180 / PI, below.moved, SLOPE_T);
    printf("  at 1.05 atan(mu) = %.3f deg: moved %.3g m in %.0f s\n", 1.05 * t0 * 180 / PI, above.moved, SLOPE_T);
    CHECK(below.ok && fabs(below.moved) < STAY, "mu %.2f, theta = 0.95 atan(mu): the cloth moved %.3g m (>= %.3g)", mu,
          below.moved, STAY);
    CHECK(above.ok && above.moved > SLIDE, "mu %.2f, theta = 1.05 atan(mu): the cloth moved %.3g m (<= %.3g)", mu,
          above.moved, SLIDE);

    /* sweep 0.70 ... 1.30 atan(mu) by 0.02: below the first angle where the cloth does not stay put, it stays put
     * at every angle (the definition); above it, it must slide at every angle (one transition, not a creep that
     * starts early or a stick that comes back); then bisect between the last angle that stays and the first not */
    enum { NS = 31 };
    double f[NS], moved[NS];
    int first = -1, ok = 1;
    for (int i = 0; i < NS; i++) {
        f[i] = 0.70 + 0.02 * i;
        slope_result r = slope_run(mu, f[i] * t0);
        ok &= r.ok;
        moved[i] = r.moved;
        if (first < 0 && !(fabs(r.moved) < STAY)) first = i;
    }
    printf("  sweep (angle / atan(mu): m moved in %.0f s):", SLOPE_T);
    for (int i = 0; i < NS; i++) printf("%s %.2f: %.3g", i % 6 ? "," : "\n   ", f[i], moved[i]);
    printf("\n");
    CHECK(ok, "mu %.2f: a step of the sweep failed", mu);
    if (!CHECK(first > 0, "mu %.2f: %s", mu,
               first < 0 ? "the cloth stays put up to 1.3 atan(mu)" : "the cloth moves already at 0.7 atan(mu)"))
        return;
    for (int i = first + 1; i < NS; i++)
        CHECK(moved[i] > SLIDE,
              "mu %.2f: the cloth does not slide at %.2f atan(mu) (moved %.3g m), although it "
              "left at %.2f atan(mu)",
              mu, f[i], moved[i], f[first]);
    double lo = f[first - 1] * t0, hi = f[first] * t0;
    for (int it = 0; it < 12; it++) {
        double mid = 0.5 * (lo + hi);
        slope_result r = slope_run(mu, mid);
        if (!CHECK(r.ok, "mu %.2f: a step of the bisection failed", mu)) break;
        if (fabs(r.moved) < STAY) lo = mid;
        else hi = mid;
    }
    double th = 0.5 * (lo + hi);
    printf("  measured threshold %.4f deg = %.5f atan(mu) (bracket %.2e rad)\n", th * 180 / PI, th / t0, hi - lo);
    CHECK(fabs(th - t0) <= 0.05 * t0, "mu %.2f: threshold angle %.4f deg vs atan(mu) = %.4f deg: off by %.2f%%", mu,
          th * 180 / PI, t0 * 180 / PI, 100 * fabs(th - t0) / t0);

    /* sliding: friction mu N, so the acceleration is g (sin - mu cos) */
    double ts = 1.2 * t0;
    slope_result sl = slope_run(mu, ts);
    double a_exp = G * (sin(ts) - mu * cos(ts));
    printf("  at 1.2 atan(mu) = %.3f deg: acceleration %.5f m/s^2 (expected g (sin - mu cos) = %.5f), "
           "moved %.4f m in %.0f s (%.4f m from rest at that rate)\n",
           ts * 180 / PI, sl.accel, a_exp, sl.moved, SLOPE_T, 0.5 * a_exp * SLOPE_T * SLOPE_T);
    CHECK(sl.ok, "mu %.2f: sliding run failed", mu);
    CHECK_REL(sl.accel, a_exp, 0.03, 0.0);
    /* the Newton step too: its linear solves must not bias a small velocity change */
    sl = slope_run_solver(mu, ts, NAN, CLOTH_NEWTON);
    printf("  Newton step: acceleration %.5f m/s^2\n", sl.accel);
    CHECK(sl.ok, "mu %.2f: sliding run failed (Newton)", mu);
    CHECK_REL(sl.accel, a_exp, 0.03, 0.0);
}

/* ------------------------------------------------------- horizontal slide */

/* The cloth on the plane z = 0 gets v0 along x, at once (settle = 0) or
 * after `settle` seconds at rest. Reports the distance its centre of mass
 * travels until it stops (or 3 s pass), the deceleration between 0.05 s
 * and 0.35 s after the kick, and whether it came to rest. */
static void slide_test(double mu, double v0, double settle, const char *name)
{
    dWorldID w = dWorldCreate();
    dSpaceID s = dSimpleSpaceCreate(0);
    dCreatePlane(s, 0, 0, 1, 0);
    double centre[3] = {0, 0, THICK}, ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0};
    dClothID c = make_cloth(w, s, 11, 0.3, centre, ex, ey, mu);
    if (!c) goto out;
    int ok = 1;
    for (int k = 0; k < (int)(settle / H + 0.5) && ok; k++) ok = step(w, c, name);
    cloth *core = dClothGetCore(c);
    int n = cloth_vertex_count(core);
    double *vel = calloc(3 * (size_t)n, sizeof *vel);
    if (!CHECK(vel != NULL, "out of memory")) goto out;
    for (int i = 0; i < n; i++) vel[3 * i] = v0;
    CHECK(cloth_set_velocities(core, vel) == CLOTH_OK, "cloth_set_velocities: %s", cloth_last_error(core));
    free(vel);

    double x0[3], x[3], v[3], va = NAN, vb = NAN, t_stop = NAN;
    int ka = (int)(0.05 / H + 0.5), kb = (int)(0.35 / H + 0.5);
    cloth_com(c, x0, v);
    for (int k = 1; k <= (int)(3.0 / H + 0.5) && ok; k++) {
        ok = step(w, c, name);
        cloth_com(c, x, v);
        if (k == ka) va = v[0];
        if (k == kb) vb = v[0];
        if (isnan(t_stop) && fabs(v[0]) < 1e-3) t_stop = k * H;
    }
    double d = x[0] - x0[0], d_exp = v0 * v0 / (2 * mu * G);
    double decel = (va - vb) / ((kb - ka) * H), t_exp = v0 / (mu * G);
    printf("slide %s, mu = %.2f, v0 = %.1f m/s: deceleration %.4f m/s^2 (mu g = %.4f); stopped after %.4f m "
           "(v0^2/(2 mu g) = %.4f m, %+.1f%%) at t = %.2f s (v0/(mu g) = %.2f s); |v| at 3 s %.2e m/s\n",
           name, mu, v0, decel, mu * G, d, d_exp, 100 * (d - d_exp) / d_exp, t_stop, t_exp, fabs(v[0]));
    CHECK(ok, "%s: a step failed", name);
    CHECK(!isnan(t_stop), "%s: the cloth did not come to rest in 3 s", name);
    CHECK(va > 0.5 * v0 && vb > 0.0, "%s: the cloth was not sliding over 0.05-0.35 s (v = %.4f, %.4f m/s)", name, va,
          vb);
    CHECK(fabs(decel - mu * G) <= 0.05 * mu * G, "%s: deceleration %.4f m/s^2 vs mu g = %.4f (%+.1f%%)", name, decel,
          mu * G, 100 * (decel - mu * G) / (mu * G));
    CHECK(fabs(d - d_exp) <= 0.10 * d_exp, "%s: stopping distance %.4f m vs v0^2/(2 mu g) = %.4f m (%+.1f%%)", name, d,
          d_exp, 100 * (d - d_exp) / d_exp);
out:
    dClothDestroy(c);
    dSpaceDestroy(s);
    dWorldDestroy(w);
}

/* ------------------------------------------------------------ sphere drag */

#define SPHERE_R 0.2
#define SPHERE_V 0.5
#define DRAG_T 3.0

static void drag_test(double mu)
{
    dWorldID w = dWorldCreate();
    dSpaceID s = dSimpleSpaceCreate(0);
    dBodyID b = dBodyCreate(w);
    dBodySetKinematic(b);
    dBodySetPosition(b, 0, 0, 0);
    dGeomID g = dCreateSphere(s, SPHERE_R);
    dGeomSetBody(g, b);
    /* 2 mm above the contact distance: it lands and drapes */
    double centre[3] = {0, 0, SPHERE_R + THICK + 0.002}, ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0};
    dClothID c = make_cloth(w, s, 15, 0.5, centre, ex, ey, 1.0);
    if (!c) goto out;
    int ok = 1;
    for (int k = 0; k < (int)(2.0 / H + 0.5) && ok; k++) ok = step(w, c, "drape");
    double x0[3], x1[3], x[3], v[3];
    cloth_com(c, x0, v);
    int contacts0 = dClothGetStats(c)->contacts;
    printf("drag, mu = %.1f: draped for 2 s: %d contacts, centre of mass (%.4f, %.4f, %.4f), |v| %.2e m/s\n", mu,
           contacts0, x0[0], x0[1], x0[2], sqrt(dot3(v, v)));
    CHECK(contacts0 > 0 && x0[2] > 0, "the cloth is not draped on the sphere (%d contacts, z %.3f)", contacts0, x0[2]);

    CHECK(dClothSetFriction(c, mu) == CLOTH_OK, "dClothSetFriction: %s", dClothGetLastError(c));
    dBodySetLinearVel(b, SPHERE_V, 0, 0);
    int steps = (int)(DRAG_T / H + 0.5), k1 = steps - (int)(1.0 / H + 0.5);
    for (int k = 1; k <= steps && ok; k++) {
        ok = step(w, c, "drag");
        if (k == k1) cloth_com(c, x1, v);
    }
    cloth_com(c, x, v);
    const dReal *p = dBodyGetPosition(b);
    double v_last = (x[0] - x1[0]) / ((steps - k1) * H), v_mean = (x[0] - x0[0]) / (steps * H);
    double lag = p[0] - x[0];
    int contacts = dClothGetStats(c)->contacts;
    printf("  after %.0f s at %.2f m/s: sphere x %.4f, cloth centre of mass (%.4f, %.4f, %.4f), lag %.4f m; "
           "mean cloth velocity over the last 1 s %.4f m/s, over %.0f s %.4f m/s; %d contacts\n",
           DRAG_T, SPHERE_V, p[0], x[0], x[1], x[2], lag, v_last, DRAG_T, v_mean, contacts);
    CHECK(ok, "drag mu %.1f: a step failed", mu);
    if (mu > 0) {
        CHECK(fabs(v_last - SPHERE_V) <= 0.03 * SPHERE_V,
              "mu %.1f: the cloth moves at %.4f m/s, the sphere at %.4f m/s", mu, v_last, SPHERE_V);
        CHECK(fabs(lag) <= 0.02, "mu %.1f: the cloth's centre is %.4f m behind the sphere's", mu, lag);
        CHECK(contacts > 0, "mu %.1f: the cloth left the sphere", mu);
    } else {
        CHECK(v_mean < 0.5 * SPHERE_V, "mu 0: the cloth was dragged at %.4f m/s (sphere %.4f m/s)", v_mean, SPHERE_V);
        CHECK(contacts == 0 && lag > SPHERE_R, "mu 0: the cloth is still on the sphere (%d contacts, lag %.4f m)",
              contacts, lag);
    }
out:
    dClothDestroy(c);
    dSpaceDestroy(s);
    dWorldDestroy(w);
}

int main(void)
{
    dInitODE2(0);
    slope_tests(0.4);
    slope_tests(0.8);
    per_geom_friction();
    slide_test(0.3, 2.0, 0.0, "(a) from the start");
    slide_test(0.3, 2.0, 0.2, "(b) after resting");
    drag_test(1.0);
    drag_test(0.0);
    dCloseODE();
    return check_summary();
}
