/* Unit: the crease law (material.k_crease; core/src/crease_law.c, docs/materials.md "The crease law") against
 * its closed forms.
 *
 *   - the rule: a link taken through random fold angles phi keeps the set angle
 *     s = clamp(s, phi - y, phi + y) (y = 2 acos(alpha), s >= 0), as the chord l1 = l0 cos(s / 2), to 1e-12 of
 *     l0; alpha 0 never sets; a set unchanged keeps l1 bit for bit;
 *   - a single hinge held at an angle: a cloth folded along its middle column by 150 degrees (alpha 0.7, so
 *     the interlaced links across the crease set, the diagonals, turned 86 degrees, do not), then opened to
 *     phi: each crossing link's l1 is l0 cos((150 deg - y) / 2); the force on a crease node is the hinge's
 *     k_crease (s_p - |s|) along the sagitta, s_p = h sin(s / 2), |s| = h sin(phi / 2); the energy's
 *     derivative in phi (central differences) is minus the moment k (s_p - |s|) h cos(phi / 2) / 2 per hinge,
 *     and flat, the moment per length is 2 S sin(s / 2) with S the fabric's crease_stiffness;
 *   - grid independence: the same fabric (crease_stiffness S, its k_crease derived for 9 x 9 and 17 x 17
 *     grids of 1 m), folded by 170 degrees at alpha 0.8 (the diagonals set too), opened to 10 degrees: the
 *     moment per length of crease, by central differences of the interior hinges' energy, is the same on
 *     both grids;
 *   - forces are minus the energy's gradient (central differences), and the linearised step's K w and the
 *     Newton matrix's hinge blocks are the forces' derivative, on a crumpled cloth carrying sets;
 *   - in the step: a crease set by 170 degrees, laid flat but for 0.001 rad and let go without gravity,
 *     folds again past half its set within 2 s (Newton and linearised solvers); with the paper's rule it
 *     stays flat.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "odecloth/fabric.h"
#include "internal.h"
#include "bsr.h"
#include "check.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)

static double clampd(double v, double lo, double hi) { return v < lo ? lo : v > hi ? hi : v; }

static void check_rule(void)
{
    rng g = rng_seed(0xc4ea5eu);
    const double l0 = 0.1, alphas[] = {0.0, 0.3, 0.5, 0.8, 1.0};
    double worst = 0.0;
    int sets = 0, bitwise = 1;
    for (int a = 0; a < 5; a++) {
        double y = 2.0 * acos(alphas[a]), s = 0.0, l1 = l0;
        int plastic = 0;
        for (int k = 0; k < 500; k++) {
            double phi = rng_range(&g, 0.0, PI), d = l0 * cos(0.5 * phi), before = l1;
            double phid = oc_crease_fold_angle(l0, d); /* the angle the rule reads, phi to rounding */
            double s_new = clampd(clampd(s, phid - y, phid + y), 0.0, PI);
            oc_crease_rule(alphas[a], l0, d, &plastic, &l1);
            double want = l0 * cos(0.5 * s_new);
            if (s_new == s && plastic) bitwise &= l1 == before;
            s = s_new;
            worst = fmax(worst, fabs((plastic ? l1 : l0) - want) / l0);
            CHECK(plastic == (s > 1e-12) || fabs(s) < 1e-7, "alpha %g: plastic %d with set %g rad", alphas[a], plastic,
                  s);
            sets += plastic;
        }
        if (alphas[a] == 0.0) CHECK(!plastic && l1 == l0, "alpha 0 set a link (l1 %g)", l1);
    }
    CHECK(worst <= 1e-12, "l1 against l0 cos(s / 2): worst %.3g of l0", worst);
    CHECK(bitwise, "a set left unchanged moved l1");
    CHECK(sets > 500, "only %d of the walk's steps carried a set", sets);
    /* one history in figures: folded 150 degrees at alpha 0.8, flattened, folded 100 degrees */
    int p = 0;
    double l1 = l0, y = 2.0 * acos(0.8);
    oc_crease_rule(0.8, l0, l0 * cos(75.0 * DEG), &p, &l1);
    CHECK(p && fabs(l1 - l0 * cos(0.5 * (150.0 * DEG - y))) <= 1e-14, "150 deg: l1 %.17g", l1);
    oc_crease_rule(0.8, l0, l0, &p, &l1);
    CHECK(p && fabs(l1 - l0 * cos(0.5 * y)) <= 1e-14, "flattened: set %g deg, want the yield %g deg",
          2.0 * acos(l1 / l0) / DEG, y / DEG);
    double kept = l1;
    oc_crease_rule(0.8, l0, l0 * cos(50.0 * DEG), &p, &l1);
    CHECK(p && l1 == kept, "folded 100 deg within the yield of the set: l1 moved");
}

/* an n x n cloth of 1 m, k_b 0 (only the hinges store energy across a kink), the fabric's crease law */
static cloth *make_cloth(int n, double alpha, double S)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = n;
    d.width = d.height = 1.0;
    cloth_fabric f = cloth_fabric_preset(CLOTH_FABRIC_COTTON);
    f.crease_stiffness = S;
    f.bend_curvature = 5.0; /* coarse grids allowed */
    if (cloth_fabric_apply(&f, &d, NULL) != CLOTH_OK) return NULL;
    d.material.alpha = alpha;
    d.material.k_b = 0.0;
    d.material.c_b = d.material.c_t = 0.0;
    cloth *c = NULL;
    return cloth_create(&d, &c, NULL) == CLOTH_OK ? c : NULL;
}

/* positions folded by phi along the middle column: the left half in z = 0, the right turned about y */
static void fold(int n, double phi, double *x)
{
    double h = 1.0 / (n - 1);
    int mid = (n - 1) / 2;
    for (int r = 0; r < n; r++)
        for (int col = 0; col < n; col++) {
            double u = (col - mid) * h, *p = x + 3 * (r * n + col);
            p[0] = u <= 0.0 ? u : u * cos(phi);
            p[1] = r * h;
            p[2] = u <= 0.0 ? 0.0 : u * sin(phi);
        }
}

/* the hinges' energy whose middle node lies in an interior row (the same share of every grid) */
static double interior_energy(const cloth *c, int n, const double *x)
{
    double E = 0.0;
    for (int e = 0; e < c->n_int; e++) {
        int m = (c->lint[e].i + c->lint[e].j) / 2, row = m / n;
        if (c->st.plastic[e] && row > 0 && row < n - 1) E += oc_crease_hinge(c, e, x, x, NULL, NULL);
    }
    return E;
}

static void check_single_hinge(void)
{
    const int n = 9;
    const double S = 0.02, alpha = 0.7, h = 1.0 / (n - 1), y = 2.0 * acos(alpha), phif = 150.0 * DEG;
    cloth *c = make_cloth(n, alpha, S);
    CHECK(c != NULL, "cloth");
    if (!c) return;
    double *x = malloc(3 * (size_t)c->n * sizeof *x), *f = malloc(3 * (size_t)c->n * sizeof *f);
    fold(n, phif, x);
    cloth_set_positions(c, x);
    int count = cloth_update_plastic(c), across = 0, others = 0;
    double setang = phif - y, l1err = 0.0;
    for (int e = 0; e < c->n_int; e++) {
        const link_topo *L = c->lint + e;
        int m = (L->i + L->j) / 2, straight = L->j - L->i == 2;
        if (m % n == (n - 1) / 2 && straight) {
            across += c->st.plastic[e];
            l1err = fmax(l1err, fabs(c->st.l1[e] - L->rest * cos(0.5 * setang)));
        } else {
            others += c->st.plastic[e];
        }
    }
    CHECK(across == n && others == 0 && count == n, "set links: %d across (want %d), %d others", across, n, others);
    CHECK(l1err <= 1e-15, "l1 of the crossing links: off by %.3g m", l1err);
    const double K = c->desc.material.k_crease, sp = h * sin(0.5 * setang);
    CHECK(fabs(K - 4.0 * S / h) <= 1e-14 * K, "k_crease %g, want 4 S / h", K);
    /* opened to 30 degrees: the force on an interior crease node, and the moment by the energy's slope */
    const double phi = 30.0 * DEG, dphi = 1e-5;
    fold(n, phi, x);
    cloth_set_positions(c, x);
    oc_forces_eval(c, x, x, 0, f);
    int node = 4 * n + (n - 1) / 2;
    double s_len = h * sin(0.5 * phi), want = K * (sp - s_len), dir[3] = {sin(0.5 * phi), 0.0, -cos(0.5 * phi)};
    double ferr = 0.0; /* along the sagitta x_m - (x_i + x_j) / 2, deepening the fold */
    for (int r = 0; r < 3; r++) ferr = fmax(ferr, fabs(f[3 * node + r] - want * dir[r]));
    CHECK(want > 0.0 && ferr <= 1e-9 * want,
          "force on the crease node off by %.3g N, want k (s_p - |s|) = %.12g N "
          "along the sagitta",
          ferr, want);
    double E[2];
    for (int k = 0; k < 2; k++) {
        fold(n, phi + (k ? dphi : -dphi), x);
        cloth_set_positions(c, x);
        E[k] = cloth_energies(c).elastic;
    }
    double moment = -(E[1] - E[0]) / (2.0 * dphi) / n, closed = K * (sp - s_len) * h * cos(0.5 * phi) / 2.0;
    CHECK(fabs(moment - closed) <= 1e-6 * closed, "moment per hinge %.10g N m, closed form %.10g", moment, closed);
    /* flat: the moment per length 2 S sin(s / 2), the force along the sagitta as the step began */
    CHECK(fabs(K * sp * h / 2.0 / h - 2.0 * S * sin(0.5 * setang)) <= 1e-14, "flat moment per length: the derivation");
    double *x0 = malloc(3 * (size_t)c->n * sizeof *x0), fm[3];
    fold(n, 1e-3, x0);
    fold(n, 0.0, x);
    int e_node = -1;
    for (int e = 0; e < c->n_int && e_node < 0; e++)
        if ((c->lint[e].i + c->lint[e].j) / 2 == node && c->lint[e].j - c->lint[e].i == 2) e_node = e;
    oc_crease_hinge(c, e_node, x, x0, fm, NULL);
    double fmn = sqrt(fm[0] * fm[0] + fm[1] * fm[1] + fm[2] * fm[2]);
    CHECK(fabs(fmn - K * sp) <= 1e-9 * K * sp && fm[2] > 0.0,
          "flat: hinge force %.12g N (z %.3g), want k s_p = %.12g N, the ends up as the fold began", fmn, fm[2],
          K * sp);
    free(x0);
    free(x);
    free(f);
    cloth_destroy(c);
}

/* the moment per length of crease at the fold angle phi of a cloth set by folding to phif */
static double moment_per_length(int n, double alpha, double S, double phif, double phi)
{
    cloth *c = make_cloth(n, alpha, S);
    if (!c) return NAN;
    double *x = malloc(3 * (size_t)c->n * sizeof *x), dphi = 1e-5, E[2];
    fold(n, phif, x);
    cloth_set_positions(c, x);
    cloth_update_plastic(c);
    for (int k = 0; k < 2; k++) {
        fold(n, phi + (k ? dphi : -dphi), x);
        E[k] = interior_energy(c, n, x);
    }
    free(x);
    cloth_destroy(c);
    double h = 1.0 / (n - 1);
    return -(E[1] - E[0]) / (2.0 * dphi) / ((n - 2) * h);
}

static void check_grids(void)
{
    const double S = 0.02;
    double m9 = moment_per_length(9, 0.8, S, 170.0 * DEG, 10.0 * DEG);
    double m17 = moment_per_length(17, 0.8, S, 170.0 * DEG, 10.0 * DEG);
    printf("moment per length at 10 deg (set by 170 deg, alpha 0.8): 9 x 9 %.9g N, 17 x 17 %.9g N\n", m9, m17);
    CHECK(m9 > 0.0 && fabs(m9 - m17) <= 1e-6 * m9, "moment per length %.9g N on 9 x 9, %.9g N on 17 x 17", m9, m17);
    /* the diagonals set too: more than the crossing links alone */
    double y = 2.0 * acos(0.8), sp = sin(0.5 * (170.0 * DEG - y)),
           only = 4.0 * S * (sp - sin(5.0 * DEG)) * cos(5.0 * DEG) / 2.0;
    CHECK(m9 > 1.01 * only, "moment %.6g N: the diagonals add to the crossing links' %.6g N", m9, only);
}

static void check_derivatives(void)
{
    const int n = 9;
    cloth *c = make_cloth(n, 0.6, 0.05);
    CHECK(c != NULL, "cloth");
    if (!c) return;
    size_t n3 = 3 * (size_t)c->n;
    double *x = malloc(n3 * sizeof *x), *x0 = malloc(n3 * sizeof *x0), *w = malloc(n3 * sizeof *w);
    double *f = calloc(n3, sizeof *f), *fp = calloc(n3, sizeof *fp), *fm = calloc(n3, sizeof *fm);
    double *kw = calloc(n3, sizeof *kw), *aw = malloc(n3 * sizeof *aw);
    rng g = rng_seed(0x5e7u);
    /* crumpled: a fold of 160 degrees with random bumps sets the middle column, opened to 30 degrees */
    fold(n, 160.0 * DEG, x);
    for (size_t k = 0; k < n3; k++) x[k] += 0.01 * rng_range(&g, -1.0, 1.0);
    cloth_set_positions(c, x);
    int sets = cloth_update_plastic(c);
    fold(n, 30.0 * DEG, x);
    for (size_t k = 0; k < n3; k++) x[k] += 0.01 * rng_range(&g, -1.0, 1.0);
    for (size_t k = 0; k < n3; k++) {
        x0[k] = x[k] + 0.01 * rng_range(&g, -1.0, 1.0); /* the step's start: the hinges' directions */
        w[k] = rng_range(&g, -1.0, 1.0);
    }
    oc_crease_forces(c, x, x0, 1.0, f);
    double eps = 1e-6, gerr = 0.0, gmax = 0.0;
    for (size_t k = 0; k < n3; k++) {
        double keep = x[k];
        x[k] = keep + eps;
        double Ep = oc_crease_energy(c, x, x0);
        x[k] = keep - eps;
        double Em = oc_crease_energy(c, x, x0);
        x[k] = keep;
        gerr = fmax(gerr, fabs(-(Ep - Em) / (2.0 * eps) - f[k]));
        gmax = fmax(gmax, fabs(f[k]));
    }
    CHECK(sets > 0 && gmax > 0.0 && gerr <= 1e-7 * gmax, "forces against the energy: %.3g of %.3g (%d set)", gerr, gmax,
          sets);
    /* K w: the forces' derivative along w, the hinge's direction that of x itself */
    for (size_t k = 0; k < n3; k++) aw[k] = x[k] + eps * w[k];
    oc_crease_forces(c, aw, x, 1.0, fp);
    for (size_t k = 0; k < n3; k++) aw[k] = x[k] - eps * w[k];
    oc_crease_forces(c, aw, x, 1.0, fm);
    oc_crease_Kw(c, x, w, kw);
    double kerr = 0.0, kmax = 0.0;
    for (size_t k = 0; k < n3; k++) {
        kerr = fmax(kerr, fabs((fp[k] - fm[k]) / (2.0 * eps) - kw[k]));
        kmax = fmax(kmax, fabs(kw[k]));
    }
    CHECK(kmax > 0.0 && kerr <= 1e-6 * kmax, "K w against the forces' differences: %.3g of %.3g", kerr, kmax);
    /* the Newton matrix's hinge blocks: A w = -(df/dx) w */
    oc_bsr_zero(&c->A);
    oc_crease_matrix(c, x, x, 1.0);
    oc_bsr_mul(&c->A, w, aw);
    double aerr = 0.0;
    for (size_t k = 0; k < n3; k++) aerr = fmax(aerr, fabs(aw[k] + kw[k]));
    CHECK(aerr <= 1e-12 * kmax, "the matrix's hinge blocks against K w: %.3g of %.3g", aerr, kmax);
    free(x), free(x0), free(w), free(f), free(fp), free(fm), free(kw), free(aw);
    cloth_destroy(c);
}

/* the turning angle at the middle column of row r */
static double turning(const cloth *c, int n, int r)
{
    const double *x = cloth_positions(c);
    int m = r * n + (n - 1) / 2;
    double a[3], b[3], ab = 0.0, aa = 0.0, bb = 0.0;
    for (int k = 0; k < 3; k++) {
        a[k] = x[3 * m + k] - x[3 * (m - 1) + k];
        b[k] = x[3 * (m + 1) + k] - x[3 * m + k];
        ab += a[k] * b[k], aa += a[k] * a[k], bb += b[k] * b[k];
    }
    return acos(clampd(ab / sqrt(aa * bb), -1.0, 1.0));
}

/* A crease set by a fold of 170 degrees (alpha 0.8), laid flat but for 0.001 rad and let go without
 * gravity: with the law its hinges fold it again, past half its set angle, in either solver; without
 * (the paper's rule) the set links are elastic again once flattened, and it stays flat. */
static void check_reforms(void)
{
    const int n = 9;
    const double y = 2.0 * acos(0.8), set = 170.0 * DEG - y, g[3] = {0.0, 0.0, 0.0};
    for (int run = 0; run < 3; run++) {
        cloth *c = make_cloth(n, 0.8, 0.02);
        if (!c) return;
        cloth_desc d = cloth_get_desc(c);
        if (run == 2) d.material.k_crease = 0.0;
        if (run == 1) d.solver.nonlinear = CLOTH_LINEARIZED;
        CHECK(cloth_set_material(c, &d.material) == CLOTH_OK && cloth_set_solver(c, &d.solver) == CLOTH_OK &&
                  cloth_set_gravity(c, g) == CLOTH_OK,
              "run %d: settings", run);
        double *x = malloc(3 * (size_t)c->n * sizeof *x);
        fold(n, 170.0 * DEG, x);
        cloth_set_positions(c, x);
        cloth_update_plastic(c);
        fold(n, 1e-3, x);
        cloth_set_positions(c, x);
        int failed = 0;
        for (int k = 0; k < 120; k++) failed += cloth_step(c, 1.0 / 60.0, NULL) != CLOTH_OK;
        double phi = turning(c, n, (n - 1) / 2);
        printf("run %d (%s): turning after 2 s %.2f deg, set %.2f deg\n", run,
               run == 2   ? "paper's rule"
               : run == 1 ? "crease law, linearised"
                          : "crease law, Newton",
               phi / DEG, set / DEG);
        CHECK(failed == 0, "run %d: %d steps failed", run, failed);
        if (run < 2)
            CHECK(phi > 0.5 * set, "run %d: refolded to %.2f deg of a set %.2f deg", run, phi / DEG, set / DEG);
        else CHECK(phi < 1.0 * DEG, "the paper's rule refolded to %.2f deg", phi / DEG);
        free(x);
        cloth_destroy(c);
    }
}

int main(void)
{
    check_rule();
    check_single_hinge();
    check_grids();
    check_derivatives();
    check_reforms();
    return check_summary();
}
