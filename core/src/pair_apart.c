/* Separating axes for self-contact's pairs: see pair_apart.h. */
#include <math.h>
#include "pair_apart.h"
#include "vec3.h"

static inline double larger(double a, double b) { return a > b ? a : b; }

void oc_pair_apart_frame(const double *a, const double *b, const double *c, double *f)
{
    const double *v[3] = {a, b, c};
    double e1[3], e2[3], l;
    vec3_sub(b, a, e1);
    vec3_sub(c, a, e2);
    vec3_cross(e1, e2, f);
    l = vec3_norm(f);
    for (int k = 0; k < 12; k++) f[k] = k < 3 && l > 0.0 ? f[k] / l : 0.0;
    if (!(l > 0.0) || !isfinite(l)) return;
    for (int k = 0; k < 3; k++) {
        double e[3], *m = f + 3 + 3 * k;
        vec3_sub(v[(k + 1) % 3], v[k], e);
        vec3_cross(e, f, m); /* outward when (a, b, c) turns about the normal */
        double lm = vec3_norm(m);
        for (int r = 0; r < 3; r++) m[r] = lm > 0.0 ? m[r] / lm : 0.0;
    }
}

double oc_pair_apart_point_triangle_gap(const double *p, const double *a, const double *b, const double *c,
                                        const double *f, double enough)
{
    const double *v[3] = {a, b, c};
    double r[3];
    vec3_sub(p, a, r);
    double gap = fabs(vec3_dot(r, f));
    for (int k = 0; k < 3 && !(gap >= enough); k++) {
        vec3_sub(p, v[k], r);
        gap = larger(gap, vec3_dot(r, f + 3 + 3 * k));
    }
    return gap;
}

int oc_pair_apart_point_triangle(const double *p, const double *a, const double *b, const double *c, const double *f,
                                 double D)
{
    double lim = D * PAIR_APART_MARGIN;
    return oc_pair_apart_point_triangle_gap(p, a, b, c, f, lim) >= lim;
}

/* How far segment cd lies from the line through a along u, on the side of c's offset from it (0: not all
 * on one side) */
static double beyond_line(const double *a, const double *u, const double *c, const double *d)
{
    double ac[3], ad[3], t[3], uu = vec3_dot(u, u);
    if (!(uu > 0.0)) return 0.0;
    vec3_sub(c, a, ac);
    vec3_sub(d, a, ad);
    double k = vec3_dot(ac, u) / uu;
    for (int r = 0; r < 3; r++) t[r] = ac[r] - k * u[r];
    double lt = vec3_norm(t);
    double near = vec3_dot(ac, t), other = vec3_dot(ad, t);
    near = other < near ? other : near;
    return lt > 0.0 && near > 0.0 ? near / lt : 0.0;
}

double oc_pair_apart_edges_gap(const double *a, const double *b, const double *c, const double *d, double enough)
{
    double u[3], w[3], n[3], ac[3], gap = 0.0;
    vec3_sub(b, a, u);
    vec3_sub(d, c, w);
    vec3_cross(u, w, n);
    vec3_sub(c, a, ac);
    double ln = vec3_norm(n);
    if (ln > 0.0) gap = fabs(vec3_dot(ac, n)) / ln;
    if (!(gap >= enough)) gap = larger(gap, beyond_line(a, u, c, d));
    if (!(gap >= enough)) gap = larger(gap, beyond_line(c, w, a, b));
    return gap;
}

int oc_pair_apart_edges(const double *a, const double *b, const double *c, const double *d, double D)
{
    double lim = D * PAIR_APART_MARGIN;
    return oc_pair_apart_edges_gap(a, b, c, d, lim) >= lim;
}
