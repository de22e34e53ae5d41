/* The sleep stage (sleep.c): a cloth at rest with nothing moving near it is not solved. */
#ifndef ODECLOTH_SLEEP_H
#define ODECLOTH_SLEEP_H

#include "odecloth/dcloth.h"

/* The settings (on, steps, speed: dClothSetAutoSleep) and state: steps still so far, asleep, and n geoms
 * near the cloth when it fell asleep; dClothSave and the state file copy it whole */
struct sleep_state {
    int on, steps, still, asleep, n;
    double speed;
    double gravity[3]; /* the world's gravity when it fell asleep */
};

/* The sleep stage's state, carried between steps: the above, and the geoms near the cloth when it fell
 * asleep (state.n of them) */
struct dcloth_sleep {
    struct sleep_state state;
    double *geoms; /* per geom then: its position (3), the geom itself in ids */
    dGeomID *ids;
    int cap;
};

/* before a step, 1 if the cloth sleeps through it (then the step
 * is done: forces re-applied, stats set), -1 on no memory; after a solved
 * step, whether it now falls asleep. */
int dcloth_sleep_before(dClothID c, double h, double t0);
void dcloth_sleep_after(dClothID c);

#endif
