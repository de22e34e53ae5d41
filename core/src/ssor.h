/* SSOR-preconditioned CG with Eisenstat's trick (ssor.c). */
#ifndef ODECLOTH_SSOR_H
#define ODECLOTH_SSOR_H

#include "mpcg.h"

/* Solve P's system like mpcg_run (same constraint handling, same stopping
 * norm), preconditioned by symmetric block Gauss-Seidel on the filtered
 * matrix. cflag: n flags, vertex constrained; Ah: 9 nnzb doubles of
 * workspace (the filtered matrix); P->pc is ignored. w: 6 * 3n doubles. */
mpcg_result ssor_run(const mpcg_problem *P, const unsigned char *cflag, double *Ah, double *x, double *w);

#endif
