/* Save and restore an ODE body's motion state (pose, velocities, and the
 * force accumulated for the next world step), for the plugin tests that
 * compare runs or check that a failed call left the bodies alone. */
#ifndef ODECLOTH_TEST_BODY_STATE_H
#define ODECLOTH_TEST_BODY_STATE_H

#include <string.h>
#include <ode/ode.h>

typedef struct body_state {
    dReal pos[3], q[4], lv[3], av[3], f[3];
} body_state;

static inline void body_save(dBodyID b, body_state *s)
{
    memcpy(s->pos, dBodyGetPosition(b), sizeof s->pos);
    memcpy(s->q, dBodyGetQuaternion(b), sizeof s->q);
    memcpy(s->lv, dBodyGetLinearVel(b), sizeof s->lv);
    memcpy(s->av, dBodyGetAngularVel(b), sizeof s->av);
    memcpy(s->f, dBodyGetForce(b), sizeof s->f);
}

/* pose and velocities (the force accumulator is ODE's own to clear) */
static inline void body_restore(dBodyID b, const body_state *s)
{
    dBodySetPosition(b, s->pos[0], s->pos[1], s->pos[2]);
    dBodySetQuaternion(b, s->q);
    dBodySetLinearVel(b, s->lv[0], s->lv[1], s->lv[2]);
    dBodySetAngularVel(b, s->av[0], s->av[1], s->av[2]);
}

#endif
