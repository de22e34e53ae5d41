/* Unit: the plastic rule of interlaced links (paper eq. 8-12; docs/model.md).
 *
 * The rule, as the paper states it (plastic iff d / l0 <= alpha):
 *   - entering the plastic region sets l1 to the entry length d;
 *   - while plastic, d < l1 ratchets l1 down to d; d >= l1 keeps l1, and the
 *     law is then k_s above l1 (int_law: k_hi = k_s, k_lo = k_b, rest l1);
 *   - d / l0 > alpha is elastic again (rest l0, k_b both ways), and the next
 *     entry sets l1 anew;
 *   - alpha = 0: never plastic, however compressed; alpha = 1: plastic for
 *     any d < l0, elastic for d > l0.
 *
 * Checked through oc_plastic_rule() directly (scripted sequences, the exact
 * boundary d = alpha l0, random walks against a reference written here), and
 * through a cloth: a grid folded along a row into a V of known angle, where
 * the interlaced links across the fold have lengths known in closed form
 * (2 s cos(phi/2) for links across the crease, phi the fold rotation) and all
 * other links keep their rest length. cloth_update_plastic's count,
 * cloth_get_link's plastic/l1 and cloth_energies().elastic are compared with
 * the expected state through fold, deeper fold, partial unfold, flattening
 * and refolding, for alpha = 0.8, 0, 1.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "check.h"

/* The reference rule. */
static void ref_rule(double alpha, double l0, double d, int *plastic, double *l1)
{
    if (d / l0 <= alpha) {
        if (!*plastic) {
            *plastic = 1;
            *l1 = d;
        } else if (d < *l1) *l1 = d;
    } else *plastic = 0;
}

static cloth_material test_material(double alpha)
{
    cloth_material m = cloth_material_preset(CLOTH_COTTON);
    m.k_t = 3100.0;
    m.k_c = 73.0;
    m.k_b = 2.3;
    m.k_s = 11.7;
    m.alpha = alpha;
    return m;
}

/* ---------------------------------------------------------------- direct */

static void check_scripted(void)
{
    const cloth_material m = test_material(0.8);
    const double l0 = 2.0; /* alpha l0 = 1.6 */
    struct {
        double d;
        int plastic;
        double l1;
        const char *what;
    } s[] = {
        {1.90, 0, 0, "slightly compressed, above alpha l0: elastic"},
        {1.62, 0, 0, "just above alpha l0: elastic"},
        {1.50, 1, 1.50, "below alpha l0: enters with l1 = d"},
        {1.40, 1, 1.40, "further compression ratchets l1 down"},
        {1.20, 1, 1.20, "further compression ratchets l1 down"},
        {1.50, 1, 1.20, "re-extension below alpha l0 keeps l1"},
        {1.58, 1, 1.20, "re-extension below alpha l0 keeps l1"},
        {1.30, 1, 1.20, "back down but above l1 keeps l1"},
        {1.70, 0, 0, "above alpha l0: elastic again"},
        {1.55, 1, 1.55, "re-entry sets l1 anew"},
        {2.20, 0, 0, "stretched: elastic"},
        {0.10, 1, 0.10, "strongly compressed: enters with l1 = d"},
    };
    int plastic = 0;
    double l1 = 12345.0;
    for (size_t k = 0; k < sizeof s / sizeof s[0]; k++) {
        oc_plastic_rule(m.alpha, l0, s[k].d, &plastic, &l1);
        CHECK(plastic == s[k].plastic && (!plastic || l1 == s[k].l1),
              "oc_plastic_rule step %zu (d = %g, %s): plastic %d l1 %g, want plastic %d l1 %g", k, s[k].d, s[k].what,
              plastic, l1, s[k].plastic, s[k].l1);
        plastic = s[k].plastic; /* continue from the expected state */
        l1 = s[k].plastic ? s[k].l1 : 777.0;

        /* the law in this state */
        {
            spring_law law = int_law(&m, l0, plastic, l1);
            double xi[3] = {0.1, -0.2, 0.3}, xj[3] = {0.1 + s[k].d, -0.2, 0.3}, f[3];
            double rest = plastic ? l1 : l0;
            double k_use = plastic ? (s[k].d >= l1 ? m.k_s : m.k_b) : m.k_b;
            CHECK(law.rest == rest && law.k_hi == (plastic ? m.k_s : m.k_b) && law.k_lo == m.k_b,
                  "int_law step %zu (%s): (k_hi %g, k_lo %g, rest %g), want (%g, %g, %g)", k, s[k].what, law.k_hi,
                  law.k_lo, law.rest, plastic ? m.k_s : m.k_b, m.k_b, rest);
            oc_spring_eval(xi, xj, law, 1, f, NULL);
            /* u = +x: f_i . u = k (d - rest) */
            CHECK_REL(f[0], k_use * (s[k].d - rest), 1e-12, 1e-14);
        }
    }
    /* the exact boundary: d / l0 == alpha exactly (0.5 * 2 = 1 in binary) */
    plastic = 0;
    oc_plastic_rule(0.5, 2.0, 1.0, &plastic, &l1);
    CHECK(plastic == 1 && l1 == 1.0, "d / l0 == alpha exactly should be plastic (d/l0 <= alpha): plastic %d l1 %g",
          plastic, l1);
}

static void check_alpha_extremes(void)
{
    rng r = rng_seed(0x5EED0301u);
    int bad0 = 0, bad1 = 0, bad1s = 0, badl1 = 0;
    for (int t = 0; t < 2000; t++) {
        double l0 = rng_range(&r, 0.01, 2.0);
        double ratio = t < 1000 ? pow(10.0, rng_range(&r, -6, 0)) * 0.999 : rng_range(&r, 0.001, 0.999);
        double d = ratio * l0;
        int p;
        double l1;
        /* alpha = 0, from either state */
        p = 0, l1 = 0.5 * l0;
        oc_plastic_rule(0.0, l0, d, &p, &l1);
        if (p) bad0++;
        p = 1, l1 = 0.5 * d;
        oc_plastic_rule(0.0, l0, d, &p, &l1);
        if (p) bad0++;
        /* alpha = 1: any compression is plastic, entering at l1 = d */
        p = 0, l1 = 0.0;
        oc_plastic_rule(1.0, l0, d, &p, &l1);
        if (!p) bad1++;
        else if (l1 != d) badl1++;
        /* alpha = 1: any stretch is elastic, from either state */
        d = l0 * rng_range(&r, 1.001, 2.0);
        p = 0, l1 = 0.0;
        oc_plastic_rule(1.0, l0, d, &p, &l1);
        if (p) bad1s++;
        p = 1, l1 = 0.5 * l0;
        oc_plastic_rule(1.0, l0, d, &p, &l1);
        if (p) bad1s++;
    }
    CHECK(bad0 == 0, "alpha = 0: %d compressed links became or stayed plastic", bad0);
    CHECK(bad1 == 0, "alpha = 1: %d compressed links (d < l0) not plastic", bad1);
    CHECK(badl1 == 0, "alpha = 1: %d links entered with l1 != d", badl1);
    CHECK(bad1s == 0, "alpha = 1: %d stretched links (d > l0) plastic", bad1s);
}

/* random walks of d against the reference rule */
static void check_random_walks(void)
{
    rng r = rng_seed(0x5EED0302u);
    int mismatches = 0, entries = 0, ratchets = 0, exits = 0;
    for (int w = 0; w < 200; w++) {
        double alpha = rng_range(&r, 0.05, 0.95), l0 = rng_range(&r, 0.05, 1.5);
        double ratio = rng_range(&r, 0.3, 1.3);
        int p = 0, pr = 0;
        double l1 = 0, l1r = 0;
        for (int t = 0; t < 100; t++) {
            double d;
            int was = pr;
            double l1was = l1r;
            ratio += rng_range(&r, -0.08, 0.08);
            if (ratio < 0.02) ratio = 0.02;
            if (ratio > 1.5) ratio = 1.5;
            if (fabs(ratio - alpha) < 1e-9) ratio += 1e-6; /* keep off the exact boundary */
            d = ratio * l0;
            oc_plastic_rule(alpha, l0, d, &p, &l1);
            ref_rule(alpha, l0, d, &pr, &l1r);
            if (!was && pr) entries++;
            if (was && pr && l1r < l1was) ratchets++;
            if (was && !pr) exits++;
            if (p != pr || (pr && l1 != l1r)) {
                if (mismatches < 5)
                    CHECK(0,
                          "random walk %d step %d (alpha %g, d/l0 %g): plastic %d l1/l0 %g, want plastic %d "
                          "l1/l0 %g",
                          w, t, alpha, ratio, p, l1 / l0, pr, l1r / l0);
                mismatches++;
                p = pr, l1 = l1r; /* resynchronise */
            }
        }
    }
    CHECK(mismatches == 0, "%d random-walk steps disagree with the reference rule", mismatches);
    CHECK(entries > 100 && ratchets > 100 && exits > 100, "random walks too tame: %d entries %d ratchets %d exits",
          entries, ratchets, exits);
    printf("oc_plastic_rule random walks: 20000 steps, %d entries, %d ratchets, %d exits, %d mismatches\n", entries,
           ratchets, exits, mismatches);
}

/* ----------------------------------------------------------------- cloth */

enum { R = 7, C = 6, RF = 3 }; /* fold along row RF */

typedef struct folded {
    cloth *c;
    cloth_material m;
    double su, sv, rest[3 * R * C], u[3], v[3], nrm[3];
    int n_int;
    int *ref_plastic;
    double *ref_l1;
} folded;

/* Fold rows > RF about the line of row RF by phi (0 = flat) out of the
 * plane, then scale everything by s about node 0. */
static void fold_positions(const folded *F, double phi, double s, double *x)
{
    for (int r = 0; r < R; r++)
        for (int c = 0; c < C; c++) {
            int i = r * C + c, base = RF * C + c;
            for (int a = 0; a < 3; a++) {
                double p = r <= RF
                               ? F->rest[3 * i + a]
                               : F->rest[3 * base + a] + (r - RF) * F->sv * (cos(phi) * F->v[a] + sin(phi) * F->nrm[a]);
                x[3 * i + a] = F->rest[a] + s * (p - F->rest[a]);
            }
        }
}

static int fold_setup(folded *F, double alpha)
{
    cloth_desc d = cloth_default_desc();
    cloth_error err;
    d.rows = R;
    d.cols = C;
    d.width = 0.5;  /* su = 0.1 */
    d.height = 0.6; /* sv = 0.1 */
    d.material = test_material(alpha);
    F->m = d.material;
    F->su = d.width / (C - 1);
    F->sv = d.height / (R - 1);
    F->c = NULL;
    if (!CHECK(cloth_create(&d, &F->c, &err) == CLOTH_OK && F->c, "cloth_create: %s", err.message)) return 0;
    memcpy(F->rest, cloth_positions(F->c), sizeof F->rest);
    for (int a = 0; a < 3; a++) {
        F->u[a] = (F->rest[3 + a] - F->rest[a]) / F->su;
        F->v[a] = (F->rest[3 * C + a] - F->rest[a]) / F->sv;
    }
    F->nrm[0] = F->u[1] * F->v[2] - F->u[2] * F->v[1];
    F->nrm[1] = F->u[2] * F->v[0] - F->u[0] * F->v[2];
    F->nrm[2] = F->u[0] * F->v[1] - F->u[1] * F->v[0];
    F->n_int = cloth_link_count(F->c, CLOTH_INTERLACED);
    F->ref_plastic = calloc((size_t)F->n_int, sizeof(int));
    F->ref_l1 = calloc((size_t)F->n_int, sizeof(double));
    return 1;
}

static void fold_teardown(folded *F)
{
    cloth_destroy(F->c);
    free(F->ref_plastic);
    free(F->ref_l1);
}

/* Fold to phi, scale s, update the plastic state, and compare with the
 * expected state (closed-form lengths + the reference rule). */
static void fold_stage(folded *F, double phi, double s, const char *what, int want_count)
{
    double x[3 * R * C], e_want = 0;
    int count, n_expected = 0, bad = 0, bad_len = 0, seq_plastic = 0;
    long failed_before = check_failures();
    fold_positions(F, phi, s, x);
    CHECK(cloth_set_positions(F->c, x) == CLOTH_OK, "%s: set_positions: %s", what, cloth_last_error(F->c));
    count = cloth_update_plastic(F->c);
    for (int e = 0; e < F->n_int; e++) {
        cloth_link L;
        int ri, ci, rj, cj;
        double dlen, dx[3];
        cloth_get_link(F->c, CLOTH_INTERLACED, e, &L);
        ri = L.i / C, ci = L.i % C, rj = L.j / C, cj = L.j % C;
        /* closed form: across the crease (rows RF-1 and RF+1) or rigid */
        if (ri == RF - 1 && rj == RF + 1) {
            double along = (cj - ci) * F->su, across = 2 * F->sv * cos(phi / 2);
            dlen = s * sqrt(along * along + across * across);
        } else dlen = s * L.rest;
        for (int a = 0; a < 3; a++) dx[a] = x[3 * L.j + a] - x[3 * L.i + a];
        if (fabs(sqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]) - dlen) > 1e-12) bad_len++;
        ref_rule(F->m.alpha, L.rest, dlen, &F->ref_plastic[e], &F->ref_l1[e]);
        if (F->ref_plastic[e]) n_expected++;
        if (L.plastic != F->ref_plastic[e] || (L.plastic && fabs(L.l1 - F->ref_l1[e]) > 1e-12 * L.rest)) {
            if (bad < 4)
                CHECK(0, "%s: link (%d,%d)-(%d,%d) d/l0 %.4f: plastic %d l1/l0 %.6f, want plastic %d l1/l0 %.6f", what,
                      ri, ci, rj, cj, dlen / L.rest, L.plastic, L.plastic ? L.l1 / L.rest : 0.0, F->ref_plastic[e],
                      F->ref_plastic[e] ? F->ref_l1[e] / L.rest : 0.0);
            bad++;
        }
        /* the energy this link should hold in its region */
        {
            double rest = F->ref_plastic[e] ? F->ref_l1[e] : L.rest;
            double k = F->ref_plastic[e] && dlen >= rest ? F->m.k_s : F->m.k_b;
            e_want += 0.5 * k * (dlen - rest) * (dlen - rest);
        }
    }
    for (int e = 0; e < cloth_link_count(F->c, CLOTH_SEQUENTIAL); e++) {
        cloth_link L;
        cloth_get_link(F->c, CLOTH_SEQUENTIAL, e, &L);
        if (L.plastic) seq_plastic++;
        /* every sequential link is rigid in the fold: its energy is s-stretch only */
        {
            double k = s >= 1 ? F->m.k_t : F->m.k_c;
            e_want += 0.5 * k * (s - 1) * L.rest * (s - 1) * L.rest;
        }
    }
    CHECK(bad_len == 0, "%s: test geometry wrong for %d links (closed form vs positions)", what, bad_len);
    CHECK(bad == 0, "%s: %d interlaced links in the wrong plastic state", what, bad);
    CHECK(seq_plastic == 0, "%s: %d sequential links marked plastic", what, seq_plastic);
    CHECK(count == n_expected, "%s: cloth_update_plastic returned %d, want %d", what, count, n_expected);
    CHECK(n_expected == want_count, "%s: test set-up expected %d plastic links, reference gives %d", what, want_count,
          n_expected);
    {
        double e = cloth_energies(F->c).elastic;
        CHECK(fabs(e - e_want) <= 1e-9 * e_want + 1e-15,
              "%s: elastic energy %.12g, want %.12g from the expected regions (k_s above l1, k_b below)", what, e,
              e_want);
    }
    printf("  %-58s phi %6.2f deg: %2d plastic%s\n", what, phi * 45.0 / atan(1.0), count,
           check_failures() > failed_before ? "  (FAILURES)" : "");
}

/* the fold rotation phi that puts links straight across the crease at d/l0 = q */
static double phi_for(double q) { return 2 * acos(q); }

static void check_cloth_folds(void)
{
    folded F;
    /* cotton's alpha 0.8. Across the crease: straight links (C of them) at
     * d/l0 = q; diagonal ones (2 (C-2)) at sqrt((1 + q^2)/2) (su = sv). */
    printf("cloth fold, alpha 0.8:\n");
    if (fold_setup(&F, 0.8)) {
        fold_stage(&F, 0, 1, "flat", 0);
        fold_stage(&F, phi_for(0.70), 1, "fold: straight links enter (0.70), diagonals 0.86 elastic", C);
        fold_stage(&F, phi_for(0.45), 1, "deeper: straight ratchet to 0.45, diagonals 0.78 enter", C + 2 * (C - 2));
        fold_stage(&F, phi_for(0.65), 1, "unfold to 0.65: straight keep l1 0.45 (k_s), diag. 0.84 out", C);
        fold_stage(&F, phi_for(0.75), 1, "unfold to 0.75: straight still keep l1 0.45", C);
        fold_stage(&F, 0, 1, "flatten: all elastic", 0);
        fold_stage(&F, phi_for(0.72), 1, "refold to 0.72: l1 set anew", C);
        fold_stage(&F, phi_for(0.72), 0.97, "same fold squeezed by 0.97: ratchet", C);
        fold_teardown(&F);
    }
    printf("cloth fold, alpha 0:\n");
    if (fold_setup(&F, 0.0)) {
        fold_stage(&F, phi_for(0.05), 1, "sharp fold (0.05): never plastic", 0);
        fold_stage(&F, phi_for(0.05), 0.5, "sharp fold squeezed by half: never plastic", 0);
        fold_teardown(&F);
    }
    printf("cloth fold, alpha 1:\n");
    if (fold_setup(&F, 1.0)) {
        /* everything stretched by 1%, so links away from the crease have d > l0 */
        fold_stage(&F, phi_for(0.95), 1.01, "slight fold, 1% stretch: only the crease plastic", C + 2 * (C - 2));
        fold_stage(&F, phi_for(0.999), 1.02, "almost flat, 2% stretch: d > l0 everywhere, elastic", 0);
        fold_stage(&F, 0, 0.99, "flat, squeezed 1%: every interlaced link plastic", F.n_int);
        fold_teardown(&F);
    }
}

int main(void)
{
    check_scripted();
    check_alpha_extremes();
    check_random_walks();
    check_cloth_folds();
    return check_summary();
}
