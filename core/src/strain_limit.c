/* The elongation limit delta (paper Table 1): after a step no sequential
 * link may be longer than (1 + delta) l0. Provot (1995): passes over the
 * over-stretched links, each moving its two ends toward each other in
 * proportion to their inverse masses, until none is over or the passes run
 * out. A pinned end does not move; an end constrained to a plane or line
 * moves only along its free directions (the filter S). Velocities follow the
 * positions through the method's x_new = a + cfac v_new, so the corrected
 * state stays consistent. */
#include <math.h>
#include "internal.h"

int strain_limit(const cloth *c, double *x, double *v, const double *S, double cfac, int iterations)
{
    double limit = 1.0 + c->desc.material.delta;
    int first = 0;
    for (int it = 0; it < iterations; it++) {
        int over = 0;
        for (int e = 0; e < c->n_seq; e++) {
            int i = c->seq[e].i, j = c->seq[e].j;
            double *xi = x + 3 * i, *xj = x + 3 * j;
            double u[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
            double d = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
            double lmax = limit * c->seq[e].rest;
            if (!(d > lmax)) continue;
            over++;
            double wi = c->con[i].ndof == 3 ? 0.0 : 1.0 / c->mass[i];
            double wj = c->con[j].ndof == 3 ? 0.0 : 1.0 / c->mass[j];
            if (wi + wj <= 0.0) continue;
            double s = (d - lmax) / (d * (wi + wj)); /* per unit inverse mass, along u*d */
            double di[3], dj[3];
            for (int k = 0; k < 3; k++) {
                di[k] = wi * s * u[k];
                dj[k] = -wj * s * u[k];
            }
            const double *Si = S + 9 * (size_t)i, *Sj = S + 9 * (size_t)j;
            for (int r = 0; r < 3; r++) {
                double mi = Si[3 * r] * di[0] + Si[3 * r + 1] * di[1] + Si[3 * r + 2] * di[2];
                double mj = Sj[3 * r] * dj[0] + Sj[3 * r + 1] * dj[1] + Sj[3 * r + 2] * dj[2];
                xi[r] += mi;
                xj[r] += mj;
                v[3 * i + r] += mi / cfac;
                v[3 * j + r] += mj / cfac;
            }
        }
        if (it == 0) first = over;
        if (!over) break;
    }
    return first;
}
