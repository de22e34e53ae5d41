/* The bodies a step touched, each as it was before (its force and torque
 * accumulators and velocities), so that dClothWorldStep can put them back. */
#include <stdlib.h>
#include "dcloth_internal.h"
#include "journal.h"

int dcloth_touch(dClothID c, dBodyID b)
{
    for (int k = 0; k < c->njournal; k++)
        if (c->journal[k].b == b) return 0;
    if (c->njournal == c->journal_cap) {
        int cap = c->journal_cap ? 2 * c->journal_cap : 8;
        struct body_rec *j = realloc(c->journal, (size_t)cap * sizeof *j);
        if (!j) return -1;
        c->journal = j;
        c->journal_cap = cap;
    }
    struct body_rec *r = &c->journal[c->njournal++];
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
    for (int k = c->njournal - 1; k >= 0; k--) {
        const struct body_rec *r = &c->journal[k];
        dBodySetForce(r->b, r->f[0], r->f[1], r->f[2]);
        dBodySetTorque(r->b, r->t[0], r->t[1], r->t[2]);
        dBodySetLinearVel(r->b, r->lv[0], r->lv[1], r->lv[2]);
        dBodySetAngularVel(r->b, r->av[0], r->av[1], r->av[2]);
    }
    c->njournal = 0;
}
