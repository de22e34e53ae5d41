/* Unit: the core is deterministic and its state is all there is.
 *
 * Scene (per method x preconditioner: backward Euler and BDF2 with each of
 * the 4 preconditioners, symplectic Euler at a stable h): a 9 x 8 cloth,
 * randomly perturbed (seeded), two corners pinned, one of them moving on a
 * circle, a plane constraint on a third corner, per-vertex external forces,
 * plastic links (alpha 0.95), substep retries on (3), 40 steps of 1/120 s.
 *
 * 1. Two runs of the scene in two cloths give bitwise the same positions,
 *    velocities and constraint forces.
 * 2. Save after 15 steps, then do other things to the same cloth (another
 *    h, another solver and material, released constraints, 10 steps with
 *    heavy gravity: every workspace and warm start scribbled over), restore,
 *    put the scene's settings and constraints back, finish: bitwise the
 *    uninterrupted run (nothing that matters lives outside cloth_state).
 * 3. The same through a state file record into a brand-new cloth.
 * Backward Euler and BDF2 again with Newton's step (CLOTH_NEWTON; a step
 * left unconverged kept after one halving; the circle within the row's
 * limit and forces of 3 N that pull links past it), whose warm start and
 * elongation-limit multipliers carry from step to step: some multipliers
 * are non-zero in the record, and the other work (linearised: all its steps
 * taken) leaves them changed.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define STEPS 40
#define SAVE_AT 15

typedef struct scene {
    cloth_method m;
    cloth_precond p;
    double h;
    cloth_nonlinear nl;
} scene;

static cloth *make(const scene *sc)
{
    cloth_desc d = cloth_default_desc();
    d.rows = 9;
    d.cols = 8;
    d.solver.method = sc->m;
    d.solver.precond = sc->p;
    d.solver.max_substep_halvings = 3;
    d.material.alpha = 0.95;
    d.solver.nonlinear = sc->nl;
    if (sc->nl == CLOTH_NEWTON) {
        /* a step left unconverged is kept after one halving: a run stopped
         * early would compare nothing */
        d.solver.keep_unconverged = 1;
        d.solver.max_substep_halvings = 1;
    }
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return NULL;
    int n = cloth_vertex_count(c);
    double *x = malloc(3 * (size_t)n * sizeof *x), *f = malloc(3 * (size_t)n * sizeof *f);
    memcpy(x, cloth_positions(c), 3 * (size_t)n * sizeof *x);
    rng g = rng_seed(0xd37e7u);
    for (int k = 0; k < 3 * n; k++) {
        x[k] += 2e-3 * rng_range(&g, -1, 1);
        f[k] = (sc->nl == CLOTH_NEWTON ? 3.0 : 1e-3) * rng_range(&g, -1, 1);
    }
    cloth_set_positions(c, x);
    cloth_set_external_forces(c, f);
    free(x);
    free(f);
    return c;
}

/* The constraints of step s: corner 0 fixed, corner C-1 on a circle, the
 * last corner on a tilted plane. */
static void constrain(cloth *c, int s, const scene *sc)
{
    int C = cloth_cols(c), n = cloth_vertex_count(c);
    /* Newton: a circle within the row's limit, so its multipliers act (a
     * link the pins hold past the limit keeps the plain law, no multiplier) */
    double p0[3] = {-0.5, -0.5, 1.0}, t = (s + 1) * sc->h, r = sc->nl == CLOTH_NEWTON ? 0.02 : 0.1;
    double p1[3] = {0.5 + r * sin(4 * t), -0.5 + r * (1 - cos(4 * t)), 1.0};
    cloth_pin(c, 0, p0);
    cloth_pin(c, C - 1, p1);
    cloth_constraint k = {.vertex = n - 1, .ndof = 1, .axis = {0.2, 0, 1}, .target = {0.5, 0.5, 1.0}};
    cloth_set_constraint(c, &k);
}

static int run(cloth *c, const scene *sc, int from, int to)
{
    for (int s = from; s < to; s++) {
        constrain(c, s, sc);
        if (!CHECK(cloth_step(c, sc->h, NULL) == CLOTH_OK, "step %d: %s", s, cloth_last_error(c))) return -1;
    }
    return 0;
}

static int same(const cloth *a, const cloth *b)
{
    size_t n3 = 3 * (size_t)cloth_vertex_count(a);
    if (memcmp(cloth_positions(a), cloth_positions(b), n3 * sizeof(double))) return 0;
    if (memcmp(cloth_velocities(a), cloth_velocities(b), n3 * sizeof(double))) return 0;
    for (int i = 0; i < cloth_vertex_count(a); i++) {
        double fa[3], fb[3];
        cloth_constraint_force(a, i, fa);
        cloth_constraint_force(b, i, fb);
        if (memcmp(fa, fb, sizeof fa)) return 0;
    }
    return 1;
}

static double maxdiff(const cloth *a, const cloth *b)
{
    double m = 0.0;
    for (int k = 0; k < 3 * cloth_vertex_count(a); k++)
        m = fmax(m, fabs(cloth_positions(a)[k] - cloth_positions(b)[k]));
    return m;
}

/* Links whose elongation-limit multiplier a state record (version 3) holds
 * non-zero: the q doubles before the interlaced links' permanent sets and
 * bent flags (9 bytes each) and the checksum. */
static int multipliers_set(const cloth *c, const unsigned char *rec, size_t len)
{
    int q = cloth_link_count(c, CLOTH_SEQUENTIAL), set = 0;
    size_t tail = 9 * (size_t)cloth_link_count(c, CLOTH_INTERLACED);
    for (int e = 0; e < q; e++) {
        const unsigned char *p = rec + len - 8 - tail - 8 * (size_t)(q - e);
        uint64_t v = 0;
        for (int k = 7; k >= 0; k--) v = v << 8 | p[k];
        double d;
        memcpy(&d, &v, sizeof d);
        set += d != 0.0;
    }
    return set;
}

/* Other work on c, every step of it taken (the state does change). With the
 * linearised step: Newton's fails on its strain here, which would leave the
 * state, multipliers included, as saved. */
static void scribble(cloth *c, const char *name)
{
    cloth_desc d = cloth_get_desc(c);
    cloth_solver sv = d.solver;
    sv.method = CLOTH_BDF2;
    sv.precond = CLOTH_PRECOND_MULTIGRID;
    sv.warm_start = 1;
    sv.nonlinear = CLOTH_LINEARIZED;
    cloth_material m = cloth_material_preset(CLOTH_WOOL);
    double g[3] = {3, 0, -30};
    cloth_set_solver(c, &sv);
    cloth_set_material(c, &m);
    cloth_set_gravity(c, g);
    cloth_release_all(c);
    cloth_pin(c, 5, cloth_positions(c) + 15);
    int taken = 0;
    for (int s = 0; s < 10; s++) taken += cloth_step(c, 1.0 / 37, NULL) == CLOTH_OK;
    CHECK(taken == 10, "%s: other work took %d of its 10 steps: %s", name, taken, cloth_last_error(c));
    cloth_set_solver(c, &d.solver);
    cloth_set_material(c, &d.material);
    cloth_set_gravity(c, d.gravity);
    cloth_release_all(c);
}

int main(void)
{
    static const char *mn[] = {"BE", "explicit", "symplectic", "BDF2"}, *pn[] = {"block", "jacobi", "mg", "ssor"};
    scene scenes[17];
    int ns = 0;
    for (int nl = 0; nl < 2; nl++)
        for (int m = 0; m < 2; m++)
            for (int p = 0; p < 4; p++)
                scenes[ns++] = (scene){m ? CLOTH_BDF2 : CLOTH_BACKWARD_EULER, (cloth_precond)p, 1.0 / 120,
                                       nl ? CLOTH_NEWTON : CLOTH_LINEARIZED};
    scenes[ns++] = (scene){CLOTH_SYMPLECTIC_EULER, CLOTH_PRECOND_BLOCK_JACOBI, 2e-5, CLOTH_LINEARIZED};
    for (int k = 0; k < ns; k++) {
        const scene *sc = &scenes[k];
        char name[48];
        snprintf(name, sizeof name, "%s/%s%s", mn[sc->m], pn[sc->p], sc->nl == CLOTH_NEWTON ? "/Newton" : "");
        cloth *a = make(sc), *b = make(sc), *c = make(sc);
        if (!a || !b || !c) continue;
        /* 1. two runs */
        run(a, sc, 0, STEPS);
        run(b, sc, 0, STEPS);
        CHECK(same(a, b), "%s: two runs differ (positions by %.3g)", name, maxdiff(a, b));
        /* 2. save, scribble, restore, finish */
        cloth_state *s = cloth_state_create(c);
        run(c, sc, 0, SAVE_AT);
        cloth_save(c, s);
        size_t len = cloth_state_size_bytes(s);
        unsigned char *rec = malloc(len);
        cloth_state_write(s, rec, len, NULL, NULL);
        if (sc->nl == CLOTH_NEWTON)
            CHECK(multipliers_set(c, rec, len) > 0, "%s: no elongation-limit multiplier to carry at the save", name);
        scribble(c, name);
        CHECK(cloth_restore(c, s) == CLOTH_OK, "%s: restore", name);
        run(c, sc, SAVE_AT, STEPS);
        CHECK(same(a, c),
              "%s: save, other work, restore, continue differs from the uninterrupted run (positions by "
              "%.3g)",
              name, maxdiff(a, c));
        /* 3. through a record into a new cloth */
        cloth *e = make(sc);
        cloth_state *se = cloth_state_create(e);
        CHECK(cloth_state_read(se, rec, len, NULL) == CLOTH_OK && cloth_restore(e, se) == CLOTH_OK, "%s: read", name);
        run(e, sc, SAVE_AT, STEPS);
        CHECK(same(a, e), "%s: continued in a new cloth from a state record: differs by %.3g", name, maxdiff(a, e));
        printf("%s: %d steps, two runs, restore after other work, and a new cloth from a record: %s\n", name, STEPS,
               same(a, b) && same(a, c) && same(a, e) ? "bitwise equal" : "DIFFER");
        free(rec);
        cloth_state_destroy(s);
        cloth_state_destroy(se);
        cloth_destroy(a);
        cloth_destroy(b);
        cloth_destroy(c);
        cloth_destroy(e);
    }
    return check_summary();
}
