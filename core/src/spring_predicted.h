/* A link in the Newton step, inline for the assembly's loop (oc_spring_eval_predicted in internal.h):
 * tension and the limit along the link, compression along the frozen direction u0; a slack link's
 * Newton matrix gains w k_hi u u^T (potential.c). */
#ifndef ODECLOTH_SPRING_PREDICTED_H
#define ODECLOTH_SPRING_PREDICTED_H

#include "internal.h"
#include "mat3.h"
#include "tuning.h"

/* E, f_i (may be NULL) and K (may be NULL) of the link; *slack (may be
 * NULL) whether it is shorter than its rest length; lim (may be NULL) the
 * elongation limit's share: its energy, and c with its force on i c (xj - xi). */
MAT3_INLINE double spring_predicted_lim(const double xi[3], const double xj[3], const double u0[3], spring_law s,
                                        double w, double f_i[3], double K[9], int *slack, double lim[2])
{
    double u[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
    double d = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    if (d > SPRING_MIN_LENGTH)
        for (int r = 0; r < 3; r++) u[r] /= d;
    double fe = 0.0, k = 0.0, E = 0.0, ks = 0.0;
    if (d >= s.rest) { /* at rest length too: a cloth at rest is stiff */
        fe = s.k_hi * (d - s.rest);
        k = s.k_hi;
        E = 0.5 * fe * (d - s.rest);
    } else {
        ks = w * s.k_hi;
    }
    if (slack) *slack = d < s.rest;
    if (lim) lim[0] = lim[1] = 0.0;
    if (d > s.lim) {
        fe += s.k_lim * (d - s.lim);
        k += s.k_lim;
        E += 0.5 * s.k_lim * (d - s.lim) * (d - s.lim);
        if (lim) lim[0] = 0.5 * s.k_lim * (d - s.lim) * (d - s.lim);
        if (lim && d > SPRING_MIN_LENGTH) lim[1] = s.k_lim * (d - s.lim) / d;
    }
    /* compression: the length along u0, (x_j - x_i) . u0 = d (u . u0) */
    double sc = d * (u[0] * u0[0] + u[1] * u0[1] + u[2] * u0[2]) - s.rest, kc = 0.0;
    if (sc < 0.0) {
        kc = s.k_lo;
        E += 0.5 * kc * sc * sc;
    }
    if (d <= SPRING_MIN_LENGTH) fe = k = ks = 0.0;
    if (f_i)
        for (int r = 0; r < 3; r++) f_i[r] = fe * u[r] + kc * sc * u0[r];
    if (!K) return E;
    double kt = d > SPRING_MIN_LENGTH ? fe / d : 0.0;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double uu = u[a] * u[b], vv = u0[a] * u0[b]; /* bitwise symmetric blocks */
            K[3 * a + b] = (k - kt) * uu + (a == b ? kt : 0.0) + kc * vv;
            if (ks != 0.0) K[3 * a + b] += ks * uu;
        }
    return E;
}

MAT3_INLINE double spring_predicted(const double xi[3], const double xj[3], const double u0[3], spring_law s, double w,
                                    double f_i[3], double K[9], int *slack)
{
    return spring_predicted_lim(xi, xj, u0, s, w, f_i, K, slack, NULL);
}

#endif
