/* Saving and restoring a plugin cloth (dClothSave / dClothRestore): the core's state plus what the
 * plugin carries between steps (contact histories, pins, sleep, held steps, pending forces, last
 * stats), so a restore continues exactly as the uninterrupted run. */
#include <stdlib.h>
#include <string.h>
#include "dcloth_internal.h"

dClothState *dClothStateCreate(dClothID c)
{
    if (!c) return NULL;
    dClothState *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->n = c->n;
    s->core = cloth_state_create(c->core);
    s->vc = malloc((size_t)c->n * sizeof *s->vc);
    s->pin = malloc((size_t)c->n * sizeof *s->pin);
    s->fadd = calloc(3 * (size_t)c->n, sizeof *s->fadd);
    if (!s->core || !s->vc || !s->pin || !s->fadd) {
        dClothStateDestroy(s);
        return NULL;
    }
    return s;
}

void dClothStateDestroy(dClothState *s)
{
    if (!s) return;
    cloth_state_destroy(s->core);
    free(s->vc);
    free(s->pin);
    free(s->fadd);
    free(s->sleep_geoms);
    free(s->sleep_ids);
    free(s);
}

/* copy the sleep snapshot arrays (n geoms) into *ids / *geoms, grown */
static int copy_snapshot(int n, const dGeomID *ids_in, const double *geoms_in, dGeomID **ids, double **geoms)
{
    if (n == 0) return 0;
    dGeomID *i2 = realloc(*ids, (size_t)n * sizeof *i2);
    if (!i2) return -1;
    *ids = i2;
    double *g2 = realloc(*geoms, 3 * (size_t)n * sizeof *g2);
    if (!g2) return -1;
    *geoms = g2;
    memcpy(i2, ids_in, (size_t)n * sizeof *i2);
    memcpy(g2, geoms_in, 3 * (size_t)n * sizeof *g2);
    return 0;
}

cloth_status dClothSave(dClothID c, dClothState *s)
{
    if (!c) return CLOTH_EINVAL;
    if (!s) return dcloth_fail(c, CLOTH_EINVAL, "dClothSave: state is NULL");
    if (s->n != c->n)
        return dcloth_fail(c, CLOTH_EINVAL, "dClothSave: the state is for %d vertices, the cloth has %d", s->n, c->n);
    if (copy_snapshot(c->sleep.state.n, c->sleep.ids, c->sleep.geoms, &s->sleep_ids, &s->sleep_geoms))
        return dcloth_fail(c, CLOTH_ENOMEM, "dClothSave: out of memory");
    cloth_status r = cloth_save(c->core, s->core);
    if (r != CLOTH_OK) return dcloth_fail(c, r, "dClothSave: %s", cloth_last_error(c->core));
    memcpy(s->vc, c->vc, (size_t)c->n * sizeof *s->vc);
    memcpy(s->pin, c->pin, (size_t)c->n * sizeof *s->pin);
    memcpy(s->fadd, c->fadd, 3 * (size_t)c->n * sizeof *s->fadd);
    s->held_run = c->held_run;
    s->stats = c->stats;
    s->sleep = c->sleep.state;
    s->surf_tmax = c->surf_tmax;
    return CLOTH_OK;
}

cloth_status dClothRestore(dClothID c, const dClothState *s)
{
    if (!c) return CLOTH_EINVAL;
    if (!s) return dcloth_fail(c, CLOTH_EINVAL, "dClothRestore: state is NULL");
    if (s->n != c->n)
        return dcloth_fail(c, CLOTH_EINVAL, "dClothRestore: the state is for %d vertices, the cloth has %d", s->n,
                           c->n);
    /* the snapshot first (the only step that can fail), into the cloth's own arrays */
    if (s->sleep.n > c->sleep.cap) {
        if (copy_snapshot(s->sleep.n, s->sleep_ids, s->sleep_geoms, &c->sleep.ids, &c->sleep.geoms))
            return dcloth_fail(c, CLOTH_ENOMEM, "dClothRestore: out of memory");
        c->sleep.cap = s->sleep.n;
    } else if (s->sleep.n > 0) {
        memcpy(c->sleep.ids, s->sleep_ids, (size_t)s->sleep.n * sizeof *c->sleep.ids);
        memcpy(c->sleep.geoms, s->sleep_geoms, 3 * (size_t)s->sleep.n * sizeof *c->sleep.geoms);
    }
    cloth_status r = cloth_restore(c->core, s->core);
    if (r != CLOTH_OK) return dcloth_fail(c, r, "dClothRestore: %s", cloth_last_error(c->core));
    memcpy(c->vc, s->vc, (size_t)c->n * sizeof *c->vc);
    memcpy(c->pin, s->pin, (size_t)c->n * sizeof *c->pin);
    memcpy(c->fadd, s->fadd, 3 * (size_t)c->n * sizeof *c->fadd);
    c->held_run = s->held_run;
    c->stats = s->stats;
    c->sleep.state = s->sleep;
    c->surf_tmax = s->surf_tmax;
    return CLOTH_OK;
}
