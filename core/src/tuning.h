/* The core's tuning constants, each with its unit and reason: the methods' own choices, not meant to
 * be changed per scene (users tune cloth_solver and cloth_material). Measurements behind the values:
 * docs/newton.md, docs/self_collision.md. */
#ifndef ODECLOTH_TUNING_H
#define ODECLOTH_TUNING_H

/* ---------------------------------------------------------------- Newton's step (newton.c) */

/* A step ends only once the energy the residual can have made is within this share (1) of what
 * the exact step dissipates: a quarter keeps an inexact step dissipative with room to spare
 * (docs/newton.md, "Where a calm step's iterations go"). */
#define NEWTON_GAIN_SHARE 0.25

/* That bound is no less than the kinetic energy of the cloth at this fraction (1) of
 * newton_tolerance: a cloth at rest jitters at about it, and no bound below it can be met. */
#define NEWTON_REL_FLOOR 1e-4

/* Backtracking: a trial is accepted at this fraction (1) of the decrease its slope promises
 * (Armijo's rule, the usual 1e-4), after at most this many halvings. */
#define LINE_SEARCH_ARMIJO 1e-4
#define LINE_SEARCH_HALVINGS 16

/* ------------------------------------------------------- Newton's matrix (potential.c) */

/* A slack sequential link's share (1) of its taut stiffness along itself in Newton's matrix,
 * halved for each matrix in a row it stays slack (at most SLACK_AGE_MAX halvings): the exact
 * Hessian's zero carries it far past its kink (docs/newton.md, "The Newton matrix of slack links"). */
#define SLACK_SHARE 0.1
#define SLACK_AGE_MAX 60

/* ------------------------------------- the elongation limit's multipliers (limit_multipliers.c) */

/* A link whose violation a round shrank by less than RHO_SHRINK (1) gets a penalty RHO_GROWTH
 * times stiffer, up to RHO_MAX times its own: the augmented Lagrangian's rule for a penalty too
 * soft (Nocedal-Wright Alg. 17.4, whose usual factors these are). */
#define RHO_SHRINK 0.25
#define RHO_GROWTH 10.0
#define RHO_MAX 1e3

/* A link whose violation a round with a stiffened penalty shrank by less than this part (1) does
 * not respond to its force: the constraints dictate its length, and a multiplier would only grow. */
#define DICTATED_SHRINK 0.01

/* ------------------------------------------------------ the linearised step (linearized.c) */

/* A sequential link within its limit at x0 and past NEWTON_CROSS times delta at x1 (1): its
 * linearisation missed the stiffening, and the step corrects it (a quarter of delta of slack). */
#define NEWTON_CROSS 1.25

/* The limit's multipliers are updated and the step corrected again while any changed by more
 * than this share (1) of its limit length. */
#define LIMIT_TOL 1e-6

/* ------------------------------------------------------------------ contacts (contacts.c) */

/* Two planes whose normals' cross product is shorter than this (1: the sine of their angle,
 * 0.6 deg) are not held together: their line is ill-posed (the force split divides by it). */
#define PLANES_PARALLEL 1e-2

/* ------------------------------------------- the elongation-limit projection (strain_limit.c) */

/* A link is at its limit within SL_TOL (1); the link system's CG stops at SL_CG_TOL or SL_CG_MAX
 * (a safety net); the Levenberg-Marquardt damping stays in [SL_MU_MIN, SL_MU_MAX] of the diagonal (1);
 * at most SL_INNER active-set rounds and SL_HALVINGS halvings per projection. */
#define SL_TOL 1e-9
#define SL_CG_TOL 1e-3
#define SL_CG_MAX 100
#define SL_MU_MIN 1e-8
#define SL_MU_MAX 1e4
#define SL_INNER 4
#define SL_HALVINGS 6

/* ------------------------------------------------ self-contact's barrier (self_contact.c) */

/* A touch is a pair within SELF_CONTACT_TOUCH of the thickness when coplanar (1: ccd.h); an
 * update stops at SELF_CONTACT_STOP of the way to its first (1: IPC's choice, half). */
#define SELF_CONTACT_TOUCH 1e-3
#define SELF_CONTACT_STOP 0.5

/* Candidates: pairs whose regions (paths and step start widened by SELF_CONTACT_SKIN thicknesses) come
 * within the thickness; motions over SELF_CONTACT_LONG are swept unlisted. When few vertices leave
 * (SELF_CONTACT_FEW, up to _FEW_MAX) only their regions grow: a growth tests all, a relisting is linear. */
#define SELF_CONTACT_SKIN 1.0
#define SELF_CONTACT_LONG 16.0
#define SELF_CONTACT_FEW 512
#define SELF_CONTACT_FEW_MAX 16

/* Close pairs: candidates possibly within the thickness plus 2 SELF_CONTACT_SLACK thicknesses at the
 * reference (none other comes within it while no vertex moves farther, the whole cloth's common
 * translation taken out; a sweep, touches only, half a thickness farther); SELF_CONTACT_SPARE earlier
 * lists kept, as Newton's start tries several positions. */
#define SELF_CONTACT_SLACK 0.25
#define SELF_CONTACT_SPARE 3

/* A bound proves a pair apart only beyond the thickness by this factor (1): the pair's distance,
 * computed otherwise, has rounding of its own. */
#define PAIR_APART_MARGIN (1.0 + 1e-6)

/* ---------------------------------------------- the self-collision pass (selfcollision.c) */

/* Proximity passes after a step (SC_PASSES); barycentric slack (1) for a point over an edge or
 * corner (SC_EDGE_SLACK) and for "over the triangle" before a crossing (SC_OVER_MARGIN). */
#define SC_PASSES 3
#define SC_EDGE_SLACK 0.02
#define SC_OVER_MARGIN 0.25

/* ------------------------------------------------------------ continuous tests (ccd.c) */

/* A cubic value within CCD_FTOL of its scale counts as zero; a distance under CCD_NEAR of eta has
 * no direction of its own; a normal speed under CCD_CLOSING of the relative speed is not closing;
 * a root's time is refined to CCD_TTOL (all 1: near double precision's reach). */
#define CCD_FTOL 1e-12
#define CCD_NEAR 1e-6
#define CCD_CLOSING 1e-12
#define CCD_TTOL 1e-14

/* ------------------------------------------------------------- broadphase (sweep_grid.c) */

/* A box over SWEEP_GRID_MAX_CELLS cells, or with cell coordinates beyond SWEEP_FAR, is kept in a
 * list every query scans: a blown-up displacement costs one pass, never a loop over its cells. */
#define SWEEP_GRID_MAX_CELLS 64
#define SWEEP_FAR 1e15

/* --------------------------------------------------------- speed (multigrid.c, potential.c) */

/* Rows a V-cycle's sweep fetches ahead (its rows wait on each other, so the core cannot run
 * ahead itself) and links the assembly fetches ahead: far enough to hide a memory access. */
#define SWEEP_PREFETCH_ROWS 8
#define ASSEMBLY_PREFETCH_LINKS 8

/* The coarsest multigrid level is solved densely: a grid whose coarsest level would have more
 * unknowns than this (a side under 5 nodes does not coarsen) takes block Jacobi instead. */
#define MG_DENSE_MAX 3072

/* ------------------------------------------------ the accuracy-driven controller (adaptive.c) */

/* The next frame aims the global estimate at ADAPTIVE_AIM of the request, the local at ADAPTIVE_LOCAL_AIM of the
 * budget (1): room for the estimate's error. A large rate is kept ADAPTIVE_KMEM s (the norm can pass near zero as it
 * turns); symplectic Euler at ADAPTIVE_SYM_FRAC of stable (1) keeps the shadow's 2 h stable; ADAPTIVE_CGF: CG tol. */
#define ADAPTIVE_AIM 0.5
#define ADAPTIVE_LOCAL_AIM 0.7
#define ADAPTIVE_KMEM 0.5
#define ADAPTIVE_SYM_FRAC 0.4
#define ADAPTIVE_CGF 1.0

/* The first frame takes symplectic Euler under ADAPTIVE_SYM_PREFER times backward Euler's cost (1; BE's first-frame
 * estimate understates its need); later frames return to BE under ADAPTIVE_BACK_TO_IMPLICIT of symplectic's (1).
 * A BE substep costs ADAPTIVE_BE_COST_FIXED + ADAPTIVE_BE_COST_PER_CG per CG iteration symplectic substeps (1). */
#define ADAPTIVE_SYM_PREFER 2.0
#define ADAPTIVE_BACK_TO_IMPLICIT 0.35
#define ADAPTIVE_BE_COST_FIXED 2.5
#define ADAPTIVE_BE_COST_PER_CG 0.15

/* -------------------------------------------------------------------------- numerics */

/* Below this length (m) a link has no direction; it exerts no force. */
#define SPRING_MIN_LENGTH 1e-12

#endif
