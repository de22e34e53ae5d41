/* How bodies move under the cloth: a geom's fastest point, a body's point's
 * velocity, a vertex's speed against a body, where a body-fixed point goes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "dcloth_internal.h"
#include "body_motion.h"

/* A body's velocity, or 0 if it has none or it is not finite (a body whose
 * velocity is NaN or inf is treated as static here: every vertex's reach
 * infinite gave every vertex a contact and a NaN target; found in review) */
static int body_velocity(dBodyID b, const dReal **v, const dReal **w)
{
    if (!b) return 0;
    *v = dBodyGetLinearVel(b);
    *w = dBodyGetAngularVel(b);
    for (int k = 0; k < 3; k++)
        if (!isfinite((*v)[k]) || !isfinite((*w)[k])) return 0;
    return 1;
}

/* An upper bound of the speed of any point of geom g (0 if it has no
 * body): |v| + |w| (distance from the body's centre to the AABB's centre +
 * the AABB's half diagonal); |v| alone where that distance is not finite. */
double dcloth_geom_speed(dGeomID g)
{
    dBodyID b = dGeomGetBody(g);
    const dReal *v, *w;
    if (!body_velocity(b, &v, &w)) return 0.0;
    const dReal *o = dBodyGetPosition(b);
    dReal aabb[6];
    dGeomGetAABB(g, aabb);
    double cen[3], half = 0.0, arm = 0.0;
    for (int k = 0; k < 3; k++) {
        double e = 0.5 * (aabb[2 * k + 1] - aabb[2 * k]);
        cen[k] = 0.5 * (aabb[2 * k + 1] + aabb[2 * k]) - o[k];
        half += e * e;
        arm += cen[k] * cen[k];
    }
    double lin = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), wn = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    double ang = wn > 0.0 ? wn * (sqrt(arm) + sqrt(half)) : 0.0;
    return isfinite(ang) ? lin + ang : lin;
}

/* r = v - the velocity of the body's point at x: how a vertex at x with
 * velocity v moves against a geom of body b (0: static) */
void dcloth_relative_velocity(dBodyID b, const double *x, const double *v, double r[3])
{
    for (int k = 0; k < 3; k++) r[k] = v[k];
    const dReal *l, *w;
    if (body_velocity(b, &l, &w)) {
        const dReal *o = dBodyGetPosition(b);
        double d[3] = {x[0] - o[0], x[1] - o[1], x[2] - o[2]};
        r[0] -= l[0] + w[1] * d[2] - w[2] * d[1];
        r[1] -= l[1] + w[2] * d[0] - w[0] * d[2];
        r[2] -= l[2] + w[0] * d[1] - w[1] * d[0];
    }
}

/* |dcloth_relative_velocity|, inf if not finite */
double dcloth_relative_speed(dBodyID b, const double *x, const double *v)
{
    double r[3];
    dcloth_relative_velocity(b, x, v, r);
    double s = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    return isfinite(s) ? s : INFINITY;
}

/* the velocity of body's point p (zero without a body) */
void dcloth_point_velocity(dBodyID body, const double p[3], double v[3])
{
    dVector3 pv = {0, 0, 0};
    if (body) dBodyGetPointVel(body, p[0], p[1], p[2], pv);
    for (int k = 0; k < 3; k++) v[k] = pv[k];
}

/* Where a point fixed in body b's frame (local) is now (w) and where it
 * will be at the end of the step (target, advanced along its velocity):
 * what a pin to a body, and a contact sticking to a kinematic body, aim at. */
void dcloth_follow_body(dBodyID b, const double local[3], double h, double w[3], double target[3])
{
    dVector3 p, pv;
    dBodyGetRelPointPos(b, local[0], local[1], local[2], p);
    dBodyGetPointVel(b, p[0], p[1], p[2], pv);
    for (int r = 0; r < 3; r++) {
        w[r] = p[r];
        target[r] = p[r] + h * pv[r];
    }
}
