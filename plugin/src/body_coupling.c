/* Body coupling (dcloth.h, step 4): the moving bodies that hold the cloth
 * are solved with it (cloth_body), and the core's step is taken with this
 * step's solver. */
#include <stdlib.h>
#include "dcloth_internal.h"
#include "body_coupling.h"

/* The index of body b among this step's coupled bodies, adding it (mass, world inertia, centre and
 * ODE's current forces) when new; -1 if not coupled or out of memory. Static, kinematic, disabled,
 * coupling off or jointed bodies are not coupled: a joint changes the body's answer unseen by the solve. */
static int coupled_body(dClothID c, dBodyID b)
{
    if (!b || !c->implicit || dBodyIsKinematic(b) || !dBodyIsEnabled(b) || dBodyGetNumJoints(b) > 0) return -1;
    for (int k = 0; k < c->coupled.n; k++)
        if (c->coupled.bodies[k] == b) return k;
    if (c->coupled.n == c->coupled.cap) {
        int cap = c->coupled.cap ? 2 * c->coupled.cap : 8;
        dBodyID *nb = realloc(c->coupled.bodies, (size_t)cap * sizeof *nb);
        if (nb) c->coupled.bodies = nb;
        cloth_body *nd = nb ? realloc(c->coupled.bdesc, (size_t)cap * sizeof *nd) : NULL;
        if (nd) c->coupled.bdesc = nd;
        if (!nb || !nd) return -1;
        c->coupled.cap = cap;
    }
    dMass m;
    dBodyGetMass(b, &m);
    const dReal *R = dBodyGetRotation(b), *pos = dBodyGetPosition(b);
    const dReal *F = dBodyGetForce(b), *T = dBodyGetTorque(b);
    dVector3 g = {0, 0, 0};
    if (dBodyGetGravityMode(b)) dWorldGetGravity(c->world, g);
    cloth_body *d = &c->coupled.bdesc[c->coupled.n];
    d->mass = m.mass;
    /* I_world = R I R^T (ODE's 3x3 matrices have rows of 4) */
    for (int r = 0; r < 3; r++)
        for (int q = 0; q < 3; q++) {
            double s = 0.0;
            for (int a = 0; a < 3; a++)
                for (int e = 0; e < 3; e++) s += R[4 * r + a] * m.I[4 * a + e] * R[4 * q + e];
            d->inertia[3 * r + q] = s;
        }
    for (int r = 0; r < 3; r++) {
        /* symmetric to rounding: ODE keeps I symmetric, the product may not */
        for (int q = 0; q < r; q++) d->inertia[3 * r + q] = d->inertia[3 * q + r];
        d->com[r] = pos[r];
        d->force[r] = F[r] + m.mass * g[r];
        d->torque[r] = T[r];
        d->velocity[r] = dBodyGetLinearVel(b)[r];
        d->velocity[3 + r] = dBodyGetAngularVel(b)[r];
    }
    c->coupled.bodies[c->coupled.n] = b;
    return c->coupled.n++;
}

/* The body vertex i is pinned to, in contact with, or a contact candidate
 * of (the step may hold it on the body's surface), or 0. */
static dBodyID holder(dClothID c, int i)
{
    const vcontact *nw = &c->vc_new[i];
    return c->pin[i].active ? c->pin[i].body : nw->active || nw->candidate ? nw->body : 0;
}

/* Hand this pass's moving bodies to the core: an enabled dynamic body a
 * vertex is pinned to, touches or may touch (holder) is solved with the
 * cloth (cloth_body), so neither overshoots the other. */
void dcloth_couple_bodies(dClothID c)
{
    cloth *core = c->core;
    c->coupled.n = 0;
    for (int i = 0; i < c->n; i++) {
        dBodyID b = holder(c, i);
        if (b) coupled_body(c, b);
    }
    if (cloth_set_bodies(core, c->coupled.bdesc, c->coupled.n) != CLOTH_OK) return; /* invalid mass: explicit */
    for (int i = 0; i < c->n && c->coupled.n > 0; i++) {
        dBodyID b = holder(c, i);
        int k = b ? coupled_body(c, b) : -1;
        if (k >= 0) cloth_hold_by_body(core, i, k);
    }
}

/* Whether a dynamic body holds a vertex (a pin, a contact or a candidate's
 * surface): it takes the cloth's reactions, leftover momentum included. */
static int body_holds(dClothID c)
{
    for (int i = 0; i < c->n; i++) {
        dBodyID b = c->pin[i].active ? c->pin[i].body : c->vc_new[i].geom ? c->vc_new[i].body : 0;
        if (b && !dBodyIsKinematic(b)) return 1;
    }
    return 0;
}

/* The core's step with this step's solver: one more substep halving for each step held in a row (up to
 * the solver's bound), and Newton's solves to their relative stop only while a dynamic body holds the
 * cloth (what a shorter solve leaves over would move it). */
cloth_status dcloth_coupled_step(dClothID c, cloth *core, double h, cloth_step_stats *st)
{
    cloth_solver sv0 = cloth_get_desc(core).solver, sv = sv0;
    int exact = sv0.nonlinear == CLOTH_NEWTON && sv0.newton_cg_share > 0.0 && body_holds(c);
    if (!c->held_run && !exact) return cloth_step(core, h, st);
    if (exact) sv.newton_cg_share = 0.0;
    sv.max_substep_halvings = sv0.max_substep_halvings + c->held_run;
    if (sv.max_substep_halvings > DCLOTH_HOLD_MAX_HALVINGS) sv.max_substep_halvings = DCLOTH_HOLD_MAX_HALVINGS;
    cloth_set_solver(core, &sv);
    cloth_status s = cloth_step(core, h, st);
    cloth_set_solver(core, &sv0);
    return s;
}
