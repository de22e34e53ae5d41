/* Unit: the opt-in plastic memory rule (material.plastic_memory = 1,
 * oc_plastic_rule_memory in core/src/plastic.c) against the paper's per-step
 * rule (the default) and closed forms.
 *
 *   - memory 0 is the paper's rule bit for bit: oc_plastic_rule() and
 *     oc_plastic_rule_memory(.., 0, ..) agree on random walks, and a link
 *     opened above alpha l0 is elastic (int_law: rest l0, k_b both ways);
 *   - memory 1: entry at d <= alpha l0 sets l1 = d, a deeper bend ratchets
 *     l1 = min(l1, d), and opening the link above alpha l0 (even past l0)
 *     keeps it plastic with its l1; a link never plastic stays elastic
 *     above alpha l0; alpha 0 never enters;
 *   - the force of a remembered link at d = l0 is k_s (l0 - l1) toward l1
 *     (oc_spring_eval on int_law), below l1 it is k_b (l1 - d) apart;
 *   - through a cloth: a grid folded so that the links straight across the
 *     crease sit at d/l0 = q (diagonals at sqrt((1 + q^2)/2)), then
 *     flattened: the default forgets every crease (0 plastic, elastic energy
 *     0); memory keeps each with l1 = the closed form and holds the energy
 *     sum 1/2 k_s (l0 - l1)^2; cloth_save / cloth_restore / the state record
 *     carry it to another cloth exactly;
 *   - dynamics: a memory cloth released near flat from a remembered crease
 *     folds back in (the straight links shorten), the default cloth opens;
 *   - bad input: plastic_memory other than 0 or 1 is CLOTH_EINVAL with a
 *     message naming it (validate, cloth_create, cloth_set_material).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "check.h"

static void check_direct(void)
{
    const double l0 = 2.0, alpha = 0.8; /* alpha l0 = 1.6 */
    cloth_material m = cloth_material_preset(CLOTH_COTTON);
    m.k_b = 0.7;
    m.k_s = 9.0;
    for (int mem = 0; mem <= 1; mem++) {
        int p = 0;
        double l1 = l0;
        oc_plastic_rule_memory(alpha, mem, l0, 1.4, &p, &l1);
        CHECK(p == 1 && l1 == 1.4, "memory %d: entry at 0.7 l0: plastic %d l1 %g, want 1, 1.4", mem, p, l1);
        oc_plastic_rule_memory(alpha, mem, l0, 1.8, &p, &l1); /* opened above alpha l0 */
        if (!mem) {
            spring_law s = int_law(&m, l0, p, l1);
            CHECK(p == 0, "paper rule: a link opened to 0.9 l0 is elastic (plastic %d)", p);
            CHECK(s.rest == l0 && s.k_hi == m.k_b && s.k_lo == m.k_b,
                  "paper rule: opened link's law (k_hi %g, k_lo %g, rest %g), want (k_b, k_b, l0)", s.k_hi, s.k_lo,
                  s.rest);
            continue;
        }
        CHECK(p == 1 && l1 == 1.4, "memory: opened to 0.9 l0 keeps plastic %d l1 %g (want 1, 1.4)", p, l1);
        oc_plastic_rule_memory(alpha, mem, l0, 2.1, &p, &l1); /* past l0 */
        CHECK(p == 1 && l1 == 1.4, "memory: opened past l0 keeps plastic %d l1 %g (want 1, 1.4)", p, l1);
        oc_plastic_rule_memory(alpha, mem, l0, 1.0, &p, &l1); /* deeper than l1 */
        CHECK(p == 1 && l1 == 1.0, "memory: bent deeper to 0.5 l0: l1 %g, want 1.0", l1);
        oc_plastic_rule_memory(alpha, mem, l0, 1.2, &p, &l1); /* between l1 and alpha l0 */
        CHECK(p == 1 && l1 == 1.0, "memory: back to 0.6 l0 keeps l1 %g (want 1.0)", l1);
        oc_plastic_rule_memory(alpha, mem, l0, 1.9, &p, &l1);
        CHECK(p == 1 && l1 == 1.0, "memory: opened again keeps l1 %g (want 1.0, the minimum)", l1);
        {
            spring_law s = int_law(&m, l0, p, l1);
            CHECK(s.rest == 1.0 && s.k_hi == m.k_s && s.k_lo == m.k_b,
                  "memory: opened link's law (k_hi %g, k_lo %g, rest %g), want (k_s, k_b, l1 1.0)", s.k_hi, s.k_lo,
                  s.rest);
        }
    }
    /* memory never makes an elastic link plastic above alpha l0, nor alpha 0 plastic */
    {
        int p = 0;
        double l1 = l0;
        oc_plastic_rule_memory(alpha, 1, l0, 1.7, &p, &l1);
        CHECK(p == 0, "memory: a never-plastic link at 0.85 l0 is elastic (plastic %d)", p);
        oc_plastic_rule_memory(0.0, 1, l0, 0.01, &p, &l1);
        CHECK(p == 0, "memory, alpha 0: never plastic at d = 0.005 l0 (plastic %d)", p);
        p = 1, l1 = 0.5;
        oc_plastic_rule_memory(0.0, 1, l0, 0.4, &p, &l1);
        CHECK(p == 0, "memory, alpha 0: a link marked plastic is elastic again (plastic %d)", p);
    }
    /* memory 0 is oc_plastic_rule exactly, on random walks */
    {
        rng seed = rng_seed(0x5eed5eedULL);
        int mism = 0;
        for (int w = 0; w < 200; w++) {
            double a = rng_unit(&seed), l1a = l0, l1b = l0;
            int pa = 0, pb = 0;
            for (int k = 0; k < 100; k++) {
                double d = l0 * 1.1 * rng_unit(&seed);
                oc_plastic_rule(a, l0, d, &pa, &l1a);
                oc_plastic_rule_memory(a, 0, l0, d, &pb, &l1b);
                if (pa != pb || (pa && memcmp(&l1a, &l1b, sizeof l1a))) mism++;
            }
        }
        CHECK(mism == 0, "oc_plastic_rule vs oc_plastic_rule_memory(memory 0): %d mismatches in 20000 steps", mism);
    }
}

/* The force of a remembered link: node i at the origin, j at distance d on x. */
static void check_force(void)
{
    cloth_material m = cloth_material_preset(CLOTH_COTTON);
    m.k_b = 0.05;
    m.k_s = 10.0;
    const double l0 = 0.1, l1 = 0.07;
    int p = 0;
    double L1 = l0;
    oc_plastic_rule_memory(0.8, 1, l0, l1, &p, &L1);
    oc_plastic_rule_memory(0.8, 1, l0, l0, &p, &L1); /* spread flat */
    spring_law s = int_law(&m, l0, p, L1);
    double xi[3] = {0, 0, 0}, xj[3] = {l0, 0, 0}, f[3];
    oc_spring_eval(xi, xj, s, 1, f, NULL);
    CHECK_NEAR(f[0], m.k_s * (l0 - l1), 1e-14);
    CHECK(fabs(f[1]) < 1e-15 && fabs(f[2]) < 1e-15, "remembered link at l0: force off-axis (%g, %g)", f[1], f[2]);
    CHECK(f[0] > 0, "remembered link at l0 pulls i toward j (toward l1): f_x %g", f[0]);
    xj[0] = 0.05; /* below l1: pushed apart with k_b */
    oc_spring_eval(xi, xj, s, 1, f, NULL);
    CHECK_NEAR(f[0], -m.k_b * (l1 - 0.05), 1e-15);
    /* the paper's rule at d = l0: elastic at rest, no force */
    p = 0, L1 = l0;
    oc_plastic_rule_memory(0.8, 0, l0, l1, &p, &L1);
    oc_plastic_rule_memory(0.8, 0, l0, l0, &p, &L1);
    xj[0] = l0;
    oc_spring_eval(xi, xj, int_law(&m, l0, p, L1), 1, f, NULL);
    CHECK(f[0] == 0.0 && p == 0, "paper rule: spread link at l0 has force %g (want 0), plastic %d", f[0], p);
}

/* --------------------------------------------------------------- cloth */

enum { R = 5, C = 3, RF = 2 }; /* fold along row RF; su = sv = 0.1 */

static cloth *make_cloth(int memory, cloth_material *out)
{
    cloth_desc d = cloth_default_desc();
    cloth_error err;
    d.rows = R;
    d.cols = C;
    d.width = 0.2;
    d.height = 0.4;
    d.material = cloth_material_preset(CLOTH_COTTON);
    d.material.k_b = 0.5;
    d.material.plastic_memory = memory;
    if (out) *out = d.material;
    cloth *c = NULL;
    CHECK(cloth_create(&d, &c, &err) == CLOTH_OK && c, "cloth_create: %s", err.message);
    return c;
}

/* rows > RF rotated by phi about row RF, out of the plane */
static void fold(const double *rest, double phi, double *x)
{
    double u[3], v[3], n[3], su = 0.1, sv = 0.1;
    for (int a = 0; a < 3; a++) u[a] = (rest[3 + a] - rest[a]) / su, v[a] = (rest[3 * C + a] - rest[a]) / sv;
    n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2], n[2] = u[0] * v[1] - u[1] * v[0];
    for (int r = 0; r < R; r++)
        for (int c = 0; c < C; c++) {
            int i = r * C + c, b = RF * C + c;
            for (int a = 0; a < 3; a++)
                x[3 * i + a] = r <= RF ? rest[3 * i + a]
                                       : rest[3 * b + a] + (r - RF) * sv * (cos(phi) * v[a] + sin(phi) * n[a]);
        }
}

/* straight links across the crease, their mean d/l0 */
static double crease_q(const cloth *c)
{
    const double *x = cloth_positions(c);
    double s = 0;
    int n = 0;
    for (int e = 0; e < cloth_link_count(c, CLOTH_INTERLACED); e++) {
        cloth_link L;
        cloth_get_link(c, CLOTH_INTERLACED, e, &L);
        if (L.i / C == RF - 1 && L.j / C == RF + 1 && L.i % C == L.j % C) {
            double d2 = 0;
            for (int a = 0; a < 3; a++) d2 += (x[3 * L.j + a] - x[3 * L.i + a]) * (x[3 * L.j + a] - x[3 * L.i + a]);
            s += sqrt(d2) / L.rest, n++;
        }
    }
    return n ? s / n : NAN;
}

static void check_cloth(void)
{
    const double q = 0.5, qd = sqrt((1 + q * q) / 2); /* straight / diagonal d/l0 across */
    double rest[3 * R * C], x[3 * R * C];
    cloth *cm[2];
    cloth_material mat[2];
    for (int mem = 0; mem <= 1; mem++) {
        cm[mem] = make_cloth(mem, &mat[mem]);
        if (!cm[mem]) return;
    }
    memcpy(rest, cloth_positions(cm[0]), sizeof rest);
    fold(rest, 2 * acos(q), x);
    for (int mem = 0; mem <= 1; mem++) {
        cloth *c = cm[mem];
        cloth_set_positions(c, x);
        int n_fold = cloth_update_plastic(c);
        CHECK(n_fold == C + 2, "memory %d: folded to q 0.5: %d plastic, want %d (3 straight, 2 diagonal)", mem, n_fold,
              C + 2);
        cloth_set_positions(c, rest); /* spread flat */
        int n_flat = cloth_update_plastic(c);
        double e = cloth_energies(c).elastic, e_want = 0;
        int bad = 0;
        for (int k = 0; k < cloth_link_count(c, CLOTH_INTERLACED); k++) {
            cloth_link L;
            cloth_get_link(c, CLOTH_INTERLACED, k, &L);
            int across = L.i / C == RF - 1 && L.j / C == RF + 1;
            double want_l1 = (L.i % C == L.j % C ? q : qd) * L.rest;
            if (mem && across) {
                if (!L.plastic || fabs(L.l1 - want_l1) > 1e-12) bad++;
                e_want += 0.5 * mat[mem].k_s * (L.rest - want_l1) * (L.rest - want_l1);
            } else if (L.plastic) bad++;
        }
        CHECK(bad == 0, "memory %d, spread flat: %d links in the wrong state", mem, bad);
        CHECK(n_flat == (mem ? C + 2 : 0), "memory %d, spread flat: %d plastic, want %d", mem, n_flat, mem ? C + 2 : 0);
        CHECK(fabs(e - e_want) <= 1e-12 + 1e-9 * e_want, "memory %d, flat: elastic energy %.12g, want %.12g", mem, e,
              e_want);
    }
    CHECK(cloth_energies(cm[1]).elastic > 0.01, "memory: the spread crease holds energy (%g J)",
          cloth_energies(cm[1]).elastic);

    /* save / restore / the state record carry the remembered crease */
    {
        cloth *c2 = make_cloth(1, NULL);
        cloth_state *s1 = cloth_state_create(cm[1]), *s2 = cloth_state_create(cm[1]), *s3 = cloth_state_create(cm[1]);
        if (c2 && s1 && s2 && s3) {
            cloth_save(cm[1], s1);
            CHECK(cloth_restore(c2, s1) == CLOTH_OK, "restore into a second cloth");
            cloth_save(c2, s2);
            CHECK(cloth_state_diff(s1, s2) == 0.0, "save/restore: diff %g", cloth_state_diff(s1, s2));
            size_t n = cloth_state_size_bytes(s1), w = 0;
            unsigned char *buf = malloc(n);
            cloth_error err;
            if (buf) {
                CHECK(cloth_state_write(s1, buf, n, &w, &err) == CLOTH_OK && w == n, "state_write");
                CHECK(cloth_state_read(s3, buf, n, &err) == CLOTH_OK, "state_read: %s", err.message);
                CHECK(cloth_state_diff(s1, s3) == 0.0, "write/read: diff %g", cloth_state_diff(s1, s3));
                free(buf);
            }
            /* the restored cloth keeps the crease through its own update */
            CHECK(cloth_update_plastic(c2) == C + 2, "restored cloth: plastic links after update");
            cloth_save(cm[0], s2);
            CHECK(cloth_state_diff(s1, s2) >= 1.0, "memory and default flat states differ in flags (%g)",
                  cloth_state_diff(s1, s2));
        }
        cloth_state_destroy(s1), cloth_state_destroy(s2), cloth_state_destroy(s3);
        cloth_destroy(c2);
    }

    /* released near flat (a 20 degree fold), no gravity: memory folds back in */
    {
        const double g0[3] = {0, 0, 0};
        double q0[2], q1[2];
        fold(rest, 20.0 * atan(1.0) / 45.0, x);
        for (int mem = 0; mem <= 1; mem++) {
            cloth *c = cm[mem];
            cloth_set_gravity(c, g0);
            cloth_set_positions(c, x);
            cloth_update_plastic(c);
            q0[mem] = crease_q(c);
            for (int k = 0; k < 120; k++)
                if (!CHECK(cloth_step(c, 1.0 / 60, NULL) == CLOTH_OK, "memory %d: step %d: %s", mem, k,
                           cloth_last_error(c)))
                    break;
            q1[mem] = crease_q(c);
        }
        printf("released at a 20 deg fold, 2 s: straight links d/l0 %.4f -> default %.4f, memory %.4f\n", q0[0], q1[0],
               q1[1]);
        CHECK(q1[1] < q0[1] - 0.1, "memory: the crease re-forms: d/l0 %.4f -> %.4f (want < start - 0.1)", q0[1], q1[1]);
        CHECK(q1[0] >= q0[0] - 1e-3, "default: the crease does not re-form: d/l0 %.4f -> %.4f", q0[0], q1[0]);
    }
    cloth_destroy(cm[0]);
    cloth_destroy(cm[1]);
}

static void check_bad_input(void)
{
    const int bad[] = {-1, 2, 7};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        cloth_material m = cloth_material_preset(CLOTH_COTTON);
        cloth_error err = {CLOTH_OK, ""};
        m.plastic_memory = bad[k];
        CHECK(cloth_material_validate(&m, &err) == CLOTH_EINVAL && strstr(err.message, "plastic_memory"),
              "plastic_memory %d: validate gives '%s'", bad[k], err.message);
        cloth_desc d = cloth_default_desc();
        d.material = m;
        cloth *c = NULL;
        CHECK(cloth_create(&d, &c, &err) == CLOTH_EINVAL && !c, "plastic_memory %d: cloth_create refused", bad[k]);
        c = make_cloth(0, NULL);
        if (c) {
            CHECK(cloth_set_material(c, &m) == CLOTH_EINVAL, "plastic_memory %d: cloth_set_material refused", bad[k]);
            CHECK(cloth_get_desc(c).material.plastic_memory == 0, "plastic_memory %d: material unchanged", bad[k]);
            cloth_destroy(c);
        }
    }
    for (int p = CLOTH_COTTON; p <= CLOTH_ELASTIC; p++)
        CHECK(cloth_material_preset((cloth_preset)p).plastic_memory == 0, "preset %d: memory off by default", p);
}

int main(void)
{
    check_direct();
    check_force();
    check_cloth();
    check_bad_input();
    return check_summary();
}
