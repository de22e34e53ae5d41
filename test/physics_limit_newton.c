/* Physics: the elongation limit held by the Newton corrections of a step
 * with a rigid body solved with the cloth (step.c's multipliers).
 *
 * The set-up of physics_newton: a 3 kg body holds the centre of a 9x9
 * cloth (cotton without plasticity: delta 0.03, k_delta 100; no gravity,
 * CG tolerance 1e-6, the post-step projection off) and moves at
 * (6, 0, -6) m/s with its centre of mass 0.2 m off the held vertex; in one
 * step of 1/60 s the links around the centre go far past the limit (0.32
 * without corrections). With the k_delta law alone the converged step
 * leaves them past it (without the multipliers the first and third checks
 * below fail);
 * with the limit held as a constraint (its multipliers updated once the
 * corrections converge, the step corrected again) the step ends with
 *   - every sequential link within (1 + delta) l0 (to 1e-5 of it), measured
 *     by the test from the positions;
 *   - the method's own equation, M (v1 - v0) - h f(x1, v1) = 0 with the
 *     forces of the plain law (cloth_internal_forces), at every free vertex
 *     whose links are all short of the limit, to the corrections' stopping
 *     rule (1e-6 of the uncorrected step's residual): the limit's forces
 *     act only on links at it;
 *   - at the others, the residual made by pulls along their links at the
 *     limit: the tensions t_e >= 0 fitted by the test (projected gradient
 *     on the non-negative least squares) explain it to 1e-3 of its size;
 *   - momentum, body + cloth, conserved (the limit's forces are internal)
 *     and the body's velocity change made by the held vertex's constraint
 *     force, m_b du = -h f_c, both to the solver's tolerance.
 * Without corrections (newton_iterations 0) the links end far past the
 * limit (checked, so that the case tests something).
 */
#include <math.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define N 9
#define NV (N * N)
#define H (1.0 / 60.0)
#define BODY_MASS 3.0

typedef struct link {
    int i, j;
    double rest;
} link;

/* the sequential links of an N x N grid: right, down and both diagonals */
static int grid_links(link *L, double spacing)
{
    int n = 0;
    for (int r = 0; r < N; r++)
        for (int c = 0; c < N; c++) {
            int i = r * N + c;
            if (c + 1 < N) L[n++] = (link){i, i + 1, spacing};
            if (r + 1 < N) L[n++] = (link){i, i + N, spacing};
            if (r + 1 < N && c + 1 < N) L[n++] = (link){i, i + N + 1, spacing * sqrt(2.0)};
            if (r + 1 < N && c > 0) L[n++] = (link){i, i + N - 1, spacing * sqrt(2.0)};
        }
    return n;
}

static double dist(const double *x, int i, int j, double u[3])
{
    double d = 0.0;
    for (int a = 0; a < 3; a++) {
        u[a] = x[3 * j + a] - x[3 * i + a];
        d += u[a] * u[a];
    }
    d = sqrt(d);
    for (int a = 0; a < 3; a++) u[a] /= d;
    return d;
}

static void run(int newton_iterations, double *strain_out, double *away_out, double *total_out)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = CLOTH_LINEARIZED; /* the linearised step's corrections are tested */
    d.rows = d.cols = N;
    d.gravity[0] = d.gravity[1] = d.gravity[2] = 0.0;
    d.material = cloth_material_preset(CLOTH_ELASTIC);
    d.solver.method = CLOTH_BACKWARD_EULER;
    d.solver.strain_limit_iterations = 0;
    d.solver.cg_tolerance = 1e-6;
    d.solver.cg_max_iterations = 20000;
    d.solver.max_substep_halvings = 0;
    d.solver.newton_iterations = newton_iterations;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return;
    const double delta = d.material.delta, spacing = d.width / (N - 1);
    int ctr = (N / 2) * N + N / 2;
    const double *m = cloth_masses(c);
    const double vb[3] = {6.0, 0.0, -6.0};
    CHECK(cloth_set_vertex(c, ctr, cloth_positions(c) + 3 * ctr, vb) == CLOTH_OK, "set vertex");
    cloth_body b = {.mass = BODY_MASS, .inertia = {0.05, 0, 0, 0, 0.05, 0, 0, 0, 0.05}};
    const double *x = cloth_positions(c);
    for (int a = 0; a < 3; a++) b.com[a] = x[3 * ctr + a] + (a == 2 ? 0.2 : 0.0);
    CHECK(cloth_set_bodies(c, &b, 1) == CLOTH_OK, "set_bodies: %s", cloth_last_error(c));
    double target[3];
    for (int a = 0; a < 3; a++) target[a] = x[3 * ctr + a] + H * vb[a];
    CHECK(cloth_pin(c, ctr, target) == CLOTH_OK, "pin: %s", cloth_last_error(c));
    CHECK(cloth_hold_by_body(c, ctr, 0) == CLOTH_OK, "hold: %s", cloth_last_error(c));
    double v0[3 * NV];
    memcpy(v0, cloth_velocities(c), sizeof v0);
    cloth_step_stats st;
    if (!CHECK(cloth_step(c, H, &st) == CLOTH_OK, "step (newton_iterations %d): %s", newton_iterations,
               cloth_last_error(c))) {
        cloth_destroy(c);
        return;
    }
    x = cloth_positions(c);
    const double *v1 = cloth_velocities(c);
    static link L[4 * NV];
    int nl = grid_links(L, spacing), at[4 * NV], nat = 0;
    unsigned char touches[NV] = {0};
    double worst = 0.0, u[3];
    for (int e = 0; e < nl; e++) {
        double s = dist(x, L[e].i, L[e].j, u) / L[e].rest - 1.0;
        if (s > worst) worst = s;
        if (s > delta - 1e-4 * (1.0 + delta)) { /* at the limit */
            at[nat++] = e;
            touches[L[e].i] = touches[L[e].j] = 1;
        }
    }
    *strain_out = worst;
    CHECK(fabs(worst - cloth_max_strain(c)) < 1e-12, "strain: the test's %.6f, the library's %.6f", worst,
          cloth_max_strain(c));
    /* the method's residual r = M dv - h f at the free vertices */
    double f[3 * NV], r[3 * NV], away = 0.0, near = 0.0;
    cloth_internal_forces(c, f);
    for (int i = 0; i < NV; i++)
        for (int a = 0; a < 3; a++) {
            r[3 * i + a] = i == ctr ? 0.0 : m[i] * (v1[3 * i + a] - v0[3 * i + a]) - H * f[3 * i + a];
            if (i == ctr) continue;
            if (touches[i]) near += r[3 * i + a] * r[3 * i + a];
            else away += r[3 * i + a] * r[3 * i + a];
        }
    *away_out = sqrt(away);
    *total_out = sqrt(away + near);
    if (newton_iterations == 0) {
        printf("newton_iterations 0: max strain %.4f, residual %.3g N s\n", worst, sqrt(away + near));
        cloth_destroy(c);
        return;
    }
    /* tensions t >= 0 on the links at the limit with r = sum_e t_e g_e (g_e: +u_e at i, -u_e at j, the pull of a
     * stretched link, times h, folded into t), fitted by projected gradient descent on |G t - r|^2 over the free
     * rows */
    static double t[4 * NV], gu[4 * NV][3];
    double res[3 * NV];
    for (int k = 0; k < nat; k++) {
        dist(x, L[at[k]].i, L[at[k]].j, gu[k]);
        t[k] = 0.0;
    }
    const double lip = 2.0 * 8.0; /* >= |G^T G|: two unit blocks a column, at most 8 links a vertex */
    for (int sweep = 0; sweep < 200000; sweep++) {
        memcpy(res, r, sizeof res);
        for (int k = 0; k < nat; k++)
            for (int a = 0; a < 3; a++) {
                res[3 * L[at[k]].i + a] -= t[k] * gu[k][a];
                res[3 * L[at[k]].j + a] += t[k] * gu[k][a];
            }
        res[3 * ctr] = res[3 * ctr + 1] = res[3 * ctr + 2] = 0.0;
        for (int k = 0; k < nat; k++) {
            double g = 0.0;
            for (int a = 0; a < 3; a++) g += gu[k][a] * (res[3 * L[at[k]].i + a] - res[3 * L[at[k]].j + a]);
            t[k] += g / lip;
            if (t[k] < 0.0) t[k] = 0.0;
        }
    }
    double fit = 0.0;
    for (int i = 0; i < NV; i++)
        if (touches[i] && i != ctr)
            for (int a = 0; a < 3; a++) fit += res[3 * i + a] * res[3 * i + a];
    double du[6], fc[3], dp = 0.0, p0 = 0.0, react = 0.0, dun = 0.0;
    cloth_body_velocity_change(c, 0, du);
    cloth_constraint_force(c, ctr, fc);
    for (int a = 0; a < 3; a++) {
        double P = BODY_MASS * du[a];
        for (int i = 0; i < NV; i++) P += m[i] * (v1[3 * i + a] - v0[3 * i + a]);
        dp += P * P;
        p0 += BODY_MASS * vb[a] * BODY_MASS * vb[a];
        double e = BODY_MASS * du[a] + H * fc[a];
        react += e * e;
        dun += du[a] * du[a];
    }
    printf("newton_iterations %d: %d corrections, max strain %.6f, %d links at the limit; residual away from it "
           "%.3g N s, at it %.3g N s, of which the fitted pulls leave %.3g; momentum %.2g, body reaction %.2g\n",
           newton_iterations, st.newton, worst, nat, sqrt(away), sqrt(near), sqrt(fit / near), sqrt(dp / p0),
           sqrt(react / dun) / BODY_MASS);
    CHECK(worst <= delta + 1e-5 * (1.0 + delta), "max strain %.6f > delta %.3f (+1e-5 of the limit)", worst, delta);
    CHECK(nat > 0, "no link at the limit: the case does not test it");
    CHECK(sqrt(fit / near) < 1e-3, "pulls along the links at the limit explain the residual there to %.3g only",
          sqrt(fit / near));
    CHECK(sqrt(dp / p0) < 1e-5, "momentum changed by %.3g of the body's", sqrt(dp / p0));
    CHECK(sqrt(react / dun) / BODY_MASS < 1e-4, "m_b du = -h f_c to %.3g", sqrt(react / dun) / BODY_MASS);
    cloth_destroy(c);
}

int main(void)
{
    double off = 0.0, on = 0.0, off_away = 0.0, off_total = 0.0, on_away = 0.0, on_total = 0.0;
    run(0, &off, &off_away, &off_total);
    run(64, &on, &on_away, &on_total);
    CHECK(off > 0.03 + 0.05, "without corrections the links are not past the limit: strain %.4f", off);
    /* the corrections stop when the free rows' residual (the limit's
     * forces included) is within cg_tolerance of the uncorrected step's */
    printf("away from the limit the corrected step's residual is %.3g of the uncorrected one's\n", on_away / off_total);
    CHECK(on_away <= 1.01e-6 * off_total,
          "the method's equation away from the limit: residual %.3g of the "
          "uncorrected step's",
          on_away / off_total);
    return check_summary();
}
