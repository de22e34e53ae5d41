/* Internal structures and kernels of the cloth core. Unit tests include this
 * header to check single links against finite differences; users should not. */
#ifndef ODECLOTH_INTERNAL_H
#define ODECLOTH_INTERNAL_H

#include <math.h>
#include "odecloth/cloth.h"
#include "bsr.h"
#include "mpcg.h"
#include "multigrid.h"

/* ---------------------------------------------------------------- springs */

/* A piecewise-quadratic spring (springs.c): E = 1/2 k_hi (d - rest)^2 above rest, 1/2 k_lo (d -
 * rest)^2 below, plus 1/2 k_lim (d - lim)^2 past the elongation limit lim (HUGE_VAL where none).
 * Every link type and region of the paper reduces to one of these (cloth_link_law). */
typedef struct spring_law {
    double k_hi, k_lo, rest;
    double k_lim, lim; /* extra stiffness past length lim (lim > rest) */
} spring_law;

/* Energy (J). */
double oc_spring_energy(const double xi[3], const double xj[3], spring_law s);

/* Elastic force on node i (f_j = -f_i) and K = df_i/dx_j (3x3, may be NULL); the other blocks follow
 * from K. definiteness != 0 applies the paper's rule: the transverse term k (1 - rest/d)(I - uu^T)
 * is dropped when d < rest, so K stays semidefinite. */
void oc_spring_eval(const double xi[3], const double xj[3], spring_law s, int definiteness, double f_i[3], double K[9]);

/* Damping along the link (eq. 4): f_i = c ((v_j - v_i) . u) u, f_j = -f_i,
 * and D = df_i/dv_j = c uu^T (3x3), also df_i/dv_i = -D. D may be NULL. */
void oc_damper_eval(const double xi[3], const double xj[3], const double vi[3], const double vj[3], double c,
                    double f_i[3], double D[9]);

/* Spring and damper of one link at once (one square root): the total force
 * on node i and, if K is not NULL, K = df_i/dx_j and D = df_i/dv_j as above.
 * The step's hot loop; equal to oc_spring_eval + oc_damper_eval. */
void oc_link_eval(const double xi[3], const double xj[3], const double vi[3], const double vj[3], spring_law s,
                  double c, int definiteness, double f_i[3], double K[9], double D[9]);

/* A link in the Newton step: tension and limit along its direction, compression along the frozen u0,
 * so E is convex, K semidefinite and E >= oc_spring_energy. Returns E; f_i, K, slack may be NULL.
 * A slack link (*slack) gets w k_hi u u^T added to K. */
double oc_spring_eval_predicted(const double xi[3], const double xj[3], const double u0[3], spring_law s, double w,
                                double f_i[3], double K[9], int *slack);

/* ------------------------------------------------------- link topology */

typedef struct link_topo {
    int i, j;
    double rest; /* l0 */
} link_topo;

/* The spring law of link e in its current region, inline for the links' loops:
 * sequential: (k_t, k_c, l0); interlaced elastic: (k_b, k_b, l0);
 * interlaced plastic: (k_s, k_b, l1); with the crease law (k_b, k_b, l1) and a hinge (crease_law.c). */
static inline spring_law seq_law(const cloth_material *m, double rest, double set)
{
    /* eq. 6-7: asymmetric, tension k_t, compression k_c << k_t; past the
     * elongation limit (1 + delta) l0 stiffer by k_delta k_t (material.c); a tension set
     * (a share of l0, tension_plastic.c) lengthens the rest length, never past the limit */
    double lim = (1.0 + m->delta) * rest, lp = rest + set * rest;
    spring_law s = {m->k_t, m->k_c, lp < lim ? lp : lim, m->k_delta * m->k_t, lim};
    return s;
}

static inline spring_law int_law(const cloth_material *m, double rest, int plastic, double l1)
{
    /* eq. 9-10: elastic bend; eq. 11-12: around the plastic rest length l1,
     * unbending (d > l1) is resisted by the spreading stiffness k_s, further bending by k_b */
    double k_open = m->k_crease > 0.0 ? m->k_b : m->k_s; /* the crease law: bending about the set; its hinge
                                                              resists unfolding (crease_law.c) */
    spring_law e = {m->k_b, m->k_b, rest, 0.0, HUGE_VAL}, p = {k_open, m->k_b, l1, 0.0, HUGE_VAL};
    return plastic ? p : e;
}

/* The plastic rule for one interlaced link of current length d: updates
 * *plastic and *l1 (paper eq. 8-12). */
void oc_plastic_rule(double alpha, double rest, double d, int *plastic, double *l1);
/* The same with the opt-in memory (material.plastic_memory; plastic.c). */
void oc_plastic_rule_memory(double alpha, int memory, double rest, double d, int *plastic, double *l1);
/* The time-dependent law (material.tau_set, tau_recover, set_hardening; viscoplastic.c) over a step of h
 * seconds ending at length d. *perm: the permanent set as a share of rest; *bent: whether the link is past
 * the yield as of the last update. */
void oc_plastic_rule_time(const cloth_material *m, double rest, double d, double h, int *plastic, double *l1,
                          double *perm, int *bent);
/* The crease law (material.k_crease; crease_law.c): whether m asks for it; a link's fold angle at chord d;
 * and its rule, the set's chord *l1 kept within the yield angle 2 acos(alpha) of the fold (*plastic: l1 < rest). */
int oc_crease_law_on(const cloth_material *m);
double oc_crease_fold_angle(double rest, double d);
void oc_crease_rule(double alpha, double rest, double d, int *plastic, double *l1);
/* Set link e's hinge at x, pushing along its sagitta at x0: energy, force f_mid on its ends' midpoint (-f_mid
 * on the middle node), K = df_mid/dx_m (NULL allowed). Then the sums over set links: energy, f += scale forces,
 * A += scale Hessian (after the links' blocks), out += (df/dx) w, the gap E(x0) - E(x) - f(x).(x0 - x). */
double oc_crease_hinge(const cloth *c, int e, const double *x, const double *x0, double f_mid[3], double K[9]);
double oc_crease_energy(const cloth *c, const double *x, const double *x0);
void oc_crease_forces(const cloth *c, const double *x, const double *x0, double scale, double *f);
void oc_crease_matrix(cloth *c, const double *x, const double *x0, double scale);
void oc_crease_Kw(const cloth *c, const double *x, const double *w, double *out);
double oc_crease_dissipation(const cloth *c, const double *x0, const double *x);
/* Whether m asks for the time-dependent law (any of its three fields > 0). */
int oc_plastic_time_on(const cloth_material *m);
struct cloth_state;
/* Link e of state s after a step of h seconds ending at length d, by the
 * material's rule (plastic.c); returns its plastic flag. */
int oc_plastic_update_link(const cloth_material *m, struct cloth_state *s, int e, double rest, double d, double h);
/* Tension plasticity (material.tension_yield, tension_set; tension_plastic.c): whether m asks for it, and
 * the tension set (a share of rest) of a sequential link of rest length rest, set so far `set`, at length d. */
int oc_tension_plastic_on(const cloth_material *m);
double oc_tension_set_rule(const cloth_material *m, double rest, double d, double set);

/* ------------------------------------------------------------------ state */

struct cloth_state {
    int n;                  /* vertices */
    int n_int;              /* interlaced links */
    double *x, *v;          /* 3n */
    unsigned char *plastic; /* n_int */
    double *l1;             /* n_int */
    double *perm;           /* n_int: permanent set, a share of l0 (viscoplastic.c) */
    unsigned char *bent;    /* n_int: past the yield at the last update (viscoplastic.c) */
    double *seq_set;        /* n_seq: tension set of each sequential link, a share of its l0
                               (tension_plastic.c) */
    /* carried between steps */
    double *x_prev, *v_prev; /* 3n, BDF2 history (valid if has_prev) */
    double h_prev;
    int has_prev;
    double *dv_prev; /* 3n, warm start */
    int n_seq;
    double *lim_shift; /* n_seq: the elongation limit's multipliers, as
                                shifts of each link's limit length (newton.c),
                                the next step's start */
};

/* ------------------------------------------------------------------ cloth */

struct cloth {
    cloth_desc desc; /* as created, with material/solver/gravity kept current */
    int rows, cols, n;
    double *mass; /* n   */
    int n_seq, n_int;
    link_topo *seq, *lint;         /* sequential and interlaced links */
    struct cloth_state st;         /* the evolving state */
    struct cloth_state retry_bk;   /* the substep retry's copy of st, and its */
    double *retry_xs, *retry_fsum; /* 3n start positions and force sums      */

    /* constraints: one slot per vertex */
    cloth_constraint *con; /* n, ndof 0 = free */
    int n_con;
    double *con_force;       /* 3n, N, from the last step */
    double *cand;            /* 6n: contact candidates (cloth_set_contact): normal, point */
    double *cand_pull;       /* n: N, a plane contact pulling beyond this lets
                                  go within the step (cloth_set_contact_pull) */
    unsigned char *cand_on;  /* n: 1 candidate, 2 made a plane, 3 let slide, 8 plane released (a candidate
                                * again), 9 made again, 4/5 released for good, 6/7 sliding/sticking candidate
                                * released for good, 10 sliding released (a candidate again), 11 made again */
    double *cand2;           /* 6n: second candidates (cloth_set_contact_second): normal, point */
    unsigned char *cand2_on; /* n: 1 a candidate, 2 held, 8 let go (a candidate again), 9 held
                                  again, 4 let go for good (contacts.c) */
    cloth_constraint *con1;  /* n: while the second plane holds a vertex (cand2_on 2 or 9), its
                                  constraint without it; con[i] is then their meet */
    double *f_ext;           /* 3n, N, external forces (cloth_set_external_forces) */
    cloth_air air;           /* air drag and wind (cloth_set_air; air.c) */
    int *air_blk;            /* 6 per grid triangle: its pairs' blocks in A (air.c) */
    double air_force[3];     /* the air's total force over the last step (N; air.c) */
    double air_torque[3];    /* and its torque about the origin (N m) */
    /* rigid bodies solved with the cloth (bodies.c) */
    int nbody;
    cloth_body *body;                  /* nbody, as set */
    double *body_ws;                   /* per body: M (36), rhs (6), du (6), Ginv (36),
                                  CG vectors (5 x 6); vbody (n ints) after */
    int *vbody;                        /* n: body of each constrained vertex, -1 none */
    int body_held;                     /* vertices held by bodies in this step's solve */
    double *body_dev;                  /* 3n: the substep retry's displacement of held
                                  vertices by their bodies' du so far */
    int body_retry;                    /* 1 while a step is retried in substeps */
    double body_hs;                    /* that substep's size */
    struct self_contact *self_contact; /* the Newton step's self-contact, bound by a
                                  self-collision pass (self_contact.h), or NULL */

    /* step workspace, sized at creation: the step allocates nothing */
    bsr A;                                      /* pattern: diagonal + one block pair per link */
    int *seq_blk, *int_blk;                     /* 2 per link: blocks (i,j) and (j,i) in A */
    int links_own_blocks;                       /* each off-diagonal block is one link's (oc_bsr_edges_own_offdiag) */
    double *work;                               /* one allocation behind the vectors below */
    double *f, *b, *dv, *z, *y, *x_new, *v_new; /* 3n each */
    double *ddv;                                /* 3n: a Newton correction of dv */
    double *warm_dv;                            /* 3n: the next step's start (cloth_set_warm_start) */
    int warm_set;                               /* 1: warm_dv is set, for the next step only */
    double *na;                                 /* 3n: x_new = na + cfac v_new (potential.c) */
    double *dvt, *xt, *vt;                      /* 3n each: the line search's trial point */
    double *ut;                                 /* 3 per link (sequential, then interlaced): the
                                  damping directions of the step */
    double *cg;                                 /* 6 * 3n: MPCG workspace */
    double *jac;                                /* 3n: scalar Jacobi inverse diagonal */
    double *x_lever;                            /* 3n: constrained vertices' predicted end-of-step
                                  positions, where bodies take their forces */
    unsigned char *cflag;                       /* n: vertex constrained (filter needed) */
    int *clist;                                 /* n_con: the constrained vertices, ascending */
    multigrid mg;                               /* levels sized at creation */
    double *con_new;                            /* 3n: constraint forces of the step being taken */
    double *pre;                                /* 9n: preconditioner blocks */
    double *S;                                  /* 9n: per-vertex filter (I - constrained projector) */
    double *Ah;                                 /* 9 nnzb: the filtered matrix, for the SSOR solver */
    double *sl;                                 /* 9 n_seq: elongation-limit projection (u, C, lambda, CG) */
    int *sl_act;                                /* n_seq: its active links */
    unsigned char *sl_held;                     /* n_seq: links held at the limit this step; then n marks */
    double *sl_vtx;                             /* 3n: its per-vertex scratch, kept zeroed */
    double *sl_x0;                              /* 3n: the positions it started from (the held vertices' levers) */
    const double *sl_x;           /* sl_x0 while it runs, else NULL (bodies.c's levers from the step's start) */
    double *sl_dv;                /* 3n: its velocity correction of the step being taken (step.c) */
    double *lim_shift;            /* n_seq: the step's multipliers of the elongation limit
                                  (newton.c: from st.lim_shift, committed with the step;
                                  linearized.c: from 0) */
    double *lim_rho;              /* n_seq: each link's penalty factor on k_lim in the step
                                  (limit_multipliers.c; 1 at the step's start) */
    double *lim_viol;             /* n_seq: its violation at the last multiplier update (< 0:
                                  dictated by the constraints, left to the plain law) */
    unsigned char *slack_age;     /* n_seq: the Newton iterates in a row each link has been
                                  slack in this step (potential.c) */
    double diss_links;            /* the links' part of the last oc_potential_residual's dissipation */
    double diss_e0;               /* the links' energy at x0 without the limit (NaN: not yet this step) */
    double *dv_saved, *con_saved; /* 3n each (linearized.c): dv and con_new when the
                                  corrections last converged */
    double *K_seq, *K_int;        /* per-link 3x3 df_i/dx_j (linearized.c's K v products) */

    cloth_step_stats stats;
    char err[256];
};

/* Set c->err and return code (printf-style). */
cloth_status oc_cloth_fail(cloth *c, cloth_status code, const char *fmt, ...);
/* Same for a cloth_error (may be NULL). */
cloth_status oc_error_set(cloth_error *e, cloth_status code, const char *fmt, ...);

/* step.c: carve the step's vectors out of c->work (0 or -1 on no memory) */
int oc_workspace_alloc(cloth *c);

/* strain_limit.c: the elongation limit on sequential links by fast
 * projection. Moves x (and v by dx / h, h the step) for at most `iterations`
 * Newton steps; returns the number of links over the limit before the first. */
int oc_strain_limit(cloth *c, double *x, double *v, const double *S, double h, int iterations);

/* Rigid bodies solved with the cloth (bodies.c): vertex i held by body g has dv_i = S_i w_i + z_i +
 * (I - S_i) J_i u_g, J_i u_g its point velocity; the CG reaches the bodies' u through ex (mpcg.h). */
typedef struct mpcg_bodies {
    mpcg_extra ex; /* size 6 nb, y the velocity changes u; rhs the impulse from all but the cloth */
    int nb;
    const int *vbody;  /* n: body of each vertex, -1 none (constrained only) */
    const double *x;   /* 3n: positions at the step's start (lever arms) */
    const double *com; /* 3 nb */
    const double *M;   /* 36 nb: 6x6 mass matrices, scaled as the cloth's rows (as is rhs) */
    double *ginv;      /* 36 nb: out of ex.factor */
} mpcg_bodies;

/* bodies.c: fill B for this step's solve (h the step, cfac the method's dx/dv_new) and return its
 * operators for mpcg_problem.extra; NULL when no constrained vertex is held by a body. */
const mpcg_extra *oc_bodies_prepare(cloth *c, double h, double cfac, mpcg_bodies *B);

/* bodies.c, for the elongation limit: whether a body holds vertex i's constrained components; u^T W u's
 * body share; F_g += s J^T P u; D = Minv F (F zeroed); q_i += s P J D; bodies' du += s D. */
int oc_body_holds(const cloth *c, int i);
/* the bodies' inverse mass with their held vertices, at the levers of the
 * positions the projection works on (c->sl_x; the step's start if NULL) */
void oc_body_limit_begin(cloth *c);
double oc_body_wnorm(const cloth *c, const double *S, int i, const double u[3]);
void oc_body_push(cloth *c, const double *S, int i, const double u[3], double s);
void oc_body_solve(cloth *c);
void oc_body_move(const cloth *c, const double *S, int i, double s, double *q);
void oc_body_kept(cloth *c, double s);
/* bodies.c, for the substep retry (step.c): reset the sums at a depth's start; shift a held vertex's
 * target by what earlier substeps gave its body; add each taken substep's du; set the total as the step's. */
void oc_bodies_retry_reset(cloth *c);
void oc_bodies_retry_target(const cloth *c, int i, double hs, double tg[3]);
void oc_bodies_retry_commit(cloth *c, double hs);
void oc_bodies_retry_finish(cloth *c);
/* linearized.c's corrections: the du when they last converged saved, and
 * restored */
void oc_bodies_newton_save(cloth *c);
void oc_bodies_newton_restore(cloth *c);
/* linearized.c: the step linearised about its start (see its comment) */
cloth_failure oc_linearized_step(cloth *c, double h, int bdf2, const double *xs, double frac, cloth_step_stats *st);
/* A Newton iteration (newton.c): the bodies' rows on their residual while
 * the correction du is solved (begin); their share of the potential at
 * u + t du, its slope along du; then u += t du (take; t 0: unchanged). */
void oc_bodies_newton_begin(cloth *c);
double oc_bodies_newton_energy(const cloth *c, double t);
double oc_bodies_newton_slope(const cloth *c);
void oc_bodies_newton_take(cloth *c, double t);
/* J_i u: how far vertex i's holding body has moved it with the velocity
 * change u taken so far in the step (0 if no body solved with the cloth
 * holds it); a contact made within the step lands there */
void oc_bodies_held_motion(const cloth *c, int i, double out[3]);
/* du^T M du over the bodies (M as scaled for the solve), during an
 * iteration: the bodies' share of the Newton step's size */
double oc_bodies_step_energy(const cloth *c);
/* the bodies' share of the potential at u, outside an iteration */
double oc_bodies_energy(const cloth *c);
/* sum of R_g^T M_g^-1 R_g over the bodies' rows, b = -R the cloth's */
double oc_bodies_residual_energy(const mpcg_problem *P, const double *b);
/* The bodies' residual's work at their velocities after the iterate,
 * sum (V0 + u)^T r_g (r_g as above, unsquared; V0 cloth_body.velocity) */
double oc_bodies_residual_work(const cloth *c, const mpcg_problem *P, const double *b);

/* limit_multipliers.c: whether both ends of a link are held in full by the same thing (the world or one
 * body), so no multiplier can change its length; and the multipliers' update s = max(0, s + d - lmax)
 * at x, returning the largest change / lmax. */
int oc_link_held_together(const cloth *c, const link_topo *L);
/* contacts.c: make planes of the free candidates that x puts behind their
 * surface by more than tol (returns how many); then set z to land them in
 * the next iteration from dv, zero elsewhere */
int oc_contacts_decide(cloth *c, const double *x, double tol);
void oc_contacts_land(cloth *c, const double *dv);
/* sticking contacts (ndof 3 with a contact) at an end of a sequential link
 * that x puts past its limit (beyond limit_tolerance) slide on their
 * surface's plane; returns how many */
int oc_contacts_slide(cloth *c, const double *x);
/* Contacts on a plane (set, made or let slide) whose force (b / cfac) pulls, at any strength at a link
 * end x puts past the limit or on a plane the step made, elsewhere by more than their cand_pull:
 * released for the step. Returns how many. */
int oc_contacts_release(cloth *c, const double *x, const double *b, double cfac);
/* at a step's start: planes kept from the last step stay constraints; on
 * its failure: the planes it made are candidates again */
void oc_contacts_begin(cloth *c);
void oc_contacts_undo(cloth *c);
double oc_limit_multipliers_update(cloth *c, const double *x, int grow);
/* every link's penalty factor 1 again (a step's start) */
void oc_limit_multipliers_begin(cloth *c);

/* constraints.c: the filter S_i of each vertex and z_i = (I - S_i)(v_target - v0), given x_new = a +
 * cfac v_new; a substep aims at frac of the way from xs (the step's start) to the target. */
void oc_constraints_build(cloth *c, const double *a, const double *v0, double cfac, const double *xs, double frac);

/* air.c: the grid triangles' air drag (cloth_set_air). oc_air_on: any drag
 * set. oc_air_blocks: find each triangle's off-diagonal blocks in A at
 * creation (0, or -1 on no memory). */
int oc_air_on(const cloth *c);
int oc_air_blocks(cloth *c);
/* Frames at xf + hf vf, velocities v: f += s F_air, A += t (area/9) D on each
 * triangle's vertex pairs (f, A may be NULL; -dF_a/dv_b = (area/9) D).
 * Returns the dissipation potential 1/2 sum area r^T D r. */
double oc_air_eval(const cloth *c, const double *xf, const double *vf, double hf, const double *v, double s, double *f,
                   bsr *A, double t);
/* The air's total force on the attempt's solution (x_new, v_new from the
 * state), in the frame the method's solve used, into out. */
void oc_air_step_force(const cloth *c, double h, double out[3], double tq[3]);

/* state.c */
int oc_state_alloc(struct cloth_state *s, int n, int n_int, int n_seq);
void oc_state_free(struct cloth_state *s);
void oc_state_copy(struct cloth_state *dst, const struct cloth_state *src);

/* forces.c: f = internal forces, plus gravity, external forces and air drag if with_gravity. */
void oc_forces_eval(const cloth *c, const double *x, const double *v, int with_gravity, double *f);
double oc_elastic_energy(const cloth *c, const double *x);
/* Largest (d - l0) / l0 over sequential links at positions x (NaN if any is). */
double oc_max_strain_of(const cloth *c, const double *x);
/* The passes over the links after a step, each length computed once (forces.c; bit for bit
 * oc_max_strain_of, cloth_update_plastic and cloth_energies): max sequential strain and energy at x;
 * the plastic update with the interlaced energy added to *elastic; the energies given the elastic part. */
double oc_max_strain_seq_energy(const cloth *c, const double *x, double *e_seq);
int oc_update_plastic_energy(cloth *c, double h, double *elastic);
cloth_energy oc_energies_with_elastic(const cloth *c, double elastic);

/* small vector helpers */
static inline int finite3(const double a[3]) { return a[0] - a[0] == 0.0 && a[1] - a[1] == 0.0 && a[2] - a[2] == 0.0; }
int oc_all_finite(const double *a, size_t n);

#endif
