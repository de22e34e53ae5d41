/*
 * odecloth core: plastic cloth of Oh, Jung, Song, Lee (2006), pure C11.
 *
 * A grid of R x C particles joined by
 *   - sequential links (8 immediate neighbours): tension k_t, compression k_c;
 *   - interlaced links (8 skip-one neighbours): bending k_b, plastic past the
 *     yield ratio alpha, spreading stiffness k_s.
 * Stepped by backward Euler + Baraff-Witkin modified PCG (default), explicit
 * Euler, symplectic Euler or BDF2.
 *
 * Conventions: SI units (m, kg, s, N); double throughout; descriptors with
 * defaults (cloth_default_desc()); errors are values (cloth_status + message);
 * the library never prints, aborts or exits; a call that fails leaves its
 * object unchanged.
 */
#ifndef ODECLOTH_CLOTH_H
#define ODECLOTH_CLOTH_H

#include <stddef.h>
#include <stdio.h> /* FILE, for the state files */
#include "export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define ODECLOTH_VERSION_MAJOR 0
#define ODECLOTH_VERSION_MINOR 1
#define ODECLOTH_VERSION_PATCH 0

/* "0.1.0" */
ODECLOTH_API const char *cloth_version(void);

/* ------------------------------------------------------------------ errors */

typedef enum cloth_status {
    CLOTH_OK = 0,
    CLOTH_EINVAL, /* a bad argument: NULL, NaN/inf, out of range      */
    CLOTH_ENOMEM, /* allocation failed or size overflows              */
    CLOTH_ESTEP   /* the step failed and was rolled back (see stats)  */
} cloth_status;

/* Short name of a status ("invalid argument", ...). Never NULL. */
ODECLOTH_API const char *cloth_status_string(cloth_status s);

/* Where create functions put a readable message; may be NULL. */
typedef struct cloth_error {
    cloth_status code;
    char message[256];
} cloth_error;

/* --------------------------------------------------------------- material */

typedef enum cloth_preset {
    CLOTH_COTTON = 0, /* Table 1: delta 0.03, alpha 0.8, k_s 10  */
    CLOTH_WOOL,       /* Table 1: delta 0.10, alpha 0.1, k_s 0.1 */
    CLOTH_ELASTIC     /* cotton with alpha = 0: never plastic    */
} cloth_preset;

typedef struct cloth_material {
    double k_t;         /* N/m     sequential link stiffness in tension (d >= l0)     */
    double k_c;         /* N/m     sequential link stiffness in compression (d < l0)   */
    double k_b;         /* N/m     interlaced link bending stiffness                  */
    double k_s;         /* N/m     spreading stiffness: resists unbending a crease    */
    double alpha;       /* 1       plastic yield ratio d/l0, in [0, 1]; 0 = elastic   */
    double delta;       /* 1       elongation limit: sequential links stretch <= delta */
    double k_delta;     /* 1       stiffening past the limit: a sequential link longer
                                than (1 + delta) l0 adds k_delta k_t on the excess
                                (0 = none; the projection alone holds delta)      */
    double c_t;         /* N s/m   damping along sequential links                     */
    double c_b;         /* N s/m   damping along interlaced links                     */
    double density;     /* kg/m^2  areal density                                      */
    int plastic_memory; /* 0 (default, the paper's per-step rule, paper eq. 8-12):
                           a link pulled back above alpha l0 is elastic again,
                           rest l0. 1 (opt-in, ours): a link once plastic stays
                           plastic with its l1 however far it is opened (its
                           unbending still resisted by k_s toward l1), so a
                           crease spread flat re-forms when let go; bent
                           deeper than l1 it still ratchets (l1 = min d).
                           Decided in oc_plastic_rule_memory (core/src/plastic.c).
                           Must be 0 or 1. With tau_recover > 0 the
                           recovery law below decides instead. */
    /* Plasticity in time (ours; core/src/viscoplastic.c, docs/materials.md): bent, l1 relaxes toward d;
     * released, toward the permanent rest length lp; each release makes a share of the set permanent.
     * All three 0 (the default) is the paper's rule above, bit for bit. */
    double tau_set;       /* s, >= 0: 0 sets at once (l1 = min(l1, d), the paper) */
    double tau_recover;   /* s, >= 0: 0 recovers at once to lp when released
                             (the paper; with plastic_memory 1, never)         */
    double set_hardening; /* 1, in [0, 1]: share of the set made permanent at
                             each release; 0 = none                           */
    /* Tension plasticity (paper sec. 2.1, knees and elbows; ours: core/src/tension_plastic.c): a sequential
     * link stretched past (1 + tension_yield) l0 keeps tension_set of the stretch beyond it, up to the limit
     * (1 + delta) l0, as a longer rest length. Either 0 (the default) leaves the links elastic, bit for bit. */
    double tension_yield; /* 1, in [0, delta]: yield stretch; 0 = off        */
    double tension_set;   /* 1, in [0, 1]: share of the stretch past the
                             yield kept (1: perfectly plastic, 0: none)       */
    /* The crease law (ours: core/src/crease_law.c, docs/materials.md): a link's set fold angle stays within
     * 2 acos(alpha) of its fold; a hinge at its middle node resists unfolding in place of k_s. 0 (the default):
     * the rules above, bit for bit; > 0 needs tau_set, tau_recover, set_hardening 0 (plastic_memory unused). */
    double k_crease; /* N/m, >= 0: the hinge's stiffness, middle node
                             against its ends' midpoint (cloth_fabric:
                             4 crease_stiffness / spacing)                     */
} cloth_material;

/* A preset's values; an unknown preset gives cotton. */
ODECLOTH_API cloth_material cloth_material_preset(cloth_preset p);
/* CLOTH_OK or CLOTH_EINVAL with a message in err (may be NULL). */
ODECLOTH_API cloth_status cloth_material_validate(const cloth_material *m, cloth_error *err);

/* ----------------------------------------------------------------- solver */

typedef enum cloth_method {
    CLOTH_BACKWARD_EULER = 0, /* implicit, eq. 21, modified PCG (default) */
    CLOTH_EXPLICIT_EULER,     /* forward Euler                             */
    CLOTH_SYMPLECTIC_EULER,   /* semi-implicit: v first, then x            */
    CLOTH_BDF2                /* 2nd-order backward differences, MPCG      */
} cloth_method;

typedef enum cloth_precond {
    CLOTH_PRECOND_BLOCK_JACOBI = 0, /* inverse 3x3 diagonal blocks                */
    CLOTH_PRECOND_JACOBI,           /* inverse scalar diagonal (Baraff-Witkin)    */
    CLOTH_PRECOND_MULTIGRID,        /* geometric multigrid V-cycle on the grid    */
    CLOTH_PRECOND_SSOR,             /* symmetric block Gauss-Seidel, Eisenstat's
                                       trick (about one matrix pass per iteration) */
    CLOTH_PRECOND_AUTO              /* default: multigrid for CLOTH_NEWTON's solves
                                       where MULTIGRID would be accepted (its
                                       coarsest level small enough to solve
                                       densely), else block Jacobi */
} cloth_precond;

typedef enum cloth_nonlinear {
    CLOTH_LINEARIZED = 0, /* one linear solve per step                   */
    CLOTH_NEWTON          /* Newton on the step's incremental potential (default) */
} cloth_nonlinear;

typedef struct cloth_solver {
    cloth_method method;
    cloth_precond precond;
    /* Stop when |S r|_D <= cg_tolerance |S (b - A z)|_D: the reduced
     * system's relative residual, S the constraint filter, and |y|_D^2 =
     * y^T D^-1 y with D the 3x3 diagonal blocks of the filtered matrix
     * (a block-diagonal-weighted norm, the same whatever the preconditioner). */
    double cg_tolerance;         /* 1, in (0, 1)                         */
    int cg_max_iterations;       /* >= 1; reaching it fails the step     */
    int definiteness_rule;       /* 1: compressed links keep only k uu^T (paper
                                     sec. 3.2); CLOTH_LINEARIZED only (Newton's
                                     matrix is its potential's Hessian) */
    int warm_start;              /* 1: start from the last step's dv (or
                                     cloth_set_warm_start's) in free directions */
    int strain_limit_iterations; /* elongation-limit projection (Newton)
                                     steps after a step: the explicit
                                     methods' limit, and the implicit
                                     ones' safety net where their own
                                     multipliers did not converge; 0 = off */
    double strain_fail;          /* 1, a step whose max sequential strain
                                     exceeds this after limiting fails    */
    int max_substep_halvings;    /* a failed step is retried in substeps
                                     h/2, h/4, ... h/2^this (0 = no retry;
                                     in [0, 16], default 4); see
                                     cloth_step */
    int newton_iterations;       /* in [0, 256], default 16. CLOTH_LINEARIZED:
                                     with rigid bodies solved with the cloth
                                     (cloth_body), at most this many Newton
                                     corrections of a step in which a
                                     sequential link went from within its
                                     limit to past 1 + 1.25 delta (0 = off).
                                     CLOTH_NEWTON: the iterations a step may
                                     take after its contacts or the limit's
                                     multipliers last changed, and the
                                     multipliers' updates (>= 1); not
                                     converged then, the step fails
                                     (CLOTH_FAIL_NEWTON) and is retried in
                                     substeps (but see keep_unconverged)  */
    /* How the implicit methods solve a step's nonlinear equations.
     * CLOTH_LINEARIZED: linearised once about the step's start
     * (Baraff-Witkin), the elongation limit by the projection after it.
     * CLOTH_NEWTON (default): Newton's method on the step's incremental potential,
     * a line search keeping every iteration a descent; damping, and the
     * compressed links' push, along the links' directions frozen over the
     * step (backward Euler: at x0, so that no exact step gains energy;
     * BDF2: at x0 + h v0, for its order), which makes the potential convex
     * and its Hessian A the Newton matrix. A step ends when the last Newton
     * step's size sqrt(ddv^T M ddv / cloth mass) (+ the bodies'; an RMS
     * velocity correction), or the residual R's sqrt(R^T M^-1 R / cloth
     * mass), is within newton_tolerance, and the energy the iterate can
     * have gained, v_new . R (+ each held body's, at its new velocity), is within
     * a quarter of what the exact step dissipates (|dv|_M^2 / 2, the dampers'
     * work and the links' Bregman gaps; docs/newton.md) (but not
     * below the kinetic energy at 1e-4 newton_tolerance), so an inexact
     * step adds no energy that shows (the warm start is kept without a
     * solve only when its residual is within newton_tolerance and
     * newton_rtol |dv|, |dv| the warm start's
     * velocity change), and no sequential link is past its limit
     * (1 + delta) l0 by more than limit_tolerance of it: the limit is a
     * constraint held by multipliers (augmented Lagrangian on the k_delta
     * law; a link the constraints hold past it keeps the plain law) carried
     * from step to step, the
     * projection above acting only where they did not converge. Design
     * and measurements: docs/newton.md. */
    cloth_nonlinear nonlinear;
    double newton_tolerance;    /* m/s, > 0 (default 1e-2)              */
    double newton_rtol;         /* 1, in [0, 1) (default 1e-2): the warm
                                     start kept unsolved only within this
                                     fraction of its velocity change, so a
                                     force too weak for newton_tolerance
                                     still acts                           */
    double limit_tolerance;     /* 1, in (0, 1) (default 1e-3)          */
    double newton_cg_tolerance; /* 1, in (0, 1) (default 1e-2): CLOTH_NEWTON's
                                     linear solves stop here, in cg_tolerance's
                                     norm (which they do not use): an
                                     inexact Newton step, the next
                                     iterations correcting what it leaves;
                                     relative to the residual with the
                                     constraints landed or, if smaller, the
                                     one before (but not below a residual of
                                     newton_tolerance's size)              */
    double newton_cg_share;     /* 1, in [0, 1) (default 0.25): while a
                                     Newton step is larger than its goal
                                     (newton_tolerance), its linear solves
                                     also stop once their error, estimated
                                     from CG's last updates in the step's
                                     norm, is within this share of the goal
                                     (not with bodies in the solve; the
                                     plugin turns it off while a dynamic
                                     body holds the cloth); 0: off        */
    int keep_unconverged;       /* 0 (default) or 1. CLOTH_NEWTON: 1 keeps
                                     the last iterate of a solve that runs
                                     out of newton_iterations at the
                                     smallest substep instead of failing
                                     the step (stats.unconverged counts
                                     it); such an iterate can add energy */
} cloth_solver;

ODECLOTH_API cloth_status cloth_solver_validate(const cloth_solver *s, cloth_error *err);

/* ------------------------------------------------------------------ cloth */

typedef struct cloth_desc {
    int rows, cols;       /* nodes along axis_v and axis_u; each >= 3          */
    double width, height; /* m, extent along axis_u (cols) and axis_v (rows)   */
    double origin[3];     /* m, rest position of node (0, 0)                   */
    double axis_u[3];     /* direction of increasing column (normalised)       */
    double axis_v[3];     /* direction of increasing row (made orthogonal to u) */
    double gravity[3];    /* m/s^2                                             */
    cloth_material material;
    cloth_solver solver;
} cloth_desc;

/* 21 x 21 nodes, 1 m x 1 m, horizontal (xy plane) at z = 1 centred on the z
 * axis, gravity (0, 0, -9.81), cotton, backward Euler + block-Jacobi MPCG. */
ODECLOTH_API cloth_desc cloth_default_desc(void);
ODECLOTH_API cloth_status cloth_desc_validate(const cloth_desc *d, cloth_error *err);

typedef struct cloth cloth;

/* Node (r, c) has index r * cols + c. On failure *out is NULL and err says why. */
ODECLOTH_API cloth_status cloth_create(const cloth_desc *d, cloth **out, cloth_error *err);
ODECLOTH_API void cloth_destroy(cloth *c); /* NULL is fine */

/* The message of the last failing call on this cloth ("" if none). */
ODECLOTH_API const char *cloth_last_error(const cloth *c);

ODECLOTH_API int cloth_rows(const cloth *c);
ODECLOTH_API int cloth_cols(const cloth *c);
ODECLOTH_API int cloth_vertex_count(const cloth *c);
ODECLOTH_API cloth_desc cloth_get_desc(const cloth *c); /* material, solver, gravity as now set */

/* Read-only arrays of 3 * vertex_count doubles, valid until the cloth is destroyed. */
ODECLOTH_API const double *cloth_positions(const cloth *c);  /* m   */
ODECLOTH_API const double *cloth_velocities(const cloth *c); /* m/s */
ODECLOTH_API const double *cloth_masses(const cloth *c);     /* kg, one per vertex */

/* Set all positions / velocities (3 * vertex_count doubles, all finite). Either restarts the step's
 * history (warm start, BDF2's last step); new positions also drop the limit's multipliers. */
ODECLOTH_API cloth_status cloth_set_positions(cloth *c, const double *x);
ODECLOTH_API cloth_status cloth_set_velocities(cloth *c, const double *v);
/* Add dv (3 * vertex_count doubles) to the velocities, keeping the step's
 * history (warm start, BDF2's last step), unlike cloth_set_velocities: a
 * correction within a step's accuracy, such as the ODE plugin's turn that
 * keeps angular momentum. Non-finite input or result: refused, unchanged. */
ODECLOTH_API cloth_status cloth_add_velocities(cloth *c, const double *dv);
/* The next step's warm start (solver.warm_start), for that step only: a
 * velocity change dv (3 * vertex_count doubles, finite) the Newton step weighs
 * against its other starts in place of the last step's dv (the linearised step
 * ignores it); for solving a step again after cloth_restore. */
ODECLOTH_API cloth_status cloth_set_warm_start(cloth *c, const double *dv);
/* One vertex's position x and velocity v; either may be NULL to keep it
 * (both NULL: CLOTH_EINVAL). */
ODECLOTH_API cloth_status cloth_set_vertex(cloth *c, int vertex, const double x[3], const double v[3]);

/* Change parameters after creation (the topology, rest lengths and masses stay). */
ODECLOTH_API cloth_status cloth_set_material(cloth *c, const cloth_material *m); /* masses unchanged */
ODECLOTH_API cloth_status cloth_set_solver(cloth *c, const cloth_solver *s);
ODECLOTH_API cloth_status cloth_set_gravity(cloth *c, const double g[3]);
/* Extra forces (N), 3 * vertex_count doubles, applied in every step from now
 * on until set again (friction, wind, a user's pull). NULL clears them. The
 * implicit step treats them as constant over the step. */
ODECLOTH_API cloth_status cloth_set_external_forces(cloth *c, const double *f);
/* The forces set (3 * vertex_count doubles, read-only, zeros if none). */
ODECLOTH_API const double *cloth_external_forces(const cloth *c);

/* Linear air drag on each grid triangle (the cells split as the plugin's
 * dClothGetTriangles): with area A, unit normal n, vbar the mean of its
 * vertices' velocities and r = vbar - wind,
 *   F = -A (drag_normal (r.n) n + drag_tangent (r - (r.n) n)),
 * a third on each vertex. Drags in N s / m^3 (>= 0; both 0, the default:
 * off); equal drags and no wind are plain air damping. Implicit steps treat
 * normals and areas as constant over the step. Configuration, not state:
 * cloth_save leaves it out, cloth_internal_forces too. */
typedef struct cloth_air {
    double wind[3];      /* m/s, uniform */
    double drag_normal;  /* N s / m^3, along the normal */
    double drag_tangent; /* N s / m^3, in the plane */
} cloth_air;
/* Validated (finite, drags >= 0); on error the cloth keeps its settings. */
ODECLOTH_API cloth_status cloth_set_air(cloth *c, const cloth_air *air);
ODECLOTH_API cloth_air cloth_get_air(const cloth *c); /* all zeros if c is NULL */
/* The air's total force on the cloth (N), averaged over the last step as
 * the step applied it; zero without drag. With the constraint forces it
 * accounts for the cloth's momentum change beyond gravity and f_ext. */
ODECLOTH_API cloth_status cloth_air_force(const cloth *c, double f[3]);
/* Its torque about the origin (N m), averaged the same way, each triangle's
 * thirds at their vertices' end-of-step positions. */
ODECLOTH_API cloth_status cloth_air_torque(const cloth *c, double t[3]);

/* ------------------------------------------------------------------ links */

typedef enum cloth_link_type {
    CLOTH_SEQUENTIAL = 0, /* 8 immediate neighbours      */
    CLOTH_INTERLACED = 1  /* 8 skip-one neighbours (bend) */
} cloth_link_type;

typedef struct cloth_link {
    int i, j;    /* vertex indices, i < j                 */
    double rest; /* m, l0                                 */
    int plastic; /* interlaced: 1 in the plastic region; sequential:
                         1 when it carries a tension set (tension_yield) */
    double l1;   /* m, plastic rest length (valid when plastic); a
                         sequential link's is its rest length in use    */
} cloth_link;

ODECLOTH_API int cloth_link_count(const cloth *c, cloth_link_type t);
ODECLOTH_API cloth_status cloth_get_link(const cloth *c, cloth_link_type t, int index, cloth_link *out);

/* Apply the plastic rule (paper eq. 8-12) to the current positions; the step
 * does this after every step. With the time-dependent law (tau_set,
 * tau_recover, set_hardening) this call lets no time pass: links enter and
 * leave, nothing relaxes. With tension_yield, the sequential links' tension
 * sets too. Returns the number of plastic interlaced links. */
ODECLOTH_API int cloth_update_plastic(cloth *c);

/* ------------------------------------------------------ forces and energy */

typedef struct cloth_energy {
    double elastic;       /* J, springs (sequential + interlaced)    */
    double kinetic;       /* J                                        */
    double gravitational; /* J, -sum m g . x                          */
} cloth_energy;

ODECLOTH_API cloth_energy cloth_energies(const cloth *c);

/* Internal spring + damping forces (no gravity), 3 * vertex_count doubles. */
ODECLOTH_API cloth_status cloth_internal_forces(const cloth *c, double *f);

/* Largest (d - l0) / l0 over sequential links. */
ODECLOTH_API double cloth_max_strain(const cloth *c);

/* ------------------------------------------------------------ constraints */

/* A velocity constraint on one vertex (Baraff-Witkin 1998 sec. 5): after the
 * step the vertex's position, along the constrained directions, equals those
 * components of `target`. The core turns this into a target velocity
 * ((target - x) / h for backward Euler) held exactly by the filtered CG.
 *   ndof 3: pin (axis ignored)
 *   ndof 1: plane, axis = normal (the one constrained direction)
 *   ndof 2: line,  axis = the line's direction (the one free direction)
 * A moving pin: set a new target before every step. */
typedef struct cloth_constraint {
    int vertex;
    int ndof;         /* 1, 2 or 3; 0 = free */
    double axis[3];   /* unit vector (normalised on set)  */
    double target[3]; /* m, end-of-step position          */
} cloth_constraint;

/* One constraint per vertex; setting replaces the vertex's constraint. */
ODECLOTH_API cloth_status cloth_set_constraint(cloth *c, const cloth_constraint *k);
ODECLOTH_API cloth_status cloth_pin(cloth *c, int vertex, const double target[3]);
ODECLOTH_API cloth_status cloth_release(cloth *c, int vertex);
ODECLOTH_API void cloth_release_all(cloth *c);
ODECLOTH_API cloth_status cloth_get_constraint(const cloth *c, int vertex, cloth_constraint *out);
ODECLOTH_API int cloth_constraint_count(const cloth *c);

/* The vertex touches, or is near, a body's surface: `normal` its outward
 * normal (normalised on set), `point` a point of it at the end of the step.
 * CLOTH_NEWTON decides the contact within the step: a free vertex that would
 * end behind the surface by more than h newton_tolerance is held on its
 * plane (a constraint of ndof 1) while it pushes (it lets go if it pulls:
 * unilateral); a pinned one (ndof 3: sticking) at an end
 * of a sequential link held past the elongation limit slides on the plane
 * (ndof 1), and a sliding one (ndof 1) there whose force pulls lets go. The
 * constraints it changes stay so after the step, undone if the step fails.
 * CLOTH_LINEARIZED ignores it. Cleared by cloth_release(_all). */
ODECLOTH_API cloth_status cloth_set_contact(cloth *c, int vertex, const double normal[3], const double point[3]);
/* After cloth_set_contact: a sliding (ndof 1) or sticking (ndof 3) contact
 * whose force pulls the vertex onto the surface by more than `pull` (N,
 * >= 0) lets go within the step wherever it is (default: infinite, only as
 * above). Newton only. */
ODECLOTH_API cloth_status cloth_set_contact_pull(cloth *c, int vertex, double pull);
/* A second surface near the vertex (CLOTH_NEWTON; CLOTH_LINEARIZED ignores
 * it), `normal` and `point` as for cloth_set_contact: a candidate the step
 * decides as it does a free one. An iterate that puts the vertex behind it
 * by more than h newton_tolerance holds the vertex on its plane, and the
 * plane lets go while its force pulls (unilateral; held again at most once
 * a step). A vertex also on a plane (its contact, one the step made, or a
 * plane constraint) is then held on the line where the two meet, free along
 * it, and each plane's normal force, recovered from the constrained
 * residual, is judged on its own: a plane that pulls lets go alone, by its
 * own rule. Not taken by a pinned or sticking vertex, one on a line, one a
 * body holds (cloth_hold_by_body), or where the planes are within 0.6 deg
 * of parallel. Cleared by cloth_release(_all). */
ODECLOTH_API cloth_status cloth_set_contact_second(cloth *c, int vertex, const double normal[3], const double point[3]);
/* After a step: the vertex's constraint without the second plane (*first;
 * cloth_get_constraint gives their meet while both hold), whether the
 * second holds it (*second), and the force (N) each exerted over the step,
 * f_first + f_second = cloth_constraint_force (f_second zero when it does
 * not hold). Any output may be NULL. */
ODECLOTH_API cloth_status cloth_get_contact_planes(const cloth *c, int vertex, cloth_constraint *first, int *second,
                                                   double f_first[3], double f_second[3]);

/* Force (N) the vertex's constraint exerted on it, averaged over the last
 * step (Baraff-Witkin: from the solve's residual). Zero if unconstrained. */
ODECLOTH_API cloth_status cloth_constraint_force(const cloth *c, int vertex, double f[3]);

/* Rigid bodies solved together with the cloth (two-way coupling, implicit).
 * A body that holds vertices (a pin, or a contact: see cloth_hold_by_body)
 * and is not much heavier than the cloth cannot be coupled explicitly (the
 * cloth's reaction applied to it only after the step): the two overshoot
 * together. Described here, its velocity change over the step (linear, and
 * angular about its centre of mass) joins the modified CG as six more
 * unknowns: the body's equation M du = h (force + the cloth's reaction) is
 * solved with the cloth's, and the held vertices' constrained components
 * move with du. The cloth's constraint forces (cloth_constraint_force) are
 * then exactly the reactions that make du; apply them, opposite, to the
 * body. Backward Euler and BDF2 only (the explicit steppers treat the
 * targets as final); gyroscopic terms are left out. A step retried in
 * substeps (max_substep_halvings) carries each body's du from substep to
 * substep and reports their sum. */
typedef struct cloth_body {
    double mass;        /* kg, > 0 */
    double inertia[9];  /* kg m^2, about the centre of mass in world axes,
                          symmetric positive definite (row-major) */
    double com[3];      /* m, centre of mass at the start of the step */
    double force[3];    /* N, everything but the cloth acting on the body
                          during the step (gravity, the user's forces) */
    double torque[3];   /* N m, about com, likewise */
    double velocity[6]; /* m/s then rad/s (about com): the body's velocity at
                          the start of the step, which bounds the work an
                          inexact Newton step does on it (zeros: at rest) */
} cloth_body;

/* Replace the bodies (count 0: none). Rejected, with nothing changed, when
 * a body is invalid or a vertex is held by a body past count. */
ODECLOTH_API cloth_status cloth_set_bodies(cloth *c, const cloth_body *bodies, int count);
ODECLOTH_API int cloth_body_count(const cloth *c);
/* Let body `index` (0-based, of cloth_set_bodies; -1: none) hold the
 * vertex's constraint: its target is then where the body's point would be
 * if the body kept its velocity, and its constrained components also follow
 * the body's velocity change, solved for with the cloth. A free vertex with
 * a contact (cloth_set_contact) is held so once the step makes it a plane.
 * Setting or releasing the vertex's constraint ends the hold. */
ODECLOTH_API cloth_status cloth_hold_by_body(cloth *c, int vertex, int index);
/* The velocity change (linear m/s, then angular rad/s) body `index`
 * (0-based) received in the last step's solve; zeros before any. */
ODECLOTH_API cloth_status cloth_body_velocity_change(const cloth *c, int index, double dv[6]);

/* ------------------------------------------------------------------- step */

typedef enum cloth_failure {
    CLOTH_FAIL_NONE = 0,
    CLOTH_FAIL_NAN,           /* NaN or inf appeared                      */
    CLOTH_FAIL_CG_MAX_ITER,   /* CG hit its iteration cap unconverged     */
    CLOTH_FAIL_CG_INDEFINITE, /* CG met p^T A p <= 0 (non-positive curvature) */
    CLOTH_FAIL_STRAIN,        /* strain past solver.strain_fail           */
    CLOTH_FAIL_BAD_STEP,      /* h not finite or <= 0                     */
    CLOTH_FAIL_NEWTON         /* Newton not converged in newton_iterations */
} cloth_failure;

ODECLOTH_API const char *cloth_failure_string(cloth_failure f);

typedef struct cloth_step_stats {
    cloth_method method;
    cloth_failure failure; /* why the step failed (its last attempt); NONE on success */
    int iterations;        /* CG iterations, summed over every attempt and
                              substep (0 for explicit methods)        */
    double residual;       /* final relative residual (solver norm); the
                              largest over the substeps               */
    cloth_energy energy;   /* after the step (before it, if it failed) */
    double max_strain;     /* after strain limiting                    */
    int plastic_links;
    int constrained;             /* constrained vertices                    */
    int strain_limited;          /* sequential links corrected by the limit,
                              summed over the substeps                */
    int substeps;                /* substeps of the committed step (1: taken
                              whole, else 2^halvings); on failure, those
                              the last attempt reached                 */
    int halvings;                /* retries: times the substep was halved (0 if
                              the whole step succeeded)               */
    int substeps_failed;         /* failed attempts: the whole step, then one
                              per substep size that failed             */
    cloth_failure first_failure; /* why the whole step failed before the
                              retries (NONE if it did not)             */
    int newton;                  /* Newton iterations, over every attempt    */
    double newton_residual;      /* m/s, the last attempt's final residual
                              size (solver.newton_tolerance's norm)   */
    double newton_goal;          /* m/s, the size that attempt had to reach
                              (newton_tolerance; less when it kept its
                              warm start unsolved)                    */
    int limit_updates;           /* updates of the elongation limit's
                              multipliers, over every attempt          */
    int line_search_cuts;        /* Newton iterations whose full step the
                              line search shortened                   */
    int unconverged;             /* Newton solves kept unconverged: solves of
                              the smallest substep (see cloth_step) that
                              ran out of newton_iterations            */
    int contacts_decided;        /* contacts (cloth_set_contact) the Newton
                              step changed: free vertices held on the
                              surface, sticking ones let slide; over
                              every attempt                           */
    int self_contact_dropped;    /* smallest substeps that the self-contact
                              barrier (odecloth/selfcollision.h) could
                              not take: taken without it, their pairs
                              left to the pass after the step         */
    double self_contact_seconds; /* wall seconds the step spent in that
                              barrier's evaluations and sweeps (0 when
                              no pass is bound)                        */
} cloth_step_stats;

/* Advance by h seconds. An h that is not finite and > 0 is a bad argument:
 * CLOTH_EINVAL, failure BAD_STEP, state unchanged.
 *
 * A step fails on NaN/inf, CG not converging (or meeting non-positive
 * curvature), strain past solver.strain_fail, or (CLOTH_NEWTON) Newton not
 * converging in newton_iterations. With solver.keep_unconverged the last is
 * not final at the smallest substep size (the whole step when
 * max_substep_halvings is 0): there the last Newton iterate is kept if it
 * passes the other checks, stats->unconverged counts it and newton_residual
 * says how far it is from converged. A failed step leaves the state as it
 * was, so calling again meets the same problem: to go on, change the state
 * (the plugin's DCLOTH_FAILURE_HOLD zeroes the velocities).
 *
 * A failed step is taken again from its start as 2 equal substeps of h/2,
 * then (if one of those fails) 4 of h/4, ... down to
 * 2^max_substep_halvings substeps; each failed depth is
 * rolled back whole, so no substep of a failed depth is kept (an unstable
 * substep can pass its own checks). Constraint targets are the
 * positions at the end of the whole step: a substep ending at time t of the
 * step aims at x0 + (t / h) (target - x0) along the constrained directions,
 * x0 the positions when the step began, so a moving pin moves at the same
 * velocity in every substep. Constraint forces are averaged over the
 * substeps (weighted by their length). If a substep of the smallest size
 * fails too, the state is restored to exactly what it was before the call,
 * the return is CLOTH_ESTEP and stats->failure says why. stats may be NULL.
 * The retry path (and only it) allocates a copy of the state; without memory
 * for it the step fails as if max_substep_halvings were 0. */
ODECLOTH_API cloth_status cloth_step(cloth *c, double h, cloth_step_stats *stats);
ODECLOTH_API const cloth_step_stats *cloth_last_stats(const cloth *c);

/* ------------------------------------------------------------------ state */

/* Positions, velocities, plastic state, and what BDF2 and warm starting carry
 * between steps: everything that evolves. Constraints are not state. */
typedef struct cloth_state cloth_state;

ODECLOTH_API cloth_state *cloth_state_create(const cloth *c); /* NULL on no memory */
ODECLOTH_API void cloth_state_destroy(cloth_state *s);
ODECLOTH_API cloth_status cloth_save(const cloth *c, cloth_state *s);
ODECLOTH_API cloth_status cloth_restore(cloth *c, const cloth_state *s); /* sizes must match */
/* Largest absolute difference of positions, velocities, l1 and the permanent
 * and tension sets, plus 1 for any plastic or bent flag that differs; 0 means
 * identical. Negative if sizes differ. */
ODECLOTH_API double cloth_state_diff(const cloth_state *a, const cloth_state *b);

/* State files: a versioned binary record of everything cloth_save keeps
 * (little-endian, IEEE 754 doubles, a checksum; the layout is in state.c),
 * so a run can be stopped and continued exactly, on this or another
 * machine. Reading checks every field (magic, version, sizes against s,
 * finite numbers, l1 > 0, flags 0 or 1, the limit's multipliers >= 0,
 * checksum, exact length) and changes s only if all pass; err (may be NULL)
 * says what is wrong. Writing makes version 4; versions 1 (without the
 * multipliers, read as zero), 2 (without the links' permanent set and
 * bent flags of material.tau_set and friends, read as zero) and 3 (without
 * the sequential links' tension sets, read as zero) are read too. */
ODECLOTH_API size_t cloth_state_size_bytes(const cloth_state *s); /* a record's size; 0 for NULL */
/* Write the record into buf (cap bytes, at least cloth_state_size_bytes);
 * *written (may be NULL) gets its size. */
ODECLOTH_API cloth_status cloth_state_write(const cloth_state *s, void *buf, size_t cap, size_t *written,
                                            cloth_error *err);
/* Read a record of exactly len bytes into s (made for the same cloth size). */
ODECLOTH_API cloth_status cloth_state_read(cloth_state *s, const void *buf, size_t len, cloth_error *err);
/* The same on an open stream (binary mode): one record, read or written
 * from the current position; reading stops at the record's end. */
ODECLOTH_API cloth_status cloth_state_write_file(const cloth_state *s, FILE *f, cloth_error *err);
ODECLOTH_API cloth_status cloth_state_read_file(cloth_state *s, FILE *f, cloth_error *err);

/* The accuracy-driven controller (cloth_adaptive_*) is declared in odecloth/adaptive.h,
 * included below so that code including this header alone still sees it. */

#ifdef __cplusplus
}
#endif

#include "adaptive.h"
#endif
