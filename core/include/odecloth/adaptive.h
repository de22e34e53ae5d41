/* Accuracy-driven stepping: a controller that steps a cloth frame by frame, choosing the
 * substeps, the CG tolerance and the method from an error estimate (core/src/adaptive.c; the
 * reasoning and measurements behind it: docs/solver.md). */
#ifndef ODECLOTH_ADAPTIVE_H
#define ODECLOTH_ADAPTIVE_H

#include "cloth.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Steps a cloth frame by frame, choosing the substeps per frame, the CG
 * tolerance and the method from an error estimate instead of the user
 * guessing them.
 *
 * Error measure: the RMS over vertices of the position error. The tolerance
 * is the error the run may gain per simulated second (m/s): a run of T
 * seconds should end within about tolerance * T of the exact motion
 * (the work-precision chart, examples/bench_workprecision.c).
 *
 * The global estimate (global_estimate 1, the default): a shadow cloth, a
 * copy made at creation, runs alongside from the same start with the same
 * method at twice the step (n / 2 substeps of 2 h per frame, n even; its
 * inputs made the cloth's at every frame: material, solver, gravity,
 * external forces, constraints, and before_substep called on it with 2 h).
 * Backward and symplectic Euler are first order, so the cloth's error is
 * about x_2h - x_h
 * (Richardson): the RMS of that difference estimates the error of the whole
 * run so far, including what the motion has done to earlier errors (a
 * swing's turning points amplify them; no local estimate sees that). It is
 * E = k int h dt with k the error per unit step and second; the next frame
 * takes h = 0.5 tolerance / k (k a maximum decaying over 0.5 s), at most
 * halving n from one frame to the next. The shadow costs about half the
 * cloth's steps again. A frame is solved again with more substeps only when
 * a step fails (NaN, strain, CG: twice the substeps and a 10x tighter CG),
 * or when the shadow started with it (the first frame, a change of method)
 * and its difference passes twice the frame's budget with the run over its
 * request; later, what a frame adds cannot be told apart from what the
 * motion does to the difference so far, and an error already made stays
 * made (docs/solver.md, "The accuracy-driven controller"). If the shadow fails
 * where the cloth did not, the frame is kept and the shadow restarted from
 * the cloth next frame (the estimate so far is carried); with rigid bodies
 * solved with the cloth (cloth_set_bodies) it is not run and the local
 * estimate below decides.
 *
 * The method (allow_explicit 1, the default, and the shadow running):
 * backward Euler, or symplectic Euler where that is cheaper at the
 * tolerance. Symplectic Euler needs no solve but is stable only while
 * h^2 k' + 2 h c' < 4 for the stiffest mode (k', c' the largest eigenvalues
 * of M^-1 K and M^-1 C, by power iteration on finite differences of the
 * forces at the cloth's state, the constraints filtered out: 40 iterations
 * at first, then 6 a frame from the last vector); it steps at 0.4 of that
 * (the shadow's 2 h at 0.8), or smaller if its estimate asks. A backward
 * Euler substep is costed as 2.5 + 0.15 CG iterations symplectic ones (21x21,
 * block Jacobi). The first frame is solved by both, backward Euler's error
 * taken as the larger of its shadow's difference and its distance to the
 * symplectic solution, and symplectic Euler kept when its substeps cost
 * less than twice backward Euler's at the tolerance (backward Euler's
 * first-frame k understates what it needs later; its coarse steps damp
 * stiff modes that its shadow, damping them too, does not see). Later
 * frames switch to symplectic Euler when it is cheaper, and back when
 * backward Euler would cost under 0.35 of it or the stable step no longer
 * fits max_substeps (a link at the elongation limit's stiffness). A change
 * of method restarts the shadow from the cloth: the estimate so far is
 * carried (added, no longer propagated). A failed symplectic frame (NaN,
 * strain) is solved again with the explicit step halved from then on, or
 * with backward Euler once that is cheaper.
 *
 * The local estimate (global_estimate 0, or bodies): each frame is n
 * backward Euler substeps; what it adds is estimated from the local
 * truncation errors, using the velocity changes the steps make anyway (no
 * extra solves; a_k = dv_k / h, RMS over vertices): the sum of h^2/2 |a_k|
 * for the positions, plus velocity_weight times h/2 |a_n - a_0| for the
 * velocities. A frame whose estimate passes twice its budget (tolerance *
 * frame time) is rolled back and solved again with the substeps it asks
 * for; the next frame's n aims at 0.7 of the budget. It does not see what
 * the motion does to earlier errors and over-reacts to contacts switching on.
 *
 * At max_substeps an over-budget frame is kept and flagged. The CG
 * tolerance: the solver's relative residual acts as a relative force error
 * that moves the positions by at most cg |a| t^2 / 2 over the simulated time
 * t so far, held to half of tolerance * t: cg = tolerance / (|a| t), t at
 * least velocity_weight (the shadow does not see this error: it makes the
 * same; the bound is pessimistic: docs/solver.md). Under
 * CLOTH_NEWTON the step's residual r (m/s) is a bias r / h in the
 * acceleration, so newton_tolerance is held to at most tolerance h / t. The
 * first frame takes at least two substeps and CG tolerance 1e-6. The cloth's own
 * solver settings are restored after each frame, and after a failed frame
 * its state and constraint forces are as before it. */
typedef struct cloth_adaptive_desc {
    double tolerance;        /* m/s, RMS position error per simulated second, > 0 */
    int min_substeps;        /* per frame, >= 1                                    */
    int max_substeps;        /* per frame, >= min_substeps                          */
    double cg_tolerance_min; /* range of the chosen CG tolerance, 0 < min <= max < 1 */
    double cg_tolerance_max;
    double velocity_weight; /* s, how long a velocity error counts as position
                                error, > 0                                       */
    /* Called before every substep with its h (contacts, moving pins): set the
     * constraints there, on the cloth passed in (the shadow's substeps call
     * it too, with the shadow and 2 h). Nonzero fails the frame (state as
     * before it; on the shadow: the shadow is restarted). May be NULL. */
    int (*before_substep)(cloth *c, double h, void *user);
    void *user;
    int global_estimate; /* 1: run the shadow (see above); 0: local estimate only */
    int allow_explicit;  /* 1: may step symplectic Euler where cheaper (needs
                                the shadow); 0: backward Euler only            */
} cloth_adaptive_desc;

/* tolerance 1e-2 m/s, substeps 1..1024, CG tolerance 1e-8..1e-1, velocity
 * weight 0.1 s, global estimate and explicit steps on */
ODECLOTH_API cloth_adaptive_desc cloth_adaptive_default_desc(void);

typedef struct cloth_adaptive_stats {
    cloth_failure failure;  /* NONE, or why the frame failed                     */
    cloth_method method;    /* what stepped the frame: backward or symplectic Euler */
    int substeps;           /* of the accepted frame (the last attempt's if failed) */
    double h;               /* s, their size                                     */
    double cg_tolerance;    /* the CG tolerance they used                        */
    double error_estimate;  /* m, the local estimate of what the frame added     */
    double error_budget;    /* m, tolerance * frame time                         */
    int attempts;           /* solves of the frame; > 1 after a rollback         */
    int steps;              /* cloth_step calls, every attempt                   */
    int cg_iterations;      /* every attempt                                     */
    int over_budget;        /* 1: the frame added more than twice its budget
                               (to the global estimate, else the local one)     */
    double global_estimate; /* m, estimated RMS position error of the run so far
                               (the shadow's difference); NaN without one       */
    double requested;       /* m, tolerance * simulated time so far             */
} cloth_adaptive_stats;

typedef struct cloth_adaptive cloth_adaptive;

/* A controller for cloth c (work arrays of c's size, state snapshots and,
 * with global_estimate, the shadow: a second cloth of c's size). On failure
 * *out is NULL and err (may be NULL) says why. */
ODECLOTH_API cloth_status cloth_adaptive_create(const cloth *c, const cloth_adaptive_desc *d, cloth_adaptive **out,
                                                cloth_error *err);
ODECLOTH_API void cloth_adaptive_destroy(cloth_adaptive *a); /* NULL is fine */

/* Advance c by one frame of frame_dt seconds (finite, > 0); c must be the
 * cloth the controller was made for. On CLOTH_ESTEP (no substep count up to
 * max_substeps worked, or the callback failed) and CLOTH_EINVAL the cloth is
 * exactly as before the call (cloth_last_error(c) says why for ESTEP);
 * stats (may be NULL) says what was chosen or last tried. */
ODECLOTH_API cloth_status cloth_adaptive_frame(cloth_adaptive *a, cloth *c, double frame_dt,
                                               cloth_adaptive_stats *stats);

#ifdef __cplusplus
}
#endif
#endif
