/* Physics: one undamped spring-mass oscillator, made from a cloth, against
 * the closed forms of each time stepper.
 *
 * A 3 x 3 cloth (spacing l = 0.5 m) with its 8 border vertices pinned at
 * rest, no gravity, no damping, k_c = k_t = k (so every sequential link is a
 * linear-in-length spring), k_b = k_s = 0, no strain limiting, the
 * definiteness rule off (it would drop the transverse terms of the
 * compressed diagonals, whose O(x) contributions otherwise cancel pairwise,
 * and make the linearisation of backward Euler inexact at O(x / l)).
 *
 * The centre vertex, displaced by x along the grid's u axis: its two links
 * along u act axially (k each), the two along v transversely (no linear
 * stiffness at rest length), the four diagonals at 45 degrees (k cos^2 45 =
 * k/2 each along u; their u-v couplings cancel in pairs). So the linearised
 * stiffness along u is 4 k and, with m the centre's lumped mass (a full
 * cell's area times the density), w = sqrt(4 k / m). The mirror symmetries
 * make the force odd in x and free of v and normal components, so the
 * nonlinearity is O((x/l)^2) = 1e-10 relative for x = 1e-5 l. This is also
 * checked against a central finite difference of cloth_internal_forces.
 *
 * In scaled coordinates (X, v) = (w x, dx/dt) every scheme is a 2 x 2 linear
 * map; with q = w h:
 *   backward Euler  amplitude factor 1 / sqrt(1 + q^2) per step (exactly);
 *   explicit Euler  sqrt(1 + q^2) per step (unstable for every h);
 *   symplectic Euler (v first, then x): conserves X^2 + v^2 - q X v, so for
 *                   q < 2 the amplitude stays within [1/sqrt(1 + q/2),
 *                   1/sqrt(1 - q/2)] of the start (from rest); for q > 2 it
 *                   grows like |lambda|^n, lambda = (|T| + sqrt(T^2 - 4)) / 2,
 *                   T = 2 - q^2;
 *   BDF2 (first step backward Euler): second order; BE first order.
 * Asserted:
 *   - the finite-difference stiffness equals 4 k to 1e-6;
 *   - BE and EE amplitude factors at q = 0.1, 1, 10 equal the closed forms
 *     to 1e-6 relative, every step for 3 steps, and the states equal the
 *     exact 2 x 2 maps to 1e-6 of the amplitude;
 *   - symplectic Euler at q = 1.9: 1000 steps, the amplitude within the
 *     bounds above and the modified energy conserved to 1e-6; at q = 2.1 the
 *     amplitude passes 1e3 times the start within 200 steps, and until then
 *     the trajectory follows the linear symplectic map (eigenvalue |lambda|)
 *     to 1e-3 of the amplitude (the nonlinearity reaches ~(x/l)^2 = 2e-4);
 *   - BDF2 integrated to T = 6.4 / w with q = 0.05, 0.025, 0.0125: the
 *     observed order log2(e(h) / e(h/2)) within 10% of 2 for both halvings,
 *     e the scaled-state error against x0 cos(w t); backward Euler the same
 *     within 10% of 1; and both trajectories equal their exact discrete
 *     recurrences (computed here) to 1e-6 of the amplitude.
 * The implicit cases run again with Newton's step (solver.nonlinear
 * CLOTH_NEWTON, newton_tolerance 1e-13): backward Euler's factor at q = 0.1
 * and 1, and both orders, to the same bounds. (Its compressed links push
 * along their direction at x0 + h v0; at q = 10 the step moves the centre
 * by as much as x0, and the map differs at the 1e-5 level.)
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define K_SPRING 100.0 /* N/m */
#define SPACING 0.5    /* m */
#define CENTRE 4

static double rest[27];
static double w_exact, m_centre;
/* how the implicit steps solve their equations: both must meet the closed
 * forms (Newton driven to round-off: the problem is linear to 1e-10) */
static cloth_nonlinear g_nonlinear = CLOTH_LINEARIZED;

static cloth *make_oscillator(cloth_method method)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 3;
    d.width = d.height = 2 * SPACING;
    d.gravity[0] = d.gravity[1] = d.gravity[2] = 0.0;
    d.material.k_t = d.material.k_c = K_SPRING;
    d.material.k_b = d.material.k_s = 0.0;
    d.material.c_t = d.material.c_b = 0.0;
    d.material.alpha = 0.0;
    d.solver.method = method;
    d.solver.nonlinear = g_nonlinear;
    d.solver.newton_tolerance = 1e-13;
    d.solver.cg_tolerance = 1e-12;
    d.solver.cg_max_iterations = 100;
    d.solver.definiteness_rule = 0;
    d.solver.strain_limit_iterations = 0;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) exit(check_summary());
    memcpy(rest, cloth_positions(c), sizeof rest);
    for (int i = 0; i < 9; i++)
        if (i != CENTRE) CHECK(cloth_pin(c, i, rest + 3 * i) == CLOTH_OK, "pin %d", i);
    m_centre = cloth_masses(c)[CENTRE];
    w_exact = sqrt(4.0 * K_SPRING / m_centre);
    return c;
}

/* place the centre at rest + x u with velocity v u (u = +x axis here) */
static void set_centre(cloth *c, double x, double v)
{
    double p[3] = {rest[3 * CENTRE] + x, rest[3 * CENTRE + 1], rest[3 * CENTRE + 2]}, vv[3] = {v, 0, 0};
    CHECK(cloth_set_vertex(c, CENTRE, p, vv) == CLOTH_OK, "set_vertex: %s", cloth_last_error(c));
}

static double cx(const cloth *c) { return cloth_positions(c)[3 * CENTRE] - rest[3 * CENTRE]; }
static double cv(const cloth *c) { return cloth_velocities(c)[3 * CENTRE]; }

/* the linear maps (x, v) -> next, per scheme */
static void exact_map(cloth_method m, double h, double w, double *x, double *v)
{
    double x0 = *x, v0 = *v, w2 = w * w;
    switch (m) {
    case CLOTH_BACKWARD_EULER:
        *v = (v0 - h * w2 * x0) / (1 + h * h * w2);
        *x = x0 + h * *v;
        break;
    case CLOTH_EXPLICIT_EULER:
        *x = x0 + h * v0;
        *v = v0 - h * w2 * x0;
        break;
    case CLOTH_SYMPLECTIC_EULER:
        *v = v0 - h * w2 * x0;
        *x = x0 + h * *v;
        break;
    default: break;
    }
}

static void check_stiffness(void)
{
    cloth *c = make_oscillator(CLOTH_BACKWARD_EULER);
    double f[27], e = 1e-6 * SPACING, fp, fm;
    set_centre(c, e, 0);
    cloth_internal_forces(c, f);
    fp = f[3 * CENTRE];
    CHECK(fabs(f[3 * CENTRE + 1]) <= 1e-9 * fabs(fp) && fabs(f[3 * CENTRE + 2]) <= 1e-9 * fabs(fp),
          "force on the displaced centre not along u: (%g %g %g)", f[3 * CENTRE], f[3 * CENTRE + 1], f[3 * CENTRE + 2]);
    set_centre(c, -e, 0);
    cloth_internal_forces(c, f);
    fm = f[3 * CENTRE];
    double k_fd = -(fp - fm) / (2 * e);
    CHECK_REL(k_fd, 4 * K_SPRING, 1e-6, 0);
    printf("stiffness along u: finite difference %.12g N/m, 4 k = %.12g; m = %g kg, w = %.9g rad/s\n", k_fd,
           4 * K_SPRING, m_centre, w_exact);
    cloth_destroy(c);
}

/* BE and EE: per-step amplitude factor against the closed form */
static void check_factor(cloth_method m, double q)
{
    cloth *c = make_oscillator(m);
    double w = w_exact, h = q / w, x0 = 1e-5 * SPACING;
    double expect = m == CLOTH_BACKWARD_EULER ? 1.0 / sqrt(1 + q * q) : sqrt(1 + q * q);
    const char *name = m == CLOTH_BACKWARD_EULER ? (g_nonlinear ? "backward Euler (Newton)" : "backward Euler")
                                                 : "explicit Euler";
    set_centre(c, x0, 0);
    double xe = x0, ve = 0;
    for (int s = 0; s < 3; s++) {
        double a0 = hypot(w * cx(c), cv(c));
        cloth_step_stats st;
        if (!CHECK(cloth_step(c, h, &st) == CLOTH_OK, "%s q = %g step %d: %s", name, q, s, cloth_last_error(c))) break;
        double a1 = hypot(w * cx(c), cv(c));
        CHECK(fabs(a1 / a0 - expect) <= 1e-6 * expect, "%s q = %g step %d: amplitude factor %.12g, closed form %.12g",
              name, q, s, a1 / a0, expect);
        exact_map(m, h, w, &xe, &ve);
        double err = hypot(w * (cx(c) - xe), cv(c) - ve);
        CHECK(err <= 1e-6 * hypot(w * xe, ve), "%s q = %g step %d: state (%.12g, %.12g) vs exact map (%.12g, %.12g)",
              name, q, s, cx(c), cv(c), xe, ve);
        if (s == 0) printf("%s q = %-4g: amplitude factor %.12f, closed form %.12f\n", name, q, a1 / a0, expect);
    }
    cloth_destroy(c);
}

static void check_symplectic(void)
{
    double w = w_exact, x0 = 1e-5 * SPACING;
    /* q = 1.9: bounded */
    {
        double q = 1.9, h = q / w;
        cloth *c = make_oscillator(CLOTH_SYMPLECTIC_EULER);
        set_centre(c, x0, 0);
        double a0 = w * x0, H0 = a0 * a0, amax = 0, amin = INFINITY, Hdev = 0;
        int ok = 1;
        for (int s = 0; s < 1000 && ok; s++) {
            ok = CHECK(cloth_step(c, h, NULL) == CLOTH_OK, "symplectic q = 1.9 step %d: %s", s, cloth_last_error(c));
            double X = w * cx(c), v = cv(c), a = hypot(X, v), H = X * X + v * v - q * X * v;
            amax = fmax(amax, a / a0);
            amin = fmin(amin, a / a0);
            Hdev = fmax(Hdev, fabs(H - H0) / H0);
        }
        double hi = 1.0 / sqrt(1 - q / 2), lo = 1.0 / sqrt(1 + q / 2);
        printf("symplectic q = 1.9, 1000 steps: amplitude in [%.6f, %.6f] of the start (bounds [%.6f, %.6f]), "
               "modified energy drift %.2e\n",
               amin, amax, lo, hi, Hdev);
        CHECK(amax <= hi * (1 + 1e-6), "symplectic q = 1.9: amplitude reached %.9g x start > bound %.9g", amax, hi);
        CHECK(amin >= lo * (1 - 1e-6), "symplectic q = 1.9: amplitude fell to %.9g x start < bound %.9g", amin, lo);
        CHECK(Hdev <= 1e-6, "symplectic q = 1.9: modified energy X^2 + v^2 - q X v drifted by %.3g", Hdev);
        cloth_destroy(c);
    }
    /* q = 2.1: unbounded */
    {
        double q = 2.1, h = q / w, T = 2 - q * q;
        double lambda = (fabs(T) + sqrt(T * T - 4)) / 2;
        cloth *c = make_oscillator(CLOTH_SYMPLECTIC_EULER);
        set_centre(c, x0, 0);
        double a0 = w * x0, a = a0, xe = x0, ve = 0, dev = 0;
        int n = 0;
        while (n < 200) {
            if (!CHECK(cloth_step(c, h, NULL) == CLOTH_OK, "symplectic q = 2.1 step %d: %s", n, cloth_last_error(c)))
                break;
            n++;
            exact_map(CLOTH_SYMPLECTIC_EULER, h, w, &xe, &ve);
            a = hypot(w * cx(c), cv(c));
            dev = fmax(dev, hypot(w * (cx(c) - xe), cv(c) - ve) / hypot(w * xe, ve));
            if (a > 1e3 * a0) break;
        }
        printf("symplectic q = 2.1: amplitude x%.3g after %d steps (|lambda|^n = %.3g); off the linear map by %.2e\n",
               a / a0, n, pow(lambda, n), dev);
        CHECK(a > 1e3 * a0, "symplectic q = 2.1: amplitude only %.3g x start after %d steps", a / a0, n);
        /* the nonlinearity is O((x / l)^2) <= 2e-4 at the largest amplitude here */
        CHECK(dev <= 1e-3, "symplectic q = 2.1: trajectory off the linear symplectic map by %.3g of the amplitude",
              dev);
        cloth_destroy(c);
    }
}

/* Integrate to T = nsteps h; returns the scaled error against the exact
 * solution, relative to the amplitude, and the deviation from the discrete
 * recurrence (same scaling) in *rec_dev. */
static double run_to_T(cloth_method m, double q, int nsteps, double *rec_dev)
{
    double w = w_exact, h = q / w, x0 = 1e-5 * SPACING, T = nsteps * h;
    cloth *c = make_oscillator(m);
    set_centre(c, x0, 0);
    /* the scheme's own recurrence */
    double xm = 0, vm = 0, xr = x0, vr = 0, dev = 0;
    for (int s = 0; s < nsteps; s++) {
        if (!CHECK(cloth_step(c, h, NULL) == CLOTH_OK, "step %d: %s", s, cloth_last_error(c))) break;
        double xn, vn;
        if (m == CLOTH_BDF2 && s > 0) {
            double a = (4.0 / 3) * xr - (1.0 / 3) * xm;
            vn = ((4.0 / 3) * vr - (1.0 / 3) * vm - (2.0 / 3) * h * w * w * a) / (1 + (4.0 / 9) * h * h * w * w);
            xn = a + (2.0 / 3) * h * vn;
        } else {
            xn = xr;
            vn = vr;
            exact_map(CLOTH_BACKWARD_EULER, h, w, &xn, &vn);
        }
        xm = xr;
        vm = vr;
        xr = xn;
        vr = vn;
        dev = fmax(dev, hypot(w * (cx(c) - xr), cv(c) - vr) / (w * x0));
    }
    *rec_dev = dev;
    double xe = x0 * cos(w * T), ve = -x0 * w * sin(w * T);
    double e = hypot(w * (cx(c) - xe), cv(c) - ve) / (w * x0);
    cloth_destroy(c);
    return e;
}

static void check_order(cloth_method m, double expect_order)
{
    const char *name = m == CLOTH_BDF2 ? (g_nonlinear ? "BDF2 (Newton)" : "BDF2")
                                       : (g_nonlinear ? "backward Euler (Newton)" : "backward Euler");
    double e[3];
    for (int k = 0; k < 3; k++) {
        double dev;
        e[k] = run_to_T(m, 0.05 / (1 << k), 128 << k, &dev);
        CHECK(dev <= 1e-6, "%s q = %g: trajectory off its discrete recurrence by %.3g of the amplitude", name,
              0.05 / (1 << k), dev);
    }
    for (int k = 0; k < 2; k++) {
        double p = log2(e[k] / e[k + 1]);
        printf("%s: error at T %.3e (q = %g) -> %.3e (q = %g): observed order %.4f\n", name, e[k], 0.05 / (1 << k),
               e[k + 1], 0.05 / (2 << k), p);
        CHECK(fabs(p - expect_order) <= 0.1 * expect_order, "%s: observed order %.4f, expected %g within 10%%", name, p,
              expect_order);
    }
}

int main(void)
{
    check_stiffness();
    const double qs[] = {0.1, 1.0, 10.0};
    for (int k = 0; k < 3; k++) {
        check_factor(CLOTH_BACKWARD_EULER, qs[k]);
        check_factor(CLOTH_EXPLICIT_EULER, qs[k]);
    }
    check_symplectic();
    check_order(CLOTH_BDF2, 2.0);
    check_order(CLOTH_BACKWARD_EULER, 1.0);
    /* Newton's compressed diagonals push along their direction at x0 + h v0,
     * off the end-of-step one by O(h v0 / l): at q = 10 that reaches 1e-6 */
    g_nonlinear = CLOTH_NEWTON;
    for (int k = 0; k < 2; k++) check_factor(CLOTH_BACKWARD_EULER, qs[k]);
    check_order(CLOTH_BDF2, 2.0);
    check_order(CLOTH_BACKWARD_EULER, 1.0);
    return check_summary();
}
