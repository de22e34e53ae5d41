/* The contact rule (dcloth.h, step 3): a vertex's contact becomes none, a
 * sticking constraint or a sliding one with its friction force, by its gap,
 * its approach, its last force and Coulomb's cone. */
#include <math.h>
#include <string.h>
#include "dcloth_internal.h"
#include "body_motion.h"
#include "contact_offers.h"
#include "contact_rule.h"

/* Pinched: this contact's target would enter the opposite contact's surface. The vertex then aims
 * midway between the two targets along the normal, held and sliding, each surface taking half of
 * what the two thicknesses lack, so the cloth enters neither (docs/contacts.md, "Design notes"). */
static void pinch(vcontact *nw, double h)
{
    double room = dcloth_pinch_room(nw, h);
    nw->pinched = room < 0.0;
    nw->pinch_shift = nw->pinched ? 0.5 * room : 0.0;
}

/* A vertex sticking to a kinematic body is held at an anchor fixed in the body's frame, as a pin is,
 * so it follows the rigid motion without drift; dynamic bodies keep the velocity form, and across the
 * surface the target stays on the shell (why: docs/contacts.md, "Design notes from the code"). */
static void anchor(vcontact *nw, const vcontact *old, int had, const double *x, double h, cloth_constraint *k)
{
    const double *n = nw->normal;
    if (had && old->anchored && old->body == nw->body) {
        memcpy(nw->anchor, old->anchor, sizeof nw->anchor);
    } else {
        dVector3 l;
        dBodyGetPosRelPoint(nw->body, x[0], x[1], x[2], l);
        for (int r = 0; r < 3; r++) nw->anchor[r] = l[r];
    }
    nw->anchored = 1;
    double w[3];
    dcloth_follow_body(nw->body, nw->anchor, h, w, k->target);
    double off = nw->gap + n[0] * (w[0] - x[0]) + n[1] * (w[1] - x[1]) + n[2] * (w[2] - x[2]);
    for (int r = 0; r < 3; r++) k->target[r] -= off * n[r];
}

/* Decide the vertex's contact for this step: none (returns 0), sticking or
 * sliding; fills its constraint and, sliding, its friction force. newton:
 * the core decides contacts within its step (candidates). */
int dcloth_contact_rule(dClothID c, int i, double h, double mass, const double g[3], vcontact *nw, const vcontact *old,
                        cloth_constraint *k, dClothStepStats *st, int forced, int newton)
{
    const double *x = cloth_positions(c->core) + 3 * i, *v = cloth_velocities(c->core) + 3 * i;
    const double *n = nw->normal;
    double rel[3] = {v[0] - nw->vbody[0], v[1] - nw->vbody[1], v[2] - nw->vbody[2]};
    double vn = dcloth_dot3(rel, n);
    pinch(nw, h);
    forced = forced || nw->pinched;
    if (!forced && nw->gap > 0.0 && nw->gap + h * vn > DCLOTH_CONTACT_SLOP * nw->thickness) return 0; /* stays apart */
    /* apart but approaching: a candidate, which the Newton step holds only
     * if it would end behind the surface and only while it pushes (held
     * ahead of the surface, a pulling contact does work across the gap) */
    if (!forced && newton && nw->gap > DCLOTH_CONTACT_SLOP * nw->thickness) return 0;
    if (!forced && nw->let_go) {
        st->released++;
        return 0;
    }
    int had = old->geom == nw->geom;
    double fn = had ? dcloth_dot3(old->force, old->normal) : 0.0;
    /* unilateral: a contact that pulled its vertex onto the body lets go unless the vertex is inside by
     * more than rounding; a triangle's contact, and a vertex's own whose last force was a triangle's share,
     * is judged by geometry alone (by_triangle_rule): its vertices can pull while the triangle presses */
    if (!forced && had && nw->gap >= -DCLOTH_TOUCH * nw->thickness &&
        ((fn < 0.0 && !nw->from_triangle && !old->from_triangle) || old->let_go)) {
        st->released++;
        return 0;
    }
    if (!had) {
        /* no force known yet: what stops the approach within the step, plus the weight pressing along the
         * normal */
        double gn = dcloth_dot3(g, n);
        fn = mass * (vn < 0.0 ? -vn : 0.0) / h + (gn < 0.0 ? -mass * gn : 0.0);
    }
    if (fn < 0.0) fn = 0.0;
    double vt[3] = {rel[0] - vn * n[0], rel[1] - vn * n[1], rel[2] - vn * n[2]};
    double vts = sqrt(dcloth_dot3(vt, vt));
    memcpy(nw->slip, vt, sizeof vt);
    /* The tangential force on the vertex other than this contact's, f_o: from the slip's change over the
     * last step less the contact's own forces then (new contact: the weight's tangential part). It sticks
     * while F = -m vt / h - f_o is within mu fn (Coulomb's cone), else slides with mu fn. */
    double fo[3], F[3];
    double gn = dcloth_dot3(g, n);
    for (int r = 0; r < 3; r++) fo[r] = mass * (g[r] - gn * n[r]);
    if (had) {
        double fnn = dcloth_dot3(old->force, old->normal);
        for (int r = 0; r < 3; r++) {
            double fc_t = old->force[r] - fnn * old->normal[r];
            fo[r] = mass * (vt[r] - old->slip[r]) / h - fc_t;
        }
    }
    for (int r = 0; r < 3; r++) F[r] = -mass * vt[r] / h - fo[r];
    double mu = nw->mu;
    double Fs = sqrt(dcloth_dot3(F, F)), limit = mu * fn;
    /* A contact made ahead of a moving body (vertex apart by over the thickness, body approaching) does
     * not stick: its vertex slides on with kinetic friction, so it is not carried with the body's point
     * before touching (docs/contacts.md). On a static geom a sticking vertex is only stopped. */
    int ahead = nw->gap > nw->thickness && h * dcloth_dot3(nw->vbody, n) > 0.1 * DCLOTH_CONTACT_SLOP * nw->thickness;
    int stick = mu > 0.0 && Fs <= limit && !ahead && (!had || nw->weight >= STICK_WEIGHT) && !nw->slides &&
                !nw->pinched;
    /* end-of-step position: moved with the body's point, the penetration
     * (negative gap) removed along the normal (paper eq. 22) */
    k->vertex = i;
    for (int r = 0; r < 3; r++) {
        k->target[r] = x[r] + h * nw->vbody[r] - nw->gap * n[r] + nw->pinch_shift * n[r];
        k->axis[r] = n[r];
        nw->friction[r] = 0.0;
    }
    nw->anchored = 0;
    if (stick && nw->body && dBodyIsKinematic(nw->body)) anchor(nw, old, had, x, h, k);
    k->ndof = stick ? 3 : 1;
    nw->sticking = stick;
    if (!stick && mu > 0.0 && limit > 0.0) {
        /* kinetic: mu fn against the slip (never more than stops it), or,
         * breaking away with no slip yet, along the force that would hold */
        if (vts > 0.0) {
            double stop = mass * vts / h, Fk = limit < stop ? limit : stop;
            for (int r = 0; r < 3; r++) nw->friction[r] = -Fk * vt[r] / vts;
        } else if (Fs > 0.0) {
            for (int r = 0; r < 3; r++) nw->friction[r] = limit * F[r] / Fs;
        }
    }
    return 1;
}
