/* Unit: tension plasticity of sequential links (material.tension_yield y, tension_set s;
 * core/src/tension_plastic.c, docs/materials.md) against its closed forms.
 *
 *   - the rule: a link of rest l0 taken through random lengths d keeps the rest length
 *     lp = l0 + s (min(d_max, (1 + delta) l0) - (1 + y) l0) (d_max its longest so far, past the yield;
 *     l0 below it), computed here in lengths, to 4 ulp of l0; below the yield the set stays 0 bit for bit;
 *     y = 0 or s = 0 changes nothing; lp never passes l0 + s (delta - y) l0 nor the limit, which stays at
 *     (1 + delta) l0;
 *   - a 3 x 17 strip, every vertex pinned and moved affinely to a stretch e past y, then held: each
 *     sequential link's rest length (cloth_get_link) is the closed form at its own length (rows: past the
 *     yield; diagonals, stretched less: below it; columns: unchanged);
 *   - released (the first column pinned, the others free along the strip only) it settles, away from the
 *     free end, at the stretch where the rows' and diagonals' tensions cancel, found here by bisection on
 *     the closed-form laws: longer than at the start (the knee bag), the sets unchanged by the release;
 *     with the option off the strip returns to its length; below the yield the runs with the option on
 *     and off are the same bit for bit;
 *   - the sets are state: restoring a state saved before them clears them, one saved after them brings
 *     them back;
 *   - forces are minus the energy's gradient (central differences) on a cloth carrying sets;
 *   - a square cloth hung by two edges, pushed 4 cm down at its centre (a knee) and let go, bags deeper
 *     with the option than without.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "check.h"

static cloth_material tensile(double yield, double share)
{
    cloth_material m = cloth_material_preset(CLOTH_COTTON);
    m.delta = 0.1;
    m.tension_yield = yield;
    m.tension_set = share;
    return m;
}

/* the rule's closed form in lengths: the rest length after the longest stretch dmax */
static double closed_rest(const cloth_material *m, double l0, double dmax)
{
    double y = (1.0 + m->tension_yield) * l0, lim = (1.0 + m->delta) * l0;
    if (m->tension_yield <= 0.0 || dmax <= y) return l0;
    return l0 + m->tension_set * (fmin(dmax, lim) - y);
}

static void check_rule(void)
{
    rng g = rng_seed(0x7e45u);
    const double l0 = 0.05;
    const double ys[] = {0.01, 0.03, 0.1}, ss[] = {0.25, 0.5, 1.0};
    int past = 0, worst_ulp = 0;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            cloth_material m = tensile(ys[a], ss[b]);
            double set = 0.0, dmax = 0.0;
            for (int k = 0; k < 400; k++) {
                double d = l0 * rng_range(&g, 0.8, 1.2);
                set = oc_tension_set_rule(&m, l0, d, set);
                dmax = fmax(dmax, d);
                double lp = seq_law(&m, l0, set).rest, want = closed_rest(&m, l0, dmax);
                int ulp = (int)ceil(fabs(lp - want) / (l0 * 0x1p-52));
                if (ulp > worst_ulp) worst_ulp = ulp;
                CHECK(ulp <= 4, "y %g s %g: lp %.17g, closed form %.17g", ys[a], ss[b], lp, want);
                if (dmax <= (1.0 + m.tension_yield) * l0)
                    CHECK(set == 0.0, "y %g s %g: below the yield (dmax %g l0) set %g", ys[a], ss[b], dmax / l0, set);
                past += set > 0.0;
                CHECK(lp <= l0 + m.tension_set * (m.delta - m.tension_yield) * l0 * (1.0 + 1e-15) &&
                          lp <= (1.0 + m.delta) * l0,
                      "y %g s %g: lp %.17g past its bound", ys[a], ss[b], lp);
                CHECK(seq_law(&m, l0, set).lim == (1.0 + m.delta) * l0, "the limit moved");
            }
        }
    CHECK(past > 1000, "only %d of the walks' lengths carried a set: the walks do not test the rule", past);
    /* off: either field 0 */
    cloth_material off1 = tensile(0.0, 0.5), off2 = tensile(0.02, 0.0);
    CHECK(oc_tension_set_rule(&off1, l0, 1.09 * l0, 0.0) == 0.0 &&
              oc_tension_set_rule(&off2, l0, 1.09 * l0, 0.0) == 0.0,
          "a rule that is off set a link");
    CHECK(!oc_tension_plastic_on(&off1) && !oc_tension_plastic_on(&off2), "oc_tension_plastic_on with a zero field");
    /* a set beyond the limit (delta lowered after it formed) is held at the limit */
    cloth_material lowered = tensile(0.01, 0.5);
    lowered.delta = 0.02;
    CHECK(seq_law(&lowered, l0, 0.5).rest == (1.0 + lowered.delta) * l0, "a rest length past the limit");
    printf("rule: 9 materials x 400 lengths, %d with a set, worst %d ulp of l0 from the closed form\n", past,
           worst_ulp);
}

/* ------------------------------------------------------------ the strip */

#define SR 3
#define SC 17   /* long enough that the free end's boundary layer (a third per column) is 1e-10 at column 4 */
#define SM 4    /* the column measured */
#define SA 0.03 /* m, column spacing */
#define SB 0.06 /* m, row spacing: the diagonals stretch less than a third as much as the rows, below the yield */

/* the strip's material: m with the sequential links alone (a closed-form equilibrium) and damped */
static cloth_material strip_material(const cloth_material *m)
{
    cloth_material s = *m;
    s.k_b = s.k_s = 0.0;
    s.k_c = s.k_t; /* the rows' set pushes as hard as the diagonals hold */
    s.c_t = 0.5;   /* settles in a few hundred steps */
    return s;
}

static cloth *strip(const cloth_material *m)
{
    cloth_desc d = cloth_default_desc();
    d.rows = SR;
    d.cols = SC;
    d.width = SA * (SC - 1);
    d.height = SB * (SR - 1);
    d.origin[0] = d.origin[1] = d.origin[2] = 0.0;
    d.gravity[2] = 0.0;
    d.material = strip_material(m);
    d.solver.nonlinear = CLOTH_LINEARIZED; /* its fixed point is the equilibrium, to the CG's tolerance */
    d.solver.cg_tolerance = 1e-10;
    cloth *c = NULL;
    cloth_error err;
    CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create the strip: %s", err.message);
    return c;
}

/* every vertex pinned at its rest position stretched by 1 + e along x (the first column fixed) */
static void pin_affine(cloth *c, const double *x0, double e)
{
    for (int i = 0; i < SR * SC; i++) {
        double t[3] = {x0[3 * i] * (1.0 + e), x0[3 * i + 1], x0[3 * i + 2]};
        cloth_pin(c, i, t);
    }
}

/* the first column pinned where it is, the others free along x only */
static void release_along_x(cloth *c)
{
    const double *x = cloth_positions(c);
    for (int i = 0; i < SR * SC; i++) {
        cloth_constraint k = {i, i % SC == 0 ? 3 : 2, {1.0, 0.0, 0.0}, {x[3 * i], x[3 * i + 1], x[3 * i + 2]}};
        CHECK(cloth_set_constraint(c, &k) == CLOTH_OK, "constraint %d: %s", i, cloth_last_error(c));
    }
}

/* tension of a sequential link of rest l0 and rest length lp at length d (paper eq. 6-7, the limit) */
static double link_tension(const cloth_material *m, double l0, double lp, double d)
{
    double lim = (1.0 + m->delta) * l0;
    return (d >= lp ? m->k_t : m->k_c) * (d - lp) + (d > lim ? m->k_delta * m->k_t * (d - lim) : 0.0);
}

/* x-force across a cut of the strip stretched by r: SR horizontal links, 2 (SR - 1) diagonals */
static double cut_force(const cloth_material *m, double lph, double lpd, double r)
{
    double dd = sqrt(SA * r * SA * r + SB * SB), l0d = sqrt(SA * SA + SB * SB);
    return SR * link_tension(m, SA, lph, SA * r) + 2 * (SR - 1) * link_tension(m, l0d, lpd, dd) * SA * r / dd;
}

/* the released strip's stretch: the root of cut_force between 1 and 1 + e */
static double released_stretch(const cloth_material *m0, double e)
{
    cloth_material sm = strip_material(m0), *m = &sm;
    double l0d = sqrt(SA * SA + SB * SB), dd = sqrt(SA * (1 + e) * SA * (1 + e) + SB * SB);
    double lph = closed_rest(m, SA, SA * (1 + e)), lpd = closed_rest(m, l0d, dd), lo = 1.0, hi = 1.0 + e;
    if (!CHECK(cut_force(m, lph, lpd, lo) <= 0.0 && cut_force(m, lph, lpd, hi) >= 0.0, "bracket")) return NAN;
    for (int k = 0; k < 200; k++) {
        double mid = 0.5 * (lo + hi);
        if (cut_force(m, lph, lpd, mid) > 0.0) hi = mid;
        else lo = mid;
    }
    return 0.5 * (lo + hi);
}

/* pulled to 1 + e over 40 steps, held 20, released 600; returns the stretch of its first SM columns */
static double pull_hold_release(const cloth_material *m, double e, cloth_state *held, cloth_state *end)
{
    cloth *c = strip(m);
    if (!c) return NAN;
    const double h = 0.01;
    double *x0 = malloc(3 * SR * SC * sizeof *x0);
    memcpy(x0, cloth_positions(c), 3 * SR * SC * sizeof *x0);
    for (int k = 1; k <= 60; k++) {
        pin_affine(c, x0, e * (k < 40 ? k / 40.0 : 1.0));
        CHECK(cloth_step(c, h, NULL) == CLOTH_OK, "pull step %d: %s", k, cloth_last_error(c));
    }
    cloth_save(c, held);
    /* held: each link's rest length is the closed form at its own length */
    for (int e2 = 0; e2 < cloth_link_count(c, CLOTH_SEQUENTIAL); e2++) {
        cloth_link L;
        cloth_get_link(c, CLOTH_SEQUENTIAL, e2, &L);
        const double *xi = cloth_positions(c) + 3 * L.i, *xj = cloth_positions(c) + 3 * L.j;
        double dx = xj[0] - xi[0], dy = xj[1] - xi[1], dz = xj[2] - xi[2];
        double d = sqrt(dx * dx + dy * dy + dz * dz), want = closed_rest(m, L.rest, d);
        CHECK_NEAR(L.l1, want, 1e-12 * L.rest);
    }
    release_along_x(c);
    for (int k = 0; k < 600; k++)
        CHECK(cloth_step(c, h, NULL) == CLOTH_OK, "release step %d: %s", k, cloth_last_error(c));
    cloth_save(c, end);
    double len = cloth_positions(c)[3 * SM] - cloth_positions(c)[0];
    cloth_destroy(c);
    free(x0);
    return len / (SA * SM);
}

/* the sets of two states (of the same strip) agree bit for bit */
static int same_sets(cloth_state *a, cloth_state *b)
{
    int q = a->n_seq, same = 1;
    for (int e = 0; e < q; e++) same = same && a->seq_set[e] == b->seq_set[e];
    return same;
}

static void check_strip(void)
{
    const double e = 0.06;
    cloth_material on = tensile(0.02, 0.5), off = tensile(0.0, 0.0);
    cloth *probe = strip(&on);
    if (!probe) return;
    cloth_state *held = cloth_state_create(probe), *end = cloth_state_create(probe);
    cloth_state *held0 = cloth_state_create(probe), *end0 = cloth_state_create(probe);
    double r = pull_hold_release(&on, e, held, end), want = released_stretch(&on, e);
    CHECK_NEAR(r, want, 1e-9);
    CHECK(r > 1.0 + 0.5 * on.tension_set * (e - on.tension_yield), "released stretch %.6f: no knee bag", r);
    CHECK(same_sets(held, end), "the release changed a set");
    double r0 = pull_hold_release(&off, e, held0, end0);
    CHECK_NEAR(r0, 1.0, 1e-9);
    printf("strip pulled to 1 + %.2f (yield %.2f, share %.2f), released: %.9f (closed form %.9f, off by %.2g), "
           "off %.9f\n",
           e, on.tension_yield, on.tension_set, r, want, fabs(r - want), r0);
    /* below the yield: the same run as with the option off, bit for bit */
    double rb = pull_hold_release(&on, 0.5 * on.tension_yield, held, end);
    double rb0 = pull_hold_release(&off, 0.5 * on.tension_yield, held0, end0);
    CHECK(rb == rb0 && cloth_state_diff(held, held0) == 0.0 && cloth_state_diff(end, end0) == 0.0,
          "below the yield the run differs from the option off: %.17g vs %.17g", rb, rb0);
    cloth_state_destroy(held);
    cloth_state_destroy(end);
    cloth_state_destroy(held0);
    cloth_state_destroy(end0);
    cloth_destroy(probe);
}

/* --------------------------------------------------- forces, energy */

/* sequential links carrying a set; each one's rest length in use is l0 exactly when it carries none */
static int count_set(const cloth *c)
{
    int n = 0;
    for (int e = 0; e < cloth_link_count(c, CLOTH_SEQUENTIAL); e++) {
        cloth_link L;
        cloth_get_link(c, CLOTH_SEQUENTIAL, e, &L);
        CHECK((L.l1 == L.rest) == !L.plastic, "link %d: plastic %d, l1 %.17g, l0 %.17g", e, L.plastic, L.l1, L.rest);
        n += L.plastic;
    }
    return n;
}

static void check_gradient(void)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 5;
    d.width = d.height = 0.2;
    d.material = tensile(0.01, 0.7);
    cloth *c = NULL;
    if (!CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK, "create")) return;
    int n = cloth_vertex_count(c), n3 = 3 * n;
    double *x = malloc((size_t)n3 * sizeof *x), *f = malloc((size_t)n3 * sizeof *f);
    double *v = calloc((size_t)n3, sizeof *v);
    rng g = rng_seed(0x91adu);
    memcpy(x, cloth_positions(c), (size_t)n3 * sizeof *x);
    for (int k = 0; k < n3; k++) x[k] = x[k] * 1.05 + rng_range(&g, -2e-3, 2e-3); /* past the yield, unevenly */
    cloth_state *fresh = cloth_state_create(c), *set = cloth_state_create(c);
    cloth_save(c, fresh);
    cloth_set_positions(c, x);
    cloth_update_plastic(c);
    int nset = count_set(c);
    CHECK(nset > 20, "only %d links set", nset);
    /* the sets are state: a state saved before them restores none, the one after them all */
    cloth_save(c, set);
    cloth_restore(c, fresh);
    CHECK(count_set(c) == 0 && cloth_state_diff(fresh, set) > 0.0, "restored before the sets: %d set", count_set(c));
    cloth_restore(c, set);
    CHECK(count_set(c) == nset, "restored after the sets: %d set, want %d", count_set(c), nset);
    cloth_state_destroy(fresh);
    cloth_state_destroy(set);
    for (int k = 0; k < n3; k++) x[k] += rng_range(&g, -3e-3, 3e-3); /* some links taut, some slack */
    cloth_set_positions(c, x);
    cloth_set_velocities(c, v);
    cloth_internal_forces(c, f);
    double worst = 0.0, fmaxabs = 0.0;
    for (int k = 0; k < n3; k++) {
        const double step = 1e-7;
        double xk = x[k];
        x[k] = xk + step;
        cloth_set_positions(c, x);
        double ep = cloth_energies(c).elastic;
        x[k] = xk - step;
        cloth_set_positions(c, x);
        double em = cloth_energies(c).elastic;
        x[k] = xk;
        worst = fmax(worst, fabs(f[k] + (ep - em) / (2 * step)));
        fmaxabs = fmax(fmaxabs, fabs(f[k]));
    }
    CHECK(worst <= 1e-8 * fmaxabs, "force vs -dE/dx: worst %.3g N of %.3g N", worst, fmaxabs);
    printf("gradient: %d links set; |f + dE/dx| worst %.3g N of %.3g N\n", nset, worst, fmaxabs);
    free(x);
    free(f);
    free(v);
    cloth_destroy(c);
}

/* ------------------------------------------------------ the knee bag */

/* a 13 x 13 cloth hung by two opposite edges, its centre pushed `push` m down over 0.4 s, held 0.2 s, let
 * go for 2 s: the centre's height below the edges at the end */
static double knee(const cloth_material *m, double push)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 13;
    d.width = d.height = 0.36;
    d.material = *m;
    cloth *c = NULL;
    if (!CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK, "create the knee cloth")) return NAN;
    const int N = 13, mid = 6 * N + 6;
    const double *x = cloth_positions(c), z0 = x[2], c0[3] = {x[3 * mid], x[3 * mid + 1], x[3 * mid + 2]};
    for (int r = 0; r < N; r++) {
        cloth_pin(c, r * N, x + 3 * r * N);
        cloth_pin(c, r * N + N - 1, x + 3 * (r * N + N - 1));
    }
    const double h = 1.0 / 60;
    for (int k = 1; k <= 36; k++) {
        double t[3] = {c0[0], c0[1], c0[2] - push * (k < 24 ? k / 24.0 : 1.0)};
        cloth_pin(c, mid, t);
        CHECK(cloth_step(c, h, NULL) == CLOTH_OK, "knee step %d: %s", k, cloth_last_error(c));
    }
    cloth_release(c, mid);
    for (int k = 0; k < 120; k++) CHECK(cloth_step(c, h, NULL) == CLOTH_OK, "hang step %d", k);
    double sag = z0 - cloth_positions(c)[3 * mid + 2];
    cloth_destroy(c);
    return sag;
}

static void check_knee(void)
{
    cloth_material on = tensile(0.01, 0.8), off = tensile(0.0, 0.0);
    double s_on = knee(&on, 0.04), s_off = knee(&off, 0.04);
    CHECK(s_on > s_off + 2e-3, "a knee bag: the centre sags %.4f m with the option, %.4f without", s_on, s_off);
    printf("knee bag: centre %.4f m below the edges with tension plasticity, %.4f without\n", s_on, s_off);
}

int main(void)
{
    check_rule();
    check_strip();
    check_gradient();
    check_knee();
    return check_summary();
}
