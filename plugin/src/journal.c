/* The bodies a step touched, each saved from before it (force and torque accumulators, velocities),
 * so that dClothWorldStep can put them back. */
#include <stdlib.h>
#include "dcloth_internal.h"
#include "journal.h"

int dcloth_touch(dClothID c, dBodyID b)
{
    for (int k = 0; k < c->journal.n; k++)
        if (c->journal.rec[k].b == b) return 0;
    if (c->journal.n == c->journal.cap) {
        int cap = c->journal.cap ? 2 * c->journal.cap : 8;
        struct body_rec *j = realloc(c->journal.rec, (size_t)cap * sizeof *j);
        if (!j) return -1;
        c->journal.rec = j;
        c->journal.cap = cap;
    }
    struct body_rec *r = &c->journal.rec[c->journal.n++];
    r->b = b;
    const dReal *f = dBodyGetForce(b), *t = dBodyGetTorque(b), *lv = dBodyGetLinearVel(b), *av = dBodyGetAngularVel(b);
    for (int k = 0; k < 3; k++) {
        r->f[k] = f[k];
        r->t[k] = t[k];
        r->lv[k] = lv[k];
        r->av[k] = av[k];
    }
    return 0;
}

void dcloth_journal_undo(dClothID c)
{
    for (int k = c->journal.n - 1; k >= 0; k--) {
        const struct body_rec *r = &c->journal.rec[k];
        dBodySetForce(r->b, r->f[0], r->f[1], r->f[2]);
        dBodySetTorque(r->b, r->t[0], r->t[1], r->t[2]);
        dBodySetLinearVel(r->b, r->lv[0], r->lv[1], r->lv[2]);
        dBodySetAngularVel(r->b, r->av[0], r->av[1], r->av[2]);
    }
    c->journal.n = 0;
}
