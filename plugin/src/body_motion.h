/* How bodies move under the cloth (body_motion.c). */
#ifndef ODECLOTH_BODY_MOTION_H
#define ODECLOTH_BODY_MOTION_H

#include "dcloth_internal.h"

/* an upper bound of the speed of any point of geom g (0 without a body) */
double dcloth_geom_speed(dGeomID g);
/* the velocity of a vertex (x, v) relative to body b's point at x (b 0: v), and its size (inf if not finite) */
void dcloth_relative_velocity(dBodyID b, const double *x, const double *v, double r[3]);
double dcloth_relative_speed(dBodyID b, const double *x, const double *v);
/* the velocity of body's point p (zero without a body) */
void dcloth_point_velocity(dBodyID body, const double p[3], double v[3]);
/* where a point fixed in body b's frame (local) is now (w) and where it will be at the end of the step of
 * h seconds (target, advanced along its velocity) */
void dcloth_follow_body(dBodyID b, const double local[3], double h, double w[3], double target[3]);

#endif
