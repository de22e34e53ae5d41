/* The implicit step's equations as a convex potential (potential.c): BE and BDF2 ask for the
 * stationary point of Phi(dv) = 1/2 dv^T M dv - e^T dv + U(x) - cfac f_c^T v + cfac/2 v^T C v, whose
 * gradient, the residual R, is an impulse. Terms and why they are convex: docs/newton.md. */
#ifndef ODECLOTH_POTENTIAL_H
#define ODECLOTH_POTENTIAL_H

#include "internal.h"

typedef struct step_eq {
    double h, beta, cfac; /* cfac = beta h = dx/dv */
    int bdf2;
    const double *a; /* 3n: x = a + cfac v */
} step_eq;

/* The step's equations: a (into c->na) and the links' frozen directions
 * (into c->ut), for a step of h from the current state. */
void oc_potential_begin(cloth *c, double h, int bdf2, step_eq *q);

/* x = a + cfac (v0 + dv) and v = v0 + dv into c->x_new, c->v_new. */
void oc_potential_state(cloth *c, const step_eq *q, const double *dv);

/* At c->x_new, c->v_new (oc_potential_state first): b = -R; returns Phi there,
 * bit for bit as oc_potential_value (and the sums oc_potential_step_dissipation takes). */
double oc_potential_residual(cloth *c, const step_eq *q, const double *dv, double *b);

/* At c->x_new, c->v_new: the Newton matrix M + cfac C + cfac^2 K (Phi's
 * Hessian, positive definite) into c->A, with stiffen, slack sequential links
 * stiffened (potential.c: SLACK_SHARE). */
void oc_potential_matrix(cloth *c, const step_eq *q, int stiffen);

/* oc_potential_residual and oc_potential_matrix at once, in one pass over the links */
double oc_potential_assemble(cloth *c, const step_eq *q, const double *dv, double *b, int stiffen);

/* The sum of R over every row at dv, out (3): M dv - e - cfac f_c summed,
 * as the links' forces and dampers cancel in pairs (not with air drag, an
 * outside force: oc_air_on). */
void oc_potential_momentum_residual(const cloth *c, const step_eq *q, const double *dv, double out[3]);

/* Phi at dv (the bodies' share apart), its positions and velocities
 * computed into x and v (3n each). */
double oc_potential_value(const cloth *c, const step_eq *q, const double *dv, double *x, double *v);

/* What backward Euler's step to c->x_new, c->v_new dissipates besides 1/2 |dv|_M^2 (0 for
 * BDF2): the dampers' work and the links' Bregman gaps U(x0) - U(x) - grad U(x).(x0 - x),
 * without the elongation limit's piece (its multiplier shifts it off the springs' energy); a pass of
 * its own, the reference the step's fused sums (below) are tested against. */
double oc_potential_dissipation(const cloth *c, const step_eq *q);

/* oc_potential_dissipation at the last oc_potential_residual's (or _assemble's) point, from that
 * pass's sums */
double oc_potential_step_dissipation(cloth *c, const step_eq *q);

#endif
