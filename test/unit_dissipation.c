/* Unit: what backward Euler's step dissipates (oc_potential_dissipation,
 * core/src/potential.h), against the energy the step's end state holds.
 *
 * For any velocity change dv, with v = v0 + dv, x = x0 + h v and R the step's
 * residual there, kinetic + elastic + gravitational energy change by
 *   dE = v . R - 1/2 |dv|_M^2 - D   (D: the dampers' work, the links' gaps)
 * where the step's potential is the springs' energy. Asserted on a 7 x 6 cloth
 * with random dv:
 * 1. every link stretched, none past the limit: dE equals that within 1e-9 of
 *    the terms' size, and D > 0 (the gaps of a stretched spring);
 * 2. links compressed, or past the elongation limit: dE is at most that (the
 *    potential exceeds the springs' energy off x0; the limit's piece, left out
 *    of D, only dissipates more), and D >= 0;
 * 3. BDF2: D is 0 (its bound keeps to the kinetic part).
 * In every trial the potential the assembly returns is oc_potential_value's bit
 * for bit (Newton's line search compares the two), and the D its sums give
 * (oc_potential_step_dissipation) is oc_potential_dissipation's within 1e-12 of the
 * links' energy.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "potential.h"
#include "check.h"

/* Kinetic + elastic + gravitational energy at (x, v). */
static double energy(const cloth *c, const double *x, const double *v)
{
    double E = oc_elastic_energy(c, x);
    const double *g = c->desc.gravity;
    for (int i = 0; i < c->n; i++) {
        const double *vi = v + 3 * i, *xi = x + 3 * i;
        E += 0.5 * c->mass[i] * (vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]);
        E -= c->mass[i] * (g[0] * xi[0] + g[1] * xi[1] + g[2] * xi[2]);
    }
    return E;
}

/* The cloth scaled in its plane by `scale` about its centre, lifted by a
 * random 1 mm, with random velocities of 5 cm/s. */
static cloth *make(double scale, rng *s)
{
    cloth_desc d = cloth_default_desc();
    d.rows = 7;
    d.cols = 6;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) return NULL;
    double ctr[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < c->n; i++)
        for (int r = 0; r < 3; r++) ctr[r] += c->st.x[3 * i + r] / c->n;
    for (int i = 0; i < c->n; i++) {
        double x[3], v[3];
        for (int r = 0; r < 3; r++) {
            x[r] = ctr[r] + scale * (c->st.x[3 * i + r] - ctr[r]);
            v[r] = 0.05 * rng_range(s, -1.0, 1.0);
        }
        x[2] += 1e-3 * rng_range(s, -1.0, 1.0);
        cloth_set_vertex(c, i, x, v);
    }
    return c;
}

static int phi_differs;   /* trials whose assembly and oc_potential_value disagree */
static double diss_apart; /* the largest relative gap between the assembly's D and oc_potential_dissipation's */

/* dE - (v . R - 1/2 |dv|_M^2 - D) for a random dv of size `dvs`, and D. */
static double mismatch(cloth *c, int bdf2, double dvs, rng *s, double *D, double *size)
{
    step_eq q;
    size_t n3 = 3 * (size_t)c->n;
    double h = 1.0 / 60, *dv = malloc(n3 * sizeof *dv), *b = malloc(n3 * sizeof *b);
    oc_potential_begin(c, h, bdf2, &q);
    memcpy(c->lim_shift, c->st.lim_shift, (size_t)c->n_seq * sizeof *c->lim_shift);
    oc_limit_multipliers_begin(c);
    for (size_t k = 0; k < n3; k++) dv[k] = dvs * rng_range(s, -1.0, 1.0);
    oc_potential_state(c, &q, dv);
    double phi = oc_potential_assemble(c, &q, dv, b, 0);
    phi_differs += phi != oc_potential_value(c, &q, dv, c->xt, c->vt);
    *D = oc_potential_dissipation(c, &q);
    double Ds = oc_potential_step_dissipation(c, &q);
    diss_apart = fmax(diss_apart, fabs(Ds - *D) / (bdf2 ? 1.0 : fabs(c->diss_e0) + fabs(*D)));
    double work = 0.0, kin = 0.0;
    for (size_t k = 0; k < n3; k++) {
        work += c->v_new[k] * b[k];
        kin += 0.5 * c->mass[k / 3] * dv[k] * dv[k];
    }
    double dE = energy(c, c->x_new, c->v_new) - energy(c, c->st.x, c->st.v);
    *size = fabs(work) + kin + fabs(*D) + fabs(dE);
    free(dv);
    free(b);
    return dE - (-work - kin - *D);
}

int main(void)
{
    rng s = rng_seed(12345);
    for (int k = 0; k < 20; k++) { /* 1: stretched 1%, the limit 3% */
        cloth *c = make(1.01, &s);
        if (!c) break;
        double D, size, m = mismatch(c, 0, 2e-3, &s, &D, &size);
        CHECK(fabs(m) <= 1e-9 * size, "stretched, trial %d: dE off the identity by %.3e (terms %.3e)", k, m, size);
        CHECK(D > 0.0, "stretched, trial %d: D = %.3e", k, D);
        cloth_destroy(c);
    }
    double scales[2] = {0.97, 1.05}; /* 2: compressed; past the limit */
    for (int t = 0; t < 2; t++)
        for (int k = 0; k < 20; k++) {
            cloth *c = make(scales[t], &s);
            if (!c) break;
            double D, size, m = mismatch(c, 0, 2e-2, &s, &D, &size);
            CHECK(m <= 1e-9 * size, "scale %.2f, trial %d: dE exceeds the bound by %.3e", scales[t], k, m);
            CHECK(D >= 0.0, "scale %.2f, trial %d: D = %.3e", scales[t], k, D);
            cloth_destroy(c);
        }
    cloth *c = make(1.01, &s); /* 3 */
    if (c) {
        double D, size;
        mismatch(c, 1, 2e-3, &s, &D, &size);
        CHECK(D == 0.0, "BDF2: D = %.3e", D);
        cloth_destroy(c);
    }
    CHECK(phi_differs == 0, "%d trials' assembly Phi differs from oc_potential_value's", phi_differs);
    CHECK(diss_apart <= 1e-12, "the assembly's D differs from oc_potential_dissipation's by %.3e of the energy",
          diss_apart);
    return check_summary();
}
