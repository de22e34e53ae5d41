/* Save and restore an ODE body's motion state (pose, velocities, and the
 * force accumulated for the next world step), for the plugin tests that
 * compare runs or check that a failed call left the bodies alone. */
#ifndef ODECLOTH_TEST_BODY_STATE_H
#define ODECLOTH_TEST_BODY_STATE_H

#include <string.h>
#include <ode/ode.h>

typedef struct body_state {
    dReal pos[3], q[4], R[12], lv[3], av[3], f[3];
} body_state;

static inline void body_save(dBodyID b, body_state *s)
{
    memcpy(s->pos, dBodyGetPosition(b), sizeof s->pos);
    memcpy(s->q, dBodyGetQuaternion(b), sizeof s->q);
    memcpy(s->R, dBodyGetRotation(b), sizeof s->R);
    memcpy(s->lv, dBodyGetLinearVel(b), sizeof s->lv);
    memcpy(s->av, dBodyGetAngularVel(b), sizeof s->av);
    memcpy(s->f, dBodyGetForce(b), sizeof s->f);
}

/* pose and velocities, bit for bit (the force accumulator is ODE's own to
 * clear). dBodySetQuaternion normalises again, which moves the last bits of
 * a turned body's orientation: the saved bits go back into ODE's own arrays. */
static inline void body_restore(dBodyID b, const body_state *s)
{
    dBodySetPosition(b, s->pos[0], s->pos[1], s->pos[2]);
    dBodySetQuaternion(b, s->q);
    memcpy((dReal *)dBodyGetQuaternion(b), s->q, sizeof s->q);
    memcpy((dReal *)dBodyGetRotation(b), s->R, sizeof s->R);
    dBodySetLinearVel(b, s->lv[0], s->lv[1], s->lv[2]);
    dBodySetAngularVel(b, s->av[0], s->av[1], s->av[2]);
}

/* 1 if b's pose and velocities are bitwise s's */
static inline int body_same(dBodyID b, const body_state *s)
{
    return !memcmp(dBodyGetPosition(b), s->pos, sizeof s->pos) && !memcmp(dBodyGetQuaternion(b), s->q, sizeof s->q) &&
           !memcmp(dBodyGetRotation(b), s->R, sizeof s->R) && !memcmp(dBodyGetLinearVel(b), s->lv, sizeof s->lv) &&
           !memcmp(dBodyGetAngularVel(b), s->av, sizeof s->av);
}

#endif
