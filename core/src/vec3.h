/* 3-vector helpers of the core (ccd.c, selfcollision.c, cloth.c). */
#ifndef ODECLOTH_VEC3_H
#define ODECLOTH_VEC3_H

#include <math.h>

static inline void vec3_sub(const double *a, const double *b, double *o)
{
    o[0] = a[0] - b[0];
    o[1] = a[1] - b[1];
    o[2] = a[2] - b[2];
}

static inline double vec3_dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static inline void vec3_cross(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double vec3_norm(const double *a) { return sqrt(vec3_dot(a, a)); }

/* o += s a */
static inline void vec3_axpy(double *o, double s, const double *a)
{
    o[0] += s * a[0];
    o[1] += s * a[1];
    o[2] += s * a[2];
}

/* (a x b) . c */
static inline double vec3_triple(const double *a, const double *b, const double *c)
{
    double ab[3];
    vec3_cross(a, b, ab);
    return vec3_dot(ab, c);
}

#endif
