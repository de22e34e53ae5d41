/* Physics: contact candidates (cloth_set_contact) decided inside the Newton
 * step.
 *
 * A flat 9 x 9 cloth falls rigidly (uniform velocity, no internal force)
 * onto the plane z = 0, given to the core only as a candidate on every
 * vertex, set again before every step as the plugin does. Backward Euler
 * then has a closed form: the step that would carry the cloth below the
 * plane ends with every vertex on it, v1 = -z0 / h, and the constraint
 * impulse on each vertex is m (v1 - v0 - h g); the next steps rest, v = 0.
 * A tilted cloth (its vertices land in different steps) never ends a step
 * below the plane by more than h newton_tolerance, and the impulses its
 * contacts apply equal its momentum change. The linearised solver ignores
 * candidates (documented): there the cloth passes the plane.
 * A cloth sticking to the floor, one edge pulled 5 cm in a step: the sticking
 * vertices that would hold a link past the elongation limit slide on the
 * floor and the limit holds; pulled 0.1 mm, none slides. One edge lifted
 * 10 cm in a step: the floor's planes under the vertices next to it, pulling
 * them down against links past the limit, let go, and the limit holds.
 * A cloth held on the floor by sliding contacts, or by sticking ones, no
 * gravity, each vertex pulled up by m_i a (a rigid acceleration): with a
 * pull limit (cloth_set_contact_pull) over m_i a, or none, the contacts
 * hold it (z 0, each pulling m_i a back); under it they let go within the
 * step and the cloth moves off rigidly, v = a h (closed forms).
 * Bad candidates and pull limits are refused naming the argument, the cloth
 * unchanged.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "check.h"

#define N 9
#define H (1.0 / 60.0)

static cloth *make(cloth_nonlinear how, double tilt)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = N;
    d.width = d.height = 0.5;
    d.origin[0] = d.origin[1] = -0.25;
    d.origin[2] = 0.1;
    d.axis_u[0] = cos(tilt);
    d.axis_u[1] = 0.0;
    d.axis_u[2] = sin(tilt);
    d.solver.nonlinear = how;
    d.solver.newton_tolerance = 1e-9;
    d.solver.cg_tolerance = d.solver.newton_cg_tolerance = 1e-10;
    d.solver.cg_max_iterations = 2000;
    d.solver.newton_iterations = 64;
    cloth *c = NULL;
    cloth_error err;
    CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message);
    int n = cloth_vertex_count(c);
    double *v = calloc(3 * (size_t)n, sizeof *v);
    for (int i = 0; i < n; i++) v[3 * i + 2] = -3.0;
    cloth_set_velocities(c, v);
    free(v);
    return c;
}

/* the floor z = 0 as a candidate on every vertex */
static void floor_candidates(cloth *c)
{
    static const double up[3] = {0, 0, 1};
    cloth_release_all(c);
    for (int i = 0; i < cloth_vertex_count(c); i++) {
        const double *x = cloth_positions(c) + 3 * i;
        double p[3] = {x[0], x[1], 0.0};
        cloth_set_contact(c, i, up, p);
    }
}

static double min_z(const cloth *c)
{
    double m = INFINITY;
    for (int i = 0; i < cloth_vertex_count(c); i++) m = fmin(m, cloth_positions(c)[3 * i + 2]);
    return m;
}

static void rigid_landing(void)
{
    cloth *c = make(CLOTH_NEWTON, 0.0);
    if (!c) return;
    int n = cloth_vertex_count(c), landed = -1;
    const double g = cloth_get_desc(c).gravity[2];
    for (int k = 0; k < 20; k++) {
        double z0 = cloth_positions(c)[2], vz0 = cloth_velocities(c)[2];
        floor_candidates(c);
        cloth_step_stats st;
        CHECK(cloth_step(c, H, &st) == CLOTH_OK, "step %d: %s", k, cloth_last_error(c));
        double free_z = z0 + H * (vz0 + H * g);
        if (free_z >= 0.0) {
            CHECK(st.contacts_decided == 0, "step %d above the floor added %d contacts", k, st.contacts_decided);
            continue;
        }
        CHECK(st.contacts_decided == n, "step %d: %d contacts added, expected every vertex (%d)", k,
              st.contacts_decided, n);
        double v_expect = -z0 / H, worst_v = 0.0, worst_z = 0.0, worst_f = 0.0;
        for (int i = 0; i < n; i++) {
            double f[3];
            cloth_constraint_force(c, i, f);
            double imp = cloth_masses(c)[i] * (v_expect - vz0 - H * g);
            worst_v = fmax(worst_v, fabs(cloth_velocities(c)[3 * i + 2] - v_expect));
            worst_z = fmax(worst_z, fabs(cloth_positions(c)[3 * i + 2]));
            worst_f = fmax(worst_f, fabs(H * f[2] - imp) / fabs(imp));
        }
        CHECK(worst_v <= 1e-9 * (1.0 + fabs(v_expect)), "step %d: v1 off -z0/h by %.3g m/s", k, worst_v);
        CHECK(worst_z <= 1e-12, "step %d: a vertex %.3g m off the floor", k, worst_z);
        CHECK(worst_f <= 1e-6, "step %d: contact impulse off m (v1 - v0 - h g) by %.3g of it", k, worst_f);
        if (landed < 0) landed = k;
    }
    CHECK(landed >= 0, "the cloth never reached the floor");
    double vmax = 0.0;
    for (int i = 0; i < 3 * n; i++) vmax = fmax(vmax, fabs(cloth_velocities(c)[i]));
    CHECK(vmax <= 1e-9, "resting on the floor the cloth moves at %.3g m/s", vmax);
    cloth_destroy(c);
}

/* tilted: corners land first; every step ends above the floor within the
 * tolerance, and the contacts' impulses are the momentum change */
static void tilted_landing(void)
{
    cloth *c = make(CLOTH_NEWTON, 0.3);
    if (!c) return;
    int n = cloth_vertex_count(c), added = 0;
    const double g = cloth_get_desc(c).gravity[2];
    double tol = H * cloth_get_desc(c).solver.newton_tolerance;
    for (int k = 0; k < 60; k++) {
        double p0[3] = {0, 0, 0}, p1[3] = {0, 0, 0}, J[3] = {0, 0, 0}, mt = 0.0;
        for (int i = 0; i < n; i++)
            for (int r = 0; r < 3; r++) p0[r] += cloth_masses(c)[i] * cloth_velocities(c)[3 * i + r];
        floor_candidates(c);
        cloth_step_stats st;
        CHECK(cloth_step(c, H, &st) == CLOTH_OK, "step %d: %s", k, cloth_last_error(c));
        added += st.contacts_decided;
        CHECK(min_z(c) >= -tol, "step %d: a vertex %.3g m below the floor", k, -min_z(c));
        for (int i = 0; i < n; i++) {
            double f[3];
            cloth_constraint_force(c, i, f);
            mt += cloth_masses(c)[i];
            for (int r = 0; r < 3; r++) {
                p1[r] += cloth_masses(c)[i] * cloth_velocities(c)[3 * i + r];
                J[r] += H * f[r];
            }
        }
        double scale = mt * (3.0 + fabs(g)) * 1e-6;
        for (int r = 0; r < 3; r++)
            CHECK(fabs(p1[r] - p0[r] - J[r] - (r == 2 ? H * mt * g : 0.0)) <= scale,
                  "step %d axis %d: momentum change %.9g against impulses %.9g", k, r, p1[r] - p0[r],
                  J[r] + (r == 2 ? H * mt * g : 0.0));
    }
    CHECK(added >= n, "the tilted cloth made only %d contacts", added);
    CHECK(min_z(c) < 1e-3, "the tilted cloth did not reach the floor (lowest %.3g m)", min_z(c));
    cloth_destroy(c);
}

static void linearized_ignores(void)
{
    cloth *c = make(CLOTH_LINEARIZED, 0.0);
    if (!c) return;
    for (int k = 0; k < 10; k++) {
        floor_candidates(c);
        cloth_step(c, H, NULL);
    }
    CHECK(min_z(c) < -0.1, "CLOTH_LINEARIZED held the cloth at %.3g m: candidates are Newton's", min_z(c));
    cloth_destroy(c);
}

/* A cloth on the floor, every vertex sticking (pinned where it is, with its
 * contact), its first column pinned and pulled along -x by `pull` in one
 * step: sticking vertices that would hold a link past the elongation limit
 * slide on the floor, so the limit holds; a small pull slides nothing. */
/* A Newton cloth at rest on the floor, every vertex sticking (pinned where
 * it is, with its contact) but its first column, pinned moved by d; x gets
 * the start positions (3n, the caller frees it). */
static cloth *on_floor(const double d[3], double **x)
{
    cloth *c = make(CLOTH_NEWTON, 0.0);
    if (!c) return NULL;
    int n = cloth_vertex_count(c);
    double *p = malloc(3 * (size_t)n * sizeof *p), *v = calloc(3 * (size_t)n, sizeof *v);
    memcpy(p, cloth_positions(c), 3 * (size_t)n * sizeof *p);
    for (int i = 0; i < n; i++) p[3 * i + 2] = 0.0;
    cloth_set_positions(c, p);
    cloth_set_velocities(c, v);
    static const double up[3] = {0, 0, 1};
    for (int i = 0; i < n; i++) {
        double s = i % N ? 0.0 : 1.0, t[3] = {p[3 * i] + s * d[0], p[3 * i + 1] + s * d[1], s * d[2]};
        cloth_pin(c, i, t);
        if (i % N) cloth_set_contact(c, i, up, t);
    }
    free(v);
    *x = p;
    return c;
}

static void sticking_pulled(double pull)
{
    double d[3] = {-pull, 0.0, 0.0}, *x;
    cloth *c = on_floor(d, &x);
    if (!c) return;
    int n = cloth_vertex_count(c);
    cloth_step_stats st;
    CHECK(cloth_step(c, H, &st) == CLOTH_OK, "pull %g: %s", pull, cloth_last_error(c));
    double delta = cloth_get_desc(c).material.delta, worst_z = 0.0, moved = 0.0;
    for (int i = 0; i < n; i++) {
        worst_z = fmax(worst_z, fabs(cloth_positions(c)[3 * i + 2]));
        if (i % N) moved = fmax(moved, fabs(cloth_positions(c)[3 * i] - x[3 * i]));
    }
    CHECK(worst_z <= 1e-9, "pull %g: a vertex %.3g m off the floor", pull, worst_z);
    if (pull > 0.01) {
        CHECK(st.contacts_decided > 0 && moved > 0.0, "pull %g: no sticking contact slid", pull);
        CHECK(cloth_max_strain(c) <= delta + 1e-3 * (1.0 + delta), "pull %g: strain %.5f past the limit %.3f", pull,
              cloth_max_strain(c), delta);
    } else {
        CHECK(st.contacts_decided == 0 && moved <= 1e-12, "pull %g: %d contacts slid, a vertex moved %.3g m", pull,
              st.contacts_decided, moved);
    }
    free(x);
    cloth_destroy(c);
}

/* A cloth sticking to the floor as in sticking_pulled, its first column
 * lifted by `lift` in one step: the contacts next to it, let slide, still
 * hold links past the elongation limit and pull their vertices down: they
 * let go, so the limit holds and those vertices leave the floor. */
static void lifted(double lift)
{
    double d[3] = {0.0, 0.0, lift}, *x;
    cloth *c = on_floor(d, &x);
    if (!c) return;
    int n = cloth_vertex_count(c);
    cloth_step_stats st;
    CHECK(cloth_step(c, H, &st) == CLOTH_OK, "lift %g: %s", lift, cloth_last_error(c));
    double delta = cloth_get_desc(c).material.delta, low = min_z(c), second = INFINITY;
    for (int i = 1; i < n; i += N) second = fmin(second, cloth_positions(c)[3 * i + 2]);
    CHECK(cloth_max_strain(c) <= delta + 1e-3 * (1.0 + delta), "lift %g: strain %.5f past the limit %.3f", lift,
          cloth_max_strain(c), delta);
    CHECK(low >= -H * 1e-9, "lift %g: a vertex %.3g m below the floor", lift, low);
    CHECK(second > 1e-3, "lift %g: the second column stayed on the floor (%.3g m)", lift, second);
    printf("lifted %.2f m: strain %.5f, second column at %.4f m, %d Newton iterations\n", lift, cloth_max_strain(c),
           second, st.newton);
    free(x);
    cloth_destroy(c);
}

/* limit: the pull limit over m_i a (< 0: none set); ndof: 1 sliding
 * contacts, 3 sticking */
static void pull_limited(double limit, int ndof)
{
    cloth *c = make(CLOTH_NEWTON, 0.0);
    if (!c) return;
    const double a = 2.0, zero[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    int n = cloth_vertex_count(c);
    double *f = calloc(3 * (size_t)n, sizeof *f), *x = malloc(3 * (size_t)n * sizeof *x);
    memcpy(x, cloth_positions(c), 3 * (size_t)n * sizeof *x);
    for (int i = 0; i < n; i++) x[3 * i + 2] = 0.0;
    cloth_set_positions(c, x);
    cloth_set_velocities(c, f);
    cloth_set_gravity(c, zero);
    for (int i = 0; i < n; i++) {
        const double m = cloth_masses(c)[i];
        cloth_constraint k = {.vertex = i, .ndof = ndof, .axis = {0, 0, 1}, .target = {x[3 * i], x[3 * i + 1], 0.0}};
        if (ndof == 3) k.axis[2] = 0.0;
        cloth_set_constraint(c, &k);
        cloth_set_contact(c, i, up, k.target);
        if (limit >= 0.0) CHECK(cloth_set_contact_pull(c, i, limit * m * a) == CLOTH_OK, "pull limit refused");
        f[3 * i + 2] = m * a;
    }
    cloth_set_external_forces(c, f);
    cloth_step_stats st;
    CHECK(cloth_step(c, H, &st) == CLOTH_OK, "limit %g: %s", limit, cloth_last_error(c));
    double zerr = 0.0, verr = 0.0, ferr = 0.0;
    int held = limit < 0.0 || limit > 1.0;
    for (int i = 0; i < n; i++) {
        double fc[3], m = cloth_masses(c)[i];
        cloth_constraint_force(c, i, fc);
        zerr = fmax(zerr, fabs(cloth_positions(c)[3 * i + 2] - (held ? 0.0 : a * H * H)));
        verr = fmax(verr, fabs(cloth_velocities(c)[3 * i + 2] - (held ? 0.0 : a * H)));
        ferr = fmax(ferr, fabs(fc[2] + (held ? m * a : 0.0)) / (m * a));
    }
    printf("pull limit %g m a, ndof %d: %s, |z - z*| %.2g m, |v - v*| %.2g m/s, constraint force off by %.2g m a\n",
           limit, ndof, held ? "held" : "let go", zerr, verr, ferr);
    CHECK(zerr <= 1e-9 && verr <= 1e-6 && ferr <= 1e-6,
          "limit %g, ndof %d: z off %.3g m, v off %.3g m/s, force off %.3g m a", limit, ndof, zerr, verr, ferr);
    free(f);
    free(x);
    cloth_destroy(c);
}

static void bad_input(void)
{
    cloth *c = make(CLOTH_NEWTON, 0.0);
    if (!c) return;
    double up[3] = {0, 0, 1}, zero[3] = {0, 0, 0}, p[3] = {0, 0, 0}, nan3[3] = {0, NAN, 0};
    struct {
        int v;
        const double *n, *p;
        const char *word;
    } bad[] = {{0, NULL, p, "normal"}, {0, up, NULL, "point"}, {-1, up, p, "vertex"}, {N * N, up, p, "vertex"},
               {0, zero, p, "normal"}, {0, nan3, p, "normal"}, {0, up, nan3, "point"}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        CHECK(cloth_set_contact(c, bad[k].v, bad[k].n, bad[k].p) == CLOTH_EINVAL, "bad case %zu accepted", k);
        CHECK(strstr(cloth_last_error(c), bad[k].word) != NULL, "case %zu: '%s' does not name %s", k,
              cloth_last_error(c), bad[k].word);
    }
    for (int i = 0; i < N * N; i++) CHECK(c->cand_on[i] == 0, "a refused candidate was set on vertex %d", i);
    CHECK(cloth_set_contact(NULL, 0, up, p) == CLOTH_EINVAL, "NULL cloth accepted");
    double big[3] = {0, 0, 1e300};
    CHECK(cloth_set_contact(c, 3, big, p) == CLOTH_OK, "a huge normal refused");
    CHECK(fabs(c->cand[6 * 3 + 2] - 1.0) <= 1e-15, "a huge normal normalised to %.17g", c->cand[6 * 3 + 2]);
    CHECK(cloth_release(c, 3) == CLOTH_OK && c->cand_on[3] == 0, "cloth_release left the candidate");
    struct {
        int v;
        double pull;
        const char *word;
    } badp[] = {{0, NAN, "pull"},
                {0, -1.0, "pull"},
                {-1, 1.0, "vertex"},
                {N * N, 1.0, "vertex"},
                {5, 1.0, "no contact"}};
    CHECK(cloth_set_contact(c, 0, up, p) == CLOTH_OK && cloth_set_contact_pull(c, 0, 2.0) == CLOTH_OK, "pull set");
    for (size_t k = 0; k < sizeof badp / sizeof badp[0]; k++) {
        CHECK(cloth_set_contact_pull(c, badp[k].v, badp[k].pull) == CLOTH_EINVAL, "bad pull %zu accepted", k);
        CHECK(strstr(cloth_last_error(c), badp[k].word) != NULL, "pull case %zu: '%s' does not name %s", k,
              cloth_last_error(c), badp[k].word);
    }
    CHECK(c->cand_pull[0] == 2.0 && isinf(c->cand_pull[5]), "a refused pull limit changed the cloth");
    CHECK(cloth_set_contact_pull(NULL, 0, 1.0) == CLOTH_EINVAL, "NULL cloth accepted");
    cloth_destroy(c);
}

int main(void)
{
    rigid_landing();
    tilted_landing();
    linearized_ignores();
    lifted(0.1);
    sticking_pulled(0.05);
    sticking_pulled(1e-4);
    for (int ndof = 1; ndof <= 3; ndof += 2) {
        pull_limited(-1.0, ndof);
        pull_limited(2.0, ndof);
        pull_limited(0.5, ndof);
    }
    bad_input();
    return check_summary();
}
