/* Physics: rigid bodies solved with the cloth (cloth_body, cloth.h).
 *
 * 1. Closed forms. A 3x3 cloth at rest, every vertex pinned to one body whose
 *    centre of mass is the cloth's centre: cloth and body then move as one
 *    rigid body, and the springs, at rest length, add nothing to A dv for a
 *    rigid velocity change (it is perpendicular to every link). So
 *      linear:   du = h (F + m_c g) / (m_b + m_c)
 *      angular:  dw = h (I_b + I_c)^-1 tau,  I_c = sum m_i (|r_i|^2 I - r_i r_i^T)
 *    and the pins' forces on the cloth sum to m_c du / h - m_c g.
 * 2. A light body thrown with a cloth (no gravity): a 0.05 kg body, a quarter
 *    of the cloth's mass, holding two corners of a 21x21 cotton cloth, both
 *    thrown at 2 m/s and spinning at 3 rad/s. Explicit coupling fails here within a few steps
 *    (the 0.5 kg body of plugin_coupling_light did); solved together, every
 *    step succeeds and the total linear momentum, body + cloth, is conserved
 *    to the CG tolerance (1e-10 relative: we allow 1e-7 of |P0|), with the
 *    elongation limit off and on (its projection moves the body too), and
 *    with the CG capped so that a step fails whole and is retried in
 *    substeps (the body's du carried from substep to substep).
 *    The thrown case also by Newton (CLOTH_NEWTON), momentum as above.
 * 3. By Newton, a 0.2 kg body hanging from the middle of an 11x11 cloth
 *    pinned at its corners: no line search cuts a step in 60 steps. The
 *    potential's value and the Newton step must count the bodies alike; a
 *    mismatch of u^T M u in the value made the search stall every step.
 * 4. Bad input: invalid bodies and constraints naming missing bodies are
 *    rejected and change nothing.
 */
#include <math.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

static void cross3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* solve the 3x3 system M x = b by Cramer's rule (the test's own) */
static void solve3(const double M[9], const double b[3], double x[3])
{
    double det = M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
                 M[2] * (M[3] * M[7] - M[4] * M[6]);
    for (int k = 0; k < 3; k++) {
        double A[9];
        memcpy(A, M, sizeof A);
        for (int r = 0; r < 3; r++) A[3 * r + k] = b[r];
        x[k] = (A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
                A[2] * (A[3] * A[7] - A[4] * A[6])) /
               det;
    }
}

static cloth *make(int n, double tol, const double g[3])
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = n;
    memcpy(d.gravity, g, sizeof d.gravity);
    d.solver.cg_tolerance = d.solver.newton_cg_tolerance = tol;
    d.solver.newton_tolerance = 1e-12;
    d.solver.cg_max_iterations = 2000;
    cloth *c = NULL;
    cloth_error err;
    if (cloth_create(&d, &c, &err) != CLOTH_OK) fprintf(stderr, "create: %s\n", err.message);
    return c;
}

static void closed_forms(void)
{
    const double h = 1.0 / 60.0, g[3] = {0.3, -0.2, -9.81};
    cloth *c = make(3, 1e-13, g);
    if (!CHECK(c != NULL, "cloth created")) return;
    /* the closed form is the linear model's, levers at the step's start (Newton's
     * held vertices follow the body's rotation within the step) */
    cloth_solver sv = cloth_get_desc(c).solver;
    sv.nonlinear = CLOTH_LINEARIZED;
    cloth_set_solver(c, &sv);
    int n = cloth_vertex_count(c);
    const double *x = cloth_positions(c), *m = cloth_masses(c);
    double mc = 0.0, com[3] = {0, 0, 0};
    for (int i = 0; i < n; i++) {
        mc += m[i];
        for (int a = 0; a < 3; a++) com[a] += m[i] * x[3 * i + a];
    }
    for (int a = 0; a < 3; a++) com[a] /= mc;
    cloth_body b = {.mass = 0.07,
                    .inertia = {0.002, 0, 0, 0, 0.003, 0.0005, 0, 0.0005, 0.004},
                    .force = {0.4, 1.1, -0.3},
                    .torque = {0.01, -0.02, 0.005}};
    memcpy(b.com, com, sizeof com);
    CHECK(cloth_set_bodies(c, &b, 1) == CLOTH_OK, "set_bodies: %s", cloth_last_error(c));
    for (int i = 0; i < n; i++) {
        cloth_constraint k = {.vertex = i, .ndof = 3};
        memcpy(k.target, x + 3 * i, sizeof k.target); /* body at rest: target = where it is */
        CHECK(cloth_set_constraint(c, &k) == CLOTH_OK, "constraint: %s", cloth_last_error(c));
        CHECK(cloth_hold_by_body(c, i, 0) == CLOTH_OK, "hold: %s", cloth_last_error(c));
    }
    /* I_b + I_c, from the positions before the step */
    double I[9];
    memcpy(I, b.inertia, sizeof I);
    for (int i = 0; i < n; i++) {
        double r[3] = {x[3 * i] - com[0], x[3 * i + 1] - com[1], x[3 * i + 2] - com[2]};
        double rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        for (int p = 0; p < 3; p++)
            for (int q = 0; q < 3; q++) I[3 * p + q] += m[i] * ((p == q) * rr - r[p] * r[q]);
    }
    cloth_step_stats st;
    CHECK(cloth_step(c, h, &st) == CLOTH_OK, "step: %s", cloth_last_error(c));
    double du[6];
    CHECK(cloth_body_velocity_change(c, 0, du) == CLOTH_OK, "velocity change");
    /* linear */
    for (int a = 0; a < 3; a++) {
        double want = h * (b.force[a] + mc * g[a]) / (b.mass + mc);
        CHECK_REL(du[a], want, 1e-9, 1e-12);
    }
    /* angular: (I_b + I_c) dw = h tau */
    double ht[3] = {h * b.torque[0], h * b.torque[1], h * b.torque[2]}, dw[3];
    solve3(I, ht, dw);
    for (int a = 0; a < 3; a++) CHECK_REL(du[3 + a], dw[a], 1e-9, 1e-12);
    /* the pins' forces on the cloth: m_c du / h - m_c g */
    double fs[3] = {0, 0, 0}, f[3];
    for (int i = 0; i < n; i++) {
        cloth_constraint_force(c, i, f);
        for (int a = 0; a < 3; a++) fs[a] += f[a];
    }
    for (int a = 0; a < 3; a++) CHECK_REL(fs[a], mc * du[a] / h - mc * g[a], 1e-8, 1e-10);
    /* each vertex moved rigidly: v_i = du_lin + dw x r_i (r_i at the step's start) */
    double worst = 0.0;
    const double *v = cloth_velocities(c);
    for (int i = 0; i < n; i++) {
        double r[3], wr[3];
        for (int a = 0; a < 3; a++) r[a] = x[3 * i + a] - h * v[3 * i + a] - com[a];
        cross3(du + 3, r, wr);
        for (int a = 0; a < 3; a++) worst = fmax(worst, fabs(v[3 * i + a] - du[a] - wr[a]));
    }
    CHECK(worst < 1e-12, "held vertices move with the body: worst %.3g m/s", worst);
    printf("closed forms: du = (%.9f %.9f %.9f | %.6f %.6f %.6f)\n", du[0], du[1], du[2], du[3], du[4], du[5]);
    cloth_destroy(c);
}

/* rotate R by the rotation vector a (Rodrigues), R <- rot(a) R */
static void rotate(double R[9], const double a[3])
{
    double t = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    if (t == 0.0) return;
    double k[3] = {a[0] / t, a[1] / t, a[2] / t}, s = sin(t), cth = 1.0 - cos(t);
    double K[9] = {0, -k[2], k[1], k[2], 0, -k[0], -k[1], k[0], 0}, Q[9], out[9];
    for (int p = 0; p < 3; p++)
        for (int q = 0; q < 3; q++) {
            double kk = 0;
            for (int r = 0; r < 3; r++) kk += K[3 * p + r] * K[3 * r + q];
            Q[3 * p + q] = (p == q) + s * K[3 * p + q] + cth * kk;
        }
    for (int p = 0; p < 3; p++)
        for (int q = 0; q < 3; q++)
            out[3 * p + q] = Q[3 * p] * R[q] + Q[3 * p + 1] * R[3 + q] + Q[3 * p + 2] * R[6 + q];
    memcpy(R, out, sizeof out);
}

/* returns the number of the first failed step (-1: none) */
static int light_body_thrown(int limit_iterations, double speed, int halvings, double mb, int cg_max,
                             cloth_nonlinear nonlinear)
{
    const double h = 1.0 / 60.0, zero[3] = {0, 0, 0};
    cloth *c = make(21, 1e-10, zero);
    if (!CHECK(c != NULL, "cloth created")) return 0;
    cloth_desc d = cloth_get_desc(c);
    d.solver.nonlinear = nonlinear;
    d.solver.newton_tolerance = 1e-6;
    d.solver.newton_iterations = 64;
    d.solver.strain_limit_iterations = limit_iterations; /* the projection moves the body too */
    d.solver.max_substep_halvings = halvings;
    if (cg_max > 0) { /* block Jacobi: the multigrid converges within the cap at h too */
        d.solver.cg_max_iterations = cg_max;
        d.solver.precond = CLOTH_PRECOND_BLOCK_JACOBI;
    }
    cloth_set_solver(c, &d.solver);
    int n = cloth_vertex_count(c), cols = cloth_cols(c), held[2] = {0, cols - 1};
    const double *x = cloth_positions(c), *v = cloth_velocities(c), *m = cloth_masses(c);
    double Ib = 4e-3 * mb;
    /* the body's centre midway between the two corners, 5 cm above */
    double com[3], vb[3] = {2.0 * speed, 0.5 * speed, 1.0 * speed}, wb[3] = {0.0, 3.0 * speed, 1.0 * speed},
                   R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, p[2][3];
    for (int a = 0; a < 3; a++) com[a] = 0.5 * (x[3 * held[0] + a] + x[3 * held[1] + a]);
    com[2] += 0.05;
    for (int k = 0; k < 2; k++)
        for (int a = 0; a < 3; a++) p[k][a] = x[3 * held[k] + a] - com[a];
    /* thrown together: the cloth starts with the body's rigid motion */
    double P0[3], mc = 0.0, v0[3 * 21 * 21];
    for (int i = 0; i < n; i++) {
        double r[3] = {x[3 * i] - com[0], x[3 * i + 1] - com[1], x[3 * i + 2] - com[2]}, wr[3];
        cross3(wb, r, wr);
        for (int a = 0; a < 3; a++) v0[3 * i + a] = vb[a] + wr[a];
    }
    if (limit_iterations) memset(v0, 0, sizeof v0); /* with the limit: jerked from rest */
    cloth_set_velocities(c, v0);
    for (int a = 0; a < 3; a++) P0[a] = mb * vb[a];
    for (int i = 0; i < n; i++) {
        mc += m[i];
        for (int a = 0; a < 3; a++) P0[a] += m[i] * v[3 * i + a];
    }
    int steps = 120, failed = -1, substeps0 = 0, newton = 0, cuts = 0;
    double worst = 0.0;
    for (int s = 0; s < steps; s++) {
        cloth_body b = {.mass = mb, .inertia = {Ib, 0, 0, 0, Ib, 0, 0, 0, Ib}};
        memcpy(b.com, com, sizeof com);
        cloth_set_bodies(c, &b, 1);
        for (int k = 0; k < 2; k++) {
            double w[3], vp[3], wr[3];
            for (int a = 0; a < 3; a++) w[a] = R[3 * a] * p[k][0] + R[3 * a + 1] * p[k][1] + R[3 * a + 2] * p[k][2];
            cross3(wb, w, wr);
            cloth_constraint kk = {.vertex = held[k], .ndof = 3};
            for (int a = 0; a < 3; a++) {
                vp[a] = vb[a] + wr[a];
                kk.target[a] = com[a] + w[a] + h * vp[a];
            }
            cloth_set_constraint(c, &kk);
            cloth_hold_by_body(c, held[k], 0);
        }
        cloth_step_stats sst;
        if (cloth_step(c, h, &sst) != CLOTH_OK) {
            failed = s;
            break;
        }
        if (s == 0) substeps0 = sst.substeps;
        newton += sst.newton;
        cuts += sst.line_search_cuts;
        double du[6];
        cloth_body_velocity_change(c, 0, du);
        for (int a = 0; a < 3; a++) {
            vb[a] += du[a];
            wb[a] += du[3 + a];
            com[a] += h * vb[a];
        }
        double hw[3] = {h * wb[0], h * wb[1], h * wb[2]};
        rotate(R, hw);
        double P[3];
        for (int a = 0; a < 3; a++) P[a] = mb * vb[a];
        for (int i = 0; i < n; i++)
            for (int a = 0; a < 3; a++) P[a] += m[i] * v[3 * i + a];
        double e = sqrt((P[0] - P0[0]) * (P[0] - P0[0]) + (P[1] - P0[1]) * (P[1] - P0[1]) +
                        (P[2] - P0[2]) * (P[2] - P0[2]));
        worst = fmax(worst, e);
    }
    double p0 = sqrt(P0[0] * P0[0] + P0[1] * P0[1] + P0[2] * P0[2]);
    CHECK(worst <= 1e-7 * p0, "momentum body + cloth: worst drift %.3g N s of %.3g", worst, p0);
    printf("light body (%.2f kg, cloth %.2f kg) thrown, elongation limit %s: %d steps, momentum drift %.2e of "
           "|P0| %.3f N s, max strain %.4f\n",
           mb, mc, limit_iterations ? "on" : "off", failed < 0 ? steps : failed, worst / p0, p0, cloth_max_strain(c));
    if (halvings > 0) printf("  (first step taken in %d substeps)\n", substeps0);
    if (nonlinear == CLOTH_NEWTON)
        printf("  by Newton: %d iterations, %d shortened by the line search\n", newton, cuts);
    cloth_destroy(c);
    return failed;
}


/* A 0.2 kg body hanging from the middle of an 11x11 cloth pinned at its
 * corners, gravity on both, by Newton, h = 1/60: returns the line search's
 * cuts over 60 steps (*newton: the iterations), -1 if a step failed. */
static int newton_hanging_body(int *newton)
{
    const double h = 1.0 / 60.0, g[3] = {0.0, 0.0, -9.81};
    cloth *c = make(11, 1e-10, g);
    if (!CHECK(c != NULL, "cloth created")) return -1;
    cloth_desc d = cloth_get_desc(c);
    d.solver.nonlinear = CLOTH_NEWTON;
    d.solver.newton_tolerance = 1e-6;
    d.solver.newton_iterations = 64;
    d.solver.max_substep_halvings = 0;
    cloth_set_solver(c, &d.solver);
    int n = cloth_vertex_count(c), mid = n / 2, corner[4] = {0, 10, n - 11, n - 1};
    const double *x = cloth_positions(c);
    for (int k = 0; k < 4; k++) cloth_pin(c, corner[k], x + 3 * corner[k]);
    double com[3] = {x[3 * mid], x[3 * mid + 1], x[3 * mid + 2] - 0.05}, vb[3] = {0, 0, 0};
    const double mb = 0.2, Ib = 1e-4;
    int cuts = 0, failed = 0;
    *newton = 0;
    for (int s = 0; s < 60 && !failed; s++) {
        cloth_body b = {.mass = mb, .inertia = {Ib, 0, 0, 0, Ib, 0, 0, 0, Ib}, .force = {0, 0, -9.81 * mb}};
        memcpy(b.com, com, sizeof com);
        cloth_set_bodies(c, &b, 1);
        cloth_constraint k = {.vertex = mid, .ndof = 3};
        for (int a = 0; a < 3; a++) k.target[a] = com[a] + h * vb[a] + (a == 2 ? 0.05 : 0.0);
        cloth_set_constraint(c, &k);
        cloth_hold_by_body(c, mid, 0);
        cloth_step_stats st;
        failed = cloth_step(c, h, &st) != CLOTH_OK;
        *newton += st.newton;
        cuts += st.line_search_cuts;
        double du[6];
        cloth_body_velocity_change(c, 0, du);
        for (int a = 0; a < 3; a++) {
            vb[a] += du[a];
            com[a] += h * vb[a];
        }
    }
    cloth_destroy(c);
    return failed ? -1 : cuts;
}

static void bad_input(void)
{
    const double g[3] = {0, 0, -9.81};
    cloth *c = make(3, 1e-3, g);
    if (!CHECK(c != NULL, "cloth created")) return;
    cloth_body good = {.mass = 1, .inertia = {1, 0, 0, 0, 1, 0, 0, 0, 1}};
    cloth_body bad[6];
    for (int k = 0; k < 6; k++) bad[k] = good;
    bad[0].mass = 0;
    bad[1].mass = NAN;
    bad[2].inertia[1] = 0.5; /* not symmetric */
    bad[3].inertia[0] = -1;  /* not definite */
    bad[4].force[2] = INFINITY;
    bad[5].velocity[4] = NAN;
    CHECK(cloth_set_bodies(c, &good, 1) == CLOTH_OK, "a good body");
    for (int k = 0; k < 6; k++) {
        CHECK(cloth_set_bodies(c, &bad[k], 1) == CLOTH_EINVAL, "bad body %d rejected", k);
        CHECK(cloth_body_count(c) == 1, "bodies unchanged after bad body %d", k);
        CHECK(strlen(cloth_last_error(c)) > 0, "message: %s", cloth_last_error(c));
    }
    CHECK(cloth_set_bodies(c, NULL, 1) == CLOTH_EINVAL, "NULL bodies");
    CHECK(cloth_set_bodies(c, &good, -1) == CLOTH_EINVAL, "negative count");
    CHECK(cloth_hold_by_body(c, 0, 0) == CLOTH_EINVAL, "holding a free vertex");
    cloth_constraint k = {.vertex = 0, .ndof = 3};
    CHECK(cloth_set_constraint(c, &k) == CLOTH_OK, "pin");
    CHECK(cloth_hold_by_body(c, 0, 1) == CLOTH_EINVAL, "body 1 of 1");
    CHECK(cloth_hold_by_body(c, 0, -2) == CLOTH_EINVAL, "body -2");
    CHECK(cloth_hold_by_body(c, 9, 0) == CLOTH_EINVAL, "vertex out of range");
    CHECK(cloth_hold_by_body(c, 0, 0) == CLOTH_OK, "held by body 0");
    CHECK(cloth_set_bodies(c, NULL, 0) == CLOTH_EINVAL && cloth_body_count(c) == 1,
          "removing a body that holds a vertex is refused");
    double dv[6];
    CHECK(cloth_body_velocity_change(c, 1, dv) == CLOTH_EINVAL, "index out of range");
    cloth_release_all(c);
    CHECK(cloth_set_bodies(c, NULL, 0) == CLOTH_OK && cloth_body_count(c) == 0, "bodies removed");
    cloth_destroy(c);
}

int main(void)
{
    closed_forms();
    CHECK(light_body_thrown(0, 1.0, 0, 0.05, 0, CLOTH_LINEARIZED) < 0, "thrown, elongation limit off: a step failed");
    CHECK(light_body_thrown(20, 1.0, 0, 0.05, 0, CLOTH_LINEARIZED) < 0, "thrown, elongation limit on: a step failed");
    CHECK(light_body_thrown(0, 1.0, 0, 0.05, 0, CLOTH_NEWTON) < 0, "by Newton, limit off: a step failed");
    /* A step that fails whole at h (CG capped at 80 iterations), retried in substeps of h/16: the body's du must
     * carry from substep to substep (its vertices' targets and the reported du) for momentum to hold as above. */
    int f0 = light_body_thrown(20, 1.0, 0, 0.05, 80, CLOTH_LINEARIZED);
    int f4 = light_body_thrown(20, 1.0, 4, 0.05, 80, CLOTH_LINEARIZED);
    CHECK(f0 == 0, "CG capped, without the retry: the first step should fail (failed at %d)", f0);
    CHECK(f4 < 0, "CG capped, with the retry: step %d failed", f4);
    int newton, cuts = newton_hanging_body(&newton);
    printf("a body hanging from a pinned cloth, by Newton: %d iterations, %d cut by the line search\n", newton, cuts);
    CHECK(cuts == 0,
          "hanging body by Newton: %d of %d iterations cut (the potential's bodies' share disagrees "
          "with the Newton step's)",
          cuts, newton);
    bad_input();
    return check_summary();
}
