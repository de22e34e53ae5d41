/* Plugin: a held step does not freeze the scene (DCLOTH_FAILURE_HOLD).
 *
 * A held step stops the cloth where it was; from rest the next step would
 * meet the same failure again, for ever, if nothing else changed. So each
 * step held in a row retries the next in one more substep halving. Scenes:
 * a 21x21 and a 41x41 cotton cloth thrown at 5 m/s onto a static box on a
 * plane, Newton's budget cut to 2 and 3 iterations and no substeps of its
 * own (solver.max_substep_halvings 0), 4 s at h = 1/60 by dClothWorldStep (the 21x21 cloth's skirts
 * fold down over the box's sides for about 3 s).
 * Asserted, each:
 *   - some steps are held (else the test tests nothing), never more than 4
 *     in a row (without the halvings both scenes stop for good);
 *   - the world steps on (every call CLOTH_OK) and the cloth ends at rest
 *     on the box: mean vertex speed after the last step not held under
 *     0.01 m/s, no vertex over the top deeper than half the thickness into
 *     its shell;
 *   - the user's solver settings are as set (max_substep_halvings 0).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "odecloth/dcloth.h"
#include "check.h"

#define H (1.0 / 60.0)
#define TOP 0.2
#define HALF 0.25
#define STEPS 240

static double mean_speed(const cloth *core)
{
    const double *v = cloth_velocities(core);
    int n = cloth_vertex_count(core);
    double s = 0.0;
    for (int i = 0; i < n; i++)
        s += sqrt(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
    return s / n;
}

static void scene(int n_side, int iterations)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dGeomID box = dCreateBox(sp, 2 * HALF, 2 * HALF, TOP);
    dGeomSetPosition(box, 0, 0, TOP / 2);
    dCreatePlane(sp, 0, 0, 1, 0);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = n_side;
    d.cloth.material.density = 0.2;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.5;
    d.cloth.origin[2] = TOP + d.thickness + 0.01;
    d.cloth.solver.nonlinear = CLOTH_NEWTON;
    d.cloth.solver.newton_iterations = iterations;
    d.cloth.solver.max_substep_halvings = 0;
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return;
    cloth *core = dClothGetCore(c);
    int n = cloth_vertex_count(core), held = 0, run = 0, longest = 0, ok = 1;
    double speed = INFINITY;
    double *v = calloc(3 * (size_t)n, sizeof *v);
    for (int i = 0; i < n; i++) v[3 * i + 2] = -5.0;
    cloth_set_velocities(core, v);
    for (int s = 0; s < STEPS && ok; s++) {
        ok = CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "%dx%d, step %d: %s", n_side, n_side, s,
                   dClothGetLastError(c));
        int hd = dClothGetStats(c)->held;
        held += hd;
        run = hd ? run + 1 : 0;
        if (run > longest) longest = run;
        if (!hd) speed = mean_speed(core); /* a held step's zeroed velocities say nothing */
    }
    const double *x = cloth_positions(core);
    double low = INFINITY;
    for (int i = 0; i < n; i++) {
        const double *p = x + 3 * i;
        if (fabs(p[0]) < HALF - 0.01 && fabs(p[1]) < HALF - 0.01) low = fmin(low, p[2] - TOP);
    }
    printf("%dx%d, %d Newton iterations: %d of %d steps held, at most %d in a row; mean speed after the last step "
           "not held %.2e m/s, lowest vertex over the top %.2f mm above it\n",
           n_side, n_side, iterations, held, STEPS, longest, speed, 1e3 * low);
    CHECK(held > 0, "%dx%d: no step held (the test tests nothing)", n_side, n_side);
    CHECK(longest <= 4, "%dx%d: %d steps held in a row", n_side, n_side, longest);
    CHECK(speed < 0.01, "%dx%d: still moving at %.3g m/s", n_side, n_side, speed);
    CHECK(low >= 0.5 * d.thickness, "%dx%d: a vertex %.2f mm over the top", n_side, n_side, 1e3 * low);
    CHECK(cloth_get_desc(core).solver.max_substep_halvings == 0, "%dx%d: the user's substep setting changed", n_side,
          n_side);
    free(v);
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

int main(void)
{
    dInitODE2(0);
    scene(21, 2);
    scene(41, 3);
    dCloseODE();
    return check_summary();
}
