/* The elongation limit as a constraint of the implicit step: an augmented Lagrangian on the k_delta
 * law, where past (1 + delta) l0 a sequential link's force gains max(0, lambda + rho k_lim (d - lmax)),
 * lambda kept as the shift s = lambda / k_lim (c->lim_shift), rho the link's penalty (c->lim_rho). */
#include <math.h>
#include "internal.h"
#include "tuning.h"

/* the body solved with the cloth holding vertex i, or -1 */
static int held_by(const cloth *c, int i) { return c->body_held && c->vbody && c->vbody[i] >= 0 ? c->vbody[i] : -1; }

int oc_link_held_together(const cloth *c, const link_topo *L)
{
    return c->con[L->i].ndof == 3 && c->con[L->j].ndof == 3 && held_by(c, L->i) == held_by(c, L->j);
}

void oc_limit_multipliers_begin(cloth *c)
{
    for (int e = 0; e < c->n_seq; e++) {
        c->lim_rho[e] = 1.0;
        c->lim_viol[e] = INFINITY;
    }
}

/* lim_viol < 0 marks a dictated link: the plain k_delta law for the rest
 * of the step (shift 0, penalty 1), left out of the rounds */
static int dictated(const cloth *c, int e) { return c->lim_viol[e] < 0.0; }

/* the penalty of link e after a round left it violated by viol (of lmax) */
static void grow_penalty(cloth *c, int e, double viol)
{
    double tol = c->desc.solver.limit_tolerance, prev = c->lim_viol[e];
    /* judged only against a round that left the link violated too: one within the limit then has
     * been moved past it by its neighbours since */
    if (viol > tol && prev > tol && c->lim_rho[e] > 1.0 && viol > (1.0 - DICTATED_SHRINK) * prev) {
        c->lim_shift[e] = 0.0;
        c->lim_rho[e] = 1.0;
        c->lim_viol[e] = -1.0;
        return;
    }
    if (viol > tol && prev > tol && viol > RHO_SHRINK * prev) c->lim_rho[e] = fmin(RHO_MAX, c->lim_rho[e] * RHO_GROWTH);
    c->lim_viol[e] = viol;
}

double oc_limit_multipliers_update(cloth *c, const double *x, int grow)
{
    const cloth_material *m = &c->desc.material;
    if (!(m->k_delta > 0.0) || !(m->k_t > 0.0)) return 0.0;
    double lim = 1.0 + m->delta, worst = 0.0;
    for (int e = 0; e < c->n_seq; e++) {
        const link_topo *L = &c->seq[e];
        if (oc_link_held_together(c, L) || dictated(c, e)) {
            c->lim_shift[e] = 0.0;
            continue;
        }
        double d2 = 0.0, lmax = lim * L->rest, rho = c->lim_rho[e];
        for (int r = 0; r < 3; r++) {
            double w = x[3 * L->j + r] - x[3 * L->i + r];
            d2 += w * w;
        }
        double d = sqrt(d2), s0 = c->lim_shift[e], s1 = fmax(0.0, s0 + rho * (d - lmax));
        worst = fmax(worst, fabs(s1 - s0) / rho / lmax);
        c->lim_shift[e] = s1;
        if (grow) grow_penalty(c, e, fmax(0.0, d - lmax) / lmax);
    }
    return worst;
}
