/* Plugin: contacts decided inside the Newton step. A 31x31 cotton cloth,
 * 1 m, 0.2 kg, flat 5 cm above a static sphere of radius 0.25 m and falling
 * at 1 m/s, is stepped 60 times at 1/60 s (dClothStep), once with
 * CLOTH_NEWTON and once with CLOTH_LINEARIZED. With Newton every step
 * succeeds (DCLOTH_FAILURE_STOP) and the plugin solves a step again only
 * for vertices its contact search had not reached at the step's start
 * (dClothStepStats.late_contacts): vertices it had found that would end
 * inside their shell are held by the solve itself (stats.contacts_decided
 * counts some). The linearised run, which solves steps again for those,
 * shows the scene has them (more resolves). With either, no vertex ends a
 * step inside the sphere's shell by more than the thickness (measured from
 * the sphere's closed form).
 */
#include <math.h>
#include <stdio.h>

#include "odecloth/dcloth.h"
#include "check.h"

#define N 31
#define H (1.0 / 60.0)
#define R 0.25

static void run(cloth_nonlinear how)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dCreateSphere(sp, R);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = N;
    d.cloth.material.density = 0.2;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.5;
    d.cloth.origin[2] = R + d.thickness + 0.05;
    d.cloth.solver.nonlinear = how;
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return;
    dClothSetFailureMode(c, DCLOTH_FAILURE_STOP);
    cloth *core = dClothGetCore(c);
    int n = cloth_vertex_count(core), resolves = 0, decided = 0, steps = 0, late = 0;
    double v[3 * N * N] = {0};
    for (int i = 0; i < n; i++) v[3 * i + 2] = -1.0;
    cloth_set_velocities(core, v);
    double deepest = 0.0;
    for (; steps < 60; steps++) {
        if (!CHECK(dClothStep(c, H) == CLOTH_OK, "%s step %d: %s", how == CLOTH_NEWTON ? "Newton" : "linearised", steps,
                   dClothGetLastError(c)))
            break;
        const dClothStepStats *ps = dClothGetStats(c);
        resolves += ps->resolves;
        if (how == CLOTH_NEWTON)
            CHECK(ps->late_contacts > 0 || ps->resolves == 0, "Newton step %d solved again (%d) with no late contact",
                  steps, ps->resolves);
        late += ps->late_contacts;
        decided += dClothGetStats(c)->core.contacts_decided;
        const double *x = cloth_positions(core);
        for (int i = 0; i < n; i++) {
            double r = sqrt(x[3 * i] * x[3 * i] + x[3 * i + 1] * x[3 * i + 1] + x[3 * i + 2] * x[3 * i + 2]);
            deepest = fmax(deepest, R + d.thickness - r);
        }
    }
    printf("%s: %d steps, %d solved again (%d late contacts), %d contacts decided by the solve, deepest %.2f mm "
           "inside the shell\n",
           how == CLOTH_NEWTON ? "Newton" : "linearised", steps, resolves, late, decided, 1e3 * deepest);
    CHECK(deepest <= d.thickness, "a vertex %.2f mm inside the shell", 1e3 * deepest);
    if (how == CLOTH_NEWTON) {
        CHECK(decided > 0, "Newton: no contact decided by the solve");
    } else {
        CHECK(resolves > late,
              "linearised: solved again %d times for %d late contacts only (the scene does not "
              "exercise the candidates)",
              resolves, late);
        CHECK(decided == 0, "linearised: %d contacts decided (candidates are Newton's)", decided);
    }
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

int main(void)
{
    dInitODE2(0);
    run(CLOTH_NEWTON);
    run(CLOTH_LINEARIZED);
    dCloseODE();
    return check_summary();
}
