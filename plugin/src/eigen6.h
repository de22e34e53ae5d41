/* A symmetric 6x6 eigensolver (eigen6.c). */
#ifndef ODECLOTH_EIGEN6_H
#define ODECLOTH_EIGEN6_H

#include "dcloth_internal.h"

/* eigenvalues d and orthonormal eigenvectors (columns of V) of
 * the symmetric 6x6 matrix A, destroyed (cyclic Jacobi rotations) */
void dcloth_eigen6(double A[6][6], double d[6], double V[6][6]);

#endif
