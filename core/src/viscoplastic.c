/* Rate-dependent plasticity of an interlaced link's rest length l1 (material.tau_set, tau_recover,
 * set_hardening): each law solved exactly over a step at the end length, so n steps of h equal one
 * of n h; time constant 0 is the paper's instant rule (laws: docs/materials.md, "Design notes"). */
#include <float.h>
#include <math.h>
#include "internal.h"

int oc_plastic_time_on(const cloth_material *m)
{
    return m->tau_set > 0.0 || m->tau_recover > 0.0 || m->set_hardening > 0.0;
}

/* What is left of a difference after h seconds of decay at tau (0: none). */
static double decay(double h, double tau) { return tau > 0.0 ? exp(-h / tau) : 0.0; }

void oc_plastic_rule_time(const cloth_material *m, double rest, double d, double h, int *plastic, double *l1,
                          double *perm, int *bent)
{
    double lp = rest - *perm * rest;
    if (m->alpha <= 0.0) {
        *plastic = 0; /* elastic material: never plastic */
        *bent = 0;
        return;
    }
    if (d <= m->alpha * rest) {
        if (!*plastic) {
            *plastic = 1; /* entry: the set starts from the permanent one */
            *l1 = lp;
        }
        if (d < *l1) *l1 = d + (*l1 - d) * decay(h, m->tau_set);
        *bent = 1;
        return;
    }
    if (*bent && *plastic && *l1 < lp) {
        lp -= m->set_hardening * (lp - *l1);                   /* released: part of the set stays for good */
        *perm = fmin((rest - lp) / rest, nextafter(1.0, 0.0)); /* below 1, which the state reader refuses */
        lp = rest - *perm * rest;                              /* as the next update reads it back */
    }
    *bent = 0;
    if (!*plastic) return;
    if (m->tau_recover > 0.0) {
        if (*l1 < lp) *l1 = lp - (lp - *l1) * decay(h, m->tau_recover);
        if (lp - *l1 <= 4.0 * DBL_EPSILON * lp) *l1 = lp; /* within rounding: rounding alone would stall it */
    } else if (!m->plastic_memory) {
        *l1 = lp; /* instant recovery, as the paper's rule */
    }
    if (*l1 >= rest) *plastic = 0; /* no set left: elastic again */
}
