/* Plugin: runs are reproducible, and what a save of the core alone misses.
 *
 * Scene: a 15 x 15 cotton cloth (0.8 m) dropped from 0.15 m above a static
 * box table (0.5 x 0.5 x 0.4 m) beside a kinematic cylinder (radius 0.1 m)
 * turning at 1 rad/s about a tilted axis and drifting at 0.1 m/s, mu 0.4,
 * one corner pinned to the world, 160 steps of 1/60 s with
 * dClothWorldStep: contacts of both geoms, sticking and sliding friction,
 * triangle contacts at the box edges, re-solves.
 *
 * 1. Two runs, each in its own world built from scratch, give bitwise the
 *    same cloth positions, velocities and body pose at every step, and the
 *    same contact counts.
 * 2. Save and restore. At step 80 the core state (cloth_save) and the
 *    body's pose and velocities are saved; the run goes on to 160. Then both
 *    are restored and steps 80-160 are run again. The core's state is all
 *    of the cloth's dynamics, but the plugin carries per-vertex contact
 *    history between steps (dcloth_internal.h: vc[], whether each vertex
 *    was in contact, sticking, its last contact force, which decides
 *    release and the friction cone): restoring the core alone leaves that
 *    history at step 160's. Measured and printed; asserted only that the rerun stays finite and in
 *    contact. As a control, the rerun from a restore made right after the
 *    save (so the plugin's history is the saved step's) must be bitwise the
 *    first run: the history is the only thing missing.
 * 3. dClothSave / dClothRestore carry that history: saved at step 80, a
 *    detour (the cloth's gravity tilted for 20 steps), restored (with the body), rerun
 *    to 160: bitwise the first run.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "body_state.h"

#define STEPS 160
#define SAVE_AT 80
#define H (1.0 / 60)

typedef struct run {
    dWorldID world;
    dSpaceID space;
    dGeomID table, cyl;
    dBodyID body;
    dClothID cloth;
} run;

static int make(run *r)
{
    r->world = dWorldCreate();
    dWorldSetGravity(r->world, 0, 0, -9.81);
    r->space = dHashSpaceCreate(0);
    r->table = dCreateBox(r->space, 0.5, 0.5, 0.4);
    dGeomSetPosition(r->table, 0, 0, 0.2);
    r->body = dBodyCreate(r->world);
    dBodySetKinematic(r->body);
    dBodySetPosition(r->body, 0.3, 0.0, 0.3);
    dMatrix3 R;
    dRFromAxisAndAngle(R, 1, 0.3, 0, 1.2);
    dBodySetRotation(r->body, R);
    dBodySetAngularVel(r->body, 0.2, 0.1, 1.0);
    dBodySetLinearVel(r->body, -0.1, 0.0, 0.0);
    r->cyl = dCreateCylinder(r->space, 0.1, 0.3);
    dGeomSetBody(r->cyl, r->body);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = 15;
    d.cloth.width = d.cloth.height = 0.8;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.4;
    d.cloth.origin[2] = 0.55;
    d.mu = 0.4;
    cloth_error err;
    if (!CHECK(dClothCreate(r->world, r->space, &d, &r->cloth, &err) == CLOTH_OK, "dClothCreate: %s", err.message))
        return -1;
    dClothSetFailureMode(r->cloth, DCLOTH_FAILURE_STOP); /* a failed step is an error here */
    dReal p[3] = {-0.4, -0.4, 0.55};
    dClothPinToWorld(r->cloth, 0, p);
    return 0;
}

static void destroy(run *r)
{
    dClothDestroy(r->cloth);
    dGeomDestroy(r->table);
    dGeomDestroy(r->cyl);
    dBodyDestroy(r->body);
    dSpaceDestroy(r->space);
    dWorldDestroy(r->world);
}

static int step(run *r, int s)
{
    return CHECK(dClothWorldStep(r->world, &r->cloth, 1, H, 0) == CLOTH_OK, "step %d: %s", s,
                 dClothGetLastError(r->cloth));
}

static double maxdiff(const double *a, const double *b, size_t n)
{
    double m = 0.0;
    for (size_t k = 0; k < n; k++) m = fmax(m, fabs(a[k] - b[k]));
    return m;
}

int main(void)
{
    dInitODE2(0);
    run a, b;
    if (make(&a) || make(&b)) return check_summary();
    int n = dClothGetVertexCount(a.cloth);
    size_t n3 = 3 * (size_t)n;
    double *xa_save = malloc(n3 * sizeof *xa_save), *xa_end = malloc(n3 * sizeof *xa_end);
    double *va_end = malloc(n3 * sizeof *va_end);
    int diverged_at = -1, contacts_max = 0, sticking_max = 0;
    cloth_state *saved = cloth_state_create(dClothGetCore(a.cloth));
    body_state bs;

    /* 1. two runs side by side, compared every step */
    for (int s = 0; s < STEPS; s++) {
        if (s == SAVE_AT) {
            cloth_save(dClothGetCore(a.cloth), saved);
            body_save(a.body, &bs);
            memcpy(xa_save, dClothGetPositions(a.cloth), n3 * sizeof *xa_save);
        }
        if (!step(&a, s) || !step(&b, s)) break;
        const dClothStepStats *sa = dClothGetStats(a.cloth), *sb = dClothGetStats(b.cloth);
        contacts_max = sa->contacts > contacts_max ? sa->contacts : contacts_max;
        sticking_max = sa->sticking > sticking_max ? sa->sticking : sticking_max;
        int same = memcmp(dClothGetPositions(a.cloth), dClothGetPositions(b.cloth), n3 * sizeof(double)) == 0 &&
                   memcmp(cloth_velocities(dClothGetCore(a.cloth)), cloth_velocities(dClothGetCore(b.cloth)),
                          n3 * sizeof(double)) == 0 &&
                   memcmp(dBodyGetPosition(a.body), dBodyGetPosition(b.body), 3 * sizeof(dReal)) == 0 &&
                   memcmp(dBodyGetQuaternion(a.body), dBodyGetQuaternion(b.body), 4 * sizeof(dReal)) == 0 &&
                   sa->contacts == sb->contacts && sa->sticking == sb->sticking && sa->resolves == sb->resolves;
        if (!same && diverged_at < 0) diverged_at = s;
    }
    CHECK(diverged_at < 0, "two runs of the same scene diverge at step %d", diverged_at);
    CHECK(contacts_max > 20 && sticking_max > 0, "the scene has too few contacts (%d, sticking %d) to test them",
          contacts_max, sticking_max);
    printf("two runs, %d steps, up to %d contacts (%d sticking): %s\n", STEPS, contacts_max, sticking_max,
           diverged_at < 0 ? "bitwise equal at every step" : "DIVERGE");
    memcpy(xa_end, dClothGetPositions(a.cloth), n3 * sizeof *xa_end);
    memcpy(va_end, cloth_velocities(dClothGetCore(a.cloth)), n3 * sizeof *va_end);

    /* 2. restore the core (and the body) to step 80 with the plugin's
     * contact history left at step 160's, rerun 80 steps */
    CHECK(cloth_restore(dClothGetCore(a.cloth), saved) == CLOTH_OK, "restore");
    body_restore(a.body, &bs);
    CHECK(memcmp(dClothGetPositions(a.cloth), xa_save, n3 * sizeof(double)) == 0, "restore: positions");
    for (int s = SAVE_AT; s < STEPS; s++)
        if (!step(&a, s)) break;
    const double *xr = dClothGetPositions(a.cloth);
    double dx = maxdiff(xr, xa_end, n3), dv = maxdiff(cloth_velocities(dClothGetCore(a.cloth)), va_end, n3);
    int fin = 1;
    for (size_t k = 0; k < n3; k++) fin &= isfinite(xr[k]);
    CHECK(fin && dClothGetStats(a.cloth)->contacts > 0, "rerun after restore: not finite or no contacts");
    printf("core + body restored at step %d, plugin contact history left at step %d's, rerun to %d: positions "
           "differ by %.3g m, velocities by %.3g m/s from the first run\n",
           SAVE_AT, STEPS, STEPS, dx, dv);

    /* control: a third run saves the core at step 80, scribbles on the core
     * alone (other positions, a bare core step), restores and goes on: its
     * plugin history is step 80's, so it must end as the first run did */
    {
        run c;
        if (!make(&c)) {
            for (int s = 0; s < SAVE_AT; s++) step(&c, s);
            cloth_state *now = cloth_state_create(dClothGetCore(c.cloth));
            cloth_save(dClothGetCore(c.cloth), now);
            /* scribble on the core, then restore: the plugin history is untouched */
            double *x = malloc(n3 * sizeof *x);
            memcpy(x, dClothGetPositions(c.cloth), n3 * sizeof *x);
            for (size_t k = 0; k < n3; k++) x[k] += 0.01;
            cloth_set_positions(dClothGetCore(c.cloth), x);
            cloth_step(dClothGetCore(c.cloth), H, NULL);
            CHECK(cloth_restore(dClothGetCore(c.cloth), now) == CLOTH_OK, "control: restore");
            for (int s = SAVE_AT; s < STEPS; s++) step(&c, s);
            CHECK(memcmp(dClothGetPositions(c.cloth), xa_end, n3 * sizeof(double)) == 0,
                  "control: with the plugin's history that of the saved step, the rerun differs from the first run by "
                  "%.3g m",
                  maxdiff(dClothGetPositions(c.cloth), xa_end, n3));
            free(x);
            cloth_state_destroy(now);
            destroy(&c);
        }
    }
    /* 3. dClothSave / dClothRestore: the whole cloth (core and plugin history) and the body saved at step 80, the
     * run taken on to 160 with a detour (the cloth's gravity tilted for 20 steps, then back, so the history
     * changes), restored, run again to 160: bitwise the first run */
    {
        run d;
        if (!make(&d)) {
            for (int s = 0; s < SAVE_AT; s++) step(&d, s);
            dClothState *st = dClothStateCreate(d.cloth);
            body_state bd;
            CHECK(st && dClothSave(d.cloth, st) == CLOTH_OK, "dClothSave: %s", dClothGetLastError(d.cloth));
            body_save(d.body, &bd);
            const double tilted[3] = {2, 0, -9.81}, down[3] = {0, 0, -9.81};
            cloth_set_gravity(dClothGetCore(d.cloth), tilted);
            for (int s = SAVE_AT; s < SAVE_AT + 20; s++) step(&d, s);
            cloth_set_gravity(dClothGetCore(d.cloth), down);
            for (int s = SAVE_AT + 20; s < STEPS; s++) step(&d, s);
            CHECK(memcmp(dClothGetPositions(d.cloth), xa_end, n3 * sizeof(double)) != 0,
                  "the detour changed the run (else this check proves nothing)");
            CHECK(dClothRestore(d.cloth, st) == CLOTH_OK, "dClothRestore: %s", dClothGetLastError(d.cloth));
            body_restore(d.body, &bd);
            for (int s = SAVE_AT; s < STEPS; s++) step(&d, s);
            double dd = maxdiff(dClothGetPositions(d.cloth), xa_end, n3);
            CHECK(memcmp(dClothGetPositions(d.cloth), xa_end, n3 * sizeof(double)) == 0 &&
                      memcmp(cloth_velocities(dClothGetCore(d.cloth)), va_end, n3 * sizeof(double)) == 0,
                  "dClothRestore and rerun: differs from the first run by %.3g m", dd);
            printf("dClothSave at step %d, a detour, dClothRestore, rerun to %d: %s\n", SAVE_AT, STEPS,
                   dd == 0.0 ? "bitwise the first run" : "DIFFERS");
            /* bad input */
            dClothState *small = NULL;
            CHECK(dClothSave(d.cloth, NULL) == CLOTH_EINVAL && dClothRestore(d.cloth, NULL) == CLOTH_EINVAL &&
                      dClothSave(NULL, st) == CLOTH_EINVAL && dClothStateCreate(NULL) == NULL,
                  "NULL refused");
            dClothDesc sd = dClothDefaultDesc();
            sd.cloth.rows = sd.cloth.cols = 5;
            dClothID other = NULL;
            cloth_error err;
            if (dClothCreate(d.world, 0, &sd, &other, &err) == CLOTH_OK) {
                small = dClothStateCreate(other);
                CHECK(dClothRestore(d.cloth, small) == CLOTH_EINVAL, "a state of another size refused");
                dClothDestroy(other);
            }
            dClothStateDestroy(small);
            dClothStateDestroy(st);
            destroy(&d);
        }
    }
    cloth_state_destroy(saved);
    free(xa_save);
    free(xa_end);
    free(va_end);
    destroy(&a);
    destroy(&b);
    dCloseODE();
    return check_summary();
}
