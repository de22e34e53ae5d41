/* EPA's direction toward the nearer side: see epa_side.h. */
#include <math.h>
#include "epa_side.h"

/* How far shape 2 must move along unit u (from shape 1 toward it) to be apart, by their supports */
static double overlap_along(ccd_support_fn s1, const void *o1, ccd_support_fn s2, const void *o2, const double u[3])
{
    ccd_vec3_t d = {{u[0], u[1], u[2]}}, m = {{-u[0], -u[1], -u[2]}}, p1, p2;
    s1(o1, &d, &p1);
    s2(o2, &m, &p2);
    return (u[0] * p1.v[0] + u[1] * p1.v[1] + u[2] * p1.v[2]) - (u[0] * p2.v[0] + u[1] * p2.v[1] + u[2] * p2.v[2]);
}

int dcloth_epa_near_side(ccd_support_fn s1, const void *o1, ccd_support_fn s2, const void *o2, double tol,
                         ccd_real_t *depth, ccd_vec3_t *dir)
{
    double l = sqrt(dir->v[0] * dir->v[0] + dir->v[1] * dir->v[1] + dir->v[2] * dir->v[2]);
    if (!(l > 0.0) || !isfinite(l)) return 0;
    double u[3] = {dir->v[0] / l, dir->v[1] / l, dir->v[2] / l}, m[3] = {-u[0], -u[1], -u[2]};
    /* only where EPA contradicts its own supports: their overlap along its direction far past its depth */
    double fwd = overlap_along(s1, o1, s2, o2, u), back = overlap_along(s1, o1, s2, o2, m);
    if (!(fwd - *depth > fmax(10.0 * tol, 0.5 * fwd)) || !(back < fwd - tol)) return 0;
    if (!(back > 0.0)) return -1;
    for (int k = 0; k < 3; k++) dir->v[k] = m[k];
    if (*depth > back) *depth = back;
    return 0;
}
