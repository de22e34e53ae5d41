/* Plugin: sleeping (dClothSetAutoSleep), the cost of a cloth in proportion
 * to what happens in its scene.
 *
 * A 21x21 cloth dropped 5 cm onto a static 0.6 m box (top at z = 0.6):
 *   1. off by default: it never sleeps;
 *   2. on (speed 1 mm/s, 10 steps): it falls asleep once settled, and while
 *      asleep its positions do not change by a single bit and no step
 *      solves (stats.sleeping); (RMS speed 1 cm/s, ODE's own default)
 *   3. a kinematic ball coming at a hanging flap at 0.5 m/s: the cloth
 *      sleeps while the ball is far, wakes as it comes within reach (0.25 m)
 *      and before it touches, and is pushed;
 *   4. the ball stops, pressed 10 cm in: the cloth falls asleep again;
 *   7. a 0.3 kg ball resting in a cloth hung by its corners (a hammock): the
 *      cloth falls asleep and the ball stays at rest on it (|v| < 1 mm/s
 *      over 1 s): the sleeping cloth holds it up with its last forces;
 *   5. changing the world's gravity, or a pin, wakes it;
 *   6. bad arguments are refused, with a message and nothing changed.
 * It prints the share of steps it slept (the saving).
 */
#include <math.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"

#define H (1.0 / 60)

typedef struct scene {
    dWorldID w;
    dSpaceID sp;
    dClothID c;
} scene;

static int make(scene *s)
{
    s->w = dWorldCreate();
    dWorldSetGravity(s->w, 0, 0, -9.81);
    s->sp = dHashSpaceCreate(0);
    dGeomID box = dCreateBox(s->sp, 0.6, 0.6, 0.6);
    dGeomSetPosition(box, 0, 0, 0.3);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.origin[2] = 0.65;
    cloth_error err;
    s->c = NULL;
    if (!CHECK(dClothCreate(s->w, s->sp, &d, &s->c, &err) == CLOTH_OK, "create: %s", err.message)) return 0;
    dClothSetFailureMode(s->c, DCLOTH_FAILURE_STOP); /* a failed step is an error here */
    return 1;
}

static void destroy(scene *s)
{
    dClothDestroy(s->c);
    dSpaceDestroy(s->sp);
    dWorldDestroy(s->w);
}

/* step n times; returns the number of steps slept, -1 on a failed step */
static int run(scene *s, int n)
{
    int slept = 0;
    for (int k = 0; k < n; k++) {
        if (!CHECK(dClothWorldStep(s->w, &s->c, 1, H, 0) == CLOTH_OK, "step: %s", dClothGetLastError(s->c))) return -1;
        slept += dClothGetStats(s->c)->sleeping;
    }
    return slept;
}

int main(void)
{
    dInitODE2(0);
    scene s;

    /* 1. off by default */
    if (make(&s)) {
        int slept = run(&s, 240);
        CHECK(slept == 0 && !dClothIsSleeping(s.c), "off by default: slept %d steps", slept);
        destroy(&s);
    }

    if (!make(&s)) return check_summary();
    /* 6. bad arguments (before it is on) */
    CHECK(dClothSetAutoSleep(s.c, 1, 0.0, 10) == CLOTH_EINVAL, "speed 0 refused");
    CHECK(dClothSetAutoSleep(s.c, 1, NAN, 10) == CLOTH_EINVAL, "speed NaN refused");
    CHECK(dClothSetAutoSleep(s.c, 1, -1.0, 10) == CLOTH_EINVAL, "speed < 0 refused");
    CHECK(dClothSetAutoSleep(s.c, 1, 1e-3, 0) == CLOTH_EINVAL, "steps 0 refused");
    CHECK(strstr(dClothGetLastError(s.c), "steps") != NULL, "message: %s", dClothGetLastError(s.c));
    CHECK(dClothSetAutoSleep(NULL, 1, 1e-3, 10) == CLOTH_EINVAL, "NULL cloth");
    CHECK(run(&s, 60) == 0, "still off after the refused calls");

    /* 2. on: falls asleep once settled, and then does not move */
    CHECK(dClothSetAutoSleep(s.c, 1, 1e-2, 10) == CLOTH_OK, "on: %s", dClothGetLastError(s.c));
    int n = dClothGetVertexCount(s.c), t_sleep = -1;
    for (int k = 0; k < 600 && t_sleep < 0; k++) {
        if (run(&s, 1) < 0) break;
        if (dClothIsSleeping(s.c)) t_sleep = k;
    }
    CHECK(t_sleep >= 0, "the settled cloth fell asleep within 10 s");
    double x0[3 * 441];
    memcpy(x0, dClothGetPositions(s.c), sizeof x0);
    int slept = run(&s, 60);
    CHECK(slept == 60, "asleep: %d of 60 steps slept", slept);
    CHECK(memcmp(x0, dClothGetPositions(s.c), sizeof x0) == 0, "asleep: positions unchanged bitwise");
    const double *v = cloth_velocities(dClothGetCore(s.c));
    double vmax = 0;
    for (int i = 0; i < 3 * n; i++) vmax = fmax(vmax, fabs(v[i]));
    CHECK(vmax == 0.0, "asleep: velocities zero (max %g)", vmax);
    printf("fell asleep %.2f s after the drop\n", (60 + t_sleep + 1) * H);

    /* 3. a kinematic ball coming at a hanging flap from the side */
    double xmax = -1e9;
    for (int i = 0; i < n; i++) xmax = fmax(xmax, dClothGetPositions(s.c)[3 * i]);
    dBodyID ball = dBodyCreate(s.w);
    dBodySetKinematic(ball);
    dGeomID bg = dCreateSphere(s.sp, 0.1);
    dGeomSetBody(bg, ball);
    dBodySetPosition(ball, xmax + 0.8, 0, 0.45);
    dBodySetLinearVel(ball, -0.5, 0, 0);
    double gap_wake = -1;
    int total = 0, asleep_steps = 0;
    for (int k = 0; k < 240; k++) {
        double gap = dBodyGetPosition(ball)[0] - 0.1 - xmax;
        if (run(&s, 1) < 0) break;
        total++;
        asleep_steps += dClothGetStats(s.c)->sleeping;
        if (gap_wake < 0 && !dClothIsSleeping(s.c)) gap_wake = gap;
        if (dBodyGetPosition(ball)[0] < xmax - 0.1) dBodySetLinearVel(ball, 0, 0, 0); /* 10 cm in: stop */
    }
    CHECK(gap_wake > 0.0 && gap_wake <= 0.25 + 2 * dClothGetThickness(s.c) + 0.5 * H,
          "woke as the ball came within reach: gap %.4f m (reach 0.25 m)", gap_wake);
    CHECK(memcmp(x0, dClothGetPositions(s.c), sizeof x0) != 0, "the ball moved the cloth");
    printf("kinematic ball: woke with the ball %.3f m away, after %d asleep steps\n", gap_wake, asleep_steps);

    /* 4. asleep again with the ball at rest against it */
    int again = dClothIsSleeping(s.c);
    for (int k = 0; k < 600 && !again; k++) {
        if (run(&s, 1) < 0) break;
        total++;
        again = dClothIsSleeping(s.c);
    }
    CHECK(again, "asleep again against the ball at rest");
    asleep_steps += run(&s, 60);
    total += 60;
    printf("saving: %d of %d steps slept (%.0f%%) since the ball appeared\n", asleep_steps, total,
           100.0 * asleep_steps / total);

    /* 5. what wakes it */
    dWorldSetGravity(s.w, 0, 0, -9.0);
    run(&s, 1);
    CHECK(!dClothIsSleeping(s.c) && dClothGetStats(s.c)->sleeping == 0, "a change of gravity wakes it");
    for (int k = 0; k < 600 && !dClothIsSleeping(s.c); k++) run(&s, 1);
    CHECK(dClothIsSleeping(s.c), "asleep again");
    CHECK(dClothPinToWorld(s.c, 0, dClothGetPositions(s.c)) == CLOTH_OK, "pin");
    CHECK(!dClothIsSleeping(s.c), "a pin wakes it");
    dClothSetAutoSleep(s.c, 0, 0, 0);
    CHECK(run(&s, 30) == 0, "off again: never sleeps");
    destroy(&s);

    /* 7. a ball resting in a hammock */
    scene hm;
    hm.w = dWorldCreate();
    dWorldSetGravity(hm.w, 0, 0, -9.81);
    hm.sp = dHashSpaceCreate(0);
    dClothDesc d = dClothDefaultDesc();
    cloth_error err;
    if (CHECK(dClothCreate(hm.w, hm.sp, &d, &hm.c, &err) == CLOTH_OK, "create: %s", err.message)) {
        dClothSetFailureMode(hm.c, DCLOTH_FAILURE_STOP);
        int R = d.cloth.rows, C = d.cloth.cols, corner[4] = {0, C - 1, (R - 1) * C, R * C - 1};
        for (int k = 0; k < 4; k++) dClothPinToWorld(hm.c, corner[k], dClothGetPositions(hm.c) + 3 * corner[k]);
        dClothSetAutoSleep(hm.c, 1, 1e-2, 10);
        dBodyID b = dBodyCreate(hm.w);
        dMass bm;
        dMassSetSphereTotal(&bm, 0.3, 0.1);
        dBodySetMass(b, &bm);
        dGeomID g = dCreateSphere(hm.sp, 0.1);
        dGeomSetBody(g, b);
        dBodySetPosition(b, 0, 0, 1.0 + 0.1 + 0.01);
        int asleep = 0, k = 0;
        for (; k < 1200 && !asleep; k++) {
            if (run(&hm, 1) < 0) break;
            asleep = dClothIsSleeping(hm.c);
        }
        CHECK(asleep, "the hammock fell asleep under the ball (after %.2f s)", k * H);
        double z0 = dBodyGetPosition(b)[2], worst = 0;
        int slept = 0;
        for (int q = 0; q < 60; q++) {
            if (run(&hm, 1) < 0) break;
            slept += dClothGetStats(hm.c)->sleeping;
            const dReal *bv = dBodyGetLinearVel(b);
            worst = fmax(worst, sqrt(bv[0] * bv[0] + bv[1] * bv[1] + bv[2] * bv[2]));
        }
        CHECK(slept == 60 && worst < 1e-3, "the ball rests on the sleeping hammock: slept %d of 60, |v| <= %.3g m/s",
              slept, worst);
        CHECK(fabs(dBodyGetPosition(b)[2] - z0) < 1e-3, "the ball stays: moved %.3g m", dBodyGetPosition(b)[2] - z0);
        printf("hammock: asleep after %.2f s with the ball in it; the ball's |v| <= %.2g m/s over 1 s asleep\n", k * H,
               worst);
        destroy(&hm);
    }
    dCloseODE();
    return check_summary();
}
