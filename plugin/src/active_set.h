/* The active set (active_set.c): which pins and contacts hold in each solve of a step. */
#ifndef ODECLOTH_ACTIVE_SET_H
#define ODECLOTH_ACTIVE_SET_H

#include "odecloth/dcloth.h"

/* The active set's workspace */
struct active_set_scratch {
    double *share_sum; /* n: per lead, a triangle contact's force */
};

/* This pass's constraints for the step of h seconds: pins, contacts by the contact rule, candidates,
 * and the external forces with sliding friction; counted in st */
void dcloth_constrain(dClothID c, double h, dClothStepStats *st);
/* After the step's solve number `passes`: the contacts its result shows wrong changed for the next
 * solve; how many (0: settled) */
int dcloth_revise(dClothID c, double h, int passes, dClothStepStats *st);
/* After the step: marks (let_go) each carrier of a triangle contact that, as a whole, pulled;
 * the next step lets it go */
void dcloth_mark_pulled_shares(dClothID c);

#endif
