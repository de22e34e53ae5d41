/* Physics: free fall of an unconstrained cloth, every step against each
 * scheme's exact discrete solution.
 *
 * A 5 x 5 cotton cloth (default material: stiff springs and damping), no
 * constraints, starting at its rest shape with a uniform velocity v0, under
 * gravity g. A rigid translation leaves every link at its rest length and
 * every relative velocity zero, so the internal forces vanish and each
 * vertex sees only a = g. With t = n h the schemes give, exactly:
 *   velocities, every scheme:     v_n = v0 + g t
 *   backward Euler, symplectic:   x_n = x0 + v0 t + g t^2/2 + g h t/2
 *       (x_{k+1} = x_k + h v_{k+1}: sum of h (v0 + (k+1) h g))
 *   explicit Euler:               x_n = x0 + v0 t + g t^2/2 - g h t/2
 *       (x_{k+1} = x_k + h v_k)
 *   BDF2, first step backward Euler: BDF2 is exact for quadratics, so the
 *       error e_n = x_n - (x0 + v0 t + g t^2/2) obeys the homogeneous
 *       recurrence e_{n+1} = 4/3 e_n - 1/3 e_{n-1} from e_0 = 0 and the
 *       startup step's e_1 = g h^2/2 (BE's h^2 g against the exact h^2 g/2):
 *           e_n = (3/4) g h^2 (1 - 3^-n)
 *       (its velocities are exact from the start: v_1 = v0 + g h, and the
 *       BDF2 velocity recurrence is exact for linear v).
 * Tolerance: 1e-12 of the scale |x0| + |v0| t + |g| t^2 per component (and
 * 1e-12 of |v0| + |g| t for velocities), checked at every step for 64 steps;
 * fine enough to see BDF2's 3^-n startup term for its first ~15 steps.
 *
 * To keep the fall exactly rigid in floating point (the springs are stiff:
 * w h ~ 30 at this resolution, so explicit Euler amplifies any roundoff in
 * the link lengths by ~30 per step), every input is a dyadic rational: the
 * rest grid (0.25 m spacing), density, g, v0 and h = 1/64. Then positions,
 * velocities and masses stay exact, link lengths equal their rest lengths
 * bitwise, and the only rounding left is the CG solve of the implicit
 * methods (run at tolerance 1e-14).
 * The same run also checks the BDF2 startup precisely (e_1 = g h^2 / 2 and
 * e_2 = (2/3) g h^2) and that the kinetic energy matches 1/2 M |v0 + g t|^2.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

static const double G[3] = {1.0, -0.5, -9.75};
static const double V0[3] = {0.5, 0.25, 1.5};
static const double H = 1.0 / 64;
#define NSTEPS 64

static double norm3(const double a[3]) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

static void run(cloth_method m)
{
    const char *names[] = {"backward Euler", "explicit Euler", "symplectic Euler", "BDF2"};
    const char *name = names[m];
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 5;
    d.width = d.height = 1.0;
    d.origin[0] = -0.5;
    d.origin[1] = -0.5;
    d.origin[2] = 2.0;
    memcpy(d.gravity, G, sizeof G);
    d.material.density = 0.25;
    d.solver.method = m;
    d.solver.cg_tolerance = d.solver.newton_cg_tolerance = 1e-14;
    d.solver.newton_tolerance = 1e-12; /* Newton's step solved as exactly */
    d.solver.cg_max_iterations = 1000;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "%s: cloth_create: %s", name, err.message)) return;
    int n = cloth_vertex_count(c);
    double *x0 = malloc(sizeof(double) * 3 * n), *v = malloc(sizeof(double) * 3 * n), mtot = 0;
    memcpy(x0, cloth_positions(c), sizeof(double) * 3 * n);
    for (int i = 0; i < n; i++) {
        memcpy(v + 3 * i, V0, sizeof V0);
        mtot += cloth_masses(c)[i];
    }
    CHECK(cloth_set_velocities(c, v) == CLOTH_OK, "%s: set_velocities", name);

    double worst_x = 0, worst_v = 0;
    for (int s = 1; s <= NSTEPS; s++) {
        cloth_step_stats st;
        if (!CHECK(cloth_step(c, H, &st) == CLOTH_OK, "%s: step %d: %s", name, s, cloth_last_error(c))) break;
        double t = s * H;
        const double *x = cloth_positions(c), *vv = cloth_velocities(c);
        double scale_x = norm3(x0) + norm3(V0) * t + norm3(G) * t * t, scale_v = norm3(V0) + norm3(G) * t;
        double ex = 0, ev = 0;
        for (int i = 0; i < n; i++)
            for (int a = 0; a < 3; a++) {
                double base = x0[3 * i + a] + V0[a] * t + 0.5 * G[a] * t * t, extra;
                switch (m) {
                case CLOTH_EXPLICIT_EULER: extra = -0.5 * G[a] * H * t; break;
                case CLOTH_BDF2: extra = 0.75 * G[a] * H * H * (1.0 - pow(3.0, -s)); break;
                default: extra = 0.5 * G[a] * H * t; break;
                }
                ex = fmax(ex, fabs(x[3 * i + a] - (base + extra)));
                ev = fmax(ev, fabs(vv[3 * i + a] - (V0[a] + G[a] * t)));
            }
        CHECK(ex <= 1e-12 * scale_x, "%s step %d: positions off the exact discrete solution by %.3g m (scale %.3g)",
              name, s, ex, scale_x);
        CHECK(ev <= 1e-12 * scale_v, "%s step %d: velocities off v0 + g t by %.3g m/s (scale %.3g)", name, s, ev,
              scale_v);
        worst_x = fmax(worst_x, ex / scale_x);
        worst_v = fmax(worst_v, ev / scale_v);
        double vt[3] = {V0[0] + G[0] * t, V0[1] + G[1] * t, V0[2] + G[2] * t};
        double ke = 0.5 * mtot * (vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
        CHECK_REL(st.energy.kinetic, ke, 1e-12, 0);
        if (m == CLOTH_BDF2 && s <= 2) {
            /* the startup error, component z of vertex 0, without the 3^-n formula */
            double base = x0[2] + V0[2] * t + 0.5 * G[2] * t * t;
            double e_expect = s == 1 ? 0.5 * G[2] * H * H : (2.0 / 3.0) * G[2] * H * H;
            CHECK_NEAR(x[2] - base, e_expect, 1e-9 * fabs(e_expect));
        }
    }
    printf("%-16s: %d steps, worst relative error positions %.2e, velocities %.2e\n", name, NSTEPS, worst_x, worst_v);
    free(x0);
    free(v);
    cloth_destroy(c);
}

int main(void)
{
    for (int m = CLOTH_BACKWARD_EULER; m <= CLOTH_BDF2; m++) run((cloth_method)m);
    return check_summary();
}
