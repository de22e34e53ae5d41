/* The coupled step (dcloth.h, steps 2-5): contacts and pins become the core's
 * velocity constraints, friction becomes a force, the core steps, and what
 * each constraint did to the cloth goes back, opposite, to its body. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "dcloth_internal.h"
#include "body_motion.h"
#include "broadphase.h"
#include "contact_offers.h"
#include "edges.h"
#include "vertex_contacts.h"

static double wall(void)
{
    struct timespec t;
    timespec_get(&t, TIME_UTC);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* A free vertex that ends a step deeper than this fraction of the thickness
 * inside its shell makes the step be solved again with it held, up to
 * RESOLVE_PASSES solves in all. 8, not 4: lifting a cloth off a box over
 * its edges, contacts let go in waves, one pass after another, and a step
 * whose budget ran out kept its last solve's strain: drape_table
 * --box-table, alpha 1 (--short) 0.0310 with 4; at --grid 41, 0.0405 with
 * 6 (one step took 7 solves, four took 5; delta 0.03); with 8, 0.0300. */
#define RESOLVE_DEPTH 0.1
#define RESOLVE_PASSES 8
/* a let-go spreads along the links (below) from the PEEL_AFTER-th solve
 * of a step */
#define PEEL_AFTER 3

/* A triangle's contact lets go of a vertex it pulls onto the body harder
 * than LETGO_PULL of the tension of a link at the elongation limit (k_t
 * delta l0, l0 the grid spacing), within the step: the vertex is left free
 * and the step solved again (one of the RESOLVE_PASSES; a vertex let go
 * that then ends inside its shell is held again, forced). Never let go (as
 * it was), they held a cloth lifted off a box table by its corners until
 * its links tore (drape_table --box-table: strain 0.46, step 367). Not at
 * any pull: a cloth lying over an edge is bent there, and the rim vertices'
 * contacts hold them down against the bending. Measured at 0.15 (cotton
 * 21x21: 0.45 N, about 100 vertex weights): the 21x21 lift at the limit,
 * 0.0300; plugin_coupling's 0.5 kg box on a pinned cloth 0.19%, 0.14 mm/s;
 * an 81x81 cloth at rest on a box 56 ms a step (53 never letting go). A
 * threshold of 100 vertex weights instead (the first form) re-solved most
 * 81x81 steps (116 ms) and, with no gravity, let go at any pull and failed
 * a step. The 41x41 lift reaches 0.054 (open). Vertex contacts keep their
 * rule (contact_rule: let go the step after they pulled). */
#define LETGO_PULL 0.15

/* A triangle's contact held over from the last step sticks (static
 * friction) only on vertices that carry at least this barycentric weight of
 * the contact point; the others slide. Why: a triangle lying on an edge like
 * a plank, touching it next to one vertex, held its far vertex (weight 0.018, 4 cm above the table top) on
 * the triangle's plane; the cloth's links pulling that vertex toward the
 * table read as a normal force of 22-300 N on it, and friction that large
 * anchored it to the turning table: a lock that stretched its link to strain
 * 0.11 (soak_turntable, 13,225 of 100,000 steps over 0.035); sliding, the
 * vertex lets its links relax (0.0300, none over 0.035). A new contact
 * sticks whatever its weight, stopping the approach: sliding at first too,
 * a cylinder's rim came within 0 of a triangle at impact (plugin_colliders,
 * 0.114 mm with the rule as it is). */
#define STICK_WEIGHT 0.1

/* A link counts as past the elongation limit, for sliding its sticking
 * vertices, beyond (1 + delta)(1 + SLIP_STRAIN) of its rest length (the
 * projection's rounding); after a Newton step, beyond its limit_tolerance. */
#define SLIP_STRAIN 1e-4

/* Decide the vertex's contact for this step: none (returns 0), sticking or
 * sliding; fills its constraint and, sliding, its friction force. newton:
 * the core decides contacts within its step (candidates). */
static int contact_rule(dClothID c, int i, double h, double mass, const double g[3], vcontact *nw,
                        const vcontact *old, cloth_constraint *k, dClothStepStats *st, int forced, int newton)
{
    const double *x = cloth_positions(c->core) + 3 * i, *v = cloth_velocities(c->core) + 3 * i;
    const double *n = nw->normal;
    double rel[3] = {v[0] - nw->vbody[0], v[1] - nw->vbody[1], v[2] - nw->vbody[2]};
    double vn = dcloth_dot3(rel, n);
    /* Pinched: the opposite contact's surface (another geom, facing this
     * one) would be entered by this contact's target. The vertex then
     * aims midway between the two targets along the normal, held (never
     * released, let go or left apart) and sliding: each surface takes
     * half of what the two thicknesses lack. Before, a vertex kept only
     * the nearer surface's target, inside the other: between two closing
     * plates the cloth went through the lower one by 3.9 cm and the step
     * failed (box meshes; plugin_pinch). */
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
        k->target[r] = x[r] + h * nw->vbody[r] - nw->gap * n[r] + (dmid - d1) * n[r];
        k->axis[r] = n[r];
        nw->friction[r] = 0.0;
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
    nw->anchored = 0;
    if (stick && nw->body && dBodyIsKinematic(nw->body)) {
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

/* Whether vertex i's contact lets go by the triangle contacts' rule (a pull
 * past LETGO_PULL, within the step): a triangle's, or the vertex's own that
 * follows one, whose last force was that triangle's share */
static int by_triangle_rule(dClothID c, int i)
{
    const vcontact *nw = &c->vc_new[i], *old = &c->vc[i];
    return nw->from_triangle || (old->from_triangle && old->geom == nw->geom);
}

/* Whether vertex i carries a share of a triangle's contact that Newton
 * judges as one, by its own force (mark_pulled_shares): its point weighs
 * the vertex, and it may let go (neither anchored, pinched nor forced) */
static int shared(dClothID c, int i, int newton)
{
    const vcontact *nw = &c->vc_new[i];
    return newton && nw->from_triangle && nw->tri >= 0 && nw->weight > 0.0 && !nw->anchored && !nw->pinched &&
           !nw->forced;
}

/* Marks (let_go) each carrier of a triangle contact that, as a whole,
 * pulled in this step: sum w f over its carriers, the sign of the one point
 * force that puts w lambda on each; the next step lets it go. sum: n doubles */
static void mark_pulled_shares(dClothID c, double *sum)
{
    for (int i = 0; i < c->n; i++) sum[i] = 0.0;
    for (int pass = 0; pass < 2; pass++)
        for (int i = 0; i < c->n; i++) {
            vcontact *o = &c->vc_new[i];
            if (!o->active || !shared(c, i, 1)) continue;
            const int *p = c->tri + 3 * (size_t)o->tri;
            int lead = i;
            for (int a = 0; a < 3; a++)
                if (c->vc_new[p[a]].from_triangle && c->vc_new[p[a]].query == o->query && p[a] < lead) lead = p[a];
            if (pass == 0) sum[lead] += o->weight * dcloth_dot3(o->force, o->normal);
            else o->let_go = sum[lead] < 0.0;
        }
}

/* The index of body b among this step's coupled bodies, adding it (with
 * its mass, inertia in world axes, centre and the forces ODE holds for it
 * now, gravity included) when new; -1 when it is not coupled or memory ran
 * out. Not coupled: no body (static geom), kinematic, disabled, implicit
 * coupling off, and bodies in joints (contact joints included): a joint
 * changes how the body answers a force in ways the cloth's solve does not
 * see (a box on a slider, coupled as if free, swung with its cloth). */
static int coupled_body(dClothID c, dBodyID b)
{
    if (!b || !c->implicit || dBodyIsKinematic(b) || !dBodyIsEnabled(b) || dBodyGetNumJoints(b) > 0) return -1;
    for (int k = 0; k < c->nbodies; k++)
        if (c->bodies[k] == b) return k;
    if (c->nbodies == c->bodies_cap) {
        int cap = c->bodies_cap ? 2 * c->bodies_cap : 8;
        dBodyID *nb = realloc(c->bodies, (size_t)cap * sizeof *nb);
        if (nb) c->bodies = nb;
        cloth_body *nd = nb ? realloc(c->bdesc, (size_t)cap * sizeof *nd) : NULL;
        if (nd) c->bdesc = nd;
        if (!nb || !nd) return -1;
        c->bodies_cap = cap;
    }
    dMass m;
    dBodyGetMass(b, &m);
    const dReal *R = dBodyGetRotation(b), *pos = dBodyGetPosition(b);
    const dReal *F = dBodyGetForce(b), *T = dBodyGetTorque(b);
    dVector3 g = {0, 0, 0};
    if (dBodyGetGravityMode(b)) dWorldGetGravity(c->world, g);
    cloth_body *d = &c->bdesc[c->nbodies];
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
    c->bodies[c->nbodies] = b;
    return c->nbodies++;
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
static void couple_bodies(dClothID c)
{
    cloth *core = c->core;
    c->nbodies = 0;
    for (int i = 0; i < c->n; i++) {
        dBodyID b = holder(c, i);
        if (b) coupled_body(c, b);
    }
    if (cloth_set_bodies(core, c->bdesc, c->nbodies) != CLOTH_OK) return; /* invalid mass: explicit */
    for (int i = 0; i < c->n && c->nbodies > 0; i++) {
        dBodyID b = holder(c, i);
        int k = b ? coupled_body(c, b) : -1;
        if (k >= 0) cloth_hold_by_body(core, i, k);
    }
}

/* Vertex i, near its geom but left free, as a contact candidate: the core's
 * Newton step holds it where it would end deeper in its shell than the
 * re-solve rule below lets a free vertex be (RESOLVE_DEPTH). */
static void candidate(dClothID c, int i, double h, vcontact *nw, int newton)
{
    const double *x = cloth_positions(c->core) + 3 * i;
    double p[3], d = nw->gap + RESOLVE_DEPTH * nw->thickness;
    for (int r = 0; r < 3; r++) p[r] = x[r] + h * nw->vbody[r] - d * nw->normal[r];
    nw->candidate = newton && isfinite(p[0] + p[1] + p[2]) && cloth_set_contact(c->core, i, nw->normal, p) == CLOTH_OK;
}

/* Vertex i's second surface (Newton), a candidate as above */
static void second_candidate(dClothID c, int i, double h, const vcontact *nw, int newton)
{
    const double *x = cloth_positions(c->core) + 3 * i;
    double p[3], d = nw->sec_gap + RESOLVE_DEPTH * nw->sec_thickness;
    for (int r = 0; r < 3; r++) p[r] = x[r] + h * nw->sec_vbody[r] - d * nw->sec_normal[r];
    if (newton && nw->sec_geom && !nw->pinched && isfinite(p[0] + p[1] + p[2]))
        cloth_set_contact_second(c->core, i, nw->sec_normal, p);
}

/* What the step decided (cloth_set_contact): sticking contacts it let
 * slide, free candidates it held on the normal alone, as if forced */
static void took_candidates(dClothID c, dClothStepStats *st)
{
    for (int i = 0; i < c->n; i++) {
        vcontact *nw = &c->vc_new[i];
        cloth_constraint k;
        if (!nw->geom || c->pin[i].active) continue;
        if (cloth_get_contact_planes(c->core, i, &k, NULL, NULL, NULL) != CLOTH_OK || k.ndof != 1) continue;
        if (nw->active && nw->sticking) { /* let slide by the step */
            nw->sticking = 0;
            nw->slides = 1;
            st->sticking--;
        }
        if (nw->active) continue;
        nw->active = nw->forced = 1;
        nw->pinch_shift = 0.0;
        nw->sticking = 0;
        memset(nw->friction, 0, sizeof nw->friction);
        st->contacts++;
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
static cloth_status held_run_step(dClothID c, cloth *core, double h, cloth_step_stats *st)
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

/* For the step of h seconds, every vertex's nearest surface among the candidate geoms of c->space, into
 * c->vc_new (geom 0 where there is none within reach): the vertices', the triangles' and the links' tests.
 * Returns the number of candidate geoms, or -1 when memory ran out. */
static int find_contacts(dClothID c, double h)
{
    double extra = dcloth_newton_reach(c, h);
    if (dcloth_find_surfaces(c, h, extra) < 0) return -1;
    dcloth_vertex_contacts(c, h, extra);
    c->tri_hits = 0;
    for (int a = 0; a < c->ncand; a++) c->tri_hits += dcloth_triangle_contacts(c, &c->surf[a], h);
    c->edge_hits = 0;
    for (int a = 0; a < c->ncand; a++) {
        int e = dcloth_edge_contacts(c, &c->surf[a], h, extra);
        if (e < 0) return -1;
        c->edge_hits += e;
    }
    dcloth_drop_unfit_seconds(c);
    return c->ncand;
}

cloth_status dClothStep(dClothID c, dReal h)
{
    if (!c) return CLOTH_EINVAL;
    if (!(h > 0.0) || !isfinite(h)) return dcloth_fail(c, CLOTH_EINVAL, "dClothStep: h = %g must be finite and > 0", h);
    dClothStepStats st;
    memset(&st, 0, sizeof st);
    double t0 = wall();
    c->njournal = 0;
    int sl = dcloth_sleep_before(c, h, t0);
    if (sl < 0) return dcloth_fail(c, CLOTH_ENOMEM, "dClothStep: out of memory for the candidate geoms");
    if (sl > 0) return CLOTH_OK;
    int cand = find_contacts(c, h);
    st.seconds_contacts = wall() - t0;
    if (cand < 0) return dcloth_fail(c, CLOTH_ENOMEM, "dClothStep: out of memory for the candidate geoms");
    st.candidates = cand;
    st.triangle_contacts = c->tri_hits;
    st.edge_contacts = c->edge_hits;
    cloth *core = c->core;
    const double *mass = cloth_masses(core);
    cloth_desc cd = cloth_get_desc(core);
    memcpy(c->x0, cloth_positions(core), 3 * (size_t)c->n * sizeof *c->x0);
    memcpy(c->v0, cloth_velocities(core), 3 * (size_t)c->n * sizeof *c->v0);
    memcpy(c->fuser, cloth_external_forces(core), 3 * (size_t)c->n * sizeof *c->fuser);
    cloth_save(core, c->save);
    double spacing = fmin(cd.width / (cd.cols - 1), cd.height / (cd.rows - 1));
    double letgo_t = cd.material.k_t * cd.material.delta * spacing;
    int newton = cd.solver.nonlinear == CLOTH_NEWTON;
    cloth_status s = CLOTH_OK;
    int passes = 0;
    for (;;) {
        /* constraints of this pass: pins, then contacts */
        cloth_release_all(core);
        for (size_t q = 0; q < 3 * (size_t)c->n; q++) c->fext[q] = c->fuser[q] + c->fadd[q];
        st.pins = st.contacts = st.sticking = st.released = 0;
        st.max_penetration = 0.0;
        for (int i = 0; i < c->n; i++) {
            vpin *p = &c->pin[i];
            if (!p->active) continue;
            double target[3];
            if (p->body) {
                dcloth_follow_body(p->body, p->local, h, p->world, target);
            } else {
                memcpy(target, p->local, sizeof target);
            }
            cloth_pin(core, i, target);
            st.pins++;
        }
        for (int i = 0; i < c->n; i++) {
            vcontact *nw = &c->vc_new[i];
            nw->active = nw->candidate = 0;
            if (!nw->geom || c->pin[i].active) continue;
            cloth_constraint k;
            /* a target the core refuses (not finite: a body's velocity
             * NaN) leaves the vertex free; a vertex left free is a
             * candidate the Newton step may hold on the surface */
            if (!contact_rule(c, i, h, mass[i], cd.gravity, nw, &c->vc[i], &k, &st, nw->forced, newton) ||
                cloth_set_constraint(core, &k) != CLOTH_OK) {
                candidate(c, i, h, nw, newton);
                second_candidate(c, i, h, nw, newton);
                continue;
            }
            nw->active = 1;
            /* the core's step may let a sticking contact slide, and a
             * vertex's sliding one go where it holds a link past the limit */
            if ((k.ndof == 3 && !nw->anchored && !nw->pinched) || (k.ndof == 1 && !nw->pinched)) {
                cloth_set_contact(core, i, nw->normal, k.target);
                /* Newton lets a vertex's own contact that follows a triangle's
                 * go within the step at the pull the peel below judges after
                 * it; a triangle's own goes by its force (share_pulled) */
                if (by_triangle_rule(c, i) && !shared(c, i, newton))
                    cloth_set_contact_pull(core, i, LETGO_PULL * letgo_t);
            }
            second_candidate(c, i, h, nw, newton);
            for (int r = 0; r < 3; r++) c->fext[3 * i + r] += nw->friction[r];
            st.contacts++;
            st.sticking += nw->sticking;
            if (!nw->from_triangle && -nw->gap > st.max_penetration) st.max_penetration = -nw->gap;
        }
        cloth_set_external_forces(core, c->fext);
        couple_bodies(c);
        s = held_run_step(c, core, h, &st.core);
        passes++;
        st.newton_all += st.core.newton;
        st.cg_all += st.core.iterations;
        st.self_contact_seconds_all += st.core.self_contact_seconds;
        if (s != CLOTH_OK) break;
        took_candidates(c, &st);
        /* vertices the search did not reach at the step's start (a step can
         * carry them farther than their start velocity says) that ended
         * inside a shell: contacts from now on, and the step solved again */
        int more = dcloth_find_late_contacts(c, c->x0, cloth_positions(core), RESOLVE_DEPTH);
        st.late_contacts += more;
        /* a vertex left free (released, or predicted to stay apart) that
         * ended the step inside its shell, and that the step did not decide
         * itself (a candidate): hold it and solve the step again from its
         * start (an active set, at most RESOLVE_PASSES solves) */
        const double *x1 = cloth_positions(core);
        for (int i = 0; i < c->n; i++) {
            vcontact *nw = &c->vc_new[i];
            cloth_constraint k;
            /* a shared contact the step let go counts as left free */
            int gone = shared(c, i, newton) && nw->active && cloth_get_constraint(core, i, &k) == CLOTH_OK && !k.ndof;
            if (!nw->geom || (nw->active && !gone) || nw->candidate || c->pin[i].active) continue;
            double d[3] = {x1[3 * i] - c->x0[3 * i] - h * nw->vbody[0], x1[3 * i + 1] - c->x0[3 * i + 1] - h * nw->vbody[1],
                           x1[3 * i + 2] - c->x0[3 * i + 2] - h * nw->vbody[2]};
            if (nw->gap + dcloth_dot3(d, nw->normal) < -RESOLVE_DEPTH * nw->thickness) {
                nw->forced = 1;
                more++;
            }
        }
        /* a triangle's contact that pulled its vertex onto the body, by
         * more than LETGO_PULL of a link's tension at the limit: let go,
         * and solve again */
        int peel = 0;
        for (int i = 0; i < c->n; i++) {
            vcontact *nw = &c->vc_new[i];
            if (!nw->active || !by_triangle_rule(c, i) || shared(c, i, newton) || nw->forced || nw->pinched) continue;
            double f[3];
            dcloth_first_force(core, i, f);
            if (dcloth_dot3(f, nw->normal) < -LETGO_PULL * letgo_t) {
                nw->let_go = 1;
                more++;
                peel++;
            }
        }
        /* From the step's third solve on (a peel under way), with it the
         * triangle contacts on the same geom that pull at all, reached from
         * it along sequential links through such contacts: the strip a lift
         * peels off. One at a time, each vertex let go made the next pull
         * in the next solve, and lifting a cloth off a box over its edges
         * took up to 23 solves in a step (drape_table --box-table --grid
         * 41, alpha 1: the budget of 8 ran out at strain 0.078; with this,
         * 8 at most and 0.03015, the same with a budget of 12). Not from
         * the first: a box resting
         * on a pinned cloth, whose contacts now and then let go of one
         * vertex, jittered at 3 mm/s with its neighbours let go too
         * (plugin_coupling; bound 1 mm/s; measured 0.14 mm/s without) */
        while (peel && passes >= PEEL_AFTER) {
            peel = 0;
            int nl = cloth_link_count(core, CLOTH_SEQUENTIAL);
            for (int e = 0; e < nl; e++) {
                cloth_link L;
                cloth_get_link(core, CLOTH_SEQUENTIAL, e, &L);
                for (int end = 0; end < 2; end++) {
                    int a = end ? L.j : L.i, b = end ? L.i : L.j;
                    vcontact *va = &c->vc_new[a], *vb = &c->vc_new[b];
                    /* from those let go after this solve (still active),
                     * not in this sweep (2): a sweep goes one link */
                    if (va->let_go != 1 || !va->active || vb->let_go || !vb->active || !vb->from_triangle ||
                        vb->forced || vb->pinched || vb->geom != va->geom)
                        continue;
                    double f[3];
                    dcloth_first_force(core, b, f);
                    if (dcloth_dot3(f, vb->normal) < 0.0) {
                        vb->let_go = 2;
                        more++;
                        peel++;
                    }
                }
            }
            for (int i = 0; i < c->n; i++)
                if (c->vc_new[i].let_go == 2) c->vc_new[i].let_go = 1;
        }
        /* a sticking vertex on a sequential link that ended the solve past
         * the elongation limit (beyond SLIP_STRAIN): it slides in the next
         * solve. The stick test used the last step's forces; a link
         * stretched past delta pulls harder than that friction held, and
         * two vertices sticking to one body keep their distance: a 3 kg box
         * landing in a hammock held the links under its bottom edges at
         * strain 0.031-0.039 (trampoline, 9 of 15 grids and rates over
         * delta + 1e-4; with this rule none, 0.0300-0.0301) */
        {
            const double *x1 = cloth_positions(core);
            double slip = cd.solver.nonlinear == CLOTH_NEWTON ? cd.solver.limit_tolerance : SLIP_STRAIN;
            double lim = (1.0 + cd.material.delta) * (1.0 + slip);
            int nl = cloth_link_count(core, CLOTH_SEQUENTIAL);
            for (int e = 0; e < nl; e++) {
                cloth_link L;
                cloth_get_link(core, CLOTH_SEQUENTIAL, e, &L);
                vcontact *a = &c->vc_new[L.i], *b = &c->vc_new[L.j];
                int sa = a->active && a->sticking && !a->slides, sb = b->active && b->sticking && !b->slides;
                if (!sa && !sb) continue;
                double d[3] = {x1[3 * L.j] - x1[3 * L.i], x1[3 * L.j + 1] - x1[3 * L.i + 1], x1[3 * L.j + 2] - x1[3 * L.i + 2]};
                if (dcloth_dot3(d, d) <= lim * lim * L.rest * L.rest) continue;
                if (sa) a->slides = 1;
                if (sb) b->slides = 1;
                more++;
            }
        }
        if (!more || passes >= RESOLVE_PASSES) break;
        cloth_restore(core, c->save);
    }
    st.resolves = passes - 1;
    cloth_set_external_forces(core, c->fuser); /* the user's again: friction was this step's */
    if (s != CLOTH_OK) {
        cloth_restore(core, c->save);
        st.contacts = st.sticking = 0;
        st.held = s == CLOTH_ESTEP && c->on_failure == DCLOTH_FAILURE_HOLD;
        if (st.held && c->held_run < DCLOTH_HOLD_MAX_HALVINGS) c->held_run++;
        if (st.held) { /* stopped where it was: the failed step's motion dropped, no energy added */
            memset(c->v0, 0, 3 * (size_t)c->n * sizeof *c->v0);
            cloth_set_velocities(core, c->v0);
        }
        st.seconds_total = wall() - t0;
        c->stats = st;
        dcloth_fail(c, s, "dClothStep: %s%s", cloth_last_error(core), st.held ? " (the cloth held as it was)" : "");
        return st.held ? CLOTH_OK : s;
    }

    /* the target moved the vertex across its gap (or out of its shell), less
     * a pinched vertex's midway shift: a displacement, not a velocity; the
     * normal velocity keeps only the body's (an inelastic impact, no pop);
     * all set at once, as setting velocities resets the core's history */
    int fixed = 0;
    for (int i = 0; i < c->n; i++) {
        vcontact *nw = &c->vc_new[i];
        cloth_constraint k;
        double moved = nw->gap - nw->pinch_shift; /* minus how far the target moved it out */
        if (!nw->active || moved == 0.0) continue;
        if (cloth_get_contact_planes(core, i, &k, NULL, NULL, NULL) == CLOTH_OK && k.ndof == 0) continue; /* let go */
        if (!fixed) memcpy(c->vfix, cloth_velocities(core), 3 * (size_t)c->n * sizeof *c->vfix);
        fixed = 1;
        for (int r = 0; r < 3; r++) c->vfix[3 * i + r] += moved / h * nw->normal[r];
    }
    if (fixed) cloth_set_velocities(core, c->vfix);

    /* Each body takes, at each of its vertices, the force the cloth felt there
     * (constraint, friction) and a share, by force size, of F: the momentum
     * the cloth gained that gravity, f_ext, the air and those do not explain. */
    double F[3] = {0.0, 0.0, 0.0}, wsum = 0.0;
    {
        const double *v1 = cloth_velocities(core), *fe = c->fext;
        cloth_air_force(core, F); /* the air's push is explained: no body's share */
        for (int r = 0; r < 3; r++) F[r] = -F[r];
        for (int i = 0; i < c->n; i++)
            for (int r = 0; r < 3; r++)
                F[r] += mass[i] * (v1[3 * i + r] - c->v0[3 * i + r]) / h - mass[i] * cd.gravity[r] - fe[3 * i + r];
        for (int i = 0; i < c->n; i++) {
            if (!c->pin[i].active && !c->vc_new[i].active) continue;
            double f[3];
            cloth_constraint_force(core, i, f);
            wsum += sqrt(dcloth_dot3(f, f));
            for (int r = 0; r < 3; r++) F[r] -= f[r];
        }
    }
    /* and the angular momentum no force explains (momentum.c) */
    double R[3];
    dcloth_leftover(c, h, F, wsum, R, &st);
    for (int i = 0; i < c->n; i++) {
        vpin *p = &c->pin[i];
        vcontact *nw = &c->vc_new[i];
        double f[3] = {0.0, 0.0, 0.0}, w = 0.0; /* w: the vertex's share of the leftovers */
        dBodyID b = c->holder[i]; /* the body the turn moved with the vertex */
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
    if (newton) mark_pulled_shares(c, c->share_sum);
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
