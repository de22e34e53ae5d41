/* SSOR-preconditioned CG with Eisenstat's trick (ssor.c). */
#ifndef ODECLOTH_SSOR_H
#define ODECLOTH_SSOR_H

#include "mpcg.h"

/* Solve P's system like oc_mpcg_run (same constraints and stopping norm), preconditioned by symmetric
 * block Gauss-Seidel on the filtered matrix. cflag: n constrained flags; Ah: 9 nnzb doubles for the
 * filtered matrix; P->pc ignored; w: 6 * 3n doubles. */
mpcg_result oc_ssor_run(const mpcg_problem *P, const unsigned char *cflag, double *Ah, double *x, double *w);

#endif
