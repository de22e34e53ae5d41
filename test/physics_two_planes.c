/* Physics: a second contact plane per vertex (cloth_set_contact_second),
 * decided inside the Newton step.
 *
 * A flat 3 x 3 cloth at rest, every vertex given the same wedge through its
 * own position: a floor (normal +z) and a leaning wall (normal (-cos 30, 0,
 * sin 30), 60 deg from the floor's, so the two normals are not orthogonal),
 * which meet in a line along y. Gravity has a component along the line.
 * Every vertex moves alike, so no link acts and backward Euler has a closed
 * form per vertex:
 *   - gravity into the wedge (g = (5, 2, -9.81)), both planes candidates: the
 *     step holds each vertex on both (the line), it moves along y only, v_y =
 *     k h g_y after k steps, x on the line to rounding, and each plane's force
 *     (cloth_get_contact_planes) is the closed form lambda_k n_k of -m g's
 *     part across the line, lambda from the Gram system of the normals (both
 *     push); their sum is cloth_constraint_force;
 *   - gravity off the wall (g = (-5, 2, -9.81)), the wall a sliding contact
 *     set so (cloth_set_contact, pull 0) and the floor the second candidate:
 *     the step holds the line, finds the wall pulling (its own force, from
 *     the split) and lets it go alone; the vertex slides on the floor, v =
 *     (h g_x, h g_y, 0), the floor pushing m g_z, the wall nothing;
 *   - the floor alone as a second candidate of a free vertex: held on it;
 *   - a second plane within 0.6 deg of the vertex's own is not taken.
 * CLOTH_LINEARIZED leaves contact candidates to Newton (documented); given
 * the wedge's line itself (cloth_set_constraint, ndof 2: what the Newton
 * step holds while both planes push) it meets the same closed form, the
 * constraint force -m g's part across the line. Bad input is refused naming
 * the argument.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define N 3
#define H (1.0 / 60.0)
#define STEPS 6

static const double FLOOR[3] = {0.0, 0.0, 1.0};
static double wall[3]; /* (-cos 30, 0, sin 30) */

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static cloth *make(cloth_nonlinear how, const double g[3], double **p)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = N;
    d.width = d.height = 0.2;
    d.origin[0] = d.origin[1] = -0.1;
    d.origin[2] = 0.3;
    memcpy(d.gravity, g, sizeof d.gravity);
    d.solver.nonlinear = how;
    d.solver.newton_tolerance = 1e-9;
    d.solver.cg_tolerance = d.solver.newton_cg_tolerance = 1e-10;
    d.solver.cg_max_iterations = 2000;
    d.solver.newton_iterations = 64;
    cloth *c = NULL;
    cloth_error err;
    CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message);
    if (!c) return NULL;
    int n = cloth_vertex_count(c);
    *p = malloc(3 * (size_t)n * sizeof **p);
    memcpy(*p, cloth_positions(c), 3 * (size_t)n * sizeof **p);
    return c;
}

/* -m g's part across the line as lambda_f n_floor + lambda_w n_wall (the
 * Gram system of the two unit normals) */
static void wedge_forces(double m, const double g[3], double *lf, double *lw)
{
    double c = dot3(FLOOR, wall), bf = -m * dot3(FLOOR, g), bw = -m * dot3(wall, g);
    *lf = (bf - c * bw) / (1.0 - c * c);
    *lw = (bw - c * bf) / (1.0 - c * c);
}

/* after k steps on the line from p at rest: the largest distance from the
 * closed form (x: p + (0, h^2 g_y k (k + 1) / 2, 0); v: (0, k h g_y, 0)) */
static void line_errors(const cloth *c, const double *p, const double g[3], int k, double *ex, double *ev)
{
    double y = H * H * g[1] * k * (k + 1) / 2.0;
    *ex = *ev = 0.0;
    for (int i = 0; i < cloth_vertex_count(c); i++) {
        const double *x = cloth_positions(c) + 3 * i, *v = cloth_velocities(c) + 3 * i;
        *ex = fmax(*ex, fmax(fmax(fabs(x[0] - p[3 * i]), fabs(x[2] - p[3 * i + 2])), fabs(x[1] - p[3 * i + 1] - y)));
        *ev = fmax(*ev, fmax(fmax(fabs(v[0]), fabs(v[2])), fabs(v[1] - k * H * g[1])));
    }
}

/* gravity into the wedge, both planes candidates: held on their line */
static void both_push(void)
{
    const double g[3] = {5.0, 2.0, -9.81};
    double *p = NULL;
    cloth *c = make(CLOTH_NEWTON, g, &p);
    if (!c) return;
    int n = cloth_vertex_count(c);
    for (int k = 1; k <= STEPS; k++) {
        cloth_release_all(c);
        for (int i = 0; i < n; i++) {
            cloth_set_contact(c, i, FLOOR, p + 3 * i);
            cloth_set_contact_second(c, i, wall, p + 3 * i);
        }
        cloth_step_stats st;
        CHECK(cloth_step(c, H, &st) == CLOTH_OK, "step %d: %s", k, cloth_last_error(c));
        CHECK(st.contacts_decided == 2 * n, "step %d: %d planes decided, expected both of every vertex (%d)", k,
              st.contacts_decided, 2 * n);
        double worst_x, worst_v, worst_f = 0.0;
        line_errors(c, p, g, k, &worst_x, &worst_v);
        int lines = 0, split = 1;
        for (int i = 0; i < n; i++) {
            double m = cloth_masses(c)[i], lf, lw, f[3], f1[3], f2[3];
            cloth_constraint k1, kk;
            int two = 0;
            wedge_forces(m, g, &lf, &lw);
            cloth_get_constraint(c, i, &kk);
            cloth_get_contact_planes(c, i, &k1, &two, f1, f2);
            cloth_constraint_force(c, i, f);
            lines += kk.ndof == 2 && two && k1.ndof == 1;
            for (int r = 0; r < 3; r++) {
                worst_f = fmax(worst_f, fabs(f1[r] - lf * FLOOR[r]) / (m * 9.81));
                worst_f = fmax(worst_f, fabs(f2[r] - lw * wall[r]) / (m * 9.81));
                split = split && fabs(f1[r] + f2[r] - f[r]) <= 1e-12 * m * 9.81;
            }
        }
        CHECK(lines == n, "step %d: %d of %d vertices on the line (ndof 2, both planes held)", k, lines, n);
        CHECK(worst_x <= 1e-9, "step %d: a vertex %.3g m off the line's closed form", k, worst_x);
        CHECK(worst_v <= 1e-8, "step %d: a velocity %.3g m/s off (0, k h g_y, 0)", k, worst_v);
        CHECK(worst_f <= 1e-6, "step %d: a plane's force off lambda n by %.3g of the weight", k, worst_f);
        CHECK(split, "step %d: the planes' forces do not sum to cloth_constraint_force", k);
    }
    free(p);
    cloth_destroy(c);
}

/* gravity off the wall: the wall, a contact set so, pulls once the floor (the
 * second) holds too, and lets go alone; the vertex slides on the floor */
static void wall_pulls(void)
{
    const double g[3] = {-5.0, 2.0, -9.81};
    double *p = NULL;
    cloth *c = make(CLOTH_NEWTON, g, &p);
    if (!c) return;
    int n = cloth_vertex_count(c);
    for (int i = 0; i < n; i++) {
        cloth_constraint k = {.vertex = i, .ndof = 1};
        memcpy(k.axis, wall, sizeof k.axis);
        memcpy(k.target, p + 3 * i, sizeof k.target);
        CHECK(cloth_set_constraint(c, &k) == CLOTH_OK, "wall constraint: %s", cloth_last_error(c));
        cloth_set_contact(c, i, wall, p + 3 * i);
        cloth_set_contact_pull(c, i, 0.0);
        cloth_set_contact_second(c, i, FLOOR, p + 3 * i);
    }
    cloth_step_stats st;
    CHECK(cloth_step(c, H, &st) == CLOTH_OK, "step: %s", cloth_last_error(c));
    /* each vertex: the floor made, then the wall let go */
    CHECK(st.contacts_decided == 2 * n, "%d contact changes, expected 2 a vertex (%d)", st.contacts_decided, 2 * n);
    double worst_x = 0.0, worst_v = 0.0, worst_f = 0.0;
    int ok = 0;
    for (int i = 0; i < n; i++) {
        const double *x = cloth_positions(c) + 3 * i, *v = cloth_velocities(c) + 3 * i;
        double m = cloth_masses(c)[i], f1[3], f2[3], lf, lw;
        cloth_constraint k1, kk;
        int two = 0;
        wedge_forces(m, g, &lf, &lw);
        cloth_get_constraint(c, i, &kk);
        cloth_get_contact_planes(c, i, &k1, &two, f1, f2);
        ok += kk.ndof == 1 && fabs(dot3(kk.axis, FLOOR) - 1.0) <= 1e-15 && two && k1.ndof == 0;
        double v_expect[3] = {H * g[0], H * g[1], 0.0};
        for (int r = 0; r < 3; r++) {
            worst_v = fmax(worst_v, fabs(v[r] - v_expect[r]));
            worst_x = fmax(worst_x, fabs(x[r] - p[3 * i + r] - H * v_expect[r]));
            worst_f = fmax(worst_f, fabs(f2[r] + m * g[2] * FLOOR[r]) / (m * 9.81));
            worst_f = fmax(worst_f, fabs(f1[r]) / (m * 9.81));
        }
    }
    CHECK(ok == n, "%d of %d vertices on the floor alone (the wall let go, the second held)", ok, n);
    CHECK(worst_v <= 1e-8, "a velocity %.3g m/s off (h g_x, h g_y, 0)", worst_v);
    CHECK(worst_x <= 1e-9, "a vertex %.3g m off its closed form", worst_x);
    CHECK(worst_f <= 1e-6, "the floor's force off -m g_z, or the wall's not zero, by %.3g of the weight", worst_f);
    free(p);
    cloth_destroy(c);
}

/* the floor alone as the second candidate of free vertices: held on it;
 * and a second within 0.6 deg of the vertex's own plane is not taken */
static void second_alone_and_parallel(void)
{
    const double g[3] = {0.0, 0.0, -9.81};
    double *p = NULL;
    cloth *c = make(CLOTH_NEWTON, g, &p);
    if (!c) return;
    int n = cloth_vertex_count(c);
    for (int k = 0; k < 3; k++) {
        cloth_release_all(c);
        for (int i = 0; i < n; i++) cloth_set_contact_second(c, i, FLOOR, p + 3 * i);
        CHECK(cloth_step(c, H, NULL) == CLOTH_OK, "step %d: %s", k, cloth_last_error(c));
    }
    double worst = 0.0;
    for (int i = 0; i < n; i++) {
        int two = 0;
        cloth_get_contact_planes(c, i, NULL, &two, NULL, NULL);
        CHECK(two, "vertex %d: the second plane does not hold it", i);
        worst = fmax(worst, fabs(cloth_positions(c)[3 * i + 2] - p[3 * i + 2]) + fabs(cloth_velocities(c)[3 * i + 2]));
    }
    CHECK(worst <= 1e-9, "resting on its second plane a vertex is %.3g off (z, v_z)", worst);
    /* on the floor (a plane constraint), a second tilted 0.3 deg: left alone,
     * the vertex falls through it (it is no plane of the step) */
    double t = 0.3 * M_PI / 180.0, tilted[3] = {sin(t), 0.0, cos(t)};
    cloth_release_all(c);
    for (int i = 0; i < n; i++) {
        double q[3] = {p[3 * i], p[3 * i + 1], p[3 * i + 2] + 0.01};
        cloth_constraint k = {.vertex = i, .ndof = 1};
        memcpy(k.axis, FLOOR, sizeof k.axis);
        memcpy(k.target, p + 3 * i, sizeof k.target);
        cloth_set_constraint(c, &k);
        cloth_set_contact_second(c, i, tilted, q);
    }
    cloth_step_stats st;
    CHECK(cloth_step(c, H, &st) == CLOTH_OK, "parallel: %s", cloth_last_error(c));
    CHECK(st.contacts_decided == 0, "a second plane 0.3 deg from the vertex's own was taken (%d)", st.contacts_decided);
    free(p);
    cloth_destroy(c);
}

/* CLOTH_LINEARIZED: the wedge's line as a constraint meets the closed form */
static void linearized_line(void)
{
    const double g[3] = {5.0, 2.0, -9.81};
    double *p = NULL;
    cloth *c = make(CLOTH_LINEARIZED, g, &p);
    if (!c) return;
    int n = cloth_vertex_count(c);
    double t[3] = {FLOOR[1] * wall[2] - FLOOR[2] * wall[1], FLOOR[2] * wall[0] - FLOOR[0] * wall[2],
                   FLOOR[0] * wall[1] - FLOOR[1] * wall[0]};
    for (int k = 1; k <= STEPS; k++) {
        for (int i = 0; i < n; i++) {
            cloth_constraint q = {.vertex = i, .ndof = 2};
            memcpy(q.axis, t, sizeof q.axis);
            memcpy(q.target, p + 3 * i, sizeof q.target);
            cloth_set_constraint(c, &q);
        }
        CHECK(cloth_step(c, H, NULL) == CLOTH_OK, "linearised step %d: %s", k, cloth_last_error(c));
        double worst_x, worst_v, worst_f = 0.0;
        line_errors(c, p, g, k, &worst_x, &worst_v);
        for (int i = 0; i < n; i++) {
            double m = cloth_masses(c)[i], f[3], lf, lw;
            wedge_forces(m, g, &lf, &lw);
            cloth_constraint_force(c, i, f);
            for (int r = 0; r < 3; r++) worst_f = fmax(worst_f, fabs(f[r] - lf * FLOOR[r] - lw * wall[r]) / (m * 9.81));
        }
        CHECK(worst_x <= 1e-9, "linearised step %d: a vertex %.3g m off the line's closed form", k, worst_x);
        CHECK(worst_v <= 1e-8, "linearised step %d: a velocity %.3g m/s off (0, k h g_y, 0)", k, worst_v);
        CHECK(worst_f <= 1e-6, "linearised step %d: the force off lambda_f n_f + lambda_w n_w by %.3g", k, worst_f);
    }
    free(p);
    cloth_destroy(c);
}

static void bad_input(void)
{
    const double g[3] = {0.0, 0.0, -9.81};
    double *p = NULL;
    cloth *c = make(CLOTH_NEWTON, g, &p);
    if (!c) return;
    const double zero[3] = {0, 0, 0}, nan3[3] = {NAN, 0, 1};
    CHECK(cloth_set_contact_second(c, -1, FLOOR, p) == CLOTH_EINVAL && strstr(cloth_last_error(c), "out of range"),
          "vertex -1: %s", cloth_last_error(c));
    CHECK(cloth_set_contact_second(c, 0, NULL, p) == CLOTH_EINVAL && strstr(cloth_last_error(c), "normal"),
          "NULL normal: %s", cloth_last_error(c));
    CHECK(cloth_set_contact_second(c, 0, FLOOR, NULL) == CLOTH_EINVAL && strstr(cloth_last_error(c), "point"),
          "NULL point: %s", cloth_last_error(c));
    CHECK(cloth_set_contact_second(c, 0, zero, p) == CLOTH_EINVAL && strstr(cloth_last_error(c), "non-zero"),
          "zero normal: %s", cloth_last_error(c));
    CHECK(cloth_set_contact_second(c, 0, nan3, p) == CLOTH_EINVAL && strstr(cloth_last_error(c), "normal"),
          "NaN normal: %s", cloth_last_error(c));
    CHECK(cloth_set_contact_second(NULL, 0, FLOOR, p) == CLOTH_EINVAL, "NULL cloth");
    CHECK(cloth_get_contact_planes(c, 99, NULL, NULL, NULL, NULL) == CLOTH_EINVAL, "vertex 99 accepted");
    CHECK(cloth_get_contact_planes(NULL, 0, NULL, NULL, NULL, NULL) == CLOTH_EINVAL, "NULL cloth accepted");
    free(p);
    cloth_destroy(c);
}

int main(void)
{
    double b = 30.0 * M_PI / 180.0;
    wall[0] = -cos(b), wall[1] = 0.0, wall[2] = sin(b);
    both_push();
    wall_pulls();
    second_alone_and_parallel();
    linearized_line();
    bad_input();
    return check_summary();
}
