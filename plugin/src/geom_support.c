/* An ODE geom as libccd sees it: the support point along a direction, and
 * a centre, of a box, capsule, cylinder or convex (the points handed over
 * by dClothSetConvexPoints). */
#include <ccd/ccd.h>
#include <math.h>
#include <string.h>
#include "dcloth_internal.h"
#include "geom_support.h"

int dcloth_geom_shape_of(dClothID c, dGeomID g, dcloth_geom_shape *s)
{
    memset(s, 0, sizeof *s);
    s->g = g;
    s->cls = dGeomGetClass(g);
    if (s->cls == dBoxClass) {
        dVector3 L;
        dGeomBoxGetLengths(g, L);
        for (int k = 0; k < 3; k++) s->half[k] = 0.5 * L[k];
    } else if (s->cls == dCapsuleClass || s->cls == dCylinderClass) {
        dReal r, len;
        if (s->cls == dCapsuleClass) dGeomCapsuleGetParams(g, &r, &len);
        else dGeomCylinderGetParams(g, &r, &len);
        s->half[0] = r;
        s->half[1] = 0.5 * len;
        s->half[2] = 0.0;
    } else if (s->cls == dConvexClass) {
        int k = 0;
        while (k < c->ncvx && c->cvx[k].g != g) k++;
        if (k == c->ncvx) return 0; /* no points handed over */
        s->pts = c->cvx[k].p;
        s->npts = c->cvx[k].n;
    } else {
        return 0;
    }
    return 1;
}

void dcloth_geom_support(const void *obj, const ccd_vec3_t *dir, ccd_vec3_t *out)
{
    const dcloth_geom_shape *s = obj;
    const dReal *o = dGeomGetPosition(s->g), *R = dGeomGetRotation(s->g);
    const double *d = dir->v;
    double p[3], q[3];
    for (int k = 0; k < 3; k++) p[k] = R[k] * d[0] + R[4 + k] * d[1] + R[8 + k] * d[2]; /* R^T d */
    if (s->cls == dBoxClass) {
        for (int k = 0; k < 3; k++) q[k] = p[k] >= 0.0 ? s->half[k] : -s->half[k];
    } else if (s->cls == dCapsuleClass) { /* an end point, grown by r */
        double r = s->half[0], l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), f = l > 0.0 ? r / l : 0.0;
        q[0] = f * p[0];
        q[1] = f * p[1];
        q[2] = (p[2] >= 0.0 ? s->half[1] : -s->half[1]) + f * p[2];
    } else if (s->cls == dConvexClass) { /* the farthest point along d */
        int best = 0;
        double bd = -INFINITY;
        for (int k = 0; k < s->npts; k++) {
            const double *a = s->pts + 3 * k;
            double e = a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
            if (e > bd) bd = e, best = k;
        }
        for (int k = 0; k < 3; k++) q[k] = s->pts[3 * best + k];
    } else { /* cylinder: the rim point of the cap toward d */
        double r = s->half[0], rho = sqrt(p[0] * p[0] + p[1] * p[1]), f = rho > 0.0 ? r / rho : 0.0;
        q[0] = f * p[0];
        q[1] = f * p[1];
        q[2] = p[2] >= 0.0 ? s->half[1] : -s->half[1];
    }
    for (int k = 0; k < 3; k++) out->v[k] = o[k] + R[4 * k] * q[0] + R[4 * k + 1] * q[1] + R[4 * k + 2] * q[2];
}

void dcloth_geom_center(const void *obj, ccd_vec3_t *out)
{
    const dcloth_geom_shape *s = obj;
    const dReal *o = dGeomGetPosition(s->g);
    for (int k = 0; k < 3; k++) out->v[k] = o[k];
}
