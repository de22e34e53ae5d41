/* The cloth's step (dClothStep): sleep may take the whole step; else broadphase, vertex, triangle and
 * link contacts, solves until the active set settles (contact rule, bodies coupled, core step, set
 * revised), then the reactions onto the bodies. */
#include <math.h>
#include <string.h>
#include <time.h>
#include "dcloth_internal.h"
#include "active_set.h"
#include "body_coupling.h"
#include "broadphase.h"
#include "contact_offers.h"
#include "edges.h"
#include "reactions.h"
#include "sleep.h"
#include "triangles.h"
#include "vertex_contacts.h"

static double wall(void)
{
    struct timespec t;
    timespec_get(&t, TIME_UTC);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* For the step of h seconds, every vertex's nearest surface among the candidate geoms of c->space, into
 * c->vc_new (geom 0 where there is none within reach): the vertices', the triangles' and the links' tests.
 * Returns the number of candidate geoms, or -1 when memory ran out. */
static int find_contacts(dClothID c, double h)
{
    double extra = dcloth_newton_reach(c, h);
    c->step.deepest = 0.0;
    if (dcloth_find_surfaces(c, h, extra) < 0) return -1;
    dcloth_vertex_contacts(c, h, extra);
    c->step.tri_hits = 0;
    for (int a = 0; a < c->broad.ncand; a++) c->step.tri_hits += dcloth_triangle_contacts(c, &c->broad.surf[a], h);
    c->step.edge_hits = 0;
    for (int a = 0; a < c->broad.ncand; a++) {
        int e = dcloth_edge_contacts(c, &c->broad.surf[a], h, extra);
        if (e < 0) return -1;
        c->step.edge_hits += e;
    }
    dcloth_drop_unfit_seconds(c);
    dcloth_opposites_as_seconds(c, h);
    return c->broad.ncand;
}

/* A failed step (s): the cloth put back to the step's start and, held, stopped there */
static cloth_status failed_step(dClothID c, cloth_status s, dClothStepStats *st, double t0)
{
    cloth_restore(c->core, c->step.save);
    st->contacts = st->sticking = 0;
    st->held = s == CLOTH_ESTEP && c->on_failure == DCLOTH_FAILURE_HOLD;
    if (st->held && c->held_run < DCLOTH_HOLD_MAX_HALVINGS) c->held_run++;
    if (st->held) { /* stopped where it is: the failed step's motion dropped, no energy added */
        memset(c->step.v0, 0, 3 * (size_t)c->n * sizeof *c->step.v0);
        cloth_set_velocities(c->core, c->step.v0);
    }
    st->seconds_total = wall() - t0;
    c->stats = *st;
    dcloth_fail(c, s, "dClothStep: %s%s", cloth_last_error(c->core), st->held ? " (the cloth held as it was)" : "");
    return st->held ? CLOTH_OK : s;
}

cloth_status dClothStep(dClothID c, dReal h)
{
    if (!c) return CLOTH_EINVAL;
    if (!(h > 0.0) || !isfinite(h)) return dcloth_fail(c, CLOTH_EINVAL, "dClothStep: h = %g must be finite and > 0", h);
    dClothStepStats st;
    memset(&st, 0, sizeof st);
    double t0 = wall();
    c->journal.n = 0;
    int sl = dcloth_sleep_before(c, h, t0);
    if (sl < 0) return dcloth_fail(c, CLOTH_ENOMEM, "dClothStep: out of memory for the candidate geoms");
    if (sl > 0) return CLOTH_OK;
    int cand = find_contacts(c, h);
    st.seconds_contacts = wall() - t0;
    if (cand < 0) return dcloth_fail(c, CLOTH_ENOMEM, "dClothStep: out of memory for the candidate geoms");
    st.candidates = cand;
    st.triangle_contacts = c->step.tri_hits;
    st.edge_contacts = c->step.edge_hits;
    cloth *core = c->core;
    memcpy(c->step.x0, cloth_positions(core), 3 * (size_t)c->n * sizeof *c->step.x0);
    memcpy(c->step.v0, cloth_velocities(core), 3 * (size_t)c->n * sizeof *c->step.v0);
    memcpy(c->step.fuser, cloth_external_forces(core), 3 * (size_t)c->n * sizeof *c->step.fuser);
    cloth_save(core, c->step.save);
    cloth_status s = CLOTH_OK;
    int passes = 0;
    for (;;) {
        dcloth_constrain(c, h, &st);
        dcloth_couple_bodies(c);
        s = dcloth_coupled_step(c, core, h, &st.core);
        passes++;
        st.newton_all += st.core.newton;
        st.cg_all += st.core.iterations;
        st.self_contact_seconds_all += st.core.self_contact_seconds;
        if (s != CLOTH_OK) break;
        if (!dcloth_revise(c, h, passes, &st) || passes >= DCLOTH_RESOLVE_PASSES) break;
        /* solve again from where this solve ended: a start Newton weighs against its others */
        const double *v1 = cloth_velocities(core);
        for (size_t q = 0; q < 3 * (size_t)c->n; q++) c->step.dv[q] = v1[q] - c->step.v0[q];
        cloth_restore(core, c->step.save);
        cloth_set_warm_start(core, c->step.dv);
    }
    st.resolves = passes - 1;
    cloth_set_external_forces(core, c->step.fuser); /* the user's again: friction is this step's alone */
    if (s != CLOTH_OK) return failed_step(c, s, &st, t0);
    dcloth_reactions(c, h, &st);
    dcloth_mark_pulled_shares(c);
    vcontact *t = c->vc;
    c->vc = c->vc_new;
    c->vc_new = t;
    memset(c->fadd, 0, 3 * (size_t)c->n * sizeof *c->fadd); /* applied: cleared, as ODE clears a body's */
    st.seconds_total = wall() - t0;
    c->held_run = 0;
    c->stats = st;
    dcloth_sleep_after(c);
    return CLOTH_OK;
}
