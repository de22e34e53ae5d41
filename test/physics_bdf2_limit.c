/* BDF2 with the elongation limit's projection (core/src/strain_limit.c): the
 * projection's change dx of a step's positions is an impulse dx / h on the
 * velocities, and BDF2's previous velocity takes it too, so the multistep
 * recurrence reads no acceleration into it.
 *
 * 1. The stability map's scene (examples/bench_stability.c: 21x21, 0.2 kg,
 *    pinned at two corners 0.8 m apart, shrunk to 0.8 and rumpled, gravity),
 *    at k_t 20 N/m, BDF2 at h = 1/760, 1/800, 1/827, 1/860, 1/900, 1/1000
 *    and 1/1100 s for 0.15 s: every step succeeds (no strain failure) and
 *    the total energy, elastic included, never rises above its start by
 *    more than 1e-3 of it. Nothing in the scene adds energy (pins do no
 *    work, damping and the projection take it out), so the allowance only
 *    covers round-off and a multistep method's energy not falling at every
 *    step; a blow-up passes it by orders of magnitude. With dx / (2h/3) and
 *    BDF2's history left unprojected, four of these cells blow up.
 * 2. A closed form: a 3x3 cloth with no forces at all (k_t 1e-12, no
 *    damping, bending or gravity), its first row pinned and the other rows
 *    moving away at 0.07 m/s. The projection stops each row where its link
 *    reaches (1 + delta) l0; then it must stay there at rest: every link
 *    from row to row at (1 + delta) l0 and every speed zero, to the
 *    projection's own accuracy (its link solve stops at 1e-3 of its
 *    residual: speeds within 1e-3 of the initial one, lengths within 1e-3
 *    delta l0). Without the impulse in BDF2's previous velocity the rows
 *    drift back. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "odecloth/cloth.h"

static double total_energy(const cloth *c)
{
    cloth_energy e = cloth_energies(c);
    return e.elastic + e.kinetic + e.gravitational;
}

/* The stability map's scene at k_t 20 N/m, BDF2, no substep retry. */
static cloth *map_scene(void)
{
    const int grid = 21;
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = CLOTH_LINEARIZED; /* the projection after the step is tested */
    d.solver.max_substep_halvings = 0;
    d.rows = d.cols = grid;
    d.material.density = 0.2;
    d.material.k_t = 20.0;
    d.solver.method = CLOTH_BDF2;
    cloth *c;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return NULL;
    int n = cloth_vertex_count(c);
    double *x = malloc(3 * (size_t)n * sizeof *x);
    if (!CHECK(x != NULL, "no memory")) {
        cloth_destroy(c);
        return NULL;
    }
    memcpy(x, cloth_positions(c), 3 * (size_t)n * sizeof *x);
    uint64_t s = 0x5eed5eedULL; /* the map's rumple, the same sequence */
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) {
            if (a < 2) x[3 * i + a] *= 0.8;
            s = s * 6364136223846793005ULL + 1442695040888963407ULL;
            x[3 * i + a] += (a < 2 ? 1e-4 : 1e-3) * ((double)(s >> 11) / 9007199254740992.0 - 0.5);
        }
    CHECK(cloth_set_positions(c, x) == CLOTH_OK, "set positions");
    cloth_pin(c, 0, x);
    cloth_pin(c, grid - 1, x + 3 * (grid - 1));
    free(x);
    return c;
}

static void map_cells(void)
{
    const double inv_h[] = {760.0, 800.0, 827.0, 860.0, 900.0, 1000.0, 1100.0};
    const int cells = (int)(sizeof inv_h / sizeof *inv_h);
    for (int q = 0; q < cells; q++) {
        cloth *c = map_scene();
        if (!c) return;
        double h = 1.0 / inv_h[q], e0 = total_energy(c), emax = -HUGE_VAL, tol = 1e-3 * e0;
        long steps = lround(0.15 / h), s, failed = -1;
        for (s = 0; s < steps; s++) {
            cloth_step_stats st;
            if (cloth_step(c, h, &st) != CLOTH_OK) {
                failed = s;
                break;
            }
            double e = total_energy(c);
            if (!(e <= emax)) emax = e;
        }
        printf("map scene, k_t 20, BDF2, h 1/%.0f: energy %.4f J at the start, at most %+.4f J of it after a step, "
               "%.4f J at the end%s\n",
               inv_h[q], e0, emax - e0, total_energy(c), failed >= 0 ? " (failed)" : "");
        CHECK(failed < 0, "h 1/%.0f: step %ld failed: %s", inv_h[q], failed, cloth_last_error(c));
        CHECK(emax <= e0 + tol, "h 1/%.0f: energy rose to %.6g J from %.6g J (allowed %.3g J)", inv_h[q], emax, e0,
              tol);
        cloth_destroy(c);
    }
}

/* The closed form of part 2, with the method m. */
static void stopped_rows(cloth_method m)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = CLOTH_LINEARIZED; /* the projection after the step is tested */
    d.rows = d.cols = 3;
    d.gravity[2] = 0.0;
    cloth_material *mt = &d.material;
    mt->k_t = 1e-12;
    mt->k_c = mt->k_b = mt->k_s = mt->k_delta = mt->c_t = mt->c_b = mt->alpha = 0.0;
    d.solver.method = m;
    cloth *c;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return;
    const double *x = cloth_positions(c);
    double v[27] = {0}, u[3], l0 = 0.0, speed = 0.07, h = 0.01;
    for (int r = 0; r < 3; r++) u[r] = x[9 + r] - x[r]; /* row 0 to row 1 */
    l0 = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int i = 3; i < 9; i++)
        for (int r = 0; r < 3; r++) v[3 * i + r] = speed * u[r] / l0;
    CHECK(cloth_set_velocities(c, v) == CLOTH_OK, "set velocities");
    for (int i = 0; i < 3; i++) cloth_pin(c, i, x + 3 * i);
    /* both links reach the limit by 2 delta l0 / (speed h) steps; then 100 more */
    double lmax = (1.0 + mt->delta) * l0, worst_len = 0.0, worst_v = 0.0;
    int steps = (int)ceil(2.0 * mt->delta * l0 / (speed * h)) + 100;
    for (int s = 0; s < steps; s++) {
        cloth_step_stats st;
        if (!CHECK(cloth_step(c, h, &st) == CLOTH_OK, "step %d: %s", s, cloth_last_error(c))) break;
    }
    x = cloth_positions(c);
    const double *vel = cloth_velocities(c);
    for (int i = 0; i < 9; i++) {
        if (i >= 3) { /* the link from the row before */
            double w[3] = {x[3 * i] - x[3 * i - 9], x[3 * i + 1] - x[3 * i - 8], x[3 * i + 2] - x[3 * i - 7]};
            worst_len = fmax(worst_len, fabs(sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) - lmax));
        }
        worst_v = fmax(worst_v, sqrt(vel[3 * i] * vel[3 * i] + vel[3 * i + 1] * vel[3 * i + 1] +
                                     vel[3 * i + 2] * vel[3 * i + 2]));
    }
    const char *name = m == CLOTH_BDF2 ? "BDF2" : "backward Euler";
    printf("rows stopped by the limit, %s, %d steps: |length - (1 + delta) l0| <= %.3g m, speed <= %.3g m/s\n", name,
           steps, worst_len, worst_v);
    CHECK(worst_len <= 1e-3 * mt->delta * l0, "%s: a link is %.3g m off (1 + delta) l0 = %.4g m", name, worst_len,
          lmax);
    CHECK(worst_v <= 1e-3 * speed, "%s: a vertex still moves at %.3g m/s (started at %g)", name, worst_v, speed);
    cloth_destroy(c);
}

int main(void)
{
    map_cells();
    stopped_rows(CLOTH_BACKWARD_EULER);
    stopped_rows(CLOTH_BDF2);
    return check_summary();
}
