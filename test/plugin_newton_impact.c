/* Plugin: an impact solved by Newton's method (solver.nonlinear
 * CLOTH_NEWTON). A 41x41 cotton cloth, 1 m, 0.2 kg, flat 1 cm above a
 * static box (0.5 x 0.5 m top at z = 0.2) and falling at 3 m/s, takes 30
 * steps of 1/60 s (dClothStep) at the solver's defaults. Every step must:
 *   - succeed whole or in substeps, no cloth held (DCLOTH_FAILURE_STOP);
 *   - end with the Newton residual within the step's goal (stats.newton_goal:
 *     solver.newton_tolerance, or less for a warm start kept unsolved);
 *   - leave every sequential link within (1 + delta) l0 to 1e-3 of it,
 *     measured by the test from the positions;
 *   - leave no vertex deeper in the box's shell than the thickness (none
 *     inside the box; the box floats, and the cloth may hang below it).
 * Near the box's edges the contacts' planes would make the elongation
 * limit infeasible: the step lets go of those that pull (contacts.c).
 */
#include <math.h>
#include <stdlib.h>

#include "odecloth/dcloth.h"
#include "check.h"

#define N 41
#define H (1.0 / 60.0)
#define TOP 0.2
#define HALF 0.25

int main(void)
{
    dInitODE2(0);
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dGeomID box = dCreateBox(sp, 2 * HALF, 2 * HALF, TOP);
    dGeomSetPosition(box, 0, 0, TOP / 2);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = N;
    d.cloth.material.density = 0.2;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.5;
    d.cloth.origin[2] = TOP + d.thickness + 0.01;
    d.cloth.solver.nonlinear = CLOTH_NEWTON;
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return check_summary();
    dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
    cloth *core = dClothGetCore(c);
    int n = cloth_vertex_count(core), nl = cloth_link_count(core, CLOTH_SEQUENTIAL);
    double *v = calloc(3 * (size_t)n, sizeof *v);
    for (int i = 0; i < n; i++) v[3 * i + 2] = -3.0;
    cloth_set_velocities(core, v);
    double lim = 1.0 + d.cloth.material.delta, worst_strain = 0.0, worst_depth = 0.0, worst_res = 0.0;
    int failed = 0, substepped = 0;
    for (int s = 0; s < 30; s++) {
        if (!CHECK(dClothStep(c, H) == CLOTH_OK, "step %d: %s", s, dClothGetLastError(c))) {
            failed++;
            break;
        }
        const cloth_step_stats *st = &dClothGetStats(c)->core;
        substepped += st->substeps > 1;
        worst_res = fmax(worst_res, st->newton_residual);
        CHECK(st->newton_residual <= st->newton_goal, "step %d: Newton residual %.3g m/s, goal %.3g", s,
              st->newton_residual, st->newton_goal);
        const double *x = cloth_positions(core);
        for (int e = 0; e < nl; e++) {
            cloth_link L;
            cloth_get_link(core, CLOTH_SEQUENTIAL, e, &L);
            double dx = x[3 * L.j] - x[3 * L.i], dy = x[3 * L.j + 1] - x[3 * L.i + 1],
                   dz = x[3 * L.j + 2] - x[3 * L.i + 2];
            worst_strain = fmax(worst_strain, sqrt(dx * dx + dy * dy + dz * dz) / (lim * L.rest) - 1.0);
        }
        for (int i = 0; i < n; i++) {
            /* how far the vertex is from leaving the shell (box + thickness) */
            const double *p = x + 3 * i, th = d.thickness;
            double in = fmin(fmin(HALF + th - fabs(p[0]), HALF + th - fabs(p[1])), fmin(TOP + th - p[2], p[2] + th));
            worst_depth = fmax(worst_depth, in);
        }
    }
    printf("41x41 at 3 m/s onto a box by Newton: %d failed, %d substepped; worst Newton residual %.3g m/s, "
           "links past the limit by %.2e of it, deepest %.2f mm inside the shell\n",
           failed, substepped, worst_res, worst_strain, 1e3 * worst_depth);
    CHECK(worst_strain <= 1e-3, "a link past (1 + delta) l0 by %.3g of it", worst_strain);
    CHECK(worst_depth <= d.thickness, "a vertex %.2f mm inside the box's shell (%.1f mm thick)", 1e3 * worst_depth,
          1e3 * d.thickness);
    free(v);
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
    dCloseODE();
    return check_summary();
}
