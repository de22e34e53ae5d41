/* Physics: Newton corrections of a step with a rigid body solved with the
 * cloth (solver.newton_iterations, step.c).
 *
 * A 3 kg body holds the centre of a 9x9 elastic cloth (alpha 0, no
 * gravity, elongation limit off, CG tolerance 1e-12) and moves at 3 m/s
 * across it. In one step of 1/60 s the centre's links go from their rest
 * length to about 8% past it, far past the limit (delta 3%), where they
 * stiffen 100-fold: the single linearisation about the step's start does
 * not see that. Backward Euler's step is the solution of
 *   M (v1 - v0) = h f(x0 + h v1, v1)
 * at every free vertex; the test evaluates that residual itself, with the
 * forces at the step's end (cloth_internal_forces), relative to h |f|:
 *   - without corrections it is large (the linearisation's error);
 *   - with them it falls to the solver's tolerance, and the centre's links
 *     end less stretched;
 *   - either way momentum, body + cloth, is conserved (no outside force),
 *     and the body's velocity change is made by the held vertex's
 *     constraint force: m_b du = -h f_c (after corrections the constraint
 *     force is the final residual's, not the first solve's).
 * Also: newton_iterations outside [0, 64] is refused.
 */
#include <math.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define N 9
#define H (1.0 / 60.0)
#define BODY_MASS 3.0
#define SPEED 3.0

typedef struct outcome {
    double residual;  /* |M dv - h f(x1, v1)| / |h f(x1, v1)| over free vertices */
    double strain;    /* max sequential strain after the step */
    double momentum;  /* |P1 - P0| / |P0| */
    double reaction;  /* |m_b du + h f_c| / |m_b du| */
    int newton;       /* corrections taken */
} outcome;

static int run(int newton_iterations, outcome *o)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = N;
    d.gravity[0] = d.gravity[1] = d.gravity[2] = 0.0;
    d.material = cloth_material_preset(CLOTH_ELASTIC);
    d.solver.strain_limit_iterations = 0;
    d.solver.cg_tolerance = 1e-12;
    d.solver.cg_max_iterations = 20000;
    d.solver.max_substep_halvings = 0;
    d.solver.newton_iterations = newton_iterations;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return 0;
    int n = cloth_vertex_count(c), ctr = (N / 2) * N + N / 2;
    const double *m = cloth_masses(c);
    double x0[3 * N * N], v0[3 * N * N];
    memcpy(x0, cloth_positions(c), sizeof x0);
    memcpy(v0, cloth_velocities(c), sizeof v0);
    /* the body: centre of mass at the centre vertex, moving across the
     * cloth (along its normal) with the vertex */
    const double vb[3] = {0.0, 0.0, -SPEED};
    cloth_body b = {.mass = BODY_MASS, .inertia = {0.05, 0, 0, 0, 0.05, 0, 0, 0, 0.05}};
    memcpy(b.com, x0 + 3 * ctr, sizeof b.com);
    CHECK(cloth_set_bodies(c, &b, 1) == CLOTH_OK, "set_bodies: %s", cloth_last_error(c));
    CHECK(cloth_set_vertex(c, ctr, x0 + 3 * ctr, vb) == CLOTH_OK, "set vertex");
    memcpy(v0, cloth_velocities(c), sizeof v0);
    double target[3];
    for (int a = 0; a < 3; a++) target[a] = x0[3 * ctr + a] + H * vb[a];
    CHECK(cloth_pin(c, ctr, target) == CLOTH_OK, "pin: %s", cloth_last_error(c));
    CHECK(cloth_hold_by_body(c, ctr, 0) == CLOTH_OK, "hold: %s", cloth_last_error(c));

    cloth_step_stats st;
    int ok = CHECK(cloth_step(c, H, &st) == CLOTH_OK, "step (newton_iterations %d): %s", newton_iterations,
                   cloth_last_error(c));
    if (ok) {
        const double *v1 = cloth_velocities(c);
        double f[3 * N * N], num = 0.0, den = 0.0;
        cloth_internal_forces(c, f);
        for (int i = 0; i < n; i++) {
            if (i == ctr) continue;
            for (int a = 0; a < 3; a++) {
                double r = m[i] * (v1[3 * i + a] - v0[3 * i + a]) - H * f[3 * i + a];
                num += r * r;
                den += H * f[3 * i + a] * H * f[3 * i + a];
            }
        }
        o->residual = sqrt(num / den);
        o->strain = cloth_max_strain(c);
        o->newton = st.newton;
        double du[6], fc[3], dp = 0.0, react = 0.0, p0 = BODY_MASS * SPEED;
        cloth_body_velocity_change(c, 0, du);
        cloth_constraint_force(c, ctr, fc);
        for (int a = 0; a < 3; a++) {
            double P = BODY_MASS * du[a];
            for (int i = 0; i < n; i++) P += m[i] * (v1[3 * i + a] - v0[3 * i + a]);
            dp += P * P;
            double e = BODY_MASS * du[a] + H * fc[a];
            react += e * e;
        }
        o->momentum = sqrt(dp) / p0;
        o->reaction = sqrt(react) / (BODY_MASS * sqrt(du[0] * du[0] + du[1] * du[1] + du[2] * du[2]));
        printf("newton_iterations %d: %d corrections, %d CG iterations, BE residual %.3g of h|f|, max strain "
               "%.4f, momentum %.2g, body reaction %.2g\n",
               newton_iterations, st.newton, st.iterations, o->residual, o->strain, o->momentum, o->reaction);
    }
    cloth_destroy(c);
    return ok;
}

static void bad_input(void)
{
    cloth_solver s = cloth_default_desc().solver;
    cloth_error err;
    const int bad[] = {-1, 65, -1000000};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        s.newton_iterations = bad[k];
        CHECK(cloth_solver_validate(&s, &err) == CLOTH_EINVAL, "newton_iterations %d accepted", bad[k]);
        CHECK(strstr(err.message, "newton_iterations") != NULL, "message does not name the field: %s", err.message);
    }
    s.newton_iterations = 0;
    CHECK(cloth_solver_validate(&s, &err) == CLOTH_OK, "newton_iterations 0 refused: %s", err.message);
    CHECK(cloth_default_desc().solver.newton_iterations == 8, "default newton_iterations %d",
          cloth_default_desc().solver.newton_iterations);
}

int main(void)
{
    outcome off = {0}, on = {0};
    if (run(0, &off) && run(64, &on)) {
        CHECK(off.newton == 0, "corrections taken with newton_iterations 0: %d", off.newton);
        CHECK(off.residual > 0.1, "without corrections the step is not backward Euler's: residual %.3g",
              off.residual);
        CHECK(on.newton >= 1, "no correction taken");
        CHECK(on.residual < 1e-7, "with corrections the residual is the solver's: %.3g", on.residual);
        CHECK(on.strain < off.strain, "corrected strain %.4f, uncorrected %.4f", on.strain, off.strain);
        CHECK(off.momentum < 1e-9 && on.momentum < 1e-9, "momentum: %.3g without, %.3g with", off.momentum,
              on.momentum);
        CHECK(off.reaction < 1e-6 && on.reaction < 1e-6, "m_b du = -h f_c: %.3g without, %.3g with",
              off.reaction, on.reaction);
    }
    bad_input();
    return check_summary();
}
