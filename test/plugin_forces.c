/* Plugin: the user's forces on cloth vertices (dcloth.h:
 * dClothAddVertexForce, and forces set on the core with
 * cloth_set_external_forces), added to the plugin's friction, never
 * overwritten by it.
 *
 * 1. Momentum, no gravity, no contacts. An 11x11 cloth (CG tolerance 1e-12)
 *    with a force set on its core, different on every vertex, for 30 steps
 *    of 1/60 s: its momentum must be 30 h sum f to 1e-9 of it, and the core
 *    must still hold the forces as set after the steps.
 * 2. dClothAddVertexForce on one vertex before the first step only: the
 *    momentum after it is h F, after two more steps still h F (the force
 *    applied once, then cleared as ODE clears a body's), to 1e-8 of it.
 * 3. Friction added to the user's force. The cloth lies on the plane z = 0
 *    at the contact distance, gravity on, mu = 0.3, and every vertex gets a
 *    horizontal force of twice its friction limit, 0.6 m g: it slides, and
 *    its centre of mass accelerates at (0.6 - 0.3) g, measured between 0.3 s
 *    and 1 s, within 3% (the friction test's bound for kinetic friction).
 * 4. Bad input: vertex -1 and n, a NaN or infinite component: CLOTH_EINVAL,
 *    a message, nothing added (a later step gains no momentum).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"

#define H (1.0 / 60.0)
#define G 9.81

static dClothID make(dWorldID w, dSpaceID s, double z)
{
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = 11;
    d.cloth.width = d.cloth.height = 0.3;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.15;
    d.cloth.origin[2] = z;
    d.cloth.solver.cg_tolerance = 1e-12;
    d.mu = 0.3;
    dClothID c = NULL;
    cloth_error err;
    CHECK(dClothCreate(w, s, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message);
    return c;
}

static void momentum(dClothID c, double P[3], double *mass)
{
    const cloth *core = dClothGetCore(c);
    const double *v = cloth_velocities(core), *m = cloth_masses(core);
    P[0] = P[1] = P[2] = 0.0;
    *mass = 0.0;
    for (int i = 0; i < cloth_vertex_count(core); i++) {
        *mass += m[i];
        for (int r = 0; r < 3; r++) P[r] += m[i] * v[3 * i + r];
    }
}

static double dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

static void core_forces(void)
{
    dWorldID w = dWorldCreate();
    dClothID c = make(w, 0, 1.0);
    if (!c) return;
    cloth *core = dClothGetCore(c);
    cloth_set_gravity(core, (double[3]){0, 0, 0});
    int n = cloth_vertex_count(core);
    double *f = malloc(3 * (size_t)n * sizeof *f), want[3] = {0, 0, 0}, P[3], m;
    for (int i = 0; i < n; i++)
        for (int r = 0; r < 3; r++) {
            f[3 * i + r] = 1e-3 * (r + 1) * (1.0 + 0.5 * sin(0.7 * i + r));
            want[r] += 30 * H * f[3 * i + r];
        }
    CHECK(cloth_set_external_forces(core, f) == CLOTH_OK, "set forces: %s", cloth_last_error(core));
    for (int s = 0; s < 30; s++) CHECK(dClothStep(c, H) == CLOTH_OK, "step %d: %s", s, dClothGetLastError(c));
    momentum(c, P, &m);
    double err = dist3(P, want), size = sqrt(want[0] * want[0] + want[1] * want[1] + want[2] * want[2]);
    printf("forces set on the core: momentum (%.6g %.6g %.6g), want (%.6g %.6g %.6g), error %.2e of it\n", P[0], P[1],
           P[2], want[0], want[1], want[2], err / size);
    CHECK(err <= 1e-9 * size, "momentum off by %.3g of %.3g: the forces were not applied", err, size);
    CHECK(memcmp(cloth_external_forces(core), f, 3 * (size_t)n * sizeof *f) == 0,
          "the core's forces changed under the plugin");
    free(f);
    dClothDestroy(c);
    dWorldDestroy(w);
}

static void added_force(void)
{
    dWorldID w = dWorldCreate();
    dClothID c = make(w, 0, 1.0);
    if (!c) return;
    cloth_set_gravity(dClothGetCore(c), (double[3]){0, 0, 0});
    const double F[3] = {0.02, -0.01, 0.03};
    double P[3], m;
    /* added in two parts: they add up */
    CHECK(dClothAddVertexForce(c, 7, F[0], 0, F[2]) == CLOTH_OK, "add: %s", dClothGetLastError(c));
    CHECK(dClothAddVertexForce(c, 7, 0, F[1], 0) == CLOTH_OK, "add: %s", dClothGetLastError(c));
    CHECK(dClothStep(c, H) == CLOTH_OK, "step: %s", dClothGetLastError(c));
    momentum(c, P, &m);
    double want[3] = {H * F[0], H * F[1], H * F[2]};
    /* the CG's residual (1e-12 of a right side that holds the links' forces
     * the kick set off) leaves about 1e-9 of h F */
    double tol = 1e-8 * H * sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2]);
    CHECK(dist3(P, want) <= tol, "after the step: momentum (%.6g %.6g %.6g), want (%.6g %.6g %.6g)", P[0], P[1], P[2],
          want[0], want[1], want[2]);
    for (int s = 0; s < 2; s++) dClothStep(c, H);
    momentum(c, P, &m);
    printf("dClothAddVertexForce: momentum after 3 steps (%.6g %.6g %.6g), h F (%.6g %.6g %.6g), off by %.2e\n", P[0],
           P[1], P[2], want[0], want[1], want[2], dist3(P, want));
    CHECK(dist3(P, want) <= tol, "the added force was applied again: momentum (%.6g %.6g %.6g)", P[0], P[1], P[2]);
    dClothDestroy(c);
    dWorldDestroy(w);
}

static void with_friction(void)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -G);
    dSpaceID sp = dHashSpaceCreate(0);
    dCreatePlane(sp, 0, 0, 1, 0);
    dClothID c = make(w, sp, dClothDefaultDesc().thickness);
    if (!c) return;
    cloth *core = dClothGetCore(c);
    int n = cloth_vertex_count(core);
    const double *m = cloth_masses(core);
    double *f = calloc(3 * (size_t)n, sizeof *f), P[3], M, v0 = 0.0, t0 = 0.3, t1 = 1.0;
    for (int i = 0; i < n; i++) f[3 * i] = 0.6 * m[i] * G;
    cloth_set_external_forces(core, f);
    int steps = (int)lround(t1 / H);
    for (int s = 1; s <= steps; s++) {
        CHECK(dClothStep(c, H) == CLOTH_OK, "step %d: %s", s, dClothGetLastError(c));
        momentum(c, P, &M);
        if (s == (int)lround(t0 / H)) v0 = P[0] / M;
    }
    double a = (P[0] / M - v0) / (t1 - t0), want = (0.6 - 0.3) * G;
    printf("pushed at twice its friction limit on a plane: acceleration %.4f m/s^2, (0.6 - mu) g = %.4f\n", a, want);
    CHECK(fabs(a - want) <= 0.03 * want, "acceleration %.4f, want %.4f within 3%%", a, want);
    free(f);
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

static void bad_input(void)
{
    dWorldID w = dWorldCreate();
    dClothID c = make(w, 0, 1.0);
    if (!c) return;
    cloth_set_gravity(dClothGetCore(c), (double[3]){0, 0, 0});
    int n = cloth_vertex_count(dClothGetCore(c));
    struct {
        int vertex;
        double f[3];
        const char *name;
    } bad[] = {{-1, {1, 0, 0}, "vertex -1"},
               {n, {1, 0, 0}, "vertex n"},
               {3, {NAN, 0, 0}, "NaN"},
               {3, {0, 0, INFINITY}, "inf"},
               {3, {1e308, 0, 0}, "a sum past the largest double"}};
    CHECK(dClothAddVertexForce(c, 3, 1e308, 0, 0) == CLOTH_OK, "a large finite force");
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        cloth_status s = dClothAddVertexForce(c, bad[k].vertex, bad[k].f[0], bad[k].f[1], bad[k].f[2]);
        CHECK(s == CLOTH_EINVAL && dClothGetLastError(c)[0] != '\0', "%s: status %d, message '%s'", bad[k].name, s,
              dClothGetLastError(c));
    }
    CHECK(dClothAddVertexForce(c, 3, -1e308, 0, 0) == CLOTH_OK, "cancelling the large force");
    CHECK(dClothAddVertexForce(NULL, 0, 1, 0, 0) == CLOTH_EINVAL, "a NULL cloth");
    dClothStep(c, H);
    double P[3], m;
    momentum(c, P, &m);
    /* a refused 1 N would leave h N s; a solve of the cloth at rest, round-off */
    CHECK(fabs(P[0]) + fabs(P[1]) + fabs(P[2]) <= 1e-12 * H, "refused forces were applied: momentum (%g %g %g)", P[0],
          P[1], P[2]);
    dClothDestroy(c);
    dWorldDestroy(w);
}

int main(void)
{
    dInitODE2(0);
    core_forces();
    added_force();
    with_friction();
    bad_input();
    dCloseODE();
    return check_summary();
}
