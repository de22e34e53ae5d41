/* bench_drape: impacts and fine cloths at the sizes users run.
 *
 * Every scene is a 1 m square cotton cloth (cloth_material_preset(CLOTH_COTTON),
 * 0.2 kg, N x N nodes) at the library's default solver, 2 s simulated at
 * h = 1/60 s; one CSV row per scene, variant and N:
 *   drape    flat at z = 0.35 m over a static ODE sphere geom (r 0.25 m) at
 *            the origin; dClothStep alone; N = 21, 41, 81, 161;
 *   pinned   bench_step's scene through the core (cloth_step): pinned at two
 *            adjacent corners, falling from horizontal; N = 21, 41, 81;
 *   pile     dropped from 0.5 m above a pile of six dynamic bodies on a plane
 *            (three boxes, a capsule, a sphere, a cylinder), the program's
 *            own near callback making their contact joints, dClothWorldStep
 *            with dWorldStep (variant step) or dWorldQuickStep (quick); N = 41, 81;
 *   hammock  pinned at its 4 corners, a 1 kg ball (r 0.1 m) thrown down into
 *            it at 5 m/s; dClothWorldStep; N = 25, 41, 81;
 *   each with the implicit steps linearised and by Newton (--solver; the
 *   variant names the solver: linearized, newton, step-newton, ...).
 * Columns: wall and CPU seconds of the steps, failed and substepped steps,
 * steps that kept an unconverged Newton iterate (unc; near the CSV's end,
 * ahead of the preconditioner, --precond),
 * Newton iterations and CG iterations per step (the core's counts; the
 * plugin reports its last solve's), strain over the sequential links at the
 * end (p99, max) and over the run, the deepest vertex inside the sphere (the
 * pile: any geom; the hammock: the ball), mean vertex speed over the last
 * 1/24 s, step times, and for the hammock the largest energy gain of a step
 * and whether the ball ended below the cloth. A run that passes its wall
 * budget (--max-wall) stops there with status "timeout" and its figures so far.
 * After each solver's drape rows: the CPU per step fitted as n^p over the
 * vertex count from N = 41 up, and the range of Newton iterations a step.
 * Writes DIR/bench_drape.csv and, with gnuplot, DIR/bench_drape.png.
 *
 *   bench_drape [--out DIR] [--scene drape,pinned,pile,hammock] [--grid N]
 *               [--solver linearized|newton|both] [--precond P] [--max-wall S]
 *               [--self-collision T] [--fabric F] [--fast] [--check] [--steps]
 *
 * Test bench_drape in test/CMakeLists.txt.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "odecloth/dcloth.h"
#include "odecloth/selfcollision.h"
#include "odecloth/fabric.h"
#include "bench_util.h"

#define HZ 60.0
#define G 9.81
#define SPEED_WINDOW_STEPS (HZ / 24.0) /* the mean speed's 1/24 s, in steps */
#define SPHERE_R 0.25
#define DRAPE_Z 0.35
#define PILE_TOP 0.35 /* m, the pile's highest face (the second box's top) */
#define PILE_DROP 0.5
#define HAMMOCK_Z 1.0
#define BALL_R 0.1
#define BALL_MASS 1.0
#define BALL_SPEED 5.0
#define ENERGY_TARGET 1e-3 /* J, the largest gain a hammock step may show */
#define DEPTH_TARGET 1e-4  /* m, "no vertex inside the sphere" read with this slack */

enum { DRAPE, PINNED, PILE, HAMMOCK, NSCENES };
static const char *scene_name[NSCENES] = {"drape", "pinned", "pile", "hammock"};

/* Blender 3.4's cloth on the same drape (one core of this machine, quiet),
 * and our targets, both wall seconds for 2 s simulated. */
static const int blender_n[4] = {21, 41, 81, 161};
static const double blender_s[4] = {2.95, 8.16, 38.1, 143};
static const int target_n[3] = {41, 81, 161};
static const double target_s[3] = {0.4, 1.9, 14};

/* --steps: every step's figures go to DIR/bench_drape_steps.csv (NULL: off) */
static FILE *g_steps;

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* ------------------------------------------------------------------ strain */

/* The sequential links (8 immediate neighbours) with their rest lengths,
 * and a buffer for their strains. */
typedef struct links {
    int n;
    int *ij;
    double *l0, *strain;
} links;

static int links_init(links *L, const cloth *c)
{
    L->n = cloth_link_count(c, CLOTH_SEQUENTIAL);
    L->ij = malloc(2 * (size_t)L->n * sizeof *L->ij);
    L->l0 = malloc((size_t)L->n * sizeof *L->l0);
    L->strain = malloc((size_t)L->n * sizeof *L->strain);
    if (!L->ij || !L->l0 || !L->strain) return -1;
    for (int e = 0; e < L->n; e++) {
        cloth_link k;
        cloth_get_link(c, CLOTH_SEQUENTIAL, e, &k);
        L->ij[2 * e] = k.i, L->ij[2 * e + 1] = k.j, L->l0[e] = k.rest;
    }
    return 0;
}

static void links_free(links *L)
{
    free(L->ij);
    free(L->l0);
    free(L->strain);
}

/* (d - l0) / l0 of every link at positions x, into L->strain; the largest. */
static double links_strain(links *L, const double *x)
{
    double m = -INFINITY;
    for (int e = 0; e < L->n; e++) {
        const double *a = x + 3 * L->ij[2 * e], *b = x + 3 * L->ij[2 * e + 1];
        double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        L->strain[e] = (sqrt(dot3(d, d)) - L->l0[e]) / L->l0[e];
        m = fmax(m, L->strain[e]);
    }
    return m;
}

/* The 99th percentile of the strains last computed (sorts them). */
static double links_p99(links *L)
{
    if (L->n == 0) return NAN;
    qsort(L->strain, (size_t)L->n, sizeof *L->strain, bench_cmp_double);
    int k = (int)ceil(0.99 * L->n) - 1;
    return L->strain[k < 0 ? 0 : k];
}

/* ------------------------------------------------------------------ scenes */

typedef struct scene {
    int kind, quick;
    cloth *core; /* the cloth stepped (the plugin's own in ODE scenes) */
    dClothID cl; /* 0 in the core-only scene */
    dWorldID world;
    dSpaceID space;
    dJointGroupID joints; /* the pile's contact joints between bodies */
    dGeomID geoms[8];     /* the colliders whose insides the cloth must keep out of */
    int ngeoms;
    dBodyID ball;
    cloth_self_collision *self; /* --self-collision, else NULL */
    double pass_s;              /* s, the last step's self-collision pass after it */
} scene;

/* The user's collisions between bodies and the plane (the cloth's are the
 * plugin's, never seen here). */
static void near_callback(void *ctx, dGeomID a, dGeomID b)
{
    scene *s = ctx;
    dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
    if (!ba && !bb) return;
    dContact ct[8];
    int n = dCollide(a, b, 8, &ct[0].geom, sizeof ct[0]);
    for (int i = 0; i < n; i++) {
        ct[i].surface.mode = dContactApprox1;
        ct[i].surface.mu = 0.6;
        dJointAttach(dJointCreateContact(s->world, s->joints, &ct[i]), ba, bb);
    }
}

/* how the implicit steps solve their equations in this run (--solver,
 * --precond) */
static cloth_nonlinear g_solver = CLOTH_LINEARIZED;
static cloth_precond g_precond = CLOTH_PRECOND_AUTO;
static double g_self = 0.0; /* m, --self-collision's thickness; 0: no pass */
static const char *const precond_name[] = {"block-jacobi", "jacobi", "multigrid", "ssor", "auto"};
/* --fabric: a cloth_fabric preset's springs for the grid (its own weight); -1: the material preset */
static int g_fabric = -1;
static const char *const fabric_name[] = {"cotton", "wool", "silk", "denim", "polyester"};
#define NFABRICS 5

static cloth_desc cotton_desc(int N, double z)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = g_solver;
    d.solver.precond = g_precond;
    d.rows = d.cols = N;
    d.width = d.height = 1.0;
    d.material = cloth_material_preset(CLOTH_COTTON);
    d.material.density = 0.2; /* 1 m^2: 0.2 kg */
    d.origin[0] = d.origin[1] = -0.5;
    d.origin[2] = z;
    return d;
}

/* cotton_desc, or with --fabric that fabric's material for the grid */
static int scene_desc(int N, double z, cloth_desc *d, cloth_error *err)
{
    *d = cotton_desc(N, z);
    if (g_fabric < 0) return 0;
    cloth_fabric f = cloth_fabric_preset((cloth_fabric_kind)g_fabric);
    return cloth_fabric_apply(&f, d, err) == CLOTH_OK ? 0 : -1;
}

static void new_world(scene *s)
{
    s->world = dWorldCreate();
    dWorldSetGravity(s->world, 0, 0, -G);
    s->space = dHashSpaceCreate(0);
}

/* The plugin's cloth at its defaults but the grid and placement. */
static int make_cloth(scene *s, int N, double z, cloth_error *err)
{
    dClothDesc d = dClothDefaultDesc();
    if (scene_desc(N, z, &d.cloth, err)) return -1;
    if (dClothCreate(s->world, s->space, &d, &s->cl, err) != CLOTH_OK) return -1;
    s->core = dClothGetCore(s->cl);
    return 0;
}

static int setup_drape(scene *s, int N, cloth_error *err)
{
    new_world(s);
    s->geoms[s->ngeoms++] = dCreateSphere(s->space, SPHERE_R); /* static, at the origin */
    return make_cloth(s, N, DRAPE_Z, err);
}

static int setup_pinned(scene *s, int N, cloth_error *err)
{
    cloth_desc d;
    if (scene_desc(N, 1.0, &d, err) || cloth_create(&d, &s->core, err) != CLOTH_OK) return -1;
    const double *x = cloth_positions(s->core);
    cloth_pin(s->core, 0, x);
    cloth_pin(s->core, N - 1, x + 3 * (N - 1));
    return 0;
}

enum { P_BOX, P_SPHERE, P_CAPSULE, P_CYLINDER };
typedef struct pile_body {
    int cls;
    double size[3]; /* box: sides; sphere: radius; capsule, cylinder: radius, length */
    double mass, pos[3];
    int lying; /* capsule, cylinder: axis along x (else z) */
} pile_body;

/* Resting on the plane or on each other, apart, inside the cloth's square. */
static const pile_body pile[6] = {
    {P_BOX, {0.30, 0.30, 0.20}, 2.0, {-0.18, -0.18, 0.10}, 0},
    {P_BOX, {0.20, 0.20, 0.15}, 1.0, {-0.18, -0.18, 0.275}, 0},
    {P_BOX, {0.25, 0.15, 0.15}, 1.2, {0.20, -0.20, 0.075}, 0},
    {P_CAPSULE, {0.06, 0.20, 0.0}, 0.8, {0.18, 0.05, 0.06}, 1},
    {P_SPHERE, {0.10, 0.0, 0.0}, 1.0, {-0.20, 0.20, 0.10}, 0},
    {P_CYLINDER, {0.08, 0.25, 0.0}, 0.7, {0.15, 0.28, 0.125}, 0},
};

static void add_pile_body(scene *s, const pile_body *p)
{
    dBodyID b = dBodyCreate(s->world);
    dMass m;
    dGeomID g;
    const double *z = p->size;
    if (p->cls == P_BOX) {
        dMassSetBoxTotal(&m, p->mass, z[0], z[1], z[2]);
        g = dCreateBox(s->space, z[0], z[1], z[2]);
    } else if (p->cls == P_SPHERE) {
        dMassSetSphereTotal(&m, p->mass, z[0]);
        g = dCreateSphere(s->space, z[0]);
    } else if (p->cls == P_CAPSULE) {
        dMassSetCapsuleTotal(&m, p->mass, 3, z[0], z[1]);
        g = dCreateCapsule(s->space, z[0], z[1]);
    } else {
        dMassSetCylinderTotal(&m, p->mass, 3, z[0], z[1]);
        g = dCreateCylinder(s->space, z[0], z[1]);
    }
    dBodySetMass(b, &m);
    dGeomSetBody(g, b);
    dBodySetPosition(b, p->pos[0], p->pos[1], p->pos[2]);
    if (p->lying) {
        dMatrix3 R;
        dRFromAxisAndAngle(R, 0, 1, 0, M_PI / 2);
        dBodySetRotation(b, R);
    }
    s->geoms[s->ngeoms++] = g;
}

static void world_step(scene *s, double h)
{
    dSpaceCollide(s->space, s, near_callback);
    if (s->quick) dWorldQuickStep(s->world, h);
    else dWorldStep(s->world, h);
    dJointGroupEmpty(s->joints);
}

static int setup_pile(scene *s, int N, cloth_error *err)
{
    new_world(s);
    s->joints = dJointGroupCreate(0);
    s->geoms[s->ngeoms++] = dCreatePlane(s->space, 0, 0, 1, 0);
    for (int k = 0; k < 6; k++) add_pile_body(s, &pile[k]);
    /* the pile settles for 0.25 s on its own, then the cloth comes */
    for (int k = 0; k < (int)(0.25 * HZ); k++) world_step(s, 1.0 / HZ);
    return make_cloth(s, N, PILE_TOP + PILE_DROP, err);
}

static int setup_hammock(scene *s, int N, cloth_error *err)
{
    new_world(s);
    if (make_cloth(s, N, HAMMOCK_Z, err)) return -1;
    const int corner[4] = {0, N - 1, (N - 1) * N, N * N - 1};
    for (int k = 0; k < 4; k++) dClothPinToWorld(s->cl, corner[k], dClothGetPositions(s->cl) + 3 * corner[k]);
    s->ball = dBodyCreate(s->world);
    dMass m;
    dMassSetSphereTotal(&m, BALL_MASS, BALL_R);
    dBodySetMass(s->ball, &m);
    dGeomID g = dCreateSphere(s->space, BALL_R);
    dGeomSetBody(g, s->ball);
    s->geoms[s->ngeoms++] = g;
    /* 15 mm above the cloth's 5 mm shell, over its centre */
    dBodySetPosition(s->ball, 0, 0, HAMMOCK_Z + BALL_R + 0.02);
    dBodySetLinearVel(s->ball, 0, 0, -BALL_SPEED);
    return 0;
}

static void scene_free(scene *s)
{
    cloth_self_collision_destroy(s->self);
    if (s->cl) dClothDestroy(s->cl);
    else cloth_destroy(s->core);
    if (s->joints) dJointGroupDestroy(s->joints);
    if (s->space) dSpaceDestroy(s->space); /* and its geoms */
    if (s->world) dWorldDestroy(s->world);
}

/* One step of h as the README has it: the user's collisions, then the cloth
 * and the world (dClothWorldStep), or the cloth alone where nothing moves. */
static cloth_status scene_step(scene *s, double h, cloth_step_stats *st)
{
    cloth_status rc;
    if (!s->cl) {
        rc = cloth_step(s->core, h, st);
    } else {
        if (s->joints) dSpaceCollide(s->space, s, near_callback);
        rc = s->kind == DRAPE ? dClothStep(s->cl, h) : dClothWorldStep(s->world, &s->cl, 1, h, s->quick);
        if (s->joints) dJointGroupEmpty(s->joints);
        *st = dClothGetStats(s->cl)->core;
    }
    double w = bench_wall_now();
    if (rc == CLOTH_OK && s->self) rc = cloth_self_collision_apply(s->self, s->core, NULL);
    s->pass_s = bench_wall_now() - w;
    return rc;
}

/* Cloth (springs, motion, height) plus the ball's kinetic and potential
 * energy: gravity's work is in the potentials and the fixed pins do none, so
 * a rise is energy the step made (a link turning plastic counts too). */
static double hammock_energy(const scene *s)
{
    cloth_energy e = cloth_energies(s->core);
    const double *v = dBodyGetLinearVel(s->ball), *w = dBodyGetAngularVel(s->ball);
    double inertia = 0.4 * BALL_MASS * BALL_R * BALL_R;
    return e.elastic + e.kinetic + e.gravitational + 0.5 * BALL_MASS * dot3(v, v) + 0.5 * inertia * dot3(w, w) +
           BALL_MASS * G * dBodyGetPosition(s->ball)[2];
}

/* Depth (m) of point p inside geom g, negative outside; ODE has no point
 * depth for cylinders, so theirs is computed here. */
static double geom_depth(dGeomID g, const double *p)
{
    switch (dGeomGetClass(g)) {
    case dSphereClass: return dGeomSpherePointDepth(g, p[0], p[1], p[2]);
    case dBoxClass: return dGeomBoxPointDepth(g, p[0], p[1], p[2]);
    case dCapsuleClass: return dGeomCapsulePointDepth(g, p[0], p[1], p[2]);
    case dPlaneClass: return dGeomPlanePointDepth(g, p[0], p[1], p[2]);
    case dCylinderClass: {
        dVector3 q;
        dReal r, len;
        dGeomGetPosRelPoint(g, p[0], p[1], p[2], q);
        dGeomCylinderGetParams(g, &r, &len);
        return fmin(r - sqrt(q[0] * q[0] + q[1] * q[1]), 0.5 * len - fabs(q[2]));
    }
    default: return NAN;
    }
}

/* mm, the deepest vertex inside any collider (0 if none); NaN without colliders. */
static double deepest_mm(const scene *s)
{
    if (!s->ngeoms) return NAN;
    const double *x = cloth_positions(s->core);
    double deep = 0.0;
    for (int i = 0; i < cloth_vertex_count(s->core); i++)
        for (int k = 0; k < s->ngeoms; k++) deep = fmax(deep, geom_depth(s->geoms[k], x + 3 * i));
    return 1e3 * deep;
}

/* 1 if the ball's centre is below the cloth vertex nearest to it across. */
static int ball_below(const scene *s)
{
    const double *b = dBodyGetPosition(s->ball), *x = cloth_positions(s->core);
    int best = 0;
    double d2 = INFINITY;
    for (int i = 0; i < cloth_vertex_count(s->core); i++) {
        double dx = x[3 * i] - b[0], dy = x[3 * i + 1] - b[1];
        if (dx * dx + dy * dy < d2) d2 = dx * dx + dy * dy, best = i;
    }
    return b[2] < x[3 * best + 2];
}

/* -------------------------------------------------------------------- runs */

typedef struct row {
    int scene, N;
    const char *variant, *status;
    double wall_s, cpu_s;
    int steps, failed, substepped;
    int unconverged;                  /* steps that kept an unconverged Newton iterate */
    double newton, cg;                /* per step */
    double p99, max_strain, max_seen; /* sequential links */
    double depth_mm, mean_speed, max_ms, median_ms;
    double point_mm;         /* the cloth's deepest point in a shell over the run (plugin's max_penetration_all) */
    double energy_gain;      /* J, hammock: the largest E(after) - E(before) of a
                                           step, signed; NaN elsewhere */
    int passed;              /* hammock 0/1; -1 elsewhere */
    double delta, thickness; /* m, for --check */
    double edge_r, edge_z;   /* m, the boundary vertices' mean distance from the z axis, mean z */
} row;

/* What the loop keeps: each step's wall time and the last positions
 * (a ring of `slots`), for the medians and the mean speed at the end. */
typedef struct trace {
    double *step_s, *ring;
    int slots, nv;
} trace;

/* Mean vertex speed over the last SPEED_WINDOW_STEPS steps of `steps`,
 * the earlier position interpolated between the two steps around it. */
static double mean_speed(const trace *t, int steps)
{
    double back = steps - SPEED_WINDOW_STEPS;
    if (back < 0) return NAN;
    int lo = (int)floor(back);
    double f = back - lo, sum = 0.0;
    const double *a = t->ring + (size_t)(lo % t->slots) * 3 * t->nv,
                 *b = t->ring + (size_t)((lo + 1) % t->slots) * 3 * t->nv,
                 *x = t->ring + (size_t)(steps % t->slots) * 3 * t->nv;
    for (int i = 0; i < 3 * t->nv; i += 3) {
        double d[3];
        for (int k = 0; k < 3; k++) d[k] = x[i + k] - ((1 - f) * a[i + k] + f * b[i + k]);
        sum += sqrt(dot3(d, d));
    }
    return sum / t->nv / (SPEED_WINDOW_STEPS / HZ);
}

/* The boundary vertices' mean distance from the z axis and mean height (how far a drape hangs) */
static void edge_shape(const cloth *c, double *r, double *z)
{
    int R = cloth_rows(c), C = cloth_cols(c), m = 0;
    const double *x = cloth_positions(c);
    *r = *z = 0.0;
    for (int i = 0; i < R; i++)
        for (int j = 0; j < C; j++) {
            if (i > 0 && i < R - 1 && j > 0 && j < C - 1) continue;
            const double *p = x + 3 * ((size_t)i * C + j);
            *r += sqrt(p[0] * p[0] + p[1] * p[1]);
            *z += p[2];
            m++;
        }
    *r /= m;
    *z /= m;
}

/* The figures at the end of a run of r->steps steps. */
static void finish_row(const scene *s, trace *t, links *L, long newton, long cg, row *r)
{
    int n = r->steps;
    r->newton = n ? (double)newton / n : NAN;
    r->cg = n ? (double)cg / n : NAN;
    r->max_strain = links_strain(L, cloth_positions(s->core));
    r->p99 = links_p99(L);
    r->depth_mm = deepest_mm(s);
    edge_shape(s->core, &r->edge_r, &r->edge_z);
    r->mean_speed = mean_speed(t, n);
    if (s->ball) r->passed = ball_below(s);
    if (n) {
        qsort(t->step_s, (size_t)n, sizeof *t->step_s, bench_cmp_double);
        r->median_ms = 1e3 * t->step_s[n / 2];
        r->max_ms = 1e3 * t->step_s[n - 1];
    }
}

/* One line of --steps' CSV: step k of row r just taken. */
static void steps_row(const scene *s, const row *r, int k, const cloth_step_stats *st, int ok, double energy)
{
    const dClothStepStats *ps = s->cl ? dClothGetStats(s->cl) : NULL;
    fprintf(g_steps, "%s,%s,%d,%d,%.3f,%d,%d,%d,%d,%d,%d,%d,%.5f,%.6g,%d,%d,%d,%.3f,%.3f\n", scene_name[s->kind],
            r->variant, r->N, k, 1e3 * r->wall_s, st->newton, st->iterations, st->limit_updates, st->line_search_cuts,
            st->contacts_decided, st->substeps, !ok, st->max_strain, energy, ps ? ps->resolves : 0,
            ps ? ps->newton_all : st->newton, ps ? ps->cg_all : st->iterations,
            1e3 * (ps ? ps->self_contact_seconds_all : st->self_contact_seconds), 1e3 * s->pass_s);
}

/* Steps the scene for `seconds` or until the wall budget is spent; only
 * the steps are timed, the measuring between them is not. */
static void run_loop(scene *s, double seconds, double max_wall, row *r)
{
    const double h = 1.0 / HZ;
    int total = (int)lround(seconds * HZ);
    trace t = {NULL, NULL, (int)ceil(SPEED_WINDOW_STEPS) + 1, cloth_vertex_count(s->core)};
    size_t frame = 3 * (size_t)t.nv;
    links L = {0};
    t.step_s = malloc((size_t)total * sizeof *t.step_s);
    t.ring = malloc(t.slots * frame * sizeof *t.ring);
    if (!t.step_s || !t.ring || links_init(&L, s->core)) {
        fprintf(stderr, "bench_drape: out of memory\n");
        r->status = "failed";
        goto done;
    }
    memcpy(t.ring, cloth_positions(s->core), frame * sizeof *t.ring);
    double e_prev = s->ball ? hammock_energy(s) : 0.0, start = bench_wall_now();
    long newton = 0, cg = 0;
    r->status = "ok";
    r->max_seen = links_strain(&L, cloth_positions(s->core));
    for (int k = 0; k < total; k++) {
        cloth_step_stats st;
        double w0 = bench_wall_now(), c0 = bench_cpu_now();
        cloth_status rc = scene_step(s, h, &st);
        t.step_s[k] = bench_wall_now() - w0;
        r->wall_s += t.step_s[k];
        r->cpu_s += bench_cpu_now() - c0;
        r->steps = k + 1;
        int ok = rc == CLOTH_OK && !(s->cl && dClothGetStats(s->cl)->held); /* a held cloth failed too */
        r->failed += !ok;
        r->substepped += ok && st.substeps > 1;
        r->unconverged += ok && st.unconverged > 0;
        newton += st.newton;
        cg += st.iterations;
        const double *x = cloth_positions(s->core);
        memcpy(t.ring + (size_t)((k + 1) % t.slots) * frame, x, frame * sizeof *x);
        r->max_seen = fmax(r->max_seen, links_strain(&L, x));
        if (s->cl) r->point_mm = fmax(r->point_mm, 1e3 * dClothGetStats(s->cl)->max_penetration_all);
        if (s->ball) {
            double e = hammock_energy(s);
            r->energy_gain = k ? fmax(r->energy_gain, e - e_prev) : e - e_prev;
            e_prev = e;
        }
        if (g_steps) steps_row(s, r, k, &st, ok, s->ball ? e_prev : NAN);
        if (k + 1 < total && bench_wall_now() - start > max_wall) {
            r->status = "timeout";
            break;
        }
    }
    if (r->failed && strcmp(r->status, "timeout")) r->status = "failed";
    finish_row(s, &t, &L, newton, cg, r);
done:
    links_free(&L);
    free(t.step_s);
    free(t.ring);
}

/* One row: the scene built, run and measured, then freed. */
static row run_one(int kind, int quick, int N, double seconds, double max_wall)
{
    row r = {.scene = kind, .N = N, .status = "failed", .energy_gain = NAN, .passed = -1};
    static const char *const names[2][3] = {{"linearized", "step", "quick"}, {"newton", "step-newton", "quick-newton"}};
    r.variant = names[g_solver][kind == PILE || kind == HAMMOCK ? 1 + quick : 0];
    r.p99 = r.max_strain = r.max_seen = r.depth_mm = r.mean_speed = r.max_ms = r.median_ms = NAN;
    r.edge_r = r.edge_z = NAN;
    r.point_mm = kind == PINNED ? NAN : 0.0; /* the core alone: no shells */
    r.newton = r.cg = NAN;
    scene s = {.kind = kind, .quick = quick};
    cloth_error err = {0};
    int (*setup[NSCENES])(scene *, int, cloth_error *) = {setup_drape, setup_pinned, setup_pile, setup_hammock};
    if (setup[kind](&s, N, &err)) {
        fprintf(stderr, "bench_drape: %s %dx%d: %s\n", scene_name[kind], N, N, err.message);
    } else {
        r.delta = cloth_get_desc(s.core).material.delta;
        r.thickness = s.cl ? dClothGetThickness(s.cl) : 0.0;
        /* the first apply binds the pass: every step has it */
        if (g_self > 0 && (cloth_self_collision_create(s.core, g_self, &s.self, &err) != CLOTH_OK ||
                           cloth_self_collision_apply(s.self, s.core, NULL) != CLOTH_OK))
            fprintf(stderr, "bench_drape: %s %dx%d: %s\n", scene_name[kind], N, N,
                    err.message[0] ? err.message : cloth_last_error(s.core));
        else run_loop(&s, seconds, max_wall, &r);
    }
    scene_free(&s);
    return r;
}

/* ------------------------------------------------------------------ output */

static void print_header(void)
{
    printf("%-8s %-7s %4s %8s %8s %5s %4s %4s %4s %6s %7s %7s %7s %7s %8s %8s %8s %8s %9s %4s %s\n", "scene", "variant",
           "N", "wall s", "cpu s", "steps", "fail", "sub", "unc", "newton", "CG", "p99", "max", "seen", "depth mm",
           "speed", "max ms", "med ms", "dE J", "thru", "status");
}

static void print_row(const row *r)
{
    char thru[8];
    snprintf(thru, sizeof thru, r->passed < 0 ? "-" : "%d", r->passed);
    printf("%-8s %-7s %4d %8.2f %8.2f %5d %4d %4d %4d %6.2f %7.1f %7.4f %7.4f %7.4f %8.3f %8.4f %8.1f %8.1f "
           "%9.2e %4s %s\n",
           scene_name[r->scene], r->variant, r->N, r->wall_s, r->cpu_s, r->steps, r->failed, r->substepped,
           r->unconverged, r->newton, r->cg, r->p99, r->max_strain, r->max_seen, r->depth_mm, r->mean_speed, r->max_ms,
           r->median_ms, r->energy_gain, thru, r->status);
    fflush(stdout);
}

static const char csv_header[] =
    "scene,variant,N,wall_s,cpu_s,steps,failed_steps,substepped_steps,newton_per_step,cg_per_step,"
    "p99_strain,max_strain,max_strain_seen,depth_in_sphere_mm,mean_speed,max_step_ms,median_step_ms,"
    "energy_gain_J,passed_through,status,unconverged_steps,precond,fabric,edge_radius_m,edge_height_m,deepest_point_"
    "mm\n";

static void csv_row(FILE *f, const row *r)
{
    char thru[8];
    snprintf(thru, sizeof thru, r->passed < 0 ? "nan" : "%d", r->passed);
    fprintf(f,
            "%s,%s,%d,%.4f,%.4f,%d,%d,%d,%.3f,%.2f,%.6f,%.6f,%.6f,%.4f,%.6f,%.3f,%.3f,%.6g,%s,%s,%d,%s,"
            "%s,%.5f,%.5f,%.4f\n",
            scene_name[r->scene], r->variant, r->N, r->wall_s, r->cpu_s, r->steps, r->failed, r->substepped, r->newton,
            r->cg, r->p99, r->max_strain, r->max_seen, r->depth_mm, r->mean_speed, r->max_ms, r->median_ms,
            r->energy_gain, thru, r->status, r->unconverged, precond_name[g_precond],
            g_fabric < 0 ? "preset" : fabric_name[g_fabric], r->edge_r, r->edge_z, r->point_mm);
    fflush(f);
}

/* Left: the drape's wall time against N with Blender's and the targets;
 * right: p99 strain against N, every scene. Columns as in csv_header. */
static void write_chart(const bench_opts *o, double seconds, double delta)
{
    FILE *gp = bench_open_script(o, "bench_drape");
    if (!gp) return;
    fprintf(gp,
            "set terminal pngcairo size 1300,560 font ',10'\nset output '%s/bench_drape.png'\n"
            "set datafile separator ','\n$blender << EOD\n",
            o->out);
    for (int k = 0; k < 4; k++) fprintf(gp, "%d,%g\n", blender_n[k], blender_s[k]);
    fprintf(gp, "EOD\n$target << EOD\n");
    for (int k = 0; k < 3; k++) fprintf(gp, "%d,%g\n", target_n[k], target_s[k]);
    const char *f = o->out;
    fprintf(gp,
            "EOD\nf = '%s/bench_drape.csv'\n"
            "set multiplot layout 1,2 title 'bench\\_drape: 1 m cotton cloth, %g s simulated at h = 1/60, "
            "library defaults%s'\n"
            "set logscale x\nset grid\nset xrange [15:230]\nset xtics (21, 25, 41, 81, 161)\n"
            "set xlabel 'N (N x N nodes)'\nset key below\n"
            "set logscale y\nset ylabel 'wall s'\nset title 'sphere drape: wall time'\n"
            "plot for [sv in 'linearized newton'] f every ::1 using 3:(strcol(1) eq 'drape' && strcol(2) eq sv "
            "&& strcol(20) ne 'timeout' ? $4 : 1/0) with linespoints pt 7 lw 2 title 'odecloth, '.sv, "
            "f every ::1 using 3:(strcol(1) eq 'drape' && strcol(20) eq 'timeout' ? $4 : 1/0) "
            "with points pt 8 ps 1.6 lc rgb '#c01010' title 'odecloth, timed out (at least)', "
            "$target using 1:2 with linespoints pt 2 ps 1.5 dt 2 lc rgb '#109010' title 'target', "
            "$blender using 1:2 with linespoints pt 4 dt 3 lc rgb '#606060' "
            "title 'Blender 3.4 (quiet machine)'\n"
            "unset logscale y\nset ylabel 'p99 strain, sequential links'\n"
            "set title 'p99 strain at the end (a timed-out run: at its last step)'\n"
            "set yrange [0:*]\n"
            "plot for [sc in 'drape:linearized drape:newton pile:step pile:step-newton hammock:step "
            "hammock:step-newton'] f every ::1 using 3:(strcol(1).':'.strcol(2) eq sc ? $11 : 1/0) "
            "with linespoints pt 7 title sc, "
            "%g with lines dt 2 lc rgb '#109010' title 'target: delta + 0.002'\nunset multiplot\n",
            f, seconds, seconds != 2.0 ? " (references are for 2 s)" : "", delta + 0.002);
    fclose(gp);
    bench_run_gnuplot(o, "bench_drape");
}

/* ------------------------------------------------------------------- check */

/* Prints a miss when !(value <= limit) (NaN misses); 1 if missed. */
static int miss(const row *r, const char *what, double value, double limit)
{
    if (value <= limit) return 0;
    printf("check: %s %s %dx%d: %s %.4g > %.4g\n", scene_name[r->scene], r->variant, r->N, r->N, what, value, limit);
    return 1;
}

/* The quality targets for the row's scene (the pinned scene has
 * none); the number missed. A timed-out row misses: it never got there. */
static int check_row(const row *r)
{
    if (r->scene == PINNED) return 0;
    int n = miss(r, "timed out after steps", strcmp(r->status, "timeout") ? 0 : r->steps, 0);
    n += miss(r, "failed steps", r->failed, 0);
    if (r->scene == DRAPE) {
        n += miss(r, "p99 strain", r->p99, r->delta + 0.002);
        n += miss(r, "max strain", r->max_strain, 2 * r->delta);
        n += miss(r, "depth inside the sphere (mm)", r->depth_mm, 1e3 * DEPTH_TARGET);
        n += miss(r, "mean speed (m/s)", r->mean_speed, 0.02);
    } else if (r->scene == PILE) {
        n += miss(r, "depth inside a geom (mm)", r->depth_mm, 1e3 * r->thickness);
        n += miss(r, "deepest point in a shell (mm)", r->point_mm, 2e3 * r->thickness);
        n += miss(r, "max strain over the run", r->max_seen, 2 * r->delta);
        n += miss(r, "longest step (ms)", r->max_ms, 10 * r->median_ms);
    } else {
        n += miss(r, "energy gain of a step (J)", r->energy_gain, ENERGY_TARGET);
        n += miss(r, "ball through the cloth", r->passed, 0);
    }
    return n;
}

/* ----------------------------------------------------------------- options */

static const char usage[] =
    "usage: bench_drape [--out DIR] [--scene NAME[,NAME...]] [--grid N] [--solver S] [--precond P]\n"
    "                   [--max-wall S] [--self-collision T] [--fabric F] [--fast] [--check] [--steps]\n"
    "The drape benchmark: a 1 m cotton cloth, 2 s at h = 1/60, library defaults, in four scenes:\n"
    "  drape    over a static sphere (r 0.25 m), N = 21, 41, 81, 161\n"
    "  pinned   pinned at two corners, core only (bench_step's scene), N = 21, 41, 81\n"
    "  pile     dropped 0.5 m onto six ODE bodies, dWorldStep and dWorldQuickStep, N = 41, 81\n"
    "  hammock  a 1 kg ball thrown at 5 m/s into it, corners pinned, N = 25, 41, 81\n"
    "--scene    the scenes to run (repeatable or a comma list; default all)\n"
    "--grid N   only that N, for every scene run\n"
    "--solver S  linearized, newton or both (default): how the implicit steps solve their\n"
    "           equations (cloth_solver.nonlinear)\n"
    "--precond P  auto (the default: multigrid for Newton, block Jacobi for the linearized\n"
    "           step), block-jacobi, jacobi, multigrid or ssor: the linear solves'\n"
    "           preconditioner (cloth_solver.precond; the CSV's precond column)\n"
    "--max-wall S  wall-clock budget per run in seconds (default 120; --fast 3): a run\n"
    "           past it stops with status timeout and its figures so far\n"
    "--self-collision T  the self-collision pass (odecloth/selfcollision.h) of thickness T m\n"
    "           after every step, bound to the cloth so Newton steps keep it inside too\n"
    "           (default 0: off); --steps' self_contact_ms is that barrier's time, self_pass_ms\n"
    "           the pass's after the step (both within wall_ms)\n"
    "--fabric F  cotton, wool, silk, denim or polyester: that cloth_fabric preset's springs for\n"
    "           each grid and its own weight, in place of cloth_material_preset(CLOTH_COTTON) at\n"
    "           0.2 kg (the CSV's fabric column; edge_radius_m and edge_height_m, the boundary's\n"
    "           mean distance from the z axis and mean height, show whether grids drape alike)\n"
    "--fast     N <= 41 only, 0.5 s simulated (a smoke test)\n"
    "--check    exit 1 if a drape, pile or hammock row misses the quality targets:\n"
    "           all: finished, no failed step; drape: p99 strain <= delta + 0.002, max strain\n"
    "           <= 2 delta, no vertex over 1e-4 m inside the sphere, mean speed <= 0.02 m/s;\n"
    "           pile: no vertex deeper in a geom than the thickness, no point of the cloth\n"
    "           either (deepest_point_mm: into the shell, the thickness outside), strain over\n"
    "           the run <= 2 delta, no step over 10x the median; hammock: no step gains over\n"
    "           1e-3 J, the ball does not end below the cloth\n"
    "--steps    also write every step's figures to DIR/bench_drape_steps.csv (wall_ms is\n"
    "           the run's time so far, energy the hammock's in J, resolves the plugin's extra\n"
    "           solves, newton_all and cg_all the iterations of all the step's solves, the\n"
    "           rest the core's stats of its last solve)\n"
    "Writes DIR/bench_drape.csv and .png (default DIR out/bench).";

typedef struct options {
    bench_opts b;
    int scenes[NSCENES]; /* 1: run it */
    int any_scene;
    int solvers[2];  /* 1: run with that cloth_nonlinear */
    double max_wall; /* s; 0: the default */
    int steps;       /* 1: --steps */
} options;

/* --scene's value: names separated by commas; 0, or -1 (message printed). */
static int parse_scenes(options *o, const char *v)
{
    const char *p = v;
    for (;;) {
        size_t len = strcspn(p, ",");
        int k = 0;
        while (k < NSCENES && (strlen(scene_name[k]) != len || strncmp(p, scene_name[k], len))) k++;
        if (k == NSCENES) {
            fprintf(stderr, "bench_drape: --scene '%s': scenes are drape, pinned, pile, hammock (comma separated)\n",
                    v);
            return -1;
        }
        o->scenes[k] = o->any_scene = 1;
        if (!p[len]) return 0;
        p += len + 1;
    }
}

enum { OPT_SCENE = BENCH_OWN, OPT_SOLVER, OPT_PRECOND, OPT_SELF_COLLISION, OPT_FABRIC, OPT_STEPS, OPT_MAX_WALL };

static const struct option own_options[] = {
    {"scene", required_argument, NULL, OPT_SCENE},
    {"solver", required_argument, NULL, OPT_SOLVER},
    {"precond", required_argument, NULL, OPT_PRECOND},
    {"self-collision", required_argument, NULL, OPT_SELF_COLLISION},
    {"fabric", required_argument, NULL, OPT_FABRIC},
    {"steps", no_argument, NULL, OPT_STEPS},
    {"max-wall", required_argument, NULL, OPT_MAX_WALL},
    {NULL, 0, NULL, 0},
};

/* This program's own options (bench_take_fn). */
static int take_option(void *ctx, int opt, const char *v)
{
    options *o = ctx;
    char *end;
    switch (opt) {
    case OPT_SCENE: return parse_scenes(o, v) ? 2 : 0;
    case OPT_SOLVER: {
        int k = !strcmp(v, "linearized") ? 0 : !strcmp(v, "newton") ? 1 : !strcmp(v, "both") ? 2 : -1;
        if (k < 0) {
            fprintf(stderr, "bench_drape: --solver '%s' must be linearized, newton or both\n", v);
            return 2;
        }
        o->solvers[0] = k != 1;
        o->solvers[1] = k != 0;
        return 0;
    }
    case OPT_PRECOND: {
        int k = 0;
        while (k < 5 && strcmp(v, precond_name[k])) k++;
        if (k == 5) {
            fprintf(stderr, "bench_drape: --precond '%s' must be auto, block-jacobi, jacobi, multigrid or ssor\n", v);
            return 2;
        }
        g_precond = (cloth_precond)k;
        return 0;
    }
    case OPT_SELF_COLLISION:
        g_self = strtod(v, &end);
        if (end == v || *end || !(g_self >= 0) || !(g_self <= 1)) {
            fprintf(stderr, "bench_drape: --self-collision '%s' must be a thickness in [0, 1] m (0: off)\n", v);
            return 2;
        }
        return 0;
    case OPT_FABRIC:
        g_fabric = 0;
        while (g_fabric < NFABRICS && strcmp(v, fabric_name[g_fabric])) g_fabric++;
        if (g_fabric == NFABRICS) {
            fprintf(stderr, "bench_drape: --fabric '%s' must be cotton, wool, silk, denim or polyester\n", v);
            return 2;
        }
        return 0;
    case OPT_STEPS: o->steps = 1; return 0;
    default: /* OPT_MAX_WALL */
        o->max_wall = strtod(v, &end);
        if (end == v || *end || !(o->max_wall > 0) || !(o->max_wall <= 1e6)) {
            fprintf(stderr, "bench_drape: --max-wall '%s' must be a number of seconds in (0, 1e6]\n", v);
            return 2;
        }
        return 0;
    }
}

/* Fills o from the command line; 0 to go on, -1 after --help, else the exit status. */
static int parse_options(options *o, int argc, char **argv)
{
    int rc = bench_parse(&o->b, own_options, take_option, o, argc, argv);
    if (rc >= 0) return rc ? rc : -1;
    if (!o->any_scene)
        for (int k = 0; k < NSCENES; k++) o->scenes[k] = 1;
    if (!o->solvers[0] && !o->solvers[1]) o->solvers[0] = o->solvers[1] = 1;
    if (!o->max_wall) o->max_wall = o->b.fast ? 3.0 : 120.0;
    return 0;
}

/* ---------------------------------------------------------------- scaling */

/* The drape's cost per step against the vertex count n = N^2, fitted as
 * n^p by least squares on the logs of the finished rows from N = 41 up:
 * what the linear-cost target (p <= 1.15) is judged on. */
typedef struct scaling {
    int m;
    double logn[4], logc[4], it_lo, it_hi;
} scaling;

static void scaling_add(scaling *s, const row *r)
{
    if (r->scene != DRAPE || r->N < 41 || strcmp(r->status, "ok") || r->steps < 1 || s->m >= 4) return;
    s->logn[s->m] = log((double)r->N * r->N);
    s->logc[s->m] = log(r->cpu_s / r->steps);
    s->it_lo = s->m ? fmin(s->it_lo, r->newton) : r->newton;
    s->it_hi = s->m ? fmax(s->it_hi, r->newton) : r->newton;
    s->m++;
}

static void scaling_print(const scaling *s, const char *variant)
{
    if (s->m < 2) return;
    double mx = 0.0, my = 0.0, sxx = 0.0, sxy = 0.0;
    for (int k = 0; k < s->m; k++) mx += s->logn[k] / s->m, my += s->logc[k] / s->m;
    for (int k = 0; k < s->m; k++) {
        sxx += (s->logn[k] - mx) * (s->logn[k] - mx);
        sxy += (s->logn[k] - mx) * (s->logc[k] - my);
    }
    printf("drape %s: CPU per step ~ n^%.2f over %d grids from N = 41 (target <= 1.15); "
           "Newton iterations a step %.2f-%.2f\n",
           variant, sxy / sxx, s->m, s->it_lo, s->it_hi);
}

/* ------------------------------------------------------------------- main */

static void print_load(void)
{
    char line[128] = "unknown";
    FILE *f = fopen("/proc/loadavg", "r");
    if (f) {
        if (!fgets(line, sizeof line, f)) strcpy(line, "unknown");
        fclose(f);
    }
    line[strcspn(line, "\n")] = 0;
    printf("machine load (/proc/loadavg): %s\n", line);
}

/* The grids of a scene: all, those up to 41 with --fast, or --grid. */
static int scene_grids(int kind, const options *o, int *grids)
{
    static const int all[NSCENES][4] = {{21, 41, 81, 161}, {21, 41, 81}, {41, 81}, {25, 41, 81}};
    static const int count[NSCENES] = {4, 3, 2, 3};
    if (o->b.grid) {
        grids[0] = o->b.grid;
        return 1;
    }
    int n = 0;
    for (int k = 0; k < count[kind]; k++)
        if (!o->b.fast || all[kind][k] <= 41) grids[n++] = all[kind][k];
    return n;
}

int main(int argc, char **argv)
{
    options o = {.b = {"bench_drape", usage, "out/bench", 0, 0, 0}};
    int rc = parse_options(&o, argc, argv);
    if (rc) return rc < 0 ? 0 : rc;
    double seconds = o.b.fast ? 0.5 : 2.0, delta = cloth_material_preset(CLOTH_COTTON).delta;
    FILE *csv = bench_open_csv(&o.b, "bench_drape");
    if (!csv) return 1;
    fputs(csv_header, csv);
    if (o.steps && !(g_steps = bench_open_csv(&o.b, "bench_drape_steps"))) return 1;
    if (g_steps)
        fputs("scene,variant,N,step,wall_ms,newton,cg,limit_updates,line_search_cuts,contacts_decided,substeps,"
              "failed,max_strain,energy,resolves,newton_all,cg_all,self_contact_ms,self_pass_ms\n",
              g_steps);
    print_load();
    printf("%g s simulated at h = 1/%g, wall budget %g s per run\n", seconds, HZ, o.max_wall);
    print_header();
    dInitODE2(0);
    int misses = 0;
    for (int kind = 0; kind < NSCENES; kind++) {
        if (!o.scenes[kind]) continue;
        int grids[4], ng = scene_grids(kind, &o, grids);
        for (int sv = 0; sv < 2; sv++) {
            if (!o.solvers[sv]) continue;
            g_solver = (cloth_nonlinear)sv;
            scaling fit = {0};
            for (int g = 0; g < ng; g++)
                for (int quick = 0; quick <= (kind == PILE); quick++) {
                    row r = run_one(kind, quick, grids[g], seconds, o.max_wall);
                    print_row(&r);
                    csv_row(csv, &r);
                    scaling_add(&fit, &r);
                    if (o.b.check) misses += check_row(&r);
                }
            scaling_print(&fit, sv ? "newton" : "linearized");
        }
    }
    dCloseODE();
    fclose(csv);
    if (g_steps) fclose(g_steps);
    write_chart(&o.b, seconds, delta);
    if (o.b.check) printf("check: %s (%d missed)\n", misses ? "FAILED" : "passed", misses);
    return o.b.check && misses ? 1 : 0;
}
