/* Physics: air drag with wind (cloth_set_air) against closed forms, for the
 * linearised (backward Euler, BDF2) and Newton implicit steps and
 * symplectic Euler.
 *
 * 1. Terminal velocity of a horizontal cloth falling from rest in gravity:
 *    v_t = m g / (c A). Every scheme's fixed point of dv/dt = g - k v is v_t
 *    exactly, and after 15 time constants the transient is e^-15.
 *    The corners on the cells' diagonal carry 4/3 of their mass's share of
 *    the drag, the other two 2/3, so the cloth falls twisted into a saddle.
 *    With drag_tangent = drag_normal a triangle's drag is c A r whatever
 *    its tilt: v_t to 1e-4. With drag_normal alone the tilted triangles
 *    drag less: faster than v_t, by less than 2%.
 * 2. Wind (0, 0, w) along the normal on a cloth at rest, gravity off: the
 *    first step's momentum change is h c_n A w (explicit), h c_n A w /
 *    (1 + h k) (implicit Euler, k = c_n A / m), to 1e-6.
 * 3. In-plane motion with drag_tangent c_t decays as (1 + h k)^-n with
 *    implicit Euler, (1 - h k)^n with symplectic Euler (k = c_t A / m):
 *    rigid up to the corners' uneven share of the drag: 1e-5.
 * 4. cloth_air_force is the force the step applied: a free cloth tumbling
 *    in a wind gains h (M g + F_air) a step (BDF2: its momentum equation),
 *    to 1e-9 of the air's impulse.
 * 5. cloth_air_torque is the torque of the forces the step applied: with
 *    symplectic Euler (frames and velocities at the step's start), summed
 *    here triangle by triangle at the end-of-step positions, to 1e-12.
 * 6. Bad settings are refused with a message naming the field and leave
 *    the settings as they were. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define NS 4
static const cloth_method methods[NS] = {CLOTH_BACKWARD_EULER, CLOTH_BACKWARD_EULER, CLOTH_BDF2,
                                         CLOTH_SYMPLECTIC_EULER};
static const cloth_nonlinear solves[NS] = {CLOTH_LINEARIZED, CLOTH_NEWTON, CLOTH_LINEARIZED, CLOTH_LINEARIZED};
static const char *names[NS] = {"backward Euler", "Newton (BE)", "BDF2", "symplectic Euler"};

#define SIDE 0.4 /* m: the square cloth's side, 11 x 11 nodes */

static cloth *make(int s, const double g[3])
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 11;
    d.width = d.height = SIDE;
    memcpy(d.gravity, g, sizeof d.gravity);
    d.solver.method = methods[s];
    d.solver.nonlinear = solves[s];
    d.solver.cg_tolerance = 1e-12;
    d.solver.newton_cg_tolerance = 1e-10;
    d.solver.newton_tolerance = 1e-12;
    cloth *c;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return NULL;
    return c;
}

static double total_mass(const cloth *c)
{
    double m = 0.0;
    for (int i = 0; i < cloth_vertex_count(c); i++) m += cloth_masses(c)[i];
    return m;
}

static double momentum(const cloth *c, int k)
{
    double P = 0.0;
    for (int i = 0; i < cloth_vertex_count(c); i++) P += cloth_masses(c)[i] * cloth_velocities(c)[3 * i + k];
    return P;
}

/* drag coefficient (N s / m^3) giving the cloth a time constant m / (c A) of tau */
static double drag_for(const cloth *c, double tau) { return total_mass(c) / (tau * SIDE * SIDE); }

static int run(cloth *c, int s, double h, int steps)
{
    for (int k = 0; k < steps; k++)
        if (!CHECK(cloth_step(c, h, NULL) == CLOTH_OK, "%s: step %d: %s", names[s], k, cloth_last_error(c))) return 0;
    return 1;
}

/* Falling from rest for 15 time constants: the mean vertical speed against
 * m g / (c_n A). tilt 0: drag_tangent = drag_normal, so each triangle's drag
 * is c A r whatever its tilt; tilt 1: drag_normal alone. */
static void terminal(int s, int tilt)
{
    const double g[3] = {0.0, 0.0, -9.81}, tau = 0.1;
    cloth *c = make(s, g);
    if (!c) return;
    cloth_air air = {{0.0, 0.0, 0.0}, drag_for(c, tau), tilt ? 0.0 : drag_for(c, tau)};
    cloth_set_air(c, &air);
    double h = methods[s] == CLOTH_SYMPLECTIC_EULER ? 1.0 / 16384.0 : 0.01, t = 15.0 * tau;
    double vt = total_mass(c) * 9.81 / (air.drag_normal * SIDE * SIDE);
    if (run(c, s, h, (int)lround(t / h))) {
        double v = -momentum(c, 2) / total_mass(c);
        printf("%-17s terminal (%s): v %.6f m/s, closed form %.6f m/s (rel %.2g) after %.2f s, h %.3g s\n", names[s],
               tilt ? "normal drag" : "isotropic", v, vt, (v - vt) / vt, t, h);
        if (tilt) CHECK(v > vt && v < 1.02 * vt, "%s: tilted triangles' terminal speed %.6f m/s", names[s], v);
        else CHECK_REL(v, vt, 1e-4, 0.0);
    }
    cloth_destroy(c);
}

static void wind(int s)
{
    const double g[3] = {0.0, 0.0, 0.0}, w = 3.0, h = 1e-5;
    cloth *c = make(s, g);
    if (!c) return;
    cloth_air air = {{0.0, 0.0, w}, drag_for(c, 0.1), 0.0};
    cloth_set_air(c, &air);
    double F = air.drag_normal * SIDE * SIDE * w, k = 1.0 / 0.1;
    double want = h * F / (methods[s] == CLOTH_SYMPLECTIC_EULER ? 1.0 : 1.0 + h * k);
    if (run(c, s, h, 1)) {
        double dP = momentum(c, 2);
        printf("%-17s wind: first step's impulse %.9g N s, closed form %.9g N s (rel %.2g)\n", names[s], dP, want,
               (dP - want) / want);
        CHECK_REL(dP, want, 1e-6, 0.0);
    }
    cloth_destroy(c);
}

static void tangential(int s)
{
    const double g[3] = {0.0, 0.0, 0.0}, u = 0.5, tau = 0.1;
    cloth *c = make(s, g);
    if (!c) return;
    cloth_air air = {{0.0, 0.0, 0.0}, 0.0, drag_for(c, tau)};
    cloth_set_air(c, &air);
    int n = cloth_vertex_count(c), steps = methods[s] == CLOTH_SYMPLECTIC_EULER ? 4096 : 40;
    double *v = calloc(3 * (size_t)n, sizeof *v), h = methods[s] == CLOTH_SYMPLECTIC_EULER ? 1.0 / 16384.0 : 0.005;
    for (int i = 0; i < n; i++) v[3 * i] = u;
    cloth_set_velocities(c, v);
    double P0 = momentum(c, 0), hk = h / tau;
    double rate = methods[s] == CLOTH_SYMPLECTIC_EULER ? 1.0 - hk : 1.0 / (1.0 + hk);
    if (methods[s] != CLOTH_BDF2 && run(c, s, h, steps)) {
        double P = momentum(c, 0), want = P0 * pow(rate, steps), ode = P0 * exp(-steps * h / tau);
        printf("%-17s tangential: P/P0 %.9f, discrete closed form %.9f (rel %.2g), exp(-k t) %.9f\n", names[s], P / P0,
               want / P0, (P - want) / want, ode / P0);
        CHECK_REL(P, want, 1e-5, 0.0);
    }
    free(v);
    cloth_destroy(c);
}

/* 4: the cloth spinning about x and y through a slanted wind, 20 steps */
static void reported(int s)
{
    const double g[3] = {0.0, 0.0, -9.81}, h = 0.01;
    cloth *c = make(s, g);
    if (!c) return;
    cloth_air air = {{2.0, -1.0, 3.0}, drag_for(c, 0.1), 0.3 * drag_for(c, 0.1)};
    cloth_set_air(c, &air);
    int n = cloth_vertex_count(c);
    double *v = calloc(3 * (size_t)n, sizeof *v), M = total_mass(c), worst = 0.0, dP0[3] = {0.0, 0.0, 0.0};
    const double *x = cloth_positions(c);
    for (int i = 0; i < n; i++) {
        v[3 * i + 1] = -4.0 * (x[3 * i + 2] - x[2]);
        v[3 * i + 2] = 4.0 * (x[3 * i + 1] - SIDE / 2) - 3.0 * (x[3 * i] - SIDE / 2);
    }
    cloth_set_velocities(c, v);
    for (int k = 0; k < 20; k++) {
        double P0[3], F[3], dP[3];
        for (int r = 0; r < 3; r++) P0[r] = momentum(c, r);
        if (!run(c, s, h, 1)) break;
        cloth_air_force(c, F);
        /* BDF2 after its first step: dP - dP_prev / 3 = 2/3 h f */
        int bdf2 = methods[s] == CLOTH_BDF2 && k > 0;
        for (int r = 0; r < 3; r++) {
            dP[r] = momentum(c, r) - P0[r];
            double lhs = bdf2 ? dP[r] - dP0[r] / 3.0 : dP[r], rhs = (bdf2 ? 2.0 / 3.0 : 1.0) * h * (M * g[r] + F[r]);
            worst = fmax(worst, fabs(lhs - rhs) / (h * sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2])));
        }
        memcpy(dP0, dP, sizeof dP);
    }
    printf("%-17s reported air force: worst momentum error %.2e of the step's air impulse\n", names[s], worst);
    CHECK(worst <= 1e-9, "%s: the momentum change differs from h (M g + air force) by %.3g", names[s], worst);
    free(v);
    cloth_destroy(c);
}

/* 5: a free cloth tumbling in a wind, one symplectic Euler step */
static void torque(void)
{
    const double g[3] = {0.0, 0.0, 0.0};
    cloth *c = make(3, g);
    if (!c) return;
    cloth_air air = {{2.0, -1.0, 3.0}, drag_for(c, 0.1), 0.3 * drag_for(c, 0.1)};
    cloth_set_air(c, &air);
    int n = cloth_vertex_count(c), C = 11;
    double *x0 = malloc(3 * (size_t)n * sizeof *x0), *v0 = malloc(3 * (size_t)n * sizeof *v0);
    if (!CHECK(x0 && v0, "out of memory")) goto out;
    memcpy(x0, cloth_positions(c), 3 * (size_t)n * sizeof *x0);
    for (int i = 0; i < n; i++) {
        v0[3 * i] = 0.5;
        v0[3 * i + 1] = -4.0 * (x0[3 * i + 2] - x0[2]) + 2.0 * (x0[3 * i] - SIDE / 2);
        v0[3 * i + 2] = 4.0 * (x0[3 * i + 1] - SIDE / 2) - 3.0 * (x0[3 * i] - SIDE / 2);
    }
    cloth_set_velocities(c, v0);
    if (!run(c, 3, 0.01, 1)) goto out;
    const double *y = cloth_positions(c);
    double T[3] = {0.0, 0.0, 0.0}, Tc[3], scale = 0.0;
    for (int cell = 0; cell < (C - 1) * (C - 1); cell++) {
        int a = (cell / (C - 1)) * C + cell % (C - 1), tri[2][3] = {{a, a + 1, a + C + 1}, {a, a + C + 1, a + C}};
        for (int t = 0; t < 2; t++) {
            const int *p = tri[t];
            double e1[3], e2[3], nn[3], r[3], D[3];
            for (int q = 0; q < 3; q++) {
                e1[q] = x0[3 * p[1] + q] - x0[3 * p[0] + q];
                e2[q] = x0[3 * p[2] + q] - x0[3 * p[0] + q];
                r[q] = (v0[3 * p[0] + q] + v0[3 * p[1] + q] + v0[3 * p[2] + q]) / 3.0 - air.wind[q];
            }
            nn[0] = e1[1] * e2[2] - e1[2] * e2[1];
            nn[1] = e1[2] * e2[0] - e1[0] * e2[2];
            nn[2] = e1[0] * e2[1] - e1[1] * e2[0];
            double len = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]), rn = 0.0;
            for (int q = 0; q < 3; q++) rn += r[q] * nn[q] / len;
            for (int q = 0; q < 3; q++)
                D[q] = -0.5 * len / 3.0 *
                       (air.drag_tangent * r[q] + (air.drag_normal - air.drag_tangent) * rn * nn[q] / len);
            for (int k = 0; k < 3; k++) {
                const double *z = y + 3 * p[k];
                T[0] += z[1] * D[2] - z[2] * D[1];
                T[1] += z[2] * D[0] - z[0] * D[2];
                T[2] += z[0] * D[1] - z[1] * D[0];
                scale += sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]) * sqrt(D[0] * D[0] + D[1] * D[1] + D[2] * D[2]);
            }
        }
    }
    CHECK(cloth_air_torque(c, Tc) == CLOTH_OK, "cloth_air_torque: %s", cloth_last_error(c));
    double dT[3] = {T[0] - Tc[0], T[1] - Tc[1], T[2] - Tc[2]};
    double e = sqrt(dT[0] * dT[0] + dT[1] * dT[1] + dT[2] * dT[2]);
    printf("air torque (%.4g, %.4g, %.4g) N m; differs from the sum over triangles by %.2e of its scale\n", Tc[0],
           Tc[1], Tc[2], e / scale);
    CHECK(scale > 0.0 && e <= 1e-12 * scale, "cloth_air_torque differs from the sum over triangles by %.3g N m", e);
out:
    free(x0);
    free(v0);
    cloth_destroy(c);
}

static int same(cloth_air a, cloth_air b) { return !memcmp(&a, &b, sizeof a); }

static void bad_input(void)
{
    const double g[3] = {0.0, 0.0, -9.81};
    cloth *c = make(0, g);
    if (!c) return;
    cloth_air good = {{1.0, 2.0, 3.0}, 0.5, 0.25}, a;
    CHECK(cloth_set_air(c, &good) == CLOTH_OK && same(cloth_get_air(c), good), "good settings must be kept");
    const char *field[3] = {"air", "wind", "drag_normal"};
    for (int k = 0; k < 3; k++) {
        a = good;
        if (k == 1) a.wind[1] = NAN;
        if (k == 2) a.drag_normal = -1.0;
        cloth_status r = cloth_set_air(c, k ? &a : NULL);
        CHECK(r == CLOTH_EINVAL && strstr(cloth_last_error(c), field[k]), "%s: refused with its name: %s", field[k],
              cloth_last_error(c));
        CHECK(same(cloth_get_air(c), good), "%s: the settings must be unchanged", field[k]);
    }
    a = good;
    a.drag_tangent = INFINITY;
    CHECK(cloth_set_air(c, &a) == CLOTH_EINVAL && strstr(cloth_last_error(c), "drag_tangent"),
          "infinite drag_tangent refused: %s", cloth_last_error(c));
    CHECK(cloth_set_air(NULL, &good) == CLOTH_EINVAL, "NULL cloth must be refused");
    double f[3];
    CHECK(cloth_air_force(NULL, f) == CLOTH_EINVAL, "cloth_air_force: NULL cloth must be refused");
    CHECK(cloth_air_force(c, NULL) == CLOTH_EINVAL && strstr(cloth_last_error(c), "f is NULL"),
          "cloth_air_force: NULL f refused: %s", cloth_last_error(c));
    CHECK(cloth_air_torque(NULL, f) == CLOTH_EINVAL, "cloth_air_torque: NULL cloth must be refused");
    CHECK(cloth_air_torque(c, NULL) == CLOTH_EINVAL && strstr(cloth_last_error(c), "t is NULL"),
          "cloth_air_torque: NULL t refused: %s", cloth_last_error(c));
    cloth_air none = cloth_get_air(NULL);
    CHECK(none.drag_normal == 0.0 && none.drag_tangent == 0.0 && none.wind[2] == 0.0, "NULL cloth: no air");
    cloth_destroy(c);
}

int main(void)
{
    for (int s = 0; s < NS; s++) {
        terminal(s, 0);
        terminal(s, 1);
        wind(s);
        tangential(s);
        reported(s);
    }
    torque();
    bad_input();
    return check_summary();
}
