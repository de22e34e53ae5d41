/* The bodies a step touched (journal.c), for dClothWorldStep's undo. */
#ifndef ODECLOTH_JOURNAL_H
#define ODECLOTH_JOURNAL_H

#include "odecloth/dcloth.h"

/* The bodies this step touched, each saved from before the step */
struct body_journal {
    struct body_rec {
        dBodyID b;
        dReal f[3], t[3], lv[3], av[3];
    } * rec;
    int n, cap;
};

/* Note body b's force, torque and velocities before this step
 * first changes them (0, or -1 on no memory: then the step must not change
 * b); the journal is emptied at each step's start. */
int dcloth_touch(dClothID c, dBodyID b);
/* restore the journal's bodies to their saved state, and empty it */
void dcloth_journal_undo(dClothID c);

#endif
