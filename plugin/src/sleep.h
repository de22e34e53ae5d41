/* The sleep stage (sleep.c): a cloth at rest with nothing moving near it is not solved. */
#ifndef ODECLOTH_SLEEP_H
#define ODECLOTH_SLEEP_H

#include "dcloth_internal.h"

/* before a step, 1 if the cloth sleeps through it (then the step
 * is done: forces re-applied, stats set), -1 on no memory; after a solved
 * step, whether it now falls asleep. */
int dcloth_sleep_before(dClothID c, double h, double t0);
void dcloth_sleep_after(dClothID c);

#endif
