/* Sleep's settings and waking (dClothSetAutoSleep, dClothWake): every change
 * of what the cloth sees wakes it; the sleep stage (sleep.c) decides the rest. */
#include <math.h>
#include "dcloth_internal.h"

cloth_status dClothSetAutoSleep(dClothID c, int on, dReal speed, int steps)
{
    if (!c) return CLOTH_EINVAL;
    if (on && (!(speed > 0.0) || !isfinite(speed)))
        return dcloth_fail(c, CLOTH_EINVAL, "dClothSetAutoSleep: speed = %g must be finite and > 0", speed);
    if (on && steps < 1) return dcloth_fail(c, CLOTH_EINVAL, "dClothSetAutoSleep: steps = %d must be >= 1", steps);
    c->sleep.state.on = on != 0;
    if (on) {
        c->sleep.state.speed = speed;
        c->sleep.state.steps = steps;
    }
    dClothWake(c);
    return CLOTH_OK;
}

int dClothIsSleeping(dClothID c) { return c ? c->sleep.state.asleep : 0; }

void dClothWake(dClothID c)
{
    if (!c) return;
    c->sleep.state.asleep = 0;
    c->sleep.state.still = 0;
}
