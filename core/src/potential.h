/* The implicit step's nonlinear equations as a potential (potential.c).
 * With x = a + cfac v and v = v0 + dv, backward Euler (beta 1) and BDF2
 * (beta 2/3, cfac = beta h) ask for the stationary point of
 *   Phi(dv) = 1/2 dv^T M dv - e^T dv + U(x) - cfac f_c^T v + cfac/2 v^T C v,
 * U the springs' energy, f_c gravity and external forces, e BDF2's
 * M (v0 - v_-1) / 3 (0 for backward Euler), C the links' damping along directions frozen over
 * the step and the air drag (about the wind) with its triangles' normals and areas at
 * x~ = x0 + h v0. Compressed links push along the same directions, which makes Phi convex.
 * Backward Euler's are at x0, where U equals the springs' energy and elsewhere exceeds it (no
 * exact step gains energy); BDF2's at x~, O(h^2) from x, keep it second order.
 * With a self-contact bound (self_contact.h), Phi also holds its barrier.
 * The residual R = grad Phi = M dv - e - cfac f(x, v) is an impulse. */
#ifndef ODECLOTH_POTENTIAL_H
#define ODECLOTH_POTENTIAL_H

#include "internal.h"

typedef struct step_eq {
    double h, beta, cfac; /* cfac = beta h = dx/dv */
    int bdf2;
    const double *a;      /* 3n: x = a + cfac v */
} step_eq;

/* The step's equations: a (into c->na) and the links' frozen directions
 * (into c->ut), for a step of h from the current state. */
void potential_begin(cloth *c, double h, int bdf2, step_eq *q);

/* x = a + cfac (v0 + dv) and v = v0 + dv into c->x_new, c->v_new. */
void potential_state(cloth *c, const step_eq *q, const double *dv);

/* At c->x_new, c->v_new (potential_state first): b = -R; returns Phi there,
 * bit for bit as potential_value (and the sums potential_step_dissipation takes). */
double potential_residual(cloth *c, const step_eq *q, const double *dv, double *b);

/* At c->x_new, c->v_new: the Newton matrix M + cfac C + cfac^2 K (Phi's
 * Hessian, positive definite) into c->A, with stiffen, slack sequential links
 * stiffened (potential.c: SLACK_SHARE). */
void potential_matrix(cloth *c, const step_eq *q, int stiffen);

/* potential_residual and potential_matrix at once, in one pass over the links */
double potential_assemble(cloth *c, const step_eq *q, const double *dv, double *b, int stiffen);

/* The sum of R over every row at dv, out (3): M dv - e - cfac f_c summed,
 * as the links' forces and dampers cancel in pairs (not with air drag, an
 * outside force: air_on). */
void potential_momentum_residual(const cloth *c, const step_eq *q, const double *dv, double out[3]);

/* Phi at dv (the bodies' share apart), its positions and velocities
 * computed into x and v (3n each). */
double potential_value(const cloth *c, const step_eq *q, const double *dv, double *x, double *v);

/* What backward Euler's step to c->x_new, c->v_new dissipates besides 1/2 |dv|_M^2 (0 for
 * BDF2): the dampers' work and the links' Bregman gaps U(x0) - U(x) - grad U(x).(x0 - x),
 * without the elongation limit's piece (its multiplier shifts it off the springs' energy). */
double potential_dissipation(const cloth *c, const step_eq *q);

/* potential_dissipation at the last potential_residual's (or _assemble's) point, from that
 * pass's sums */
double potential_step_dissipation(cloth *c, const step_eq *q);

#endif
