/* The contact rule (contact_rule.c): a vertex's contact to its constraint. */
#ifndef ODECLOTH_CONTACT_RULE_H
#define ODECLOTH_CONTACT_RULE_H

#include "dcloth_internal.h"

/* Decide vertex i's contact nw (old: its last step's) for the step of h seconds: none (returns 0), sticking
 * or sliding; fills its constraint k and, sliding, its friction force. mass: the vertex's; g: gravity;
 * forced: held whatever the rule says; newton: the core decides contacts within its step (candidates). */
int dcloth_contact_rule(dClothID c, int i, double h, double mass, const double g[3], vcontact *nw, const vcontact *old,
                        cloth_constraint *k, dClothStepStats *st, int forced, int newton);

#endif
