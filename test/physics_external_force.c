/* Physics: per-vertex external forces (cloth_set_external_forces) against
 * closed forms, for every scheme.
 *
 * 1. A uniform acceleration given as forces f_i = m_i a, gravity off: the
 *    cloth translates rigidly, internal forces vanish, and every vertex's
 *    velocity after n steps is v0 + a t exactly (as in physics_freefall,
 *    whose dyadic set-up this reuses so the motion stays exactly rigid).
 * 2. Arbitrary forces (random per vertex, fixed over the run), gravity off:
 *    internal forces sum to zero, so the total momentum after n steps is
 *    P0 + t sum f_i for every scheme (implicit ones up to their CG residual:
 *    tolerance 1e-12 here), although the cloth deforms.
 *    The explicit schemes run this part at h = 1/8192: the cloth deforms, and
 *    its stiff springs (w h ~ 30 at 1/64) are past their stability limit.
 * 3. The forces stay until changed; NULL clears them; a non-finite force is
 *    refused with a message and leaves the previous forces in place. After
 *    clearing, a one-step scheme keeps its momentum; BDF2, a two-step
 *    scheme, carries a third of its last step's change into the next
 *    (P_{n+1} = 4/3 P_n - 1/3 P_{n-1} with no force). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

static const cloth_method methods[4] = {CLOTH_BACKWARD_EULER, CLOTH_BDF2, CLOTH_SYMPLECTIC_EULER, CLOTH_EXPLICIT_EULER};
static const char *names[4] = {"backward Euler", "BDF2", "symplectic Euler", "explicit Euler"};

static cloth *make(cloth_method m)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 5;
    d.width = d.height = 1.0;  /* 0.25 m spacing: dyadic */
    d.material.density = 0.25; /* dyadic masses */
    d.gravity[0] = d.gravity[1] = d.gravity[2] = 0.0;
    d.solver.method = m;
    d.solver.cg_tolerance = d.solver.newton_cg_tolerance = 1e-12;
    d.solver.newton_tolerance = 1e-12; /* Newton's step solved as exactly */
    d.solver.strain_limit_iterations = 0;
    cloth *c;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return NULL;
    return c;
}

static void momentum(const cloth *c, double P[3])
{
    const double *v = cloth_velocities(c), *m = cloth_masses(c);
    P[0] = P[1] = P[2] = 0.0;
    for (int i = 0; i < cloth_vertex_count(c); i++)
        for (int k = 0; k < 3; k++) P[k] += m[i] * v[3 * i + k];
}

int main(void)
{
    const double h = 1.0 / 64.0;
    for (int s = 0; s < 4; s++) {
        /* 1: uniform acceleration */
        cloth *c = make(methods[s]);
        if (!c) continue;
        int n = cloth_vertex_count(c);
        const double a[3] = {0.5, -1.25, 2.0}, v0[3] = {0.25, 0.5, -0.75};
        double *f = malloc(3 * (size_t)n * sizeof *f), *v = malloc(3 * (size_t)n * sizeof *v);
        const double *m = cloth_masses(c);
        for (int i = 0; i < n; i++)
            for (int k = 0; k < 3; k++) {
                f[3 * i + k] = m[i] * a[k];
                v[3 * i + k] = v0[k];
            }
        cloth_set_velocities(c, v);
        CHECK(cloth_set_external_forces(c, f) == CLOTH_OK, "%s: set forces: %s", names[s], cloth_last_error(c));
        double worst = 0.0;
        for (int step = 1; step <= 32; step++) {
            if (!CHECK(cloth_step(c, h, NULL) == CLOTH_OK, "%s: step %d: %s", names[s], step, cloth_last_error(c)))
                break;
            const double *vv = cloth_velocities(c);
            for (int i = 0; i < n; i++)
                for (int k = 0; k < 3; k++) {
                    double e = fabs(vv[3 * i + k] - (v0[k] + a[k] * step * h));
                    if (e > worst) worst = e;
                }
        }
        printf("%-17s uniform force: worst |v - (v0 + a t)| = %.3g m/s over 32 steps\n", names[s], worst);
        CHECK(worst <= 1e-12 * (1.0 + 2.5 * 32 * h), "%s: velocity off the closed form by %.3g m/s", names[s], worst);
        cloth_destroy(c);

        /* 2: arbitrary forces: momentum */
        c = make(methods[s]);
        if (!c) {
            free(f);
            free(v);
            continue;
        }
        rng r = rng_seed(17 + (uint64_t)s);
        double F[3] = {0.0, 0.0, 0.0};
        for (int i = 0; i < 3 * n; i++) {
            f[i] = rng_range(&r, -0.01, 0.01); /* N; the cloth weighs 0.25 kg */
            F[i % 3] += f[i];
        }
        double hs = s >= 2 ? 1.0 / 8192.0 : h;
        cloth_set_external_forces(c, f);
        double P0[3], P[3];
        momentum(c, P0);
        double worstP = 0.0, scale = 0.0;
        int steps = 40;
        for (int step = 1; step <= steps; step++) {
            if (!CHECK(cloth_step(c, hs, NULL) == CLOTH_OK, "%s: step %d: %s", names[s], step, cloth_last_error(c)))
                break;
            momentum(c, P);
            for (int k = 0; k < 3; k++) {
                double e = fabs(P[k] - (P0[k] + F[k] * step * hs));
                if (e > worstP) worstP = e;
                if (fabs(F[k] * step * hs) > scale) scale = fabs(F[k] * step * hs);
            }
        }
        printf("%-17s random forces: worst momentum error %.3g N s (impulse scale %.3g N s)\n", names[s], worstP,
               scale);
        CHECK(worstP <= 1e-9 * scale + 1e-15, "%s: momentum off P0 + t sum f by %.3g N s", names[s], worstP);

        /* 3: NULL clears; a bad force is refused and keeps the old ones */
        double bad[3 * 25];
        memcpy(bad, f, sizeof bad);
        bad[7] = NAN;
        CHECK(cloth_set_external_forces(c, bad) == CLOTH_EINVAL && cloth_last_error(c)[0] != '\0',
              "%s: a NaN force must be refused with a message", names[s]);
        double fs = fabs(F[0]) + fabs(F[1]) + fabs(F[2]);
        momentum(c, P0);
        cloth_step(c, hs, NULL);
        momentum(c, P);
        double e = 0.0;
        for (int k = 0; k < 3; k++) e = fmax(e, fabs(P[k] - (P0[k] + F[k] * hs)));
        CHECK(e <= 1e-9 * fs * hs + 1e-15, "%s: after a refused set, the old forces must still act (%.3g)", names[s],
              e);
        CHECK(cloth_set_external_forces(c, NULL) == CLOTH_OK, "%s: clearing must succeed", names[s]);
        double carry = methods[s] == CLOTH_BDF2 ? 1.0 / 3.0 : 0.0;
        momentum(c, P0);
        cloth_step(c, hs, NULL);
        momentum(c, P);
        e = 0.0;
        for (int k = 0; k < 3; k++) e = fmax(e, fabs(P[k] - (P0[k] + carry * F[k] * hs)));
        CHECK(e <= 1e-9 * fs * hs + 1e-15, "%s: cleared forces must not act (momentum off by %.3g)", names[s], e);
        cloth_destroy(c);
        free(f);
        free(v);
    }
    CHECK(cloth_set_external_forces(NULL, NULL) == CLOTH_EINVAL, "NULL cloth must be refused");
    return check_summary();
}
