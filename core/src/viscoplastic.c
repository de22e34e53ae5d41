/* Plasticity that depends on duration and repetition: a rate law for the
 * plastic rest length l1 of an interlaced link (material.tau_set,
 * tau_recover, set_hardening; cloth.h, docs/materials.md).
 *
 * Per link: l1, the permanent rest length lp = l0 (1 - perm), and whether it
 * was bent past the yield at the last update. Over a step of h seconds the
 * end-of-step length d is taken as held, and each law is solved exactly:
 *   bent (d <= alpha l0):  dl1/dt = -(l1 - d) / tau_set    where l1 > d
 *       l1(t + h) = d + (l1 - d) exp(-h / tau_set)
 *   released:              dl1/dt = (lp - l1) / tau_recover  where l1 < lp
 *       l1(t + h) = lp - (lp - l1) exp(-h / tau_recover)
 * so n steps of h and one of n h agree to rounding. A time constant of 0 is
 * the instant limit: the paper's l1 = min(l1, d) while bent, l1 = lp when
 * released (or, with plastic_memory, l1 kept). At the update that finds a
 * bent link released, lp -= set_hardening (lp - l1): a share of the set
 * held becomes permanent, once per fold. A link is elastic (rest l0, k_b
 * both ways) while it carries no set: until it first bends past the yield,
 * and again once l1 has recovered to l0. */
#include <float.h>
#include <math.h>
#include "internal.h"

int plastic_time_on(const cloth_material *m)
{
    return m->tau_set > 0.0 || m->tau_recover > 0.0 || m->set_hardening > 0.0;
}

/* What is left of a difference after h seconds of decay at tau (0: none). */
static double decay(double h, double tau) { return tau > 0.0 ? exp(-h / tau) : 0.0; }

void plastic_rule_time(const cloth_material *m, double rest, double d, double h, int *plastic, double *l1,
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
        lp -= m->set_hardening * (lp - *l1); /* released: part of the set stays for good */
        *perm = fmin((rest - lp) / rest, nextafter(1.0, 0.0)); /* below 1, which the state reader refuses */
        lp = rest - *perm * rest; /* as the next update reads it back */
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
