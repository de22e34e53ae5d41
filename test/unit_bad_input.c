/* Unit: bad input gives an error status and a readable message and leaves the
 * object as it was (cloth.h: "errors are values ... a call that fails leaves
 * its object unchanged").
 *
 * Creation: cloth_desc_validate and cloth_create reject
 *   - NaN, +inf and -inf in every double field of cloth_desc (looped over);
 *   - rows or cols < 3; rows * cols overflowing int (100000 x 100000 must be an
 *     error, quickly, not a giant allocation or a crash);
 *   - width, height, density <= 0; negative stiffnesses or damping;
 *     alpha outside [0, 1]; plastic_memory not 0 or 1; tau_set, tau_recover < 0, set_hardening
 *     outside [0, 1]; k_crease > 0 with the time law; delta <= 0; k_delta < 0 (k_delta 0 is valid: no
 *     stiffening); axis_u or axis_v zero, or parallel
 *     (or antiparallel); cg_tolerance outside (0, 1); cg_max_iterations < 1;
 *     unknown method/precond; negative strain_limit_iterations;
 *   - NULL desc, NULL out;
 * with CLOTH_EINVAL (CLOTH_ENOMEM allowed for the overflows), err.code equal
 * to the return, a non-empty err.message, and *out set to NULL. The same bad
 * materials/solvers fail cloth_material_validate / cloth_solver_validate.
 *
 * An existing cloth (perturbed, with plastic links and constraints): each bad
 * call below returns an error (EINVAL, and for a bad h also stats.failure
 * BAD_STEP), cloth_last_error is non-empty (it is "" on a fresh cloth), and
 * the state (cloth_save + cloth_state_diff == 0), material, solver, gravity
 * (cloth_get_desc, memcmp) and constraints are unchanged:
 *   set_material / set_solver / set_gravity with bad values or NULL (each
 *   material field NaN, inf, -inf, -1, k_delta included; tension_yield above
 *   delta, tension_set above 1; the message names the field),
 *   set_positions / set_velocities with a NaN or inf anywhere, or NULL,
 *   set_vertex out of range or non-finite, get_link out of range or bad type,
 *   pin out of range / NaN / NULL target, set_constraint with ndof 4 or -1,
 *   a zero or NaN axis, NaN target, out-of-range vertex, NULL,
 *   release / get_constraint / constraint_force out of range,
 *   internal_forces into NULL, save into NULL, restore from NULL or from a
 *   state of another size, step with h = 0, < 0, NaN, inf,
 *   get_link / get_constraint / constraint_force into NULL, set_vertex
 *   with both x and v NULL.
 */
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

/* ------------------------------------------------------------- creation */

static void expect_desc_rejected(const cloth_desc *d, const char *what, int allow_enomem)
{
    cloth_error err;
    cloth_status s;
    cloth *out = (cloth *)&err; /* a non-NULL sentinel */
    int ok_status;

    memset(&err, 0, sizeof err);
    err.code = CLOTH_OK;
    s = cloth_desc_validate(d, &err);
    ok_status = s == CLOTH_EINVAL || (allow_enomem && s == CLOTH_ENOMEM);
    CHECK(ok_status, "cloth_desc_validate(%s) returned %d (%s), want EINVAL", what, (int)s, cloth_status_string(s));
    CHECK(s == CLOTH_OK || err.message[0] != '\0', "cloth_desc_validate(%s): empty message", what);

    memset(&err, 0, sizeof err);
    err.code = CLOTH_OK;
    s = cloth_create(d, &out, &err);
    ok_status = s == CLOTH_EINVAL || (allow_enomem && s == CLOTH_ENOMEM);
    CHECK(ok_status, "cloth_create(%s) returned %d (%s), want EINVAL%s", what, (int)s, cloth_status_string(s),
          allow_enomem ? " or ENOMEM" : "");
    CHECK(s == CLOTH_OK || err.message[0] != '\0', "cloth_create(%s): empty message", what);
    CHECK(s == CLOTH_OK || err.code == s, "cloth_create(%s): err.code %d but returned %d", what, (int)err.code, (int)s);
    CHECK(s == CLOTH_OK || out == NULL, "cloth_create(%s) failed but *out is not NULL", what);
    if (s == CLOTH_OK && out && out != (cloth *)&err) cloth_destroy(out);

    /* err may be NULL */
    out = NULL;
    s = cloth_create(d, &out, NULL);
    CHECK(s != CLOTH_OK && out == NULL, "cloth_create(%s, err = NULL) returned %d", what, (int)s);
    if (s == CLOTH_OK) cloth_destroy(out);
}

/* clang-format would put each entry of this table on a line of its own */
/* clang-format off */
typedef struct dfield { const char *name; size_t off; } dfield;
#define DF(f) {#f, offsetof(cloth_desc, f)}
static const dfield desc_doubles[] = {
    DF(width), DF(height), DF(origin[0]), DF(origin[1]), DF(origin[2]), DF(axis_u[0]), DF(axis_u[1]),
    DF(axis_u[2]), DF(axis_v[0]), DF(axis_v[1]), DF(axis_v[2]), DF(gravity[0]), DF(gravity[1]),
    DF(gravity[2]), DF(material.k_t), DF(material.k_c), DF(material.k_b), DF(material.k_s),
    DF(material.alpha), DF(material.delta), DF(material.k_delta), DF(material.c_t), DF(material.c_b),
    DF(material.density), DF(material.tau_set), DF(material.tau_recover), DF(material.set_hardening),
    DF(material.tension_yield), DF(material.tension_set), DF(material.k_crease),
    DF(solver.cg_tolerance), DF(solver.strain_fail),
};
/* clang-format on */
#define NDESC_DOUBLES (sizeof desc_doubles / sizeof desc_doubles[0])
#define NMATERIAL_DOUBLES 16 /* the material.* entries, in order, from index 14 */
#define MATERIAL_FIRST 14

/* material fields by offset within cloth_material */
static double *mat_field(cloth_material *m, int k)
{
    return (double *)((char *)m + (desc_doubles[MATERIAL_FIRST + k].off - offsetof(cloth_desc, material)));
}

static const double nonfinite[3] = {NAN, INFINITY, -INFINITY};
static const char *const nf_name[3] = {"NaN", "inf", "-inf"};

/* The table covers every double of the desc, and the default is valid. */
static void check_create_default(const cloth_desc *d0)
{
    cloth_error err;
    cloth *c = NULL;
    /* ten doubles, the one int plastic_memory (checked by BAD below), six doubles */
    CHECK(offsetof(cloth_material, plastic_memory) == 10 * sizeof(double) &&
              offsetof(cloth_material, tau_set) == 11 * sizeof(double) &&
              sizeof(cloth_material) == (NMATERIAL_DOUBLES + 1) * sizeof(double),
          "cloth_material has fields this test misses");
    CHECK(strcmp(desc_doubles[MATERIAL_FIRST].name, "material.k_t") == 0 &&
              strcmp(desc_doubles[MATERIAL_FIRST + 9].name, "material.density") == 0 &&
              strcmp(desc_doubles[MATERIAL_FIRST + NMATERIAL_DOUBLES - 1].name, "material.k_crease") == 0 &&
              strcmp(desc_doubles[MATERIAL_FIRST + NMATERIAL_DOUBLES].name, "solver.cg_tolerance") == 0,
          "table order");
    CHECK(cloth_desc_validate(d0, NULL) == CLOTH_OK, "the default desc is invalid");
    CHECK(cloth_create(d0, &c, &err) == CLOTH_OK && c, "cloth_create(default) failed: %s", err.message);
    cloth_destroy(c);
    cloth_destroy(NULL); /* documented as fine */
}

/* Each of n sizes (rows, cols) refused; overflow: the ones too large (ENOMEM allowed) */
static void expect_sizes_rejected(const cloth_desc *d0, const int (*sizes)[2], size_t n, int overflow)
{
    char what[128];
    for (size_t k = 0; k < n; k++) {
        cloth_desc d = *d0;
        d.rows = sizes[k][0];
        d.cols = sizes[k][1];
        snprintf(what, sizeof what, overflow ? "rows %d cols %d (overflow)" : "rows %d cols %d", d.rows, d.cols);
        expect_desc_rejected(&d, what, overflow);
    }
}

/* Every double field NaN / inf / -inf, and sizes too small or overflowing. */
static void check_create_nonfinite_and_sizes(const cloth_desc *d0)
{
    cloth_desc d;
    char what[128];
    for (size_t f = 0; f < NDESC_DOUBLES; f++)
        for (int k = 0; k < 3; k++) {
            d = *d0;
            *(double *)((char *)&d + desc_doubles[f].off) = nonfinite[k];
            snprintf(what, sizeof what, "%s = %s", desc_doubles[f].name, nf_name[k]);
            expect_desc_rejected(&d, what, 0);
        }
    static const int bad[][2] = {{2, 5}, {5, 2}, {0, 0}, {-1, 5}, {5, -3}, {1, 1}, {2, 2}, {INT_MIN, 5}};
    static const int huge[][2] = {{100000, 100000}, {46341, 46341}, {INT_MAX, 3}, {3, INT_MAX}, {INT_MAX, INT_MAX}};
    expect_sizes_rejected(d0, bad, sizeof bad / sizeof bad[0], 0);
    expect_sizes_rejected(d0, huge, sizeof huge / sizeof huge[0], 1);
}

/* Out-of-range values, one field at a time. */
static void check_create_out_of_range(const cloth_desc *d0)
{
    cloth_desc d;
#define BAD(stmt, label)                    \
    do {                                    \
        d = *d0;                            \
        stmt;                               \
        expect_desc_rejected(&d, label, 0); \
    } while (0)
    BAD(d.width = 0, "width 0");
    BAD(d.width = -1, "width -1");
    BAD(d.height = 0, "height 0");
    BAD(d.height = -0.5, "height -0.5");
    BAD(d.material.density = 0, "density 0");
    BAD(d.material.density = -0.2, "density -0.2");
    BAD(d.material.k_t = -1, "k_t -1");
    BAD(d.material.k_c = -1, "k_c -1");
    BAD(d.material.k_b = -1, "k_b -1");
    BAD(d.material.k_s = -1, "k_s -1");
    BAD(d.material.c_t = -1, "c_t -1");
    BAD(d.material.c_b = -1, "c_b -1");
    BAD(d.material.alpha = -0.01, "alpha -0.01");
    BAD(d.material.alpha = 1.01, "alpha 1.01");
    BAD(d.material.set_hardening = 1.01, "set_hardening 1.01");
    BAD(d.material.tau_set = -1e-9, "tau_set -1e-9");
    BAD(d.material.tension_yield = d.material.delta * (1.0 + 1e-12), "tension_yield above delta");
    BAD(d.material.tension_yield = -1e-300, "tension_yield -1e-300");
    BAD(d.material.tension_set = 1.0 + 1e-12, "tension_set above 1");
    BAD(d.material.tension_set = -1e-9, "tension_set -1e-9");
    BAD((d.material.k_crease = 1.0, d.material.tau_set = 1.0), "k_crease with tau_set");
    BAD((d.material.k_crease = 1.0, d.material.set_hardening = 0.5), "k_crease with set_hardening");
    BAD(d.material.plastic_memory = -1, "plastic_memory -1");
    BAD(d.material.plastic_memory = 2, "plastic_memory 2");
    BAD(d.material.plastic_memory = INT_MAX, "plastic_memory INT_MAX");
    BAD(d.material.delta = 0, "delta 0");
    BAD(d.material.delta = -0.1, "delta -0.1");
    BAD(d.material.k_delta = -1, "k_delta -1");
    BAD(d.material.k_delta = -1e-300, "k_delta -1e-300");
    BAD(d.material.k_delta = NAN, "k_delta NaN");
    BAD(d.material.k_delta = INFINITY, "k_delta inf");
    BAD((d.axis_u[0] = d.axis_u[1] = d.axis_u[2] = 0), "axis_u zero");
    BAD((d.axis_v[0] = d.axis_v[1] = d.axis_v[2] = 0), "axis_v zero");
    BAD((d.axis_u[0] = 1, d.axis_u[1] = 0, d.axis_u[2] = 0, d.axis_v[0] = 2, d.axis_v[1] = 0, d.axis_v[2] = 0),
        "axis_v parallel to axis_u");
    BAD((d.axis_u[0] = 0, d.axis_u[1] = 1, d.axis_u[2] = 1, d.axis_v[0] = 0, d.axis_v[1] = -3, d.axis_v[2] = -3),
        "axis_v antiparallel to axis_u");
    BAD(d.solver.cg_tolerance = 0, "cg_tolerance 0");
    BAD(d.solver.cg_tolerance = 1, "cg_tolerance 1");
    BAD(d.solver.cg_tolerance = -1e-3, "cg_tolerance -1e-3");
    BAD(d.solver.cg_tolerance = 2, "cg_tolerance 2");
    BAD(d.solver.cg_max_iterations = 0, "cg_max_iterations 0");
    BAD(d.solver.cg_max_iterations = -7, "cg_max_iterations -7");
    BAD(d.solver.method = (cloth_method)99, "method 99");
    BAD(d.solver.method = (cloth_method)-1, "method -1");
    BAD(d.solver.precond = (cloth_precond)99, "precond 99");
    BAD(d.solver.strain_limit_iterations = -1, "strain_limit_iterations -1");
#undef BAD
}

/* NULL desc, out and validator arguments. */
static void check_create_null(const cloth_desc *d0)
{
    cloth_error err;
    cloth *out = (cloth *)&err;
    cloth_status s;
    memset(&err, 0, sizeof err);
    s = cloth_create(NULL, &out, &err);
    CHECK(s == CLOTH_EINVAL && err.message[0] && out == NULL,
          "cloth_create(NULL desc): status %d, message \"%s\", out %p", (int)s, err.message, (void *)out);
    memset(&err, 0, sizeof err);
    s = cloth_create(d0, NULL, &err);
    CHECK(s == CLOTH_EINVAL && err.message[0], "cloth_create(out = NULL): status %d, message \"%s\"", (int)s,
          err.message);
    memset(&err, 0, sizeof err);
    s = cloth_desc_validate(NULL, &err);
    CHECK(s == CLOTH_EINVAL && err.message[0], "cloth_desc_validate(NULL): status %d", (int)s);
    memset(&err, 0, sizeof err);
    s = cloth_material_validate(NULL, &err);
    CHECK(s == CLOTH_EINVAL && err.message[0], "cloth_material_validate(NULL): status %d", (int)s);
    memset(&err, 0, sizeof err);
    s = cloth_solver_validate(NULL, &err);
    CHECK(s == CLOTH_EINVAL && err.message[0], "cloth_solver_validate(NULL): status %d", (int)s);
}

/* The stand-alone validators: presets valid, each material field bad, k_delta
 * named by the message and 0 (no stiffening) valid, bad solvers. */
static void check_validators(const cloth_desc *d0)
{
    cloth_desc d;
    cloth_error err;
    cloth *c = NULL;
    cloth_material m;
    cloth_solver sv;
    cloth_status s;
    for (int p = 0; p < 3; p++) {
        m = cloth_material_preset((cloth_preset)p);
        CHECK(cloth_material_validate(&m, NULL) == CLOTH_OK, "preset %d is invalid", p);
    }
    for (int k = 0; k < NMATERIAL_DOUBLES; k++)
        for (int v = 0; v < 4; v++) {
            m = cloth_material_preset(CLOTH_COTTON);
            *mat_field(&m, k) = v < 3 ? nonfinite[v] : -1.0;
            memset(&err, 0, sizeof err);
            s = cloth_material_validate(&m, &err);
            CHECK(s == CLOTH_EINVAL && err.message[0], "cloth_material_validate(%s = %s): status %d",
                  desc_doubles[MATERIAL_FIRST + k].name, v < 3 ? nf_name[v] : "-1", (int)s);
        }
    const double kd[] = {NAN, INFINITY, -INFINITY, -1.0, -1e-300};
    for (size_t v = 0; v < sizeof kd / sizeof kd[0]; v++) {
        m = cloth_material_preset(CLOTH_COTTON);
        m.k_delta = kd[v];
        memset(&err, 0, sizeof err);
        s = cloth_material_validate(&m, &err);
        CHECK(s == CLOTH_EINVAL && strstr(err.message, "k_delta") != NULL,
              "cloth_material_validate(k_delta = %g): status %d, message \"%s\" (want EINVAL naming k_delta)", kd[v],
              (int)s, err.message);
    }
    for (int p = 0; p < 3; p++) {
        m = cloth_material_preset((cloth_preset)p);
        CHECK(m.k_delta == 100.0, "preset %d: k_delta %g, want 100", p, m.k_delta);
        m.k_delta = 0.0;
        memset(&err, 0, sizeof err);
        s = cloth_material_validate(&m, &err);
        CHECK(s == CLOTH_OK, "preset %d with k_delta 0 rejected: %s", p, err.message);
    }
    d = *d0;
    d.material.k_delta = 0.0;
    s = cloth_create(&d, &c, &err);
    CHECK(s == CLOTH_OK && c, "cloth_create(k_delta 0) failed: %s", err.message);
    cloth_destroy(c);
    sv = d0->solver;
    CHECK(cloth_solver_validate(&sv, NULL) == CLOTH_OK, "the default solver is invalid");
    sv.cg_tolerance = NAN;
    s = cloth_solver_validate(&sv, &err);
    CHECK(s == CLOTH_EINVAL && err.message[0], "cloth_solver_validate(cg_tolerance NaN): status %d", (int)s);
    sv = d0->solver;
    sv.cg_max_iterations = 0;
    s = cloth_solver_validate(&sv, &err);
    CHECK(s == CLOTH_EINVAL && err.message[0], "cloth_solver_validate(cg_max_iterations 0): status %d", (int)s);
}

static void check_create(void)
{
    const cloth_desc d0 = cloth_default_desc();
    check_create_default(&d0);
    check_create_nonfinite_and_sizes(&d0);
    check_create_out_of_range(&d0);
    check_create_null(&d0);
    check_validators(&d0);
}

/* ----------------------------------------------------- an existing cloth */

enum { ROWS = 6, COLS = 5, NV = ROWS * COLS };

/* A cloth in an interesting state: perturbed and squeezed (plastic links),
 * moving, with a pin and a plane constraint. */
static cloth *make_cloth(void)
{
    cloth_desc d = cloth_default_desc();
    cloth *c = NULL;
    cloth_error err;
    rng r = rng_seed(0x5EED0401u);
    double x[3 * NV], v[3 * NV];
    d.rows = ROWS;
    d.cols = COLS;
    if (cloth_create(&d, &c, &err) != CLOTH_OK) {
        CHECK(0, "cloth_create: %s", err.message);
        return NULL;
    }
    memcpy(x, cloth_positions(c), sizeof x);
    for (int i = 0; i < NV; i++) {
        x[3 * i] *= 0.7; /* squeeze along x (the default cloth is centred on the z axis) */
        for (int a = 0; a < 3; a++) {
            x[3 * i + a] += rng_range(&r, -0.02, 0.02);
            v[3 * i + a] = rng_range(&r, -1, 1);
        }
    }
    if (cloth_set_positions(c, x) != CLOTH_OK || cloth_set_velocities(c, v) != CLOTH_OK) {
        CHECK(0, "setting up the state failed: %s", cloth_last_error(c));
    }
    {
        cloth_constraint k;
        memset(&k, 0, sizeof k);
        k.vertex = 7;
        k.ndof = 1;
        k.axis[2] = 1;
        memcpy(k.target, x + 3 * 7, sizeof k.target);
        if (cloth_pin(c, 0, x) != CLOTH_OK || cloth_set_constraint(c, &k) != CLOTH_OK)
            CHECK(0, "setting up constraints failed: %s", cloth_last_error(c));
    }
    return c;
}

typedef struct snapshot {
    cloth_state *st;
    cloth_desc desc;
    int ncon;
    cloth_constraint con[NV];
    cloth_status con_status[NV];
} snapshot;

static void take(const cloth *c, snapshot *s)
{
    s->st = cloth_state_create(c);
    if (s->st) cloth_save(c, s->st);
    s->desc = cloth_get_desc(c);
    s->ncon = cloth_constraint_count(c);
    for (int i = 0; i < NV; i++) {
        memset(&s->con[i], 0, sizeof s->con[i]);
        s->con_status[i] = cloth_get_constraint(c, i, &s->con[i]);
    }
}

static void compare(const snapshot *a, const snapshot *b, const char *what)
{
    double diff = a->st && b->st ? cloth_state_diff(a->st, b->st) : -1;
    int con_changed = a->ncon != b->ncon;
    CHECK(diff == 0.0, "%s changed the state (cloth_state_diff %g)", what, diff);
    CHECK(memcmp(&a->desc.material, &b->desc.material, sizeof a->desc.material) == 0, "%s changed the material", what);
    CHECK(memcmp(&a->desc.solver, &b->desc.solver, sizeof a->desc.solver) == 0, "%s changed the solver", what);
    CHECK(memcmp(a->desc.gravity, b->desc.gravity, sizeof a->desc.gravity) == 0, "%s changed gravity", what);
    for (int i = 0; i < NV; i++)
        if (a->con_status[i] != b->con_status[i] || a->con[i].ndof != b->con[i].ndof ||
            memcmp(a->con[i].axis, b->con[i].axis, sizeof a->con[i].axis) != 0 ||
            memcmp(a->con[i].target, b->con[i].target, sizeof a->con[i].target) != 0)
            con_changed = 1;
    CHECK(!con_changed, "%s changed the constraints", what);
}

static void release(snapshot *s) { cloth_state_destroy(s->st); }

/* set_material with material field f (k / 4) NaN, inf, -inf or -1 (k % 4): the message names the field. */
static cloth_status bad_material_field(cloth *c, int k, char *what, size_t wn)
{
    cloth_material m = cloth_get_desc(c).material;
    int f = k / 4, v = k % 4;
    *mat_field(&m, f) = v < 3 ? nonfinite[v] : -1.0;
    snprintf(what, wn, "cloth_set_material(%s = %s)", desc_doubles[MATERIAL_FIRST + f].name,
             v < 3 ? (v == 0   ? "NaN"
                      : v == 1 ? "inf"
                               : "-inf")
                   : "-1");
    cloth_status st = cloth_set_material(c, &m);
    /* the message names the field ("material.k_delta is not finite") */
    CHECK(st == CLOTH_OK || strstr(cloth_last_error(c), desc_doubles[MATERIAL_FIRST + f].name) != NULL,
          "%s: message \"%s\" does not name the field", what, cloth_last_error(c));
    return st;
}

/* set_material with alpha > 1, delta 0, NULL, tension_yield above delta, tension_set above 1. */
static cloth_status bad_material(cloth *c, int k, char *what, size_t wn)
{
    cloth_material m = cloth_get_desc(c).material;
    switch (k) {
    case 0:
        m.alpha = 1.5;
        snprintf(what, wn, "cloth_set_material(alpha 1.5)");
        return cloth_set_material(c, &m);
    case 1:
        m.delta = 0;
        snprintf(what, wn, "cloth_set_material(delta 0)");
        return cloth_set_material(c, &m);
    case 2: snprintf(what, wn, "cloth_set_material(NULL)"); return cloth_set_material(c, NULL);
    default: {
        if (k == 60) m.tension_yield = m.delta * 1.5;
        else m.tension_set = 1.5;
        snprintf(what, wn, "cloth_set_material(%s)", k == 60 ? "tension_yield 1.5 delta" : "tension_set 1.5");
        cloth_status st = cloth_set_material(c, &m);
        CHECK(strstr(cloth_last_error(c), k == 60 ? "tension_yield" : "tension_set") != NULL,
              "%s: message \"%s\" does not name the field", what, cloth_last_error(c));
        return st;
    }
    }
}

/* set_solver with a bad field (k 3..9) or NULL (k 10). */
static cloth_status bad_solver(cloth *c, int k, char *what, size_t wn)
{
    if (k == 10) {
        snprintf(what, wn, "cloth_set_solver(NULL)");
        return cloth_set_solver(c, NULL);
    }
    cloth_solver s = cloth_default_desc().solver;
    const char *nm[] = {"cg_tolerance 0", "cg_tolerance 1", "cg_tolerance NaN", "cg_max_iterations 0",
                        "method 99",      "precond 99",     "strain_fail NaN"};
    if (k == 3) s.cg_tolerance = 0;
    if (k == 4) s.cg_tolerance = 1;
    if (k == 5) s.cg_tolerance = NAN;
    if (k == 6) s.cg_max_iterations = 0;
    if (k == 7) s.method = (cloth_method)99;
    if (k == 8) s.precond = (cloth_precond)99;
    if (k == 9) s.strain_fail = NAN;
    snprintf(what, wn, "cloth_set_solver(%s)", nm[k - 3]);
    return cloth_set_solver(c, &s);
}

/* set_gravity with a non-finite component (k 11..13) or NULL (k 14). */
static cloth_status bad_gravity(cloth *c, int k, char *what, size_t wn)
{
    double g[3] = {0, 0, -9.81};
    if (k < 14) g[k - 11] = nonfinite[k - 11];
    snprintf(what, wn, "cloth_set_gravity(%s)", k < 14 ? "non-finite component" : "NULL");
    return cloth_set_gravity(c, k < 14 ? g : NULL);
}

/* set_positions, set_velocities, set_vertex with NaN, inf, NULL or a vertex out of range (k 15..27). */
static cloth_status bad_state(cloth *c, int k, char *what, size_t wn)
{
    double x[3 * NV];
    memcpy(x, cloth_positions(c), sizeof x);
    if (k <= 18) {
        int at[] = {0, 3 * NV / 2 + 1, 3 * NV - 1, 40};
        x[at[k - 15]] = k == 18 ? INFINITY : NAN;
        snprintf(what, wn, "cloth_set_positions(%s at %d)", k == 18 ? "inf" : "NaN", at[k - 15]);
        return cloth_set_positions(c, x);
    }
    if (k == 19) {
        snprintf(what, wn, "cloth_set_positions(NULL)");
        return cloth_set_positions(c, NULL);
    }
    if (k <= 21) {
        double v[3 * NV];
        memcpy(v, cloth_velocities(c), sizeof v);
        v[k == 20 ? 3 * NV - 1 : 17] = k == 20 ? NAN : -INFINITY;
        snprintf(what, wn, "cloth_set_velocities(%s)", k == 20 ? "NaN last" : "-inf");
        return cloth_set_velocities(c, v);
    }
    if (k == 22) {
        snprintf(what, wn, "cloth_set_velocities(NULL)");
        return cloth_set_velocities(c, NULL);
    }
    if (k <= 25) {
        int vert = k == 23 ? -1 : k == 24 ? NV : INT_MAX;
        double xv[3] = {0.1, 0.2, 0.3}, vv[3] = {0, 0, 0};
        snprintf(what, wn, "cloth_set_vertex(%d)", vert);
        return cloth_set_vertex(c, vert, xv, vv);
    }
    double xv[3] = {0.1, NAN, 0.3}, vv[3] = {0, 0, INFINITY};
    double xo[3] = {0.1, 0.2, 0.3}, vo[3] = {0, 0, 0};
    snprintf(what, wn, "cloth_set_vertex(5, %s)", k == 26 ? "x NaN" : "v inf");
    return k == 26 ? cloth_set_vertex(c, 5, xv, vo) : cloth_set_vertex(c, 5, xo, vv);
}

/* set_constraint with a bad ndof, axis, target or vertex (k 36..42), or NULL (k 43). */
static cloth_status bad_constraint(cloth *c, int k, char *what, size_t wn)
{
    if (k == 43) {
        snprintf(what, wn, "cloth_set_constraint(NULL)");
        return cloth_set_constraint(c, NULL);
    }
    cloth_constraint q;
    const char *nm[] = {"ndof 4",          "ndof -1",           "ndof 1 zero axis",   "ndof 2 zero axis",
                        "ndof 1 NaN axis", "ndof 3 NaN target", "vertex out of range"};
    memset(&q, 0, sizeof q);
    q.vertex = 3;
    q.ndof = 1;
    q.axis[2] = 1;
    memcpy(q.target, cloth_positions(c) + 9, sizeof q.target);
    if (k == 36) q.ndof = 4;
    if (k == 37) q.ndof = -1;
    if (k == 38) q.axis[2] = 0;
    if (k == 39) q.ndof = 2, q.axis[2] = 0;
    if (k == 40) q.axis[0] = NAN;
    if (k == 41) q.ndof = 3, q.target[1] = NAN;
    if (k == 42) q.vertex = NV;
    snprintf(what, wn, "cloth_set_constraint(%s)", nm[k - 36]);
    return cloth_set_constraint(c, &q);
}

/* get_link out of range or of a bad type (k 28..31); pin, release, get_constraint,
 * constraint_force out of range or with a bad target (k 32..35, 44..47). */
static cloth_status bad_index(cloth *c, int k, char *what, size_t wn)
{
    double p[3] = {0.1, 0.2, 0.3};
    switch (k) {
    case 28:
    case 29:
    case 30:
    case 31: {
        cloth_link L;
        cloth_link_type t = k == 30 ? CLOTH_INTERLACED : CLOTH_SEQUENTIAL;
        int idx = k == 28 ? -1 : k == 31 ? 0 : cloth_link_count(c, t);
        if (k == 31) t = (cloth_link_type)7;
        snprintf(what, wn, "cloth_get_link(type %d, index %d)", (int)t, idx);
        return cloth_get_link(c, t, idx, &L);
    }
    case 32:
    case 33: snprintf(what, wn, "cloth_pin(%d)", k == 32 ? -1 : NV); return cloth_pin(c, k == 32 ? -1 : NV, p);
    case 34: {
        double t[3] = {0, NAN, 0};
        snprintf(what, wn, "cloth_pin(3, NaN target)");
        return cloth_pin(c, 3, t);
    }
    case 35: snprintf(what, wn, "cloth_pin(3, NULL)"); return cloth_pin(c, 3, NULL);
    case 44:
    case 45: snprintf(what, wn, "cloth_release(%d)", k == 44 ? -1 : NV); return cloth_release(c, k == 44 ? -1 : NV);
    case 46: {
        cloth_constraint q;
        snprintf(what, wn, "cloth_get_constraint(%d)", NV);
        return cloth_get_constraint(c, NV, &q);
    }
    default: {
        double f[3];
        snprintf(what, wn, "cloth_constraint_force(-1)");
        return cloth_constraint_force(c, -1, f);
    }
    }
}

/* restore from a state of a cloth of another size, whose diff with c's is negative. */
static cloth_status bad_restore_size(cloth *c, char *what, size_t wn)
{
    cloth_desc d = cloth_default_desc();
    cloth *o = NULL;
    cloth_state *s;
    cloth_status st = CLOTH_OK;
    d.rows = ROWS + 1;
    d.cols = COLS;
    snprintf(what, wn, "cloth_restore(state of a %dx%d cloth)", ROWS + 1, COLS);
    if (cloth_create(&d, &o, NULL) != CLOTH_OK) return CLOTH_EINVAL;
    s = cloth_state_create(o);
    if (s) {
        cloth_state *mine = cloth_state_create(c);
        cloth_save(o, s);
        if (mine) {
            cloth_save(c, mine);
            CHECK(cloth_state_diff(mine, s) < 0, "cloth_state_diff of states of different sizes is not negative");
        }
        cloth_state_destroy(mine);
        st = cloth_restore(c, s);
    }
    cloth_state_destroy(s);
    cloth_destroy(o);
    return st;
}

/* step with h 0, < 0, NaN, inf (k 52..55): a bad argument, not a failed step, but stats say BAD_STEP. */
static cloth_status bad_step(cloth *c, int k, char *what, size_t wn)
{
    const double hs[] = {0.0, -0.01, NAN, INFINITY};
    cloth_step_stats stats;
    cloth_status st;
    memset(&stats, 0, sizeof stats);
    snprintf(what, wn, "cloth_step(h = %g)", hs[k - 52]);
    st = cloth_step(c, hs[k - 52], &stats);
    CHECK(st == CLOTH_OK || stats.failure == CLOTH_FAIL_BAD_STEP, "%s: stats.failure %d (%s), want BAD_STEP", what,
          (int)stats.failure, cloth_failure_string(stats.failure));
    return st;
}

/* NULL where an output or a state goes (k 48..50, 56..59). */
static cloth_status bad_null(cloth *c, int k, char *what, size_t wn)
{
    switch (k) {
    case 48: snprintf(what, wn, "cloth_internal_forces(NULL)"); return cloth_internal_forces(c, NULL);
    case 49: snprintf(what, wn, "cloth_save(NULL)"); return cloth_save(c, NULL);
    case 50: snprintf(what, wn, "cloth_restore(NULL)"); return cloth_restore(c, NULL);
    case 56: snprintf(what, wn, "cloth_get_link(out NULL)"); return cloth_get_link(c, CLOTH_SEQUENTIAL, 0, NULL);
    case 57: snprintf(what, wn, "cloth_get_constraint(out NULL)"); return cloth_get_constraint(c, 0, NULL);
    case 58: snprintf(what, wn, "cloth_constraint_force(f NULL)"); return cloth_constraint_force(c, 0, NULL);
    default: snprintf(what, wn, "cloth_set_vertex(x and v NULL)"); return cloth_set_vertex(c, 5, NULL, NULL);
    }
}

/* One bad call by number; returns the status, sets *what, *want (EINVAL for
 * all). Returns -1 past the last case. */
static int bad_call(cloth *c, int k, char *what, size_t wn, cloth_status *want)
{
    *want = CLOTH_EINVAL;
    if (k < NMATERIAL_DOUBLES * 4) return bad_material_field(c, k, what, wn);
    k -= NMATERIAL_DOUBLES * 4;
    if (k > 61) return -1;
    if (k <= 2 || k >= 60) return bad_material(c, k, what, wn);
    if (k <= 10) return bad_solver(c, k, what, wn);
    if (k <= 14) return bad_gravity(c, k, what, wn);
    if (k <= 27) return bad_state(c, k, what, wn);
    if (k >= 36 && k <= 43) return bad_constraint(c, k, what, wn);
    if (k <= 47) return bad_index(c, k, what, wn);
    if (k == 51) return bad_restore_size(c, what, wn);
    if (k >= 52 && k <= 55) return bad_step(c, k, what, wn);
    return bad_null(c, k, what, wn);
}

static void check_existing(void)
{
    char what[160];
    int ncases = 0;
    for (int k = 0;; k++) {
        cloth *c = make_cloth();
        snapshot before, after;
        cloth_status want;
        int s;
        if (!c) return;
        CHECK(cloth_last_error(c) && cloth_last_error(c)[0] == '\0', "a fresh cloth's last error is \"%s\", want \"\"",
              cloth_last_error(c) ? cloth_last_error(c) : "(NULL)");
        take(c, &before);
        what[0] = '\0';
        s = bad_call(c, k, what, sizeof what, &want);
        if (s < 0) {
            release(&before);
            cloth_destroy(c);
            break;
        }
        ncases++;
        take(c, &after);
        CHECK(s == (int)want, "%s returned %d (%s), want %d (%s)", what, s,
              s == CLOTH_OK ? "OK" : cloth_status_string((cloth_status)s), (int)want, cloth_status_string(want));
        CHECK(s == CLOTH_OK || (cloth_last_error(c) && cloth_last_error(c)[0] != '\0'),
              "%s failed but cloth_last_error is empty", what);
        compare(&before, &after, what);
        release(&before);
        release(&after);
        cloth_destroy(c);
    }
    printf("%d bad calls on an existing cloth\n", ncases);
}

/* Axes of extreme but valid size are normalised exactly (scaled by their
 * largest component first): unscaled, 1e200 and 1e-200 components would
 * give a zero normal or be refused as zero. */
static void check_extreme_axes(void)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 3;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return;
    const double in[4][3] = {{1e200, 0, 0}, {0, 3e300, 4e300}, {1e-200, 1e-200, 0}, {0, 0, -5e-310}};
    const double want[4][3] = {{1, 0, 0}, {0, 0.6, 0.8}, {M_SQRT1_2, M_SQRT1_2, 0}, {0, 0, -1}};
    for (int t = 0; t < 4; t++) {
        cloth_constraint k = {.vertex = 4, .ndof = 1};
        memcpy(k.axis, in[t], sizeof k.axis);
        memcpy(k.target, cloth_positions(c) + 12, sizeof k.target);
        cloth_constraint got;
        CHECK(cloth_set_constraint(c, &k) == CLOTH_OK && cloth_get_constraint(c, 4, &got) == CLOTH_OK,
              "axis %d taken: %s", t, cloth_last_error(c));
        for (int a = 0; a < 3; a++) CHECK_NEAR(got.axis[a], want[t][a], 1e-15);
    }
    cloth_destroy(c);
}

/* A grid that does not coarsen (a side under 5 nodes) cannot have the
 * multigrid preconditioner (its dense coarsest level: 3 x 100000 asked for
 * 6.5 TB); the others are fine, and nothing is allocated for multigrid
 * unless it is chosen. */
static void check_multigrid_shape(void)
{
    cloth_desc d = cloth_default_desc();
    d.rows = 3;
    d.cols = 5000;
    d.width = 100.0;
    d.height = 0.04;
    cloth *c = NULL;
    cloth_error err;
    d.solver.precond = CLOTH_PRECOND_MULTIGRID;
    CHECK(cloth_create(&d, &c, &err) == CLOTH_EINVAL && c == NULL && strstr(err.message, "multigrid"),
          "3 x 5000 with multigrid refused: %s", err.message);
    d.solver.precond = CLOTH_PRECOND_BLOCK_JACOBI;
    if (CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "3 x 5000 with block Jacobi: %s", err.message)) {
        cloth_solver s = cloth_get_desc(c).solver;
        s.precond = CLOTH_PRECOND_MULTIGRID;
        CHECK(cloth_set_solver(c, &s) == CLOTH_EINVAL && cloth_get_desc(c).solver.precond == CLOTH_PRECOND_BLOCK_JACOBI,
              "switching it to multigrid refused, solver unchanged: %s", cloth_last_error(c));
        CHECK(cloth_step(c, 1.0 / 60, NULL) == CLOTH_OK, "it steps: %s", cloth_last_error(c));
        cloth_destroy(c);
    }
    d = cloth_default_desc();
    if (CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "21 x 21: %s", err.message)) {
        cloth_solver s = cloth_get_desc(c).solver;
        s.precond = CLOTH_PRECOND_MULTIGRID;
        CHECK(cloth_set_solver(c, &s) == CLOTH_OK, "21 x 21 switched to multigrid: %s", cloth_last_error(c));
        CHECK(cloth_step(c, 1.0 / 60, NULL) == CLOTH_OK, "and steps: %s", cloth_last_error(c));
        cloth_destroy(c);
    }
}

int main(void)
{
    check_create();
    check_existing();
    check_extreme_axes();
    check_multigrid_shape();
    return check_summary();
}
