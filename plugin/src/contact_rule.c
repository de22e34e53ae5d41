/* The contact rule (dcloth.h, step 3): a vertex's contact becomes none, a
 * sticking constraint or a sliding one with its friction force, by its gap,
 * its approach, its last force and Coulomb's cone. */
#include <math.h>
#include <string.h>
#include "dcloth_internal.h"
#include "body_motion.h"
#include "contact_rule.h"

/* Pinched: the opposite contact's surface (another geom, facing this
 * one) would be entered by this contact's target. The vertex then
 * aims midway between the two targets along the normal, held (never
 * released, let go or left apart) and sliding: each surface takes
 * half of what the two thicknesses lack. Before, a vertex kept only
 * the nearer surface's target, inside the other: between two closing
 * plates the cloth went through the lower one by 3.9 cm and the step
 * failed (box meshes; plugin_pinch). */
static void pinch(vcontact *nw, double h)
{
    const double *n = nw->normal;
    double d1 = h * dcloth_dot3(nw->vbody, n) - nw->gap, dmid = d1;
    nw->pinched = 0;
    if (nw->opp_geom && nw->opp_geom != nw->geom) {
        double nn = dcloth_dot3(n, nw->opp_normal);
        if (nn < -DCLOTH_PINCH_COS) {
            double dmax = (h * dcloth_dot3(nw->opp_vbody, nw->opp_normal) - nw->opp_gap) / nn;
            if (d1 > dmax) {
                nw->pinched = 1;
                dmid = 0.5 * (d1 + dmax);
            }
        }
    }
    nw->pinch_shift = dmid - d1;
}

/* A vertex sticking to a kinematic body is held at a point fixed in the
 * body's frame, the anchor set when it began to stick, as a pin is.
 * Advancing its own position by the body's point velocity every step,
 * it drifted off the body's rigid motion (outward on a turning body, r
 * (w h)^2 / 2 per step, accumulating while it sticks). Measured on
 * soak_turntable (100,000 steps): without the anchor, one snap at step
 * 46,680 put 0.0127 J of kinetic energy in the table's frame (bound
 * 0.01 J); with it, at most 0.0024 J. Dynamic bodies keep the velocity
 * form: anchored to a rolling ball, the curtain's cloth overstretched
 * (strain 0.03106, delta 0.03). Across the surface the target stays on
 * the shell. */
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
int dcloth_contact_rule(dClothID c, int i, double h, double mass, const double g[3], vcontact *nw,
                        const vcontact *old, cloth_constraint *k, dClothStepStats *st, int forced, int newton)
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
    /* unilateral: a contact that pulled the vertex onto the body last step
     * lets go, unless the vertex is inside (by more than rounding: a vertex
     * the last step put exactly on its shell reads a gap of -1e-17, and was
     * held, pulling, for ever); a triangle's contact is judged
     * by its geometry alone (its vertices' forces along the triangle's
     * normal are often negative while the triangle as a whole presses:
     * releasing them made contacts on curved and edged geoms chatter), as
     * is a vertex's own contact whose last force was such a share: it lets
     * go by the triangles' rule this step (by_triangle_rule) */
    if (!forced && had && nw->gap >= -DCLOTH_TOUCH * nw->thickness &&
        ((fn < 0.0 && !nw->from_triangle && !old->from_triangle) || old->let_go)) {
        st->released++;
        return 0;
    }
    if (!had) {
        /* no force measured yet: what stops the approach within the step,
         * plus the weight pressing along the normal */
        double gn = dcloth_dot3(g, n);
        fn = mass * (vn < 0.0 ? -vn : 0.0) / h + (gn < 0.0 ? -mass * gn : 0.0);
    }
    if (fn < 0.0) fn = 0.0;
    double vt[3] = {rel[0] - vn * n[0], rel[1] - vn * n[1], rel[2] - vn * n[2]};
    double vts = sqrt(dcloth_dot3(vt, vt));
    memcpy(nw->slip, vt, sizeof vt);
    /* The tangential force on the vertex other than this contact's, f_o:
     * from the slip's change over the last step minus what the contact
     * applied then (constraint force and friction), or for a new contact
     * the weight's tangential part. Sticking holds when the force that stops
     * the slip within the step against f_o, F = -m vt / h - f_o, is within
     * mu fn (Coulomb's cone); otherwise the contact slides with mu fn. */
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
    /* A contact made ahead of a moving body (the vertex still apart, the
     * body approaching along the normal) does not stick: its vertex slides
     * onto the body, with kinetic friction. Held in all directions it was
     * carried with the body's point before touching, and two such vertices
     * of one box, one touching and one 2 cm under it, were pulled 12% apart
     * (trampoline, measured). On a static geom a sticking vertex is only
     * stopped, and keeps doing so (made to slide there too, a cloth landing
     * on a sphere ended at strain 0.0307, drape_sphere alpha 1). Only a gap
     * over the thickness counts: with any gap over the slop, cloth hanging
     * beside soak_turntable's turning table slid where the side faces swept
     * toward it, and crept (strain 0.36, 1235 of 100,000 steps over 0.035,
     * a snap of 0.055 J). */
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
