/* The plastic rule of interlaced links (paper eq. 8-12; docs/model.md), and the update of both link
 * types' plastic state; the spring law of each link type and region is inline in internal.h. */
#include <math.h>
#include "internal.h"
#include "spring_predicted.h"

/* Region rule, run after each step: by default (the paper's) a link with d <= alpha l0 is plastic, l1
 * ratcheting to min(l1, d), and elastic again above alpha l0. With material.plastic_memory a plastic
 * link stays plastic, keeping l1 so a flattened crease re-forms (docs/materials.md, "Design notes"). */
void oc_plastic_rule_memory(double alpha, int memory, double rest, double d, int *plastic, double *l1)
{
    if (alpha <= 0.0) {
        *plastic = 0; /* elastic material: never plastic */
    } else if (d > alpha * rest) {
        if (!memory) *plastic = 0; /* paper: elastic region, rest length l0 */
        /* memory: a plastic link keeps plastic and l1 (an elastic one stays elastic) */
    } else if (!*plastic) {
        *plastic = 1; /* entry: l1 = the length at entry (<= alpha l0) */
        *l1 = d;
    } else if (d < *l1) {
        *l1 = d; /* the crease deepens: stores no bending energy */
    }
}

void oc_plastic_rule(double alpha, double rest, double d, int *plastic, double *l1)
{
    oc_plastic_rule_memory(alpha, 0, rest, d, plastic, l1);
}

int oc_plastic_update_link(const cloth_material *m, struct cloth_state *s, int e, double rest, double d, double h)
{
    int p = s->plastic[e];
    if (oc_crease_law_on(m)) {
        oc_crease_rule(m->alpha, rest, d, &p, &s->l1[e]);
        s->bent[e] = m->alpha > 0.0 && d <= m->alpha * rest;
    } else if (oc_plastic_time_on(m)) {
        int b = s->bent[e];
        oc_plastic_rule_time(m, rest, d, h, &p, &s->l1[e], &s->perm[e], &b);
        s->bent[e] = (unsigned char)b;
    } else {
        oc_plastic_rule_memory(m->alpha, m->plastic_memory, rest, d, &p, &s->l1[e]);
        s->bent[e] = m->alpha > 0.0 && d <= m->alpha * rest; /* kept for a time law switched on later */
    }
    /* a plastic rest length is a length: no shorter than a link with a direction */
    if (p && !(s->l1[e] >= SPRING_MIN_LENGTH)) s->l1[e] = SPRING_MIN_LENGTH;
    s->plastic[e] = (unsigned char)p;
    return p;
}

/* the length of link L at positions x */
static double length_of(const double *x, const link_topo *L)
{
    const double *xi = x + 3 * L->i, *xj = x + 3 * L->j;
    double dx = xj[0] - xi[0], dy = xj[1] - xi[1], dz = xj[2] - xi[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

int cloth_update_plastic(cloth *c)
{
    if (!c) return 0;
    const cloth_material *m = &c->desc.material;
    const double *x = c->st.x;
    int count = 0;
    for (int e = 0; oc_tension_plastic_on(m) && e < c->n_seq; e++)
        c->st.seq_set[e] = oc_tension_set_rule(m, c->seq[e].rest, length_of(x, c->seq + e), c->st.seq_set[e]);
    for (int e = 0; e < c->n_int; e++)
        count += oc_plastic_update_link(m, &c->st, e, c->lint[e].rest, length_of(x, c->lint + e), 0.0); /* no time */
    return count;
}
