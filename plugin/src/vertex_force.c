/* The force each constrained vertex puts on its body, and which body takes it
 * (vertex_force.h): shared by the step's reactions (reactions.c), the
 * angular-momentum turn (momentum.c) and the active set's peel. */
#include <math.h>
#include "dcloth_internal.h"
#include "vertex_force.h"

/* 1 + the index of the body solved with the cloth that holds vertex i's
 * constraint, or 0 if none does */
int dcloth_held_by_coupled(dClothID c, int i)
{
    dBodyID b = c->pin[i].active ? c->pin[i].body : c->vc_new[i].active ? c->vc_new[i].body : 0;
    if (!b) return 0;
    for (int k = 0; k < cloth_body_count(c->core); k++)
        if (c->coupled.bodies[k] == b) return k + 1;
    return 0;
}

/* The force (N) vertex i's contact exerted in the step, without its second
 * plane's (whose geom is static or kinematic: it takes no force) */
void dcloth_first_force(cloth *core, int i, double f[3]) { cloth_get_contact_planes(core, i, NULL, NULL, f, NULL); }

double dcloth_vertex_force(dClothID c, int i, const double F[3], double wsum, double f[3])
{
    const vpin *p = &c->pin[i];
    const vcontact *nw = &c->vc_new[i];
    double w = 0.0;
    cloth_constraint_force(c->core, i, f);
    /* the share goes to constraints on moving bodies only: a static geom or
     * the world takes any impulse without moving */
    dBodyID hb = p->active ? p->body : nw->body;
    if (hb && !dBodyIsKinematic(hb)) w = wsum > 0.0 ? sqrt(dcloth_dot3(f, f)) / wsum : 0.0;
    if (!p->active) dcloth_first_force(c->core, i, f);
    for (int r = 0; r < 3; r++) f[r] += w * F[r] + (p->active ? 0.0 : nw->friction[r]);
    return w;
}

dBodyID dcloth_force_body(dClothID c, int i, const double f[3])
{
    const vcontact *nw = &c->vc_new[i];
    if (c->pin[i].active) return c->pin[i].body;
    if (!nw->active) return 0;
    /* pinched and pushed toward this contact's body: the push came from the
     * opposite body, which takes the reaction */
    if (nw->pinched && dcloth_dot3(f, nw->normal) < 0.0 && !dcloth_held_by_coupled(c, i)) return nw->opp_body;
    return nw->body;
}
