/* The elongation limit as a constraint of the implicit step (augmented
 * Lagrangian on the k_delta law): past (1 + delta) l0 a sequential link's
 * force gains max(0, lambda + k_lim (d - lmax)), its multiplier lambda kept
 * as the shift s = lambda / k_lim of its limit length (c->lim_shift). */
#include <math.h>
#include "internal.h"

/* the body solved with the cloth holding vertex i, or -1 */
static int held_by(const cloth *c, int i) { return c->body_held && c->vbody && c->vbody[i] >= 0 ? c->vbody[i] : -1; }

int link_held_together(const cloth *c, const link_topo *L)
{
    return c->con[L->i].ndof == 3 && c->con[L->j].ndof == 3 && held_by(c, L->i) == held_by(c, L->j);
}

double limit_multipliers_update(cloth *c, const double *x)
{
    const cloth_material *m = &c->desc.material;
    if (!(m->k_delta > 0.0) || !(m->k_t > 0.0)) return 0.0;
    double lim = 1.0 + m->delta, worst = 0.0;
    for (int e = 0; e < c->n_seq; e++) {
        const link_topo *L = &c->seq[e];
        if (link_held_together(c, L)) {
            c->lim_shift[e] = 0.0;
            continue;
        }
        double d2 = 0.0, lmax = lim * L->rest;
        for (int r = 0; r < 3; r++) {
            double w = x[3 * L->j + r] - x[3 * L->i + r];
            d2 += w * w;
        }
        double s0 = c->lim_shift[e], s1 = fmax(0.0, s0 + sqrt(d2) - lmax);
        worst = fmax(worst, fabs(s1 - s0) / lmax);
        c->lim_shift[e] = s1;
    }
    return worst;
}
