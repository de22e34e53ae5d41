/* Stepping several cloths and the world together (dClothWorldStep), all or nothing: when a cloth fails,
 * the cloths stepped before it and the bodies they pushed (from each step's journal) are restored, and
 * the world is not stepped. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "dcloth_internal.h"
#include "journal.h"

/* The cloth's whole state before a step (dClothSave), for undo. */
static int save_undo(dClothID c)
{
    if (!c->undo) c->undo = dClothStateCreate(c);
    return c->undo && dClothSave(c, c->undo) == CLOTH_OK ? 0 : -1;
}

/* Undo a step taken since save_undo: the cloth, then the bodies it touched. */
static void undo(dClothID c)
{
    dClothRestore(c, c->undo);
    dcloth_journal_undo(c);
}

#define WORLD_STEP_MAX_UNDO 64

cloth_status dClothWorldStep(dWorldID world, dClothID *cloths, int n, dReal h, int quick)
{
    if (!world || n < 0 || (n > 0 && !cloths)) return CLOTH_EINVAL;
    for (int k = 0; k < n; k++)
        if (!cloths[k]) return CLOTH_EINVAL;
    /* checked here too, so that no cloth is stepped and dWorldStep never
     * sees a bad h (its assertion would end the program) */
    if (!(h > 0.0) || !isfinite(h))
        return n > 0 ? dcloth_fail(cloths[0], CLOTH_EINVAL, "dClothWorldStep: h = %g must be finite and > 0", h)
                     : CLOTH_EINVAL;
    for (int k = 0; k < n; k++) {
        if (cloths[k]->world != world)
            return dcloth_fail(cloths[k], CLOTH_EINVAL, "dClothWorldStep: cloth %d is not in this world", k);
        for (int j = 0; j < k; j++)
            if (cloths[j] == cloths[k])
                return dcloth_fail(cloths[k], CLOTH_EINVAL, "dClothWorldStep: cloth %d is also cloth %d", k, j);
    }
    if (n > WORLD_STEP_MAX_UNDO)
        return dcloth_fail(cloths[0], CLOTH_EINVAL, "dClothWorldStep: %d cloths, at most %d at once", n,
                           WORLD_STEP_MAX_UNDO);
    for (int k = 0; k < n; k++) {
        dClothID c = cloths[k];
        cloth_status s = CLOTH_OK;
        if (n > 1 && save_undo(c) != 0)
            s = dcloth_fail(c, CLOTH_ENOMEM, "dClothWorldStep: out of memory for the undo copy");
        if (s == CLOTH_OK) s = dClothStep(c, h);
        if (s != CLOTH_OK) {
            for (int j = k - 1; j >= 0; j--) undo(cloths[j]);
            return s;
        }
    }
    if (quick) dWorldQuickStep(world, h);
    else dWorldStep(world, h);
    return CLOTH_OK;
}
