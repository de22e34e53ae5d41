/* Physics: Newton corrections of a step with a rigid body solved with the
 * cloth (solver.newton_iterations, step.c).
 *
 * A 3 kg body holds the centre of a 9x9 elastic cloth (alpha 0, no
 * gravity, elongation limit off, CG tolerance 1e-6); its centre of mass is
 * 0.2 m off the held vertex (a lever arm: the body turns too), and it moves
 * at (2, 0, -2) m/s, along the cloth and across it. In one step of 1/60 s
 * the links around the centre go far past the limit (delta 3%), where they
 * stiffen 100-fold: the single linearisation about the step's start does
 * not see that. The step is the solution of the method's own equation at
 * every free vertex, which the test evaluates itself with the forces at
 * the step's end (cloth_internal_forces), relative to beta h |f|:
 *   backward Euler:  M (v1 - v0) - h f(x1, v1) = 0
 *   BDF2 (a second step of the same h):
 *                    M (v2 - v1) - M (v1 - v0) / 3 - 2/3 h f(x2, v2) = 0
 *   - without corrections the residual is as large as the forces (the
 *     linearisation's error); with them it falls to cg_tolerance (1e-6) of
 *     that, and the links end less stretched;
 *   - with backward Euler, momentum, body + cloth, is conserved either way
 *     (no outside force), to the solver's tolerance; with both methods the
 *     body's velocity change is made by the held vertex's constraint force,
 *     m_b du = -h f_c (after corrections the constraint force is the final
 *     residual's, not the first solve's).
 * Also: newton_iterations outside [0, 64] is refused.
 */
#include <math.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define N 9
#define H (1.0 / 60.0)
#define BODY_MASS 3.0

typedef struct outcome {
    double residual; /* the method's equation at the free vertices, relative to beta h |f| */
    double absres;   /* the same, absolute (N s) */
    double strain;   /* max sequential strain after the step */
    double momentum; /* |P1 - P0| / |P0| over the step checked */
    double reaction; /* |m_b du + h f_c| / |m_b du| */
    int newton;      /* corrections taken in the step checked */
} outcome;

/* the body's pin on the centre vertex for a step from its current place */
static void hold(cloth *c, int ctr, const double vb[3])
{
    const double *x = cloth_positions(c);
    double target[3];
    for (int a = 0; a < 3; a++) target[a] = x[3 * ctr + a] + H * vb[a];
    CHECK(cloth_pin(c, ctr, target) == CLOTH_OK, "pin: %s", cloth_last_error(c));
    CHECK(cloth_hold_by_body(c, ctr, 0) == CLOTH_OK, "hold: %s", cloth_last_error(c));
}

/* bdf2 0: one backward Euler step checked; 1: a backward Euler step, then
 * the BDF2 step checked */
static int run(int bdf2, int newton_iterations, outcome *o)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = CLOTH_LINEARIZED; /* the linearised step's corrections are tested */
    d.rows = d.cols = N;
    d.gravity[0] = d.gravity[1] = d.gravity[2] = 0.0;
    d.material = cloth_material_preset(CLOTH_ELASTIC);
    d.solver.method = bdf2 ? CLOTH_BDF2 : CLOTH_BACKWARD_EULER;
    d.solver.strain_limit_iterations = 0;
    d.solver.cg_tolerance = 1e-6;
    d.solver.cg_max_iterations = 20000;
    d.solver.max_substep_halvings = 0;
    /* the step before the one checked (BDF2) is the same in both runs */
    d.solver.newton_iterations = bdf2 ? 64 : newton_iterations;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return 0;
    int n = cloth_vertex_count(c), ctr = (N / 2) * N + N / 2;
    const double *m = cloth_masses(c);
    const double vb[3] = {2.0, 0.0, -2.0};
    CHECK(cloth_set_vertex(c, ctr, cloth_positions(c) + 3 * ctr, vb) == CLOTH_OK, "set vertex");
    double vprev[3 * N * N], v0[3 * N * N], u[6] = {vb[0], vb[1], vb[2], 0, 0, 0};
    int ok = 1;
    cloth_step_stats st;
    for (int step = 0; step <= bdf2 && ok; step++) {
        /* the body at its velocity so far, centre of mass 0.2 m above the vertex */
        cloth_body b = {.mass = BODY_MASS, .inertia = {0.05, 0, 0, 0, 0.05, 0, 0, 0, 0.05}};
        const double *x = cloth_positions(c);
        for (int a = 0; a < 3; a++) b.com[a] = x[3 * ctr + a] + (a == 2 ? 0.2 : 0.0);
        CHECK(cloth_set_bodies(c, &b, 1) == CLOTH_OK, "set_bodies: %s", cloth_last_error(c));
        double vpt[3];
        /* the held point's velocity: u_lin + w x r, r = vertex - com */
        double r[3] = {0.0, 0.0, -0.2};
        vpt[0] = u[0] + u[4] * r[2] - u[5] * r[1];
        vpt[1] = u[1] + u[5] * r[0] - u[3] * r[2];
        vpt[2] = u[2] + u[3] * r[1] - u[4] * r[0];
        hold(c, ctr, vpt);
        if (step == bdf2) {
            cloth_solver sv = cloth_get_desc(c).solver;
            sv.newton_iterations = newton_iterations;
            CHECK(cloth_set_solver(c, &sv) == CLOTH_OK, "set_solver: %s", cloth_last_error(c));
        }
        memcpy(vprev, v0, sizeof v0);
        memcpy(v0, cloth_velocities(c), sizeof v0);
        ok = CHECK(cloth_step(c, H, &st) == CLOTH_OK, "step %d (bdf2 %d, newton_iterations %d): %s", step, bdf2,
                   newton_iterations, cloth_last_error(c));
        if (ok && step < bdf2) {
            double du[6];
            cloth_body_velocity_change(c, 0, du);
            for (int k = 0; k < 6; k++) u[k] += du[k];
        }
    }
    if (ok) {
        double beta = bdf2 ? 2.0 / 3.0 : 1.0;
        const double *v1 = cloth_velocities(c);
        double f[3 * N * N], num = 0.0, den = 0.0;
        cloth_internal_forces(c, f);
        for (int i = 0; i < n; i++) {
            if (i == ctr) continue;
            for (int a = 0; a < 3; a++) {
                double r = m[i] * (v1[3 * i + a] - v0[3 * i + a]) - beta * H * f[3 * i + a];
                if (bdf2) r -= m[i] * (v0[3 * i + a] - vprev[3 * i + a]) / 3.0;
                num += r * r;
                den += beta * H * f[3 * i + a] * beta * H * f[3 * i + a];
            }
        }
        o->residual = sqrt(num / den);
        o->absres = sqrt(num);
        o->strain = cloth_max_strain(c);
        o->newton = st.newton;
        double du[6], fc[3], dp = 0.0, react = 0.0, dun = 0.0, p0 = 0.0;
        cloth_body_velocity_change(c, 0, du);
        cloth_constraint_force(c, ctr, fc);
        for (int a = 0; a < 3; a++) {
            double P = BODY_MASS * du[a];
            for (int i = 0; i < n; i++) P += m[i] * (v1[3 * i + a] - v0[3 * i + a]);
            dp += P * P;
            double e = BODY_MASS * du[a] + H * fc[a];
            react += e * e;
            dun += du[a] * du[a];
            p0 += BODY_MASS * u[a] * BODY_MASS * u[a];
        }
        o->momentum = sqrt(dp / p0);
        o->reaction = dun > 0.0 ? sqrt(react / dun) / BODY_MASS : INFINITY;
        printf("%s, newton_iterations %d: %d corrections, %d CG iterations, residual %.3g of beta h|f|, max strain "
               "%.4f, momentum %.2g, body reaction %.2g (|du| %.3g m/s)\n",
               bdf2 ? "BDF2 (second step)" : "backward Euler", newton_iterations, st.newton, st.iterations, o->residual,
               o->strain, o->momentum, o->reaction, sqrt(dun));
    }
    cloth_destroy(c);
    return ok;
}

static void bad_input(void)
{
    cloth_solver s = cloth_default_desc().solver;
    s.nonlinear = CLOTH_LINEARIZED; /* where 0 corrections are allowed */
    cloth_error err;
    const int bad[] = {-1, 257, -1000000};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        s.newton_iterations = bad[k];
        CHECK(cloth_solver_validate(&s, &err) == CLOTH_EINVAL, "newton_iterations %d accepted", bad[k]);
        CHECK(strstr(err.message, "newton_iterations") != NULL, "message does not name the field: %s", err.message);
    }
    s.newton_iterations = 0;
    CHECK(cloth_solver_validate(&s, &err) == CLOTH_OK, "newton_iterations 0 refused: %s", err.message);
    CHECK(cloth_default_desc().solver.newton_iterations == 16, "default newton_iterations %d",
          cloth_default_desc().solver.newton_iterations);
}

int main(void)
{
    for (int bdf2 = 0; bdf2 <= 1; bdf2++) {
        outcome off = {0}, on = {0};
        const char *m = bdf2 ? "BDF2" : "backward Euler";
        if (!run(bdf2, 0, &off) || !run(bdf2, 64, &on)) continue;
        CHECK(off.newton == 0, "%s: corrections taken with newton_iterations 0: %d", m, off.newton);
        CHECK(off.residual > 0.1, "%s: without corrections the step is not the method's: residual %.3g", m,
              off.residual);
        CHECK(on.newton >= 1, "%s: no correction taken", m);
        /* the step stops correcting when the free rows' residual is within
         * cg_tolerance of the residual the uncorrected step leaves */
        printf("%s: the corrected step's residual is %.3g of the uncorrected one's\n", m, on.absres / off.absres);
        CHECK(on.absres <= 1.01e-6 * off.absres, "%s: with corrections the residual is %.3g of the uncorrected one's",
              m, on.absres / off.absres);
        CHECK(on.strain < off.strain, "%s: corrected strain %.4f, uncorrected %.4f", m, on.strain, off.strain);
        /* backward Euler conserves momentum to the solver's tolerance;
         * BDF2's cloth rows carry the history term M (v1 - v0) / 3, its body
         * rows none (bodies.c), so its step exchanges momentum with the past */
        if (!bdf2)
            CHECK(off.momentum < 1e-5 && on.momentum < 1e-5, "%s: momentum: %.3g without, %.3g with", m, off.momentum,
                  on.momentum);
        /* to the solver's tolerance: the body's row is solved with the cloth's */
        CHECK(off.reaction < 1e-4 && on.reaction < 1e-4, "%s: m_b du = -h f_c: %.3g without, %.3g with", m,
              off.reaction, on.reaction);
    }
    bad_input();
    return check_summary();
}
