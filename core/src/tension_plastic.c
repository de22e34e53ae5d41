/* Tension plasticity of sequential links (paper sec. 2.1; material.tension_yield y, tension_set s): stretched
 * to d past (1 + y) l0, a link keeps lp = l0 + s (min(d, (1 + delta) l0) - (1 + y) l0), the longest stretch
 * deciding; the limit stays at (1 + delta) l0. The law and its closed forms: docs/materials.md. */
#include "internal.h"

int oc_tension_plastic_on(const cloth_material *m) { return m->tension_yield > 0.0 && m->tension_set > 0.0; }

double oc_tension_set_rule(const cloth_material *m, double rest, double d, double set)
{
    double yield = (1.0 + m->tension_yield) * rest, lim = (1.0 + m->delta) * rest;
    if (!oc_tension_plastic_on(m) || !(d > yield)) return set; /* below the yield (or no length): unchanged */
    double s = m->tension_set * ((d < lim ? d : lim) - yield) / rest;
    return s > set ? s : set;
}
