/* The active set (dcloth.h, step 3): which pins and contacts hold in each solve of a step. Each pass
 * sets the constraints, the core solves, and contacts the solve shows wrong change for the next pass,
 * at most DCLOTH_RESOLVE_PASSES solves. */
#include <math.h>
#include <string.h>
#include "dcloth_internal.h"
#include "active_set.h"
#include "body_motion.h"
#include "contact_rule.h"
#include "late_triangles.h"
#include "vertex_contacts.h"
#include "vertex_force.h"

/* a link's tension at the elongation limit (N): k_t delta l0, l0 the grid spacing */
static double letgo_tension(const cloth_desc *cd)
{
    double spacing = fmin(cd->width / (cd->cols - 1), cd->height / (cd->rows - 1));
    return cd->material.k_t * cd->material.delta * spacing;
}

/* Whether vertex i's contact lets go by the triangle contacts' rule (a pull
 * past LETGO_PULL, within the step): a triangle's, or the vertex's own that
 * follows one, whose last force was that triangle's share */
static int by_triangle_rule(dClothID c, int i)
{
    const vcontact *nw = &c->vc_new[i], *old = &c->vc[i];
    return nw->from_triangle || (old->from_triangle && old->geom == nw->geom);
}

/* Whether vertex i carries a share of a triangle's contact judged as one, by
 * its own force (mark_pulled_shares): its point weighs the vertex, and it may
 * let go (neither anchored, pinched nor forced) */
static int shared(dClothID c, int i)
{
    const vcontact *nw = &c->vc_new[i];
    return nw->from_triangle && nw->tri >= 0 && nw->weight > 0.0 && !nw->anchored && !nw->pinched && !nw->forced;
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
    if (newton && nw->sec_geom && isfinite(p[0] + p[1] + p[2])) cloth_set_contact_second(c->core, i, nw->sec_normal, p);
}

/* This pass's constraints, from the step's start: pins, then contacts by the contact rule (the others left
 * free or as the Newton step's candidates), and the external forces with sliding friction. */
void dcloth_constrain(dClothID c, double h, dClothStepStats *st)
{
    cloth *core = c->core;
    const double *mass = cloth_masses(core);
    cloth_desc cd = cloth_get_desc(core);
    double letgo_t = letgo_tension(&cd);
    int newton = cd.solver.nonlinear == CLOTH_NEWTON;
    cloth_release_all(core);
    for (size_t q = 0; q < 3 * (size_t)c->n; q++) c->step.fext[q] = c->step.fuser[q] + c->fadd[q];
    st->pins = st->contacts = st->sticking = st->released = 0;
    st->max_penetration = 0.0;
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
        st->pins++;
    }
    for (int i = 0; i < c->n; i++) {
        vcontact *nw = &c->vc_new[i];
        nw->active = nw->candidate = 0;
        if (!nw->geom || c->pin[i].active) continue;
        cloth_constraint k;
        /* a target the core refuses (not finite: a body's velocity
         * NaN) leaves the vertex free; a vertex left free is a
         * candidate the Newton step may hold on the surface */
        if (!dcloth_contact_rule(c, i, h, mass[i], cd.gravity, nw, &c->vc[i], &k, st, nw->forced, newton) ||
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
             * it; a triangle's own goes by its force (dcloth_mark_pulled_shares) */
            if (by_triangle_rule(c, i) && !shared(c, i)) cloth_set_contact_pull(core, i, LETGO_PULL * letgo_t);
        }
        second_candidate(c, i, h, nw, newton);
        for (int r = 0; r < 3; r++) c->step.fext[3 * i + r] += nw->friction[r];
        st->contacts++;
        st->sticking += nw->sticking;
        if (!nw->from_triangle && -nw->gap > st->max_penetration) st->max_penetration = -nw->gap;
    }
    /* the search's deepest point, or a late contact's */
    st->max_penetration_all = fmax(c->step.deepest, st->max_penetration);
    cloth_set_external_forces(core, c->step.fext);
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

/* a vertex left free (released, or predicted apart) that ended the step inside its shell and that
 * the step did not decide itself (a candidate): hold it and solve the step again from its start
 * (at most DCLOTH_RESOLVE_PASSES solves) */
static int hold_inside(dClothID c, double h)
{
    cloth *core = c->core;
    int more = 0;
    const double *x1 = cloth_positions(core);
    for (int i = 0; i < c->n; i++) {
        vcontact *nw = &c->vc_new[i];
        cloth_constraint k;
        /* a shared contact the step let go counts as left free */
        int gone = shared(c, i) && nw->active && cloth_get_constraint(core, i, &k) == CLOTH_OK && !k.ndof;
        if (!nw->geom || (nw->active && !gone) || nw->candidate || c->pin[i].active) continue;
        double d[3] = {x1[3 * i] - c->step.x0[3 * i] - h * nw->vbody[0],
                       x1[3 * i + 1] - c->step.x0[3 * i + 1] - h * nw->vbody[1],
                       x1[3 * i + 2] - c->step.x0[3 * i + 2] - h * nw->vbody[2]};
        if (nw->gap + dcloth_dot3(d, nw->normal) < -RESOLVE_DEPTH * nw->thickness) {
            nw->forced = 1;
            more++;
        }
    }
    return more;
}

/* a vertex contact by the triangle rule, not a share of one, that pulled its vertex onto the body, by
 * more than LETGO_PULL of a link's tension at the limit: let go,
 * and solve again */
static int let_go_pulling(dClothID c, double letgo_t)
{
    cloth *core = c->core;
    int peel = 0;
    for (int i = 0; i < c->n; i++) {
        vcontact *nw = &c->vc_new[i];
        if (!nw->active || !by_triangle_rule(c, i) || shared(c, i) || nw->forced || nw->pinched) continue;
        double f[3];
        dcloth_first_force(core, i, f);
        if (dcloth_dot3(f, nw->normal) < -LETGO_PULL * letgo_t) {
            nw->let_go = 1;
            peel++;
        }
    }
    return peel;
}

/* One sweep of a peel: each triangle contact on the same geom that pulls at all, one sequential link from
 * a vertex let go after this solve, let go too; how many */
static int peel_sweep(dClothID c)
{
    cloth *core = c->core;
    int peel = 0;
    int nl = cloth_link_count(core, CLOTH_SEQUENTIAL);
    for (int e = 0; e < nl; e++) {
        cloth_link L;
        cloth_get_link(core, CLOTH_SEQUENTIAL, e, &L);
        for (int end = 0; end < 2; end++) {
            int a = end ? L.j : L.i, b = end ? L.i : L.j;
            vcontact *va = &c->vc_new[a], *vb = &c->vc_new[b];
            /* from those let go after this solve (still active),
             * not in this sweep (2): a sweep goes one link */
            if (va->let_go != 1 || !va->active || vb->let_go || !vb->active || !vb->from_triangle || vb->forced ||
                vb->pinched || vb->geom != va->geom)
                continue;
            double f[3];
            dcloth_first_force(core, b, f);
            if (dcloth_dot3(f, vb->normal) < 0.0) {
                vb->let_go = 2;
                peel++;
            }
        }
    }
    for (int i = 0; i < c->n; i++)
        if (c->vc_new[i].let_go == 2) c->vc_new[i].let_go = 1;
    return peel;
}

/* a sticking vertex on a sequential link the solve left past the limit (beyond SLIP_STRAIN) slides in
 * the next solve: the stick test used the last step's forces, and two vertices sticking to one body
 * keep their distance, so the link stays stretched (docs/contacts.md, "Design notes from the code") */
static int let_slide(dClothID c, const cloth_desc *cd)
{
    cloth *core = c->core;
    int more = 0;
    const double *x1 = cloth_positions(core);
    double slip = cd->solver.nonlinear == CLOTH_NEWTON ? cd->solver.limit_tolerance : SLIP_STRAIN;
    double lim = (1.0 + cd->material.delta) * (1.0 + slip);
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
    return more;
}

/* After a solve (pass `passes` of the step): what the step decided, and the contacts this solve shows
 * wrong: late contacts, free vertices ended inside, triangle contacts that pull (and the strip a peel takes),
 * sticking vertices on links past the limit. How many changed: 0, the active set is settled. */
int dcloth_revise(dClothID c, double h, int passes, dClothStepStats *st)
{
    cloth *core = c->core;
    cloth_desc cd = cloth_get_desc(core);
    took_candidates(c, st);
    /* vertices the search did not reach at the step's start (a step can
     * carry them farther than their start velocity says) that ended
     * inside a shell: contacts from now on, and the step solved again */
    int more = dcloth_find_late_contacts(c, c->step.x0, cloth_positions(core), RESOLVE_DEPTH);
    /* and triangles' vertices, where a slow start hid a triangle from its swept test */
    more += dcloth_late_triangles(c, h);
    st->late_contacts += more;
    more += hold_inside(c, h);
    int peel = let_go_pulling(c, letgo_tension(&cd));
    more += peel;
    /* From the step's third solve on (a peel under way), the triangle contacts on the same geom that pull,
     * reached along sequential links, let go together: the strip a lift peels off, which one vertex per
     * solve peels too slowly. Not earlier, where it makes resting bodies jitter (docs/contacts.md). */
    while (peel && passes >= PEEL_AFTER) {
        peel = peel_sweep(c);
        more += peel;
    }
    return more + let_slide(c, &cd);
}

/* Marks (let_go) each carrier of a triangle contact that, as a whole,
 * pulled in this step: sum w f over its carriers, the sign of the one point
 * force that puts w lambda on each; the next step lets it go. */
void dcloth_mark_pulled_shares(dClothID c)
{
    double *sum = c->active_set.share_sum;
    for (int i = 0; i < c->n; i++) sum[i] = 0.0;
    for (int pass = 0; pass < 2; pass++)
        for (int i = 0; i < c->n; i++) {
            vcontact *o = &c->vc_new[i];
            if (!o->active || !shared(c, i)) continue;
            const int *p = c->tri + 3 * (size_t)o->tri;
            int lead = i;
            for (int a = 0; a < 3; a++)
                if (c->vc_new[p[a]].from_triangle && c->vc_new[p[a]].query == o->query && p[a] < lead) lead = p[a];
            if (pass == 0) sum[lead] += o->weight * dcloth_dot3(o->force, o->normal);
            else o->let_go = sum[lead] < 0.0;
        }
}
