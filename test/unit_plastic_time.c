/* Unit: plasticity that depends on duration and repetition
 * (material.tau_set, tau_recover, set_hardening; oc_plastic_rule_time in
 * core/src/viscoplastic.c) against the law's closed forms.
 *
 *   - held: a link bent to d <= alpha l0 and held has
 *     l1(t) = d + (l0 - d) exp(-t / tau_set), after 300 steps of h and
 *     1200 of h/4 alike (to 1e-13 l0);
 *   - released to d = l0 at T: l1 = lp - (lp - l1(T)) exp(-t / tau_recover)
 *     with lp = l0 - beta (l0 - l1(T)); without hardening the link is
 *     elastic again (plastic 0, l1 = l0) once recovered;
 *   - folded n times (hold T, release R, each), the law composed by hand;
 *     with instant recovery the permanent rest length is the geometric
 *     d + (1 - beta (1 - exp(-T / tau_set)))^n (l0 - d); five folds leave
 *     more set than one;
 *   - all three 0 is the paper's rule: oc_plastic_rule_time agrees with
 *     oc_plastic_rule_memory on random walks (memory 0 and 1);
 *   - through a cloth: a 5 x 3 grid pinned folded (cloth_step, h and h/4),
 *     then pinned flat: each link across the fold follows the closed forms;
 *     state records taken during the hold (bent flags 1) and mid-recovery,
 *     read into a second cloth, continue bit for bit like the first (the
 *     permanent set and bent flags carried);
 *   - a link set fully (set_hardening 1, bent to almost 0) writes a permanent
 *     set below 1, so its record reads back;
 *   - the bent flags follow the paper's rule too: a link bent and released
 *     with the law off, the law switched on while it is straight, hardens not.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "check.h"
#include "spring_predicted.h"

static cloth_material timed(double tau_set, double tau_recover, double beta)
{
    cloth_material m = cloth_material_preset(CLOTH_COTTON);
    m.tau_set = tau_set;
    m.tau_recover = tau_recover;
    m.set_hardening = beta;
    return m;
}

typedef struct link_state {
    int plastic, bent;
    double l1, perm;
} link_state;

/* steps of h at length d, n of them */
static void run(const cloth_material *m, double l0, double d, double h, int n, link_state *s)
{
    for (int k = 0; k < n; k++) oc_plastic_rule_time(m, l0, d, h, &s->plastic, &s->l1, &s->perm, &s->bent);
}

static void check_held_released(void)
{
    const double l0 = 0.1, d = 0.05, T = 3.0, Rt = 2.0;
    const double beta = 0.3;
    cloth_material m = timed(1.5, 4.0, beta);
    link_state a[2];
    for (int q = 0; q < 2; q++) {
        int div = q ? 4 : 1;
        double h = 0.01 / div;
        link_state *s = &a[q];
        *s = (link_state){0, 0, l0, 0.0};
        run(&m, l0, d, h, 300 * div, s);
        double want = d + (l0 - d) * exp(-T / m.tau_set);
        CHECK(s->plastic == 1 && s->bent == 1, "h/%d held: plastic %d bent %d", div, s->plastic, s->bent);
        CHECK_NEAR(s->l1, want, 1e-13 * l0);
        double l1T = s->l1, lp = l0 - beta * (l0 - l1T);
        run(&m, l0, l0, h, 200 * div, s);
        double want_r = lp - (lp - l1T) * exp(-Rt / m.tau_recover);
        CHECK(s->plastic == 1 && s->bent == 0, "h/%d released: plastic %d bent %d", div, s->plastic, s->bent);
        CHECK_NEAR(s->l1, want_r, 1e-13 * l0);
        CHECK_NEAR(l0 - s->perm * l0, lp, 1e-15 * l0);
    }
    CHECK_NEAR(a[0].l1, a[1].l1, 1e-13 * l0);
    printf("held %.1f s at d/l0 0.5, released %.1f s: l1/l0 %.15f (h) %.15f (h/4)\n", T, Rt, a[0].l1 / l0,
           a[1].l1 / l0);

    /* a brief fold mostly recovers, a long one sets deeper */
    link_state brief = {0, 0, l0, 0.0}, longer = {0, 0, l0, 0.0};
    run(&m, l0, d, 0.01, 50, &brief);
    run(&m, l0, d, 0.01, 1000, &longer);
    CHECK(brief.l1 - d > 0.7 * (l0 - d) && longer.l1 - d < 1e-2 * (l0 - d),
          "0.5 s sets l1/l0 %.4f, 10 s %.4f (tau_set 1.5 s)", brief.l1 / l0, longer.l1 / l0);

    /* no hardening: recovered, the link is elastic again with l1 = l0 */
    cloth_material m0 = timed(1.5, 0.05, 0.0);
    link_state s = {0, 0, l0, 0.0};
    run(&m0, l0, d, 0.01, 100, &s);
    run(&m0, l0, l0, 0.01, 1000, &s); /* 200 tau_recover */
    CHECK(s.plastic == 0 && s.l1 == l0 && s.perm == 0.0, "recovered: plastic %d l1 %.17g perm %g", s.plastic, s.l1,
          s.perm);
}

static void check_folds(void)
{
    const double l0 = 0.1, d = 0.04, h = 0.02;
    const int Ts = 50, Rs = 25; /* steps held, released */
    cloth_material m = timed(2.0, 1.5, 0.25);
    double Es = exp(-Ts * h / m.tau_set), Er = exp(-Rs * h / m.tau_recover);
    double set[6] = {0};
    for (int n = 1; n <= 5; n++) {
        link_state s = {0, 0, l0, 0.0};
        double l1 = l0, lp = l0;
        for (int k = 0; k < n; k++) {
            run(&m, l0, d, h, Ts, &s);
            run(&m, l0, l0, h, Rs, &s);
            l1 = d + (l1 - d) * Es;
            lp -= m.set_hardening * (lp - l1);
            l1 = lp - (lp - l1) * Er;
        }
        CHECK_NEAR(s.l1, l1, 1e-13 * l0);
        CHECK_NEAR(l0 - s.perm * l0, lp, 1e-13 * l0);
        set[n] = l0 - s.l1;
    }
    CHECK(set[5] > 1.5 * set[1], "five folds leave a set of %.4g l0, one %.4g l0", set[5] / l0, set[1] / l0);
    printf("folded n times (%.1f s held, %.1f s released): set/l0", Ts * h, Rs * h);
    for (int n = 1; n <= 5; n++) printf(" %.4f", set[n] / l0);
    printf("\n");

    /* instant recovery: the permanent set alone, geometric in n */
    cloth_material mi = timed(2.0, 0.0, 0.25);
    link_state s = {0, 0, l0, 0.0};
    for (int n = 1; n <= 5; n++) {
        run(&mi, l0, d, h, Ts, &s);
        run(&mi, l0, l0, h, 1, &s);
        double want = d + pow(1.0 - mi.set_hardening * (1.0 - Es), n) * (l0 - d);
        CHECK_NEAR(s.l1, want, 1e-13 * l0);
        CHECK(s.plastic == 1, "fold %d: a permanent set keeps the link plastic", n);
    }
}

static void check_paper(void)
{
    rng g = rng_seed(0x7a11u);
    int mism = 0, changes = 0;
    for (int mem = 0; mem <= 1; mem++)
        for (int w = 0; w < 50; w++) {
            cloth_material m = timed(0, 0, 0);
            m.plastic_memory = mem;
            m.alpha = rng_range(&g, 0.0, 1.0);
            const double l0 = 0.1;
            int pa = 0, pb = 0, b = 0;
            double la = l0, lb = l0, perm = 0;
            for (int k = 0; k < 200; k++) {
                double d = l0 * rng_range(&g, 0.2, 1.1);
                oc_plastic_rule_memory(m.alpha, mem, l0, d, &pa, &la);
                oc_plastic_rule_time(&m, l0, d, 0.01, &pb, &lb, &perm, &b);
                mism += pa != pb || (pa && la != lb) || perm != 0.0;
                changes += pa;
            }
        }
    CHECK(oc_plastic_time_on(&(cloth_material){0}) == 0, "all zero asks for the time law");
    CHECK(mism == 0 && changes > 0, "zero time constants vs the paper's rule: %d mismatches (%d plastic)", mism,
          changes);
}

/* ---------------------------------------------------------------- cloth */

enum { R = 5, C = 3, RF = 2 }; /* fold along row RF, 0.1 m cells */

static cloth *make_cloth(const cloth_material *m)
{
    cloth_desc d = cloth_default_desc();
    cloth_error err;
    d.rows = R;
    d.cols = C;
    d.width = 0.2;
    d.height = 0.4;
    d.material = *m;
    cloth *c = NULL;
    CHECK(cloth_create(&d, &c, &err) == CLOTH_OK && c, "cloth_create: %s", err.message);
    return c;
}

/* rows > RF turned by phi about row RF, out of the plane */
static void fold(const double *rest, double phi, double *x)
{
    for (int r = 0; r < R; r++)
        for (int c = 0; c < C; c++) {
            int i = r * C + c, b = RF * C + c;
            memcpy(x + 3 * i, rest + 3 * i, 3 * sizeof *x);
            if (r > RF) {
                x[3 * i + 1] = rest[3 * b + 1] + (r - RF) * 0.1 * cos(phi);
                x[3 * i + 2] = rest[3 * b + 2] + (r - RF) * 0.1 * sin(phi);
            }
        }
}

static void pin_all(cloth *c, const double *x)
{
    for (int i = 0; i < R * C; i++) cloth_pin(c, i, x + 3 * i);
}

/* the straight link across the fold at column 1 */
static int across(const cloth *c)
{
    for (int e = 0; e < cloth_link_count(c, CLOTH_INTERLACED); e++) {
        cloth_link L;
        cloth_get_link(c, CLOTH_INTERLACED, e, &L);
        if (L.i == (RF - 1) * C + 1 && L.j == (RF + 1) * C + 1) return e;
    }
    return -1;
}

static double l1_of(const cloth *c, int e)
{
    cloth_link L;
    cloth_get_link(c, CLOTH_INTERLACED, e, &L);
    return L.plastic ? L.l1 : L.rest;
}

/* A record of state st written, read into a new cloth of material m, pinned
 * to rest and stepped from step s0 to s1 of h ends where the first did (l1). */
static void continue_from(const cloth_material *m, const cloth_state *st, const double *rest, int e, int s0, int s1,
                          double h, double l1, const char *what)
{
    size_t len = cloth_state_size_bytes(st);
    unsigned char *buf = malloc(len);
    cloth *c2 = make_cloth(m);
    cloth_state *s2 = c2 ? cloth_state_create(c2) : NULL;
    cloth_error err;
    if (CHECK(buf && s2, "no memory") && CHECK(cloth_state_write(st, buf, len, NULL, &err) == CLOTH_OK &&
                                                   cloth_state_read(s2, buf, len, &err) == CLOTH_OK,
                                               "%s record: %s", what, err.message)) {
        cloth_restore(c2, s2);
        pin_all(c2, rest);
        for (int s = s0; s < s1; s++) cloth_step(c2, h, NULL);
        CHECK(l1_of(c2, e) == l1, "from the %s record: l1 %.17g, the first cloth %.17g", what, l1_of(c2, e), l1);
    }
    free(buf);
    cloth_state_destroy(s2);
    cloth_destroy(c2);
}

static void check_cloth(void)
{
    const double q = 0.5, l0 = 0.2, T = 1.0, Rt = 0.5;
    cloth_material m = timed(0.8, 1.2, 0.4);
    m.k_b = 0.5;
    double rest[3 * R * C], x[3 * R * C], l1[2];
    for (int k = 0; k < 2; k++) {
        int div = k ? 4 : 1, steps = 60 * div;
        double h = T / steps;
        cloth *c = make_cloth(&m);
        if (!c) return;
        memcpy(rest, cloth_positions(c), sizeof rest);
        fold(rest, 2 * acos(q), x);
        cloth_set_positions(c, x);
        pin_all(c, x);
        int e = across(c), ok = 1;
        for (int s = 0; s < steps; s++) ok &= cloth_step(c, h, NULL) == CLOTH_OK;
        double want = q * l0 + (l0 - q * l0) * exp(-T / m.tau_set);
        CHECK(ok && e >= 0, "h/%d: steps failed or no link across", div);
        CHECK_NEAR(l1_of(c, e), want, 1e-12 * l0);
        double l1T = l1_of(c, e), lp = l0 - m.set_hardening * (l0 - l1T);
        cloth_state *held = cloth_state_create(c), *mid = cloth_state_create(c);
        cloth_save(c, held);
        pin_all(c, rest);
        for (int s = 0; s < steps / 2; s++) {
            ok &= cloth_step(c, h, NULL) == CLOTH_OK;
            if (s == steps / 4) cloth_save(c, mid);
        }
        double want_r = lp - (lp - l1T) * exp(-Rt / m.tau_recover);
        CHECK(ok, "h/%d: release steps failed", div);
        CHECK_NEAR(l1_of(c, e), want_r, 1e-12 * l0);
        l1[k] = l1_of(c, e);
        if (k == 0) {
            /* records held (bent 1) and mid-recovery continue exactly in another cloth */
            CHECK(c->st.bent[e] == 0 && held->bent[e] == 1, "bent flags: %d at the end, %d in the held record",
                  c->st.bent[e], held->bent[e]);
            continue_from(&m, held, rest, e, 0, steps / 2, h, l1[0], "held");
            continue_from(&m, mid, rest, e, steps / 4 + 1, steps / 2, h, l1[0], "mid-recovery");
        }
        cloth_state_destroy(held);
        cloth_state_destroy(mid);
        cloth_destroy(c);
    }
    CHECK_NEAR(l1[0], l1[1], 1e-12 * l0);
    printf("cloth: held %.1f s at d/l0 %.1f, released %.1f s: l1/l0 %.15f (h) %.15f (h/4)\n", T, q, Rt, l1[0] / l0,
           l1[1] / l0);
}

/* Set fully (set_hardening 1) at a length of almost 0, a link's permanent set
 * rounds to 1: it is written below 1, so the record reads back. */
/* Whether c's state, written to a record, reads back into c2's unchanged */
static int record_reads(cloth *c, cloth *c2, const char *what)
{
    cloth_state *st = cloth_state_create(c), *s2 = cloth_state_create(c2);
    size_t len = st ? cloth_state_size_bytes(st) : 0;
    unsigned char *buf = len ? malloc(len) : NULL;
    cloth_error err = {0};
    int ok = 0;
    if (CHECK(st && s2 && buf, "no memory")) {
        cloth_save(c, st);
        ok = CHECK(cloth_state_write(st, buf, len, NULL, &err) == CLOTH_OK &&
                       cloth_state_read(s2, buf, len, &err) == CLOTH_OK && cloth_state_diff(st, s2) == 0.0,
                   "%s: %s", what, err.message);
    }
    free(buf);
    cloth_state_destroy(st);
    cloth_state_destroy(s2);
    return ok;
}

static void check_full_set(void)
{
    cloth_material m = timed(0.0, 0.0, 1.0);
    m.plastic_memory = 1; /* keeps l1 > 0, which the reader asks too */
    cloth *c = make_cloth(&m), *c2 = make_cloth(&m);
    if (CHECK(c && c2, "no memory")) {
        int e = across(c);
        double l0 = c->lint[e].rest;
        oc_plastic_update_link(&m, &c->st, e, l0, 1e-20 * l0, 0.01);
        oc_plastic_update_link(&m, &c->st, e, l0, l0, 0.01);
        /* the largest set: l1 down to the shortest length a link has (SPRING_MIN_LENGTH) */
        CHECK(c->st.perm[e] < 1.0 && c->st.perm[e] > 1.0 - 2.0 * SPRING_MIN_LENGTH / l0, "fully set: perm %.17g",
              c->st.perm[e]);
        record_reads(c, c2, "a fully set link's record");
    }
    cloth_destroy(c);
    cloth_destroy(c2);
    /* the paper's rule on a link folded to zero length: its l1 stays a length */
    cloth_material p = timed(0.0, 0.0, 0.0);
    c = make_cloth(&p), c2 = make_cloth(&p);
    if (CHECK(c && c2, "no memory")) {
        int e = across(c);
        oc_plastic_update_link(&p, &c->st, e, c->lint[e].rest, 0.0, 0.01);
        CHECK(c->st.plastic[e] && c->st.l1[e] > 0.0, "collapsed link: plastic %d, l1 %g", c->st.plastic[e],
              c->st.l1[e]);
        record_reads(c, c2, "a collapsed link's record");
    }
    cloth_destroy(c);
    cloth_destroy(c2);
}

/* The bent flag kept by the paper's rule: bent under the law, released with
 * it off, then switched on while straight, a link takes no hardening. */
static void check_switch(void)
{
    cloth_material on = timed(0.0, 1.0, 0.5), off = timed(0.0, 0.0, 0.0);
    on.plastic_memory = off.plastic_memory = 1; /* the set stays while straight */
    cloth *c = make_cloth(&on);
    if (!c) return;
    double rest[3 * R * C], x[3 * R * C];
    memcpy(rest, cloth_positions(c), sizeof rest);
    fold(rest, 2 * acos(0.5), x);
    int e = across(c);
    cloth_set_positions(c, x);
    cloth_update_plastic(c);
    CHECK(c->st.bent[e] == 1 && c->st.plastic[e] == 1, "folded under the law: bent %d", c->st.bent[e]);
    cloth_set_material(c, &off);
    cloth_set_positions(c, rest);
    cloth_update_plastic(c);
    CHECK(c->st.bent[e] == 0, "released with the law off: bent %d", c->st.bent[e]);
    cloth_set_positions(c, x);
    cloth_update_plastic(c);
    CHECK(c->st.bent[e] == 1, "bent with the law off: bent %d", c->st.bent[e]);
    cloth_set_positions(c, rest);
    cloth_update_plastic(c);
    cloth_set_material(c, &on);
    cloth_update_plastic(c);
    CHECK(c->st.plastic[e] == 1 && c->st.perm[e] == 0.0, "switched on while straight: plastic %d perm %g",
          c->st.plastic[e], c->st.perm[e]);
    /* bent with the law off, switched on while bent: released, it hardens */
    cloth_set_material(c, &off);
    cloth_set_positions(c, x);
    cloth_update_plastic(c);
    cloth_set_material(c, &on);
    cloth_set_positions(c, rest);
    cloth_update_plastic(c);
    CHECK(c->st.perm[e] > 0.0, "switched on while bent, released: perm %g", c->st.perm[e]);
    cloth_destroy(c);
}

int main(void)
{
    check_held_released();
    check_folds();
    check_paper();
    check_cloth();
    check_full_set();
    check_switch();
    return check_summary();
}
