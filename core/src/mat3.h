/* 3x3 block helpers shared by the step, the solver and the multigrid. */
#ifndef ODECLOTH_MAT3_H
#define ODECLOTH_MAT3_H

#include <math.h>

/* y = M x (y may not alias x) */
static inline void mat3vec(const double *M, const double *x, double *y)
{
    y[0] = M[0] * x[0] + M[1] * x[1] + M[2] * x[2];
    y[1] = M[3] * x[0] + M[4] * x[1] + M[5] * x[2];
    y[2] = M[6] * x[0] + M[7] * x[1] + M[8] * x[2];
}

/* C = A B */
static inline void mat3mul(const double *A, const double *B, double *C)
{
    for (int r = 0; r < 3; r++)
        for (int s = 0; s < 3; s++)
            C[3 * r + s] = A[3 * r] * B[s] + A[3 * r + 1] * B[3 + s] + A[3 * r + 2] * B[6 + s];
}

/* o = m^-1 by cofactors; returns the determinant (o untouched if it is zero
 * or not finite). */
static inline double mat3inv(const double *m, double *o)
{
    double c0 = m[4] * m[8] - m[5] * m[7], c1 = m[5] * m[6] - m[3] * m[8], c2 = m[3] * m[7] - m[4] * m[6];
    double det = m[0] * c0 + m[1] * c1 + m[2] * c2;
    if (det == 0.0 || !isfinite(det)) return det;
    double id = 1.0 / det;
    o[0] = c0 * id;
    o[1] = (m[2] * m[7] - m[1] * m[8]) * id;
    o[2] = (m[1] * m[5] - m[2] * m[4]) * id;
    o[3] = c1 * id;
    o[4] = (m[0] * m[8] - m[2] * m[6]) * id;
    o[5] = (m[2] * m[3] - m[0] * m[5]) * id;
    o[6] = c2 * id;
    o[7] = (m[1] * m[6] - m[0] * m[7]) * id;
    o[8] = (m[0] * m[4] - m[1] * m[3]) * id;
    return det;
}

#endif
