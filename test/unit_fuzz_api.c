/* Unit: random and extreme input to every public core function (seeded, so
 * every run feeds the same inputs). The rule checked (cloth.h): a call
 * returns an error or a valid result, never crashes, never leaves NaN or inf
 * in the state, and leaves its object unchanged when it fails.
 *
 * 1. Descriptors: 2000 descriptors, each the default with 1-4 fields (any
 *    of the 34 of cloth_desc, material and solver included) set to an
 *    extreme: NaN, +-inf, +-0, +-1, 1e-310, +-1e-300, +-1e300, DBL_MAX,
 *    small and huge ints, INT_MIN / INT_MAX, out-of-range enums. Asserted:
 *    cloth_desc_validate and cloth_create agree (a descriptor validate
 *    accepts must create, a refused one gives EINVAL with a message and
 *    *out NULL); every created cloth has finite positive masses, finite
 *    positions and positive finite rest lengths (the grid is representable),
 *    and survives 3 steps (OK or ESTEP) with a finite state, unchanged by a
 *    failed step. The same fields through cloth_material_validate /
 *    cloth_solver_validate and cloth_set_material / cloth_set_solver (a
 *    refused one changes nothing).
 * 2. A random walk of 4000 calls over three small cloths (3x3, 4x6, 7x5):
 *    every setter, getter, constraint, force, state and step function with
 *    random arguments drawn half from sane values and half from extremes
 *    (NULL pointers, out-of-range indices, NaN/inf/huge vectors, bad enums,
 *    bad h, states of another size). After each call: the status is one of
 *    the enum's; the state and constraint count are finite and, if the call
 *    failed, unchanged (cloth_state_diff == 0, same constraint count and
 *    forces); cloth_last_error is non-empty after a failure.
 *    State records of the cloth, written, damaged (a bit, a length) or not,
 *    read and restored (a sound one changes nothing, a damaged one is
 *    refused).
 *    Rigid bodies (cloth_set_bodies with bad masses, inertias, counts,
 *    cloth_hold_by_body, cloth_body_velocity_change) and adaptive frames
 *    (bad descriptors, frame lengths, the wrong cloth) are in the walk.
 * 3. Every function with a NULL cloth returns an error or a neutral value.
 */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

static const double XD[] = {NAN,     -NAN,  INFINITY, -INFINITY, 0.0,      -0.0,  1.0,  -1.0, 1e-310, 1e-300,
                            -1e-300, 1e300, -1e300,   DBL_MAX,   -DBL_MAX, 1e-12, 1e12, 0.5,  2.0,    1e6};
static const int XI[] = {INT_MIN, -1000, -2, -1, 0, 1, 2, 3, 4, 5, 7, 16, 17, 64, 1000, 100000, INT_MAX};
#define NXD (sizeof XD / sizeof XD[0])
#define NXI (sizeof XI / sizeof XI[0])

static double xd(rng *g) { return XD[rng_u64(g) % NXD]; }
static int xi(rng *g) { return XI[rng_u64(g) % NXI]; }
/* half sane (within [lo, hi]), half extreme */
static double dval(rng *g, double lo, double hi) { return rng_u64(g) % 2 ? rng_range(g, lo, hi) : xd(g); }

static int finite_all(const double *a, size_t n)
{
    for (size_t k = 0; k < n; k++)
        if (!isfinite(a[k])) return 0;
    return 1;
}

static int status_ok(cloth_status s)
{
    return s == CLOTH_OK || s == CLOTH_EINVAL || s == CLOTH_ENOMEM || s == CLOTH_ESTEP;
}

/* Set field f (0..NFIELDS-1) of d to an extreme value. Small grids only where the
 * value is accepted, so nothing allocates gigabytes. */
static void perturb(rng *g, cloth_desc *d, int f)
{
    double *dbl[] = {&d->width,
                     &d->height,
                     &d->origin[0],
                     &d->origin[1],
                     &d->origin[2],
                     &d->axis_u[0],
                     &d->axis_u[1],
                     &d->axis_u[2],
                     &d->axis_v[0],
                     &d->axis_v[1],
                     &d->axis_v[2],
                     &d->gravity[0],
                     &d->gravity[1],
                     &d->gravity[2],
                     &d->material.k_t,
                     &d->material.k_c,
                     &d->material.k_b,
                     &d->material.k_s,
                     &d->material.alpha,
                     &d->material.delta,
                     &d->material.k_delta,
                     &d->material.c_t,
                     &d->material.c_b,
                     &d->material.density,
                     &d->solver.cg_tolerance,
                     &d->solver.strain_fail,
                     &d->solver.newton_tolerance,
                     &d->solver.newton_rtol,
                     &d->solver.limit_tolerance,
                     &d->solver.newton_cg_tolerance,
                     &d->solver.newton_cg_share,
                     &d->material.tau_set,
                     &d->material.tau_recover,
                     &d->material.set_hardening,
                     &d->material.tension_yield,
                     &d->material.tension_set};
    int nd = (int)(sizeof dbl / sizeof dbl[0]);
    if (f < nd) {
        *dbl[f] = xd(g);
        return;
    }
    int v = xi(g);
    switch (f - nd) {
    /* a valid 100000 x 3 grid would ask multigrid for terabytes:
     * only sizes that must be refused (INT_MAX) stay large */
    case 0: d->rows = v > 64 && v < INT_MAX ? 64 : v; break;
    case 1: d->cols = v > 64 && v < INT_MAX ? 64 : v; break;
    case 2: d->solver.method = (cloth_method)v; break;
    case 3: d->solver.precond = (cloth_precond)v; break;
    case 4: d->solver.cg_max_iterations = v > 2000 ? 2000 : v; break;
    case 5: d->solver.strain_limit_iterations = v > 50 ? 50 : v; break;
    case 6: d->solver.max_substep_halvings = v > 4 && v <= 16 ? 3 : v; break;
    case 7: d->solver.nonlinear = (cloth_nonlinear)v; break;
    case 8: d->solver.newton_iterations = v > 32 && v <= 256 ? 32 : v; break;
    case 9: d->solver.keep_unconverged = v; break;
    default: d->solver.definiteness_rule = v; break;
    }
}
#define NFIELDS 47 /* the 36 doubles above, then the switch's 11 cases (the last its default) */

/* The created cloth is sound: masses, positions, rest lengths. */
static void check_model(const cloth *c, const char *what)
{
    int n = cloth_vertex_count(c);
    const double *m = cloth_masses(c);
    int bad_m = 0;
    for (int i = 0; i < n; i++) bad_m += !(m[i] > 0.0 && isfinite(m[i]));
    CHECK(bad_m == 0, "%s: %d masses not finite and > 0", what, bad_m);
    CHECK(finite_all(cloth_positions(c), 3 * (size_t)n), "%s: positions not finite", what);
    for (int t = 0; t < 2; t++) {
        int bad_l = 0;
        for (int e = 0; e < cloth_link_count(c, (cloth_link_type)t); e++) {
            cloth_link l;
            cloth_get_link(c, (cloth_link_type)t, e, &l);
            bad_l += !(l.rest > 0.0 && isfinite(l.rest));
        }
        CHECK(bad_l == 0, "%s: %d rest lengths of type %d not finite and > 0", what, bad_l, t);
    }
}

/* Step and check: OK with a finite state, or a failure with it unchanged. */
static void step_checked(cloth *c, cloth_state *before, cloth_state *after, double h, const char *what)
{
    cloth_save(c, before);
    cloth_step_stats st;
    cloth_status s = cloth_step(c, h, &st);
    size_t n3 = 3 * (size_t)cloth_vertex_count(c);
    CHECK(status_ok(s), "%s: step returned %d", what, (int)s);
    CHECK(finite_all(cloth_positions(c), n3) && finite_all(cloth_velocities(c), n3), "%s: step (%s) left NaN/inf", what,
          cloth_status_string(s));
    if (s != CLOTH_OK) {
        cloth_save(c, after);
        CHECK(cloth_state_diff(before, after) == 0.0,
              "%s: failed step (%s, halvings %d, first %s) changed the state by %g", what,
              cloth_failure_string(st.failure), st.halvings, cloth_failure_string(st.first_failure),
              cloth_state_diff(before, after));
        CHECK(st.failure != CLOTH_FAIL_NONE, "%s: failed step with failure NONE", what);
    }
}

static long n_valid, n_refused, n_step_ok, n_step_fail;

static void descriptors(void)
{
    rng g = rng_seed(0xde5c0001u);
    for (int k = 0; k < 2000; k++) {
        cloth_desc d = cloth_default_desc();
        d.rows = 3 + (int)(rng_u64(&g) % 4);
        d.cols = 3 + (int)(rng_u64(&g) % 4);
        int nf = 1 + (int)(rng_u64(&g) % 4);
        for (int q = 0; q < nf; q++) perturb(&g, &d, (int)(rng_u64(&g) % NFIELDS));
        char what[64];
        snprintf(what, sizeof what, "descriptor %d", k);
        cloth_error e1, e2;
        memset(&e1, 0, sizeof e1);
        memset(&e2, 0, sizeof e2);
        cloth_status v = cloth_desc_validate(&d, &e1);
        cloth *c = (cloth *)&e2;
        cloth_status s = cloth_create(&d, &c, &e2);
        CHECK(s == v || (v == CLOTH_OK && s == CLOTH_ENOMEM), "%s: validate says %s, create %s (%s)", what,
              cloth_status_string(v), cloth_status_string(s), e2.message);
        /* the material and solver parts alone */
        cloth_status mv = cloth_material_validate(&d.material, NULL), sv = cloth_solver_validate(&d.solver, NULL);
        CHECK(v != CLOTH_OK || (mv == CLOTH_OK && sv == CLOTH_OK), "%s: desc valid, material %d solver %d", what,
              (int)mv, (int)sv);
        if (s != CLOTH_OK) {
            n_refused++;
            CHECK(c == NULL, "%s: refused, *out not NULL", what);
            CHECK(e2.message[0] != '\0' && e2.code == s, "%s: refused without a message", what);
            continue;
        }
        n_valid++;
        check_model(c, what);
        cloth_state *b = cloth_state_create(c), *a = cloth_state_create(c);
        cloth_pin(c, 0, cloth_positions(c));
        for (int q = 0; q < 3; q++) step_checked(c, b, a, 1.0 / 60, what);
        n_step_ok += cloth_last_stats(c)->failure == CLOTH_FAIL_NONE;
        n_step_fail += cloth_last_stats(c)->failure != CLOTH_FAIL_NONE;
        /* set_material / set_solver of a perturbed default: refused changes nothing */
        cloth_desc e = cloth_get_desc(c);
        perturb(&g, &e, (int)(rng_u64(&g) % NFIELDS));
        cloth_desc before = cloth_get_desc(c);
        cloth_status r1 = cloth_set_material(c, &e.material);
        cloth_status r2 = cloth_set_solver(c, &e.solver);
        cloth_desc after = cloth_get_desc(c);
        CHECK(r1 == cloth_material_validate(&e.material, NULL), "%s: set_material disagrees with validate", what);
        if (r1 != CLOTH_OK)
            CHECK(memcmp(&before.material, &after.material, sizeof before.material) == 0, "%s: refused material kept",
                  what);
        if (r2 != CLOTH_OK)
            CHECK(memcmp(&before.solver, &after.solver, sizeof before.solver) == 0, "%s: refused solver kept", what);
        if (r1 == CLOTH_OK || r2 == CLOTH_OK) step_checked(c, b, a, 1.0 / 60, what);
        cloth_state_destroy(a);
        cloth_state_destroy(b);
        cloth_destroy(c);
    }
    printf("descriptors: %ld created (last step ok %ld, failed %ld), %ld refused\n", n_valid, n_step_ok, n_step_fail,
           n_refused);
}

/* ------------------------------------------------------------ random walk */

typedef struct world {
    cloth *c[3];
    cloth_state *s[3]; /* a state of each cloth, for restore / diff */
    cloth_state *before, *after;
    double *buf; /* 3 * largest n doubles */
} world;

/* base + noise of size amp (base NULL: 0), sometimes with extremes, or NULL */
static double *vec(rng *g, world *w, int n, const double *base, double amp, int *is_null)
{
    int kind = (int)(rng_u64(g) % 8);
    *is_null = kind == 0;
    if (kind == 0) return NULL;
    for (int k = 0; k < 3 * n; k++) w->buf[k] = (base ? base[k] : 0.0) + rng_range(g, -amp, amp);
    if (kind >= 5) { /* a few extremes */
        int m = 1 + (int)(rng_u64(g) % 3);
        for (int q = 0; q < m; q++) w->buf[rng_u64(g) % (uint64_t)(3 * n)] = xd(g);
    }
    return w->buf;
}

static int index_of(rng *g, int n) { return rng_u64(g) % 2 ? (int)(rng_u64(g) % (uint64_t)n) : xi(g); }

static long calls[32], fails[32], fail_why[8];

/* One call of the walk: the cloth it is made on and what the checks after it compare with. */
typedef struct call {
    rng *g;
    world *w;
    cloth *c;
    int ci, n;
    int ncon0;         /* the constraint count before the call */
    double f0[3 * 35]; /* the constraint forces before the call */
    cloth_desc d0;
    cloth_air air0;
    cloth_error rerr; /* cloth_state_read's message: it has no cloth to keep one */
    int mutates;      /* 0: the call must change nothing even when it succeeds */
} call;

/* Positions, velocities, one vertex, material, solver, gravity, forces, air. */
static cloth_status call_setter(call *cl, int op)
{
    rng *g = cl->g;
    cloth *c = cl->c;
    int n = cl->n, isnull = 0;
    cloth_status s = CLOTH_OK;
    double v3[3], *p;
    switch (op) {
    case 0:
        p = vec(g, cl->w, n, cloth_positions(c), 0.005, &isnull);
        s = cloth_set_positions(c, p);
        break;
    case 1:
        p = vec(g, cl->w, n, NULL, 2.0, &isnull);
        switch (rng_u64(g) % 3) {
        case 0: s = cloth_set_velocities(c, p); break;
        case 1: s = cloth_add_velocities(c, p); break;
        default: s = cloth_set_warm_start(c, p);
        }
        break;
    case 2: {
        const double *x = cloth_positions(c);
        int vi = index_of(g, n), vv = vi >= 0 && vi < n ? vi : 0;
        for (int r = 0; r < 3; r++) v3[r] = x[3 * vv + r] + dval(g, -0.005, 0.005);
        double u3[3] = {dval(g, -1, 1), dval(g, -1, 1), dval(g, -1, 1)};
        int mode = (int)(rng_u64(g) % 4);
        s = cloth_set_vertex(c, vi, mode & 1 ? v3 : NULL, mode & 2 ? u3 : NULL);
        break;
    }
    case 3: {
        cloth_material m = cl->d0.material;
        perturb(g, &(cloth_desc){.material = m}, 0); /* exercise perturb on a copy */
        cloth_desc e = cl->d0;
        perturb(g, &e, 14 + (int)(rng_u64(g) % 10));
        s = cloth_set_material(c, rng_u64(g) % 10 ? &e.material : NULL);
        break;
    }
    case 4: {
        cloth_desc e = cl->d0;
        if (rng_u64(g) % 2) e.solver.nonlinear = CLOTH_NEWTON; /* both steps, then one field off */
        perturb(g, &e, rng_u64(g) % 2 ? 24 + (int)(rng_u64(g) % 4) : 30 + (int)(rng_u64(g) % 8));
        if (e.solver.cg_max_iterations > 300) e.solver.cg_max_iterations = 300;
        s = cloth_set_solver(c, rng_u64(g) % 10 ? &e.solver : NULL);
        break;
    }
    case 5:
        for (int r = 0; r < 3; r++) v3[r] = dval(g, -20, 20);
        s = cloth_set_gravity(c, rng_u64(g) % 10 ? v3 : NULL);
        break;
    case 6: {
        p = vec(g, cl->w, n, NULL, 2e-3, &isnull);
        s = cloth_set_external_forces(c, p);
        break;
    }
    default: { /* air drag and wind, sometimes bad */
        cloth_air a = cl->air0;
        for (int r = 0; r < 3; r++) a.wind[r] = dval(g, -20, 20);
        a.drag_normal = dval(g, 0, 2);
        a.drag_tangent = dval(g, 0, 2);
        s = cloth_set_air(c, rng_u64(g) % 10 ? &a : NULL);
        break;
    }
    }
    return s;
}

/* Set, pin, release, read constraints and their forces; contact candidates. */
static cloth_status call_constraint(call *cl, int op)
{
    rng *g = cl->g;
    cloth *c = cl->c;
    int n = cl->n;
    cloth_status s = CLOTH_OK;
    double v3[3];
    switch (op) {
    case 7: {
        cloth_constraint k = {.vertex = index_of(g, n), .ndof = rng_u64(g) % 4 ? (int)(rng_u64(g) % 4) : xi(g)};
        const double *x = cloth_positions(c);
        int vv = k.vertex >= 0 && k.vertex < n ? k.vertex : 0;
        for (int r = 0; r < 3; r++) {
            k.axis[r] = dval(g, -1, 1);
            k.target[r] = rng_u64(g) % 4 ? x[3 * vv + r] + rng_range(g, -0.01, 0.01) : xd(g);
        }
        s = cloth_set_constraint(c, rng_u64(g) % 12 ? &k : NULL);
        break;
    }
    case 8: {
        const double *x = cloth_positions(c);
        int vi = index_of(g, n);
        int vv = vi >= 0 && vi < n ? vi : 0;
        for (int r = 0; r < 3; r++) v3[r] = rng_u64(g) % 4 ? x[3 * vv + r] : xd(g);
        s = cloth_pin(c, vi, rng_u64(g) % 12 ? v3 : NULL);
        break;
    }
    case 9: s = cloth_release(c, index_of(g, n)); break;
    case 10: cloth_release_all(c); break;
    case 11: {
        cloth_constraint k;
        int two = 0;
        double fa[3], fb[3];
        if (rng_u64(g) % 3) {
            s = cloth_get_constraint(c, index_of(g, n), rng_u64(g) % 8 ? &k : NULL);
        } else { /* the planes' forces add up to the constraint's */
            int vi = index_of(g, n);
            s = cloth_get_contact_planes(c, vi, &k, &two, fa, fb);
            if (s == CLOTH_OK) {
                cloth_constraint_force(c, vi, v3);
                for (int r = 0; r < 3; r++)
                    CHECK(fabs(fa[r] + fb[r] - v3[r]) <= 1e-9 * (1.0 + fabs(v3[r])), "planes' forces sum off");
            }
        }
        cl->mutates = 0;
        break;
    }
    case 12:
        if (rng_u64(g) % 4) s = cloth_constraint_force(c, index_of(g, n), rng_u64(g) % 8 ? v3 : NULL);
        else if (rng_u64(g) % 2) s = cloth_air_force(c, rng_u64(g) % 8 ? v3 : NULL);
        else s = cloth_air_torque(c, rng_u64(g) % 8 ? v3 : NULL);
        cl->mutates = 0;
        break;
    default: { /* a contact candidate, sometimes bad */
        const double *x = cloth_positions(c);
        int vi = index_of(g, n), vv = vi >= 0 && vi < n ? vi : 0;
        double nrm[3], pt[3];
        for (int r = 0; r < 3; r++) {
            nrm[r] = dval(g, -1, 1);
            pt[r] = rng_u64(g) % 4 ? x[3 * vv + r] - rng_range(g, -0.01, 0.01) : xd(g);
        }
        const double *pn = rng_u64(g) % 12 ? nrm : NULL, *pp = rng_u64(g) % 12 ? pt : NULL;
        s = rng_u64(g) % 3 ? cloth_set_contact(c, vi, pn, pp) : cloth_set_contact_second(c, vi, pn, pp);
        cl->mutates = 0; /* a candidate changes nothing until a step */
        break;
    }
    }
    return s;
}

/* Links, plastic update, energies, internal forces, save / restore / diff of states. */
static cloth_status call_query(call *cl, int op)
{
    rng *g = cl->g;
    cloth *c = cl->c;
    int ci = cl->ci;
    cloth_status s = CLOTH_OK;
    switch (op) {
    case 13: {
        cloth_link l;
        int t = rng_u64(g) % 4 ? (int)(rng_u64(g) % 2) : xi(g);
        s = cloth_get_link(c, (cloth_link_type)t, index_of(g, cloth_link_count(c, (cloth_link_type)t) + 1),
                           rng_u64(g) % 8 ? &l : NULL);
        cl->mutates = 0;
        break;
    }
    case 14: cloth_update_plastic(c); break;
    case 15: {
        cloth_energy e = cloth_energies(c);
        (void)e;
        double ms = cloth_max_strain(c);
        CHECK(ms == ms, "max_strain NaN");
        cl->mutates = 0;
        break;
    }
    case 16:
        s = cloth_internal_forces(c, rng_u64(g) % 8 ? cl->w->buf : NULL);
        cl->mutates = 0;
        break;
    case 17: { /* save / restore, maybe across sizes */
        int cj = rng_u64(g) % 4 ? ci : (int)(rng_u64(g) % 3);
        s = cloth_save(c, rng_u64(g) % 10 ? cl->w->s[cj] : NULL);
        cl->mutates = 0;
        break;
    }
    case 18: {
        int cj = rng_u64(g) % 4 ? ci : (int)(rng_u64(g) % 3);
        s = cloth_restore(c, rng_u64(g) % 10 ? cl->w->s[cj] : NULL);
        break;
    }
    default: {
        int cj = (int)(rng_u64(g) % 3);
        double dd = cloth_state_diff(cl->w->s[ci], rng_u64(g) % 10 ? cl->w->s[cj] : NULL);
        CHECK(dd == dd, "state_diff NaN");
        cl->mutates = 0;
        break;
    }
    }
    return s;
}

/* Rigid bodies solved with the cloth: set them, hold a vertex by one, read a velocity change. */
static cloth_status call_body(call *cl, int op)
{
    rng *g = cl->g;
    cloth *c = cl->c;
    cloth_status s;
    if (op == 24) {
        cloth_body bd[3];
        int cnt = rng_u64(g) % 4 ? (int)(rng_u64(g) % 4) : xi(g);
        for (int q = 0; q < 3; q++) {
            memset(&bd[q], 0, sizeof bd[q]);
            bd[q].mass = dval(g, 0.05, 2.0);
            for (int r = 0; r < 3; r++) {
                bd[q].inertia[4 * r] = dval(g, 1e-3, 0.1);
                bd[q].com[r] = dval(g, -1, 1);
                bd[q].force[r] = dval(g, -1, 1);
                bd[q].torque[r] = dval(g, -0.1, 0.1);
            }
            if (rng_u64(g) % 8 == 0) bd[q].inertia[1] = xd(g); /* not symmetric */
        }
        s = cloth_set_bodies(c, rng_u64(g) % 10 ? bd : NULL, cnt > 3 ? 3 : cnt);
        cl->mutates = 0; /* the state and the constraints stay */
    } else if (op == 25) {
        s = cloth_hold_by_body(c, index_of(g, cl->n), rng_u64(g) % 2 ? (int)(rng_u64(g) % 4) - 1 : xi(g));
    } else {
        double dv6[6];
        s = cloth_body_velocity_change(c, rng_u64(g) % 3 ? (int)(rng_u64(g) % 3) : xi(g), rng_u64(g) % 8 ? dv6 : NULL);
        if (s == CLOTH_OK) CHECK(finite_all(dv6, 6), "body velocity change not finite");
        cl->mutates = 0;
    }
    return s;
}

/* One adaptive frame, sometimes with bad settings or the wrong cloth. */
static cloth_status call_adaptive_frame(call *cl)
{
    rng *g = cl->g;
    cloth *c = cl->c;
    cloth_adaptive_desc ad = cloth_adaptive_default_desc();
    ad.max_substeps = 8;
    switch (rng_u64(g) % 6) {
    case 0: ad.tolerance = xd(g); break;
    case 1: ad.min_substeps = xi(g); break;
    case 2: ad.cg_tolerance_min = xd(g); break;
    default: break;
    }
    cloth_adaptive *A = NULL;
    cloth *other = cl->w->c[(cl->ci + 1) % 3];
    cloth_status r0 = cloth_adaptive_create(rng_u64(g) % 10 ? c : NULL, rng_u64(g) % 10 ? &ad : NULL, &A, NULL);
    CHECK(status_ok(r0) && (r0 == CLOTH_OK) == (A != NULL), "adaptive_create: %d", (int)r0);
    double dt = rng_u64(g) % 5 ? rng_range(g, 1e-3, 0.03) : xd(g);
    if (dt > 0.1 && isfinite(dt)) dt = 0.1;
    cloth_adaptive_stats ast;
    cloth_status s = A ? cloth_adaptive_frame(A, rng_u64(g) % 8 ? c : other, dt, rng_u64(g) % 4 ? &ast : NULL)
                       : cloth_adaptive_frame(NULL, c, dt, NULL);
    cloth_adaptive_destroy(A);
    return s;
}

/* A state record: written, maybe damaged, read into a state, restored. */
static cloth_status call_state_record(call *cl)
{
    rng *g = cl->g;
    cloth *c = cl->c;
    cloth_state *ws = cloth_state_create(c);
    size_t len = cloth_state_size_bytes(ws);
    unsigned char *rec = malloc(len + 8);
    cloth_save(c, ws);
    size_t wr = 0;
    CHECK(cloth_state_write(ws, rec, len + 8, &wr, NULL) == CLOTH_OK && wr == len, "state_write");
    int dmg = (int)(rng_u64(g) % 3);
    if (dmg == 1) rec[rng_u64(g) % len] ^= (unsigned char)(1u << (rng_u64(g) % 8));
    size_t rl = dmg == 2 ? (size_t)(rng_u64(g) % (len + 8)) : len;
    cloth_status s = cloth_state_read(cl->w->s[cl->ci], rec, rl, &cl->rerr);
    if (s == CLOTH_OK) s = cloth_restore(c, cl->w->s[cl->ci]);
    cl->mutates = 0; /* a record of c's own state: restoring it changes nothing */
    free(rec);
    cloth_state_destroy(ws);
    return s;
}

/* A step of a random, sometimes bad, h. */
static cloth_status call_step(call *cl)
{
    rng *g = cl->g;
    double h = rng_u64(g) % 6 ? rng_range(g, 1e-4, 0.05) : xd(g);
    if (h > 1.0 && isfinite(h)) h = 1.0; /* a huge finite h is fine but slow to fail */
    cloth_step_stats st;
    cloth_status s = cloth_step(cl->c, h, rng_u64(g) % 8 ? &st : NULL);
    fail_why[cloth_last_stats(cl->c)->failure]++;
    return s;
}

/* Operation op (0..30) of the walk; ops 20..23 step, so steps come more often. */
static cloth_status call_op(call *cl, int op)
{
    if (op <= 6 || op == 30) return call_setter(cl, op);
    if (op <= 12 || op == 29) return call_constraint(cl, op);
    if (op <= 19) return call_query(cl, op);
    if (op >= 24 && op <= 26) return call_body(cl, op);
    if (op == 27) return call_adaptive_frame(cl);
    if (op == 28) return call_state_record(cl);
    return call_step(cl);
}

/* Back to sane settings, and to a new cloth's rest state if strained, so that steps also succeed. */
static void reset_sane(cloth *c)
{
    cloth_desc d = cloth_get_desc(c), e = cloth_default_desc();
    e.solver.cg_max_iterations = 300;
    e.solver.max_substep_halvings = 2;
    cloth_set_material(c, &e.material);
    cloth_set_solver(c, &e.solver);
    cloth_set_gravity(c, e.gravity);
    cloth_set_external_forces(c, NULL);
    cloth_set_air(c, &(cloth_air){{0.0, 0.0, 0.0}, 0.0, 0.0});
    if (!(cloth_max_strain(c) < 0.1)) { /* a new cloth's rest state */
        cloth *fresh = NULL;
        d = cloth_get_desc(c);
        d.material = e.material;
        d.solver = e.solver;
        cloth_create(&d, &fresh, NULL);
        cloth_set_positions(c, cloth_positions(fresh));
        cloth_set_velocities(c, cloth_velocities(fresh));
        cloth_destroy(fresh);
    }
}

/* With FUZZ_DEBUG: the cloth whose constraint forces f1 are not finite. */
static void print_constraints(const cloth *c, const double *f1, int n)
{
    cloth_desc dd = cloth_get_desc(c);
    printf("  bodies %d, constraints %d, gravity %g %g %g, k_t %g density %g, stats failure %d it %d\n",
           cloth_body_count(c), cloth_constraint_count(c), dd.gravity[0], dd.gravity[1], dd.gravity[2], dd.material.k_t,
           dd.material.density, cloth_last_stats(c)->failure, cloth_last_stats(c)->iterations);
    for (int i = 0; i < n; i++) {
        cloth_constraint kk;
        cloth_get_constraint(c, i, &kk);
        if (!finite_all(f1 + 3 * i, 3) || kk.ndof)
            printf("  vertex %d ndof %d f %g %g %g target %g %g %g axis %g %g %g x %g %g %g\n", i, kk.ndof, f1[3 * i],
                   f1[3 * i + 1], f1[3 * i + 2], kk.target[0], kk.target[1], kk.target[2], kk.axis[0], kk.axis[1],
                   kk.axis[2], cloth_positions(c)[3 * i], cloth_positions(c)[3 * i + 1], cloth_positions(c)[3 * i + 2]);
    }
}

/* The checks after call it (op, status s): a known status, a finite state, and
 * nothing changed by a failed or read-only call, which leaves a message. */
static void check_call(call *cl, int it, int op, cloth_status s)
{
    cloth *c = cl->c;
    int n = cl->n;
    size_t n3 = 3 * (size_t)n;
    double f1[3 * 35];
    CHECK(status_ok(s), "call %d (op %d): status %d", it, op, (int)s);
    CHECK(finite_all(cloth_positions(c), n3) && finite_all(cloth_velocities(c), n3),
          "call %d (op %d, %s): NaN/inf in the state", it, op, cloth_status_string(s));
    cloth_save(c, cl->w->after);
    for (int i = 0; i < n; i++) cloth_constraint_force(c, i, f1 + 3 * i);
    if (!CHECK(finite_all(f1, n3), "call %d (op %d): constraint forces not finite", it, op) && getenv("FUZZ_DEBUG"))
        print_constraints(c, f1, n);
    if (s != CLOTH_OK || !cl->mutates) {
        if (s != CLOTH_OK) fails[op]++;
        CHECK(cloth_state_diff(cl->w->before, cl->w->after) == 0.0, "call %d (op %d, %s): state changed", it, op,
              cloth_status_string(s));
        CHECK(cloth_constraint_count(c) == cl->ncon0 && memcmp(cl->f0, f1, n3 * sizeof *cl->f0) == 0,
              "call %d (op %d): constraints changed by a failed or read-only call", it, op);
        cloth_desc d1 = cloth_get_desc(c);
        CHECK(memcmp(&cl->d0, &d1, sizeof cl->d0) == 0, "call %d (op %d): descriptor changed", it, op);
        cloth_air air1 = cloth_get_air(c);
        CHECK(memcmp(&cl->air0, &air1, sizeof cl->air0) == 0, "call %d (op %d): air settings changed", it, op);
    }
    if (s != CLOTH_OK)
        CHECK(cloth_last_error(c)[0] != '\0' || cl->rerr.message[0] != '\0',
              "call %d (op %d): failure without a message", it, op);
}

/* Call it of the walk: a random operation on a random cloth, checked. */
static void walk_call(rng *g, world *w, int it)
{
    call cl = {.g = g, .w = w};
    cl.ci = (int)(rng_u64(g) % 3);
    cloth *c = cl.c = w->c[cl.ci];
    if (it % 40 == 39) reset_sane(c);
    int n = cl.n = cloth_vertex_count(c);
    w->before = cloth_state_create(c);
    w->after = cloth_state_create(c);
    cloth_save(c, w->before);
    cl.ncon0 = cloth_constraint_count(c);
    for (int i = 0; i < n; i++) cloth_constraint_force(c, i, cl.f0 + 3 * i);
    cl.d0 = cloth_get_desc(c);
    cl.air0 = cloth_get_air(c);
    cl.rerr = (cloth_error){CLOTH_OK, ""};
    cl.mutates = 1;
    int op = (int)(rng_u64(g) % 31);
    cloth_status s = call_op(&cl, op);
    calls[op]++;
    if (getenv("FUZZ_DEBUG"))
        printf("call %d cloth %d op %d: %s %s\n", it, cl.ci, op, cloth_status_string(s), s ? cloth_last_error(c) : "");
    check_call(&cl, it, op, s);
    cloth_state_destroy(w->before);
    cloth_state_destroy(w->after);
}

/* The walk's counts of calls, failures and step outcomes; enough steps succeeded. */
static void walk_summary(void)
{
    long tot = 0, tf = 0;
    for (int k = 0; k < 32; k++) {
        tot += calls[k];
        tf += fails[k];
    }
    long sf = 0, sc = 0;
    for (int k = 20; k < 24; k++) {
        sf += fails[k];
        sc += calls[k];
    }
    printf("random walk: %ld calls, %ld refused or failed (steps: %ld of %ld; bodies: %ld of %ld set; adaptive "
           "frames: %ld of %ld)\n",
           tot, tf, sf, sc, fails[24], calls[24], fails[27], calls[27]);
    printf("step outcomes:");
    for (int k = 0; k <= CLOTH_FAIL_NEWTON; k++)
        printf(" %s %ld;", cloth_failure_string((cloth_failure)k), fail_why[k]);
    printf("\n");
    CHECK(fail_why[CLOTH_FAIL_NONE] > 100, "only %ld steps succeeded: the walk tests failures only",
          fail_why[CLOTH_FAIL_NONE]);
}

static void walk(void)
{
    world w;
    const int dims[3][2] = {{3, 3}, {4, 6}, {7, 5}};
    int nmax = 35;
    w.buf = malloc(3 * (size_t)nmax * sizeof *w.buf);
    for (int k = 0; k < 3; k++) {
        cloth_desc d = cloth_default_desc();
        d.rows = dims[k][0];
        d.cols = dims[k][1];
        d.solver.cg_max_iterations = 300;
        d.solver.max_substep_halvings = 2;
        cloth_create(&d, &w.c[k], NULL);
        w.s[k] = cloth_state_create(w.c[k]);
    }
    rng g = rng_seed(0x0a11ca11u);
    for (int it = 0; it < 4000; it++) walk_call(&g, &w, it);
    walk_summary();
    for (int k = 0; k < 3; k++) {
        cloth_state_destroy(w.s[k]);
        cloth_destroy(w.c[k]);
    }
    free(w.buf);
}

static void null_cloth(void)
{
    double v[3] = {0, 0, 0};
    cloth_constraint k = {0};
    cloth_link l;
    CHECK(cloth_last_error(NULL)[0] != '\0', "last_error(NULL)");
    CHECK(cloth_rows(NULL) == 0 && cloth_cols(NULL) == 0 && cloth_vertex_count(NULL) == 0, "sizes of NULL");
    CHECK(!cloth_positions(NULL) && !cloth_velocities(NULL) && !cloth_masses(NULL), "arrays of NULL");
    CHECK(cloth_set_positions(NULL, v) == CLOTH_EINVAL && cloth_set_velocities(NULL, v) == CLOTH_EINVAL, "set x/v");
    CHECK(cloth_add_velocities(NULL, v) == CLOTH_EINVAL && cloth_set_warm_start(NULL, v) == CLOTH_EINVAL,
          "add v, warm start");
    CHECK(cloth_set_vertex(NULL, 0, v, v) == CLOTH_EINVAL, "set_vertex");
    cloth_desc d = cloth_default_desc();
    CHECK(cloth_set_material(NULL, &d.material) == CLOTH_EINVAL && cloth_set_solver(NULL, &d.solver) == CLOTH_EINVAL,
          "set material/solver");
    CHECK(cloth_set_gravity(NULL, v) == CLOTH_EINVAL && cloth_set_external_forces(NULL, NULL) == CLOTH_EINVAL,
          "gravity/forces");
    cloth_air air = cloth_get_air(NULL);
    CHECK(cloth_set_air(NULL, &air) == CLOTH_EINVAL && air.drag_normal == 0.0 && air.drag_tangent == 0.0, "air");
    CHECK(cloth_air_force(NULL, v) == CLOTH_EINVAL, "air_force");
    CHECK(cloth_air_torque(NULL, v) == CLOTH_EINVAL, "air_torque");
    CHECK(cloth_link_count(NULL, CLOTH_SEQUENTIAL) == 0 && cloth_get_link(NULL, CLOTH_SEQUENTIAL, 0, &l) != CLOTH_OK,
          "links");
    CHECK(cloth_update_plastic(NULL) == 0, "update_plastic");
    cloth_energy e = cloth_energies(NULL);
    CHECK(e.kinetic == 0 && e.elastic == 0 && e.gravitational == 0, "energies of NULL");
    CHECK(cloth_internal_forces(NULL, v) == CLOTH_EINVAL, "internal_forces");
    CHECK(cloth_max_strain(NULL) == 0.0, "max_strain of NULL: %g", cloth_max_strain(NULL));
    CHECK(cloth_set_constraint(NULL, &k) == CLOTH_EINVAL && cloth_pin(NULL, 0, v) == CLOTH_EINVAL &&
              cloth_release(NULL, 0) == CLOTH_EINVAL && cloth_get_constraint(NULL, 0, &k) == CLOTH_EINVAL &&
              cloth_constraint_force(NULL, 0, v) == CLOTH_EINVAL && cloth_constraint_count(NULL) == 0,
          "constraints");
    cloth_release_all(NULL);
    CHECK(cloth_step(NULL, 0.01, NULL) == CLOTH_EINVAL && cloth_last_stats(NULL) == NULL, "step");
    CHECK(cloth_state_create(NULL) == NULL, "state_create");
    cloth_state_destroy(NULL);
    CHECK(cloth_save(NULL, NULL) == CLOTH_EINVAL && cloth_restore(NULL, NULL) == CLOTH_EINVAL, "save/restore");
    CHECK(cloth_state_diff(NULL, NULL) < 0, "state_diff");
    CHECK(cloth_create(NULL, NULL, NULL) == CLOTH_EINVAL, "create(NULL, NULL, NULL)");
    cloth *c = (cloth *)&k;
    CHECK(cloth_create(NULL, &c, NULL) == CLOTH_EINVAL && c == NULL, "create(NULL desc)");
    CHECK(cloth_desc_validate(NULL, NULL) == CLOTH_EINVAL && cloth_material_validate(NULL, NULL) == CLOTH_EINVAL &&
              cloth_solver_validate(NULL, NULL) == CLOTH_EINVAL,
          "validate NULL");
    cloth_destroy(NULL);
    CHECK(cloth_status_string((cloth_status)99)[0] && cloth_failure_string((cloth_failure)-5)[0], "strings");
    cloth_material m = cloth_material_preset((cloth_preset)1234);
    CHECK(cloth_material_validate(&m, NULL) == CLOTH_OK, "an unknown preset gives a valid material");
    CHECK(cloth_version()[0] != '\0', "version");
}

int main(void)
{
    null_cloth();
    descriptors();
    walk();
    return check_summary();
}
