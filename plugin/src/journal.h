/* The bodies a step touched (journal.c), for dClothWorldStep's undo. */
#ifndef ODECLOTH_JOURNAL_H
#define ODECLOTH_JOURNAL_H

#include "dcloth_internal.h"

/* Note body b's force, torque and velocities before this step
 * first changes them (0, or -1 on no memory: then the step must not change
 * b); the journal is emptied at each step's start. */
int dcloth_touch(dClothID c, dBodyID b);
/* restore the journal's bodies to their saved state, and empty it */
void dcloth_journal_undo(dClothID c);

#endif
