/* Reactions (dcloth.h, step 5): what each constraint did to the cloth goes
 * back, opposite, to its body, with the momentum the cloth gained that no
 * force explains shared among the moving bodies that hold it. */
#include <math.h>
#include <string.h>
#include "dcloth_internal.h"
#include "journal.h"
#include "momentum.h"
#include "reactions.h"
#include "vertex_force.h"

/* The target moved the vertex across its gap (or out of its shell), less a pinched vertex's midway
 * shift: a displacement, not a velocity; the normal velocity keeps only the body's (inelastic, no pop);
 * all set at once, as setting velocities resets the core's history */
static void fix_velocities(dClothID c, double h)
{
    cloth *core = c->core;
    int fixed = 0;
    for (int i = 0; i < c->n; i++) {
        vcontact *nw = &c->vc_new[i];
        cloth_constraint k;
        double moved = nw->gap - nw->pinch_shift; /* minus how far the target moved it out */
        if (!nw->active || moved == 0.0) continue;
        if (cloth_get_contact_planes(core, i, &k, NULL, NULL, NULL) == CLOTH_OK && k.ndof == 0) continue; /* let go */
        if (!fixed) memcpy(c->reactions.vfix, cloth_velocities(core), 3 * (size_t)c->n * sizeof *c->reactions.vfix);
        fixed = 1;
        for (int r = 0; r < 3; r++) c->reactions.vfix[3 * i + r] += moved / h * nw->normal[r];
    }
    if (fixed) cloth_set_velocities(core, c->reactions.vfix);
}

/* Each body takes, at each of its vertices, the force the cloth felt there
 * (constraint, friction) and a share, by force size, of F: the momentum
 * the cloth gained that gravity, f_ext, the air and those do not explain. */
static double leftover_force(dClothID c, double h, double F[3])
{
    cloth *core = c->core;
    const double *mass = cloth_masses(core);
    cloth_desc cd = cloth_get_desc(core);
    double wsum = 0.0;
    F[0] = F[1] = F[2] = 0.0;
    const double *v1 = cloth_velocities(core), *fe = c->step.fext;
    cloth_air_force(core, F); /* the air's push is explained: no body's share */
    for (int r = 0; r < 3; r++) F[r] = -F[r];
    for (int i = 0; i < c->n; i++)
        for (int r = 0; r < 3; r++)
            F[r] += mass[i] * (v1[3 * i + r] - c->step.v0[3 * i + r]) / h - mass[i] * cd.gravity[r] - fe[3 * i + r];
    for (int i = 0; i < c->n; i++) {
        if (!c->pin[i].active && !c->vc_new[i].active) continue;
        double f[3];
        cloth_constraint_force(core, i, f);
        wsum += sqrt(dcloth_dot3(f, f));
        for (int r = 0; r < 3; r++) F[r] -= f[r];
    }
    return wsum;
}

/* The moving bodies' share of the leftover torque taken out by the turn (momentum.c): sets c->reactions.holder, R
 * (each body gets -w R, w its vertices' shares) and st's turned and couple */
static void leftover(dClothID c, double h, const double F[3], double wsum, double R[3], dClothStepStats *st)
{
    double T[3], W = 0.0, f[3];
    for (int i = 0; i < c->n; i++) {
        c->reactions.holder[i] = 0;
        if (!c->pin[i].active && !c->vc_new[i].active) continue;
        W += dcloth_vertex_force(c, i, F, wsum, f);
        c->reactions.holder[i] = dcloth_force_body(c, i, f);
    }
    dcloth_leftover_torque(c, h, F, wsum, T);
    double dL[3] = {-h * W * T[0], -h * W * T[1], -h * W * T[2]}, done[3] = {0.0, 0.0, 0.0};
    if (W > 0.0) dcloth_turn(c, dL, done);
    for (int r = 0; r < 3; r++) {
        R[r] = W > 0.0 ? T[r] + done[r] / (h * W) : 0.0;
        st->turned[r] = -done[r]; /* done is the change the turn made: -(what it took out) */
        st->couple[r] = -W * R[r];
    }
}

/* Each constraint's force on the cloth goes back, opposite, to its body at
 * the vertex, with its share of the leftover force and torque; held
 * contacts carry their forces to the next step. */
void dcloth_reactions(dClothID c, double h, dClothStepStats *st)
{
    cloth *core = c->core;
    fix_velocities(c, h);
    double F[3], wsum = leftover_force(c, h, F);
    /* and the angular momentum no force explains (momentum.c) */
    double R[3];
    leftover(c, h, F, wsum, R, st);
    for (int i = 0; i < c->n; i++) {
        vpin *p = &c->pin[i];
        vcontact *nw = &c->vc_new[i];
        double f[3] = {0.0, 0.0, 0.0}, w = 0.0; /* w: the vertex's share of the leftovers */
        dBodyID b = c->reactions.holder[i];     /* the body the turn moved with the vertex */
        /* where the cloth felt the force: a body takes it there too, so no
         * angular momentum is made between them */
        const double *at = cloth_positions(core) + 3 * i;
        if (p->active || nw->active) w = dcloth_vertex_force(c, i, F, wsum, f);
        if (p->active) memcpy(p->force, f, sizeof f);
        else if (nw->active) memcpy(nw->force, f, sizeof f);
        if (b && !dBodyIsKinematic(b)) {
            dcloth_touch(c, b);
            dBodyAddForceAtPos(b, -f[0], -f[1], -f[2], at[0], at[1], at[2]);
            dBodyAddTorque(b, -w * R[0], -w * R[1], -w * R[2]);
        }
        if (!p->active && !nw->active) memset(nw, 0, sizeof *nw); /* only held contacts carry over */
    }
}
