/* Unit: every link force is minus the gradient of its energy (paper eq. 6-12).
 *
 * For each link type and region of the model:
 *   sequential tension        l0 < d < lim      k_t  (seq_law)
 *   sequential past the limit d > lim = (1 + delta) l0:
 *                             k_t on d - l0 plus k_delta k_t on d - lim
 *   sequential compression    d < l0            k_c  (seq_law)
 *   interlaced elastic bend   d < l0 or d > l0  k_b  (int_law, plastic = 0)
 *   interlaced plastic spread plastic, d > l1   k_s  (int_law, plastic = 1)
 *   interlaced plastic compr. plastic, d < l1   k_b  (int_law, plastic = 1)
 * random link geometries are drawn in the region and we check
 *   - the spring_law built by seq_law/int_law has the material's stiffness in
 *     the right slot and the right rest length (the material's k's are all
 *     distinct, so a swapped k is caught), and the limit term: seq_law has
 *     k_lim = k_delta k_t and lim = (1 + delta) l0, int_law k_lim = 0 and
 *     lim = HUGE_VAL (k_delta = 37 and delta = 0.07, not the presets');
 *   - oc_spring_energy = 1/2 k (d - rest)^2 with that k, plus
 *     1/2 k_delta k_t (d - lim)^2 past the limit;
 *   - oc_spring_eval's f_i = +k (d - rest) u, u = (x_j - x_i)/d, plus
 *     k_delta k_t (d - lim) u past the limit;
 *   - f_i = -dE/dx_i and f_j = -f_i = -dE/dx_j by central differences
 *     (step 1e-6 d), norm-wise relative error < 1e-6;
 *   - the force does not depend on the definiteness flag.
 * The limit term is continuous: energy and force at lim (1 - 1e-9) and
 * lim (1 + 1e-9) differ by no more than their slopes allow over that gap
 * (a term that jumped, e.g. k_lim (d - rest), would differ by ~k_lim delta l0).
 * The damper: oc_damper_eval's f_i = c ((v_j - v_i).u) u, D = df_i/dv_j by
 * central differences, and df_i/dv_i = -D.
 * The cloth: with random velocities, cloth_internal_forces minus its value at
 * zero velocity equals the sum of oc_damper_eval over every link with c_t on
 * sequential links and c_b on interlaced links.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "check.h"

enum { SEQ_TENSION, SEQ_PAST_LIMIT, SEQ_COMPRESSION, INT_ELASTIC, INT_SPREAD, INT_PLASTIC_COMPRESSION, NREGION };
static const char *region_name[NREGION] = {"sequential tension",           "sequential past the limit",
                                           "sequential compression",       "interlaced elastic",
                                           "interlaced plastic spreading", "interlaced plastic compression"};

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double norm3(const double a[3]) { return sqrt(dot3(a, a)); }

/* A material with every stiffness distinct and far apart. */
static cloth_material test_material(void)
{
    cloth_material m = cloth_material_preset(CLOTH_COTTON);
    m.k_t = 3100.0;
    m.k_c = 73.0;
    m.k_b = 2.3;
    m.k_s = 11.7;
    m.alpha = 0.8;
    m.delta = 0.07;   /* not a preset's */
    m.k_delta = 37.0; /* not a preset's, and not 1 */
    m.c_t = 0.37;
    m.c_b = 0.011;
    return m;
}

/* A random link in a region: positions, the law from seq_law/int_law, and
 * the stiffness and rest length the region must use; past the limit also
 * the extra stiffness and where it starts. */
typedef struct link_case {
    double xi[3], xj[3], d;
    spring_law law;
    double k, rest;   /* expected */
    int past;         /* expected: the limit term is active */
    double klim, lim; /* expected: k_delta k_t and (1 + delta) l0 (past only) */
} link_case;

static void make_case(rng *r, const cloth_material *m, int region, link_case *lc)
{
    double l0 = rng_range(r, 0.05, 1.0), u[3], ratio = 1.0, l1 = 0.0;
    lc->past = 0;
    lc->klim = 0.0;
    lc->lim = HUGE_VAL;
    switch (region) {
    case SEQ_TENSION: /* below the elongation limit */
        lc->law = seq_law(m, l0, 0.0);
        lc->k = m->k_t;
        lc->rest = l0;
        ratio = rng_range(r, 1.001, 1.0 + 0.99 * m->delta);
        break;
    case SEQ_PAST_LIMIT:
        lc->law = seq_law(m, l0, 0.0);
        lc->k = m->k_t;
        lc->rest = l0;
        lc->past = 1;
        lc->klim = m->k_delta * m->k_t;
        lc->lim = (1.0 + m->delta) * l0;
        ratio = rng_range(r, 1.0 + 1.01 * m->delta, 1.5);
        break;
    case SEQ_COMPRESSION:
        lc->law = seq_law(m, l0, 0.0);
        lc->k = m->k_c;
        lc->rest = l0;
        ratio = rng_range(r, 0.2, 0.99);
        break;
    case INT_ELASTIC:
        lc->law = int_law(m, l0, 0, 0.5 * l0 /* ignored when elastic */);
        lc->k = m->k_b;
        lc->rest = l0;
        /* both sides of l0: an elastic interlaced link resists both ways with k_b */
        ratio = (rng_u64(r) & 1) ? rng_range(r, m->alpha + 0.01, 0.99) : rng_range(r, 1.01, 1.5);
        break;
    case INT_SPREAD:
        l1 = l0 * rng_range(r, 0.2, 0.75); /* below alpha l0 = 0.8 l0 */
        lc->law = int_law(m, l0, 1, l1);
        lc->k = m->k_s;
        lc->rest = l1;
        ratio = rng_range(r, 1.01 * l1, 0.79 * l0) / l0; /* l1 < d < alpha l0 */
        break;
    default: /* INT_PLASTIC_COMPRESSION */
        l1 = l0 * rng_range(r, 0.2, 0.75);
        lc->law = int_law(m, l0, 1, l1);
        lc->k = m->k_b;
        lc->rest = l1;
        ratio = rng_range(r, 0.3 * l1, 0.99 * l1) / l0; /* d < l1 */
        break;
    }
    lc->d = ratio * l0;
    rng_unit_vector(r, u);
    for (int a = 0; a < 3; a++) {
        lc->xi[a] = rng_range(r, -1, 1);
        lc->xj[a] = lc->xi[a] + lc->d * u[a];
    }
    /* the actual length, as the kernels will see it */
    {
        double x[3] = {lc->xj[0] - lc->xi[0], lc->xj[1] - lc->xi[1], lc->xj[2] - lc->xi[2]};
        lc->d = norm3(x);
    }
}

static void check_laws(const cloth_material *m)
{
    spring_law s = seq_law(m, 0.25, 0.0);
    CHECK(s.k_hi == m->k_t && s.k_lo == m->k_c && s.rest == 0.25,
          "seq_law = (%g, %g, %g), want (k_t %g, k_c %g, l0 0.25)", s.k_hi, s.k_lo, s.rest, m->k_t, m->k_c);
    /* the limit term: k_delta k_t = 37 * 3100 past (1 + 0.07) l0 */
    CHECK(fabs(s.k_lim - m->k_delta * m->k_t) <= 1e-15 * m->k_delta * m->k_t &&
              fabs(s.lim - (1.0 + m->delta) * 0.25) <= 1e-15 * 0.25,
          "seq_law: k_lim %.17g lim %.17g, want k_delta k_t = %.17g and (1 + delta) l0 = %.17g", s.k_lim, s.lim,
          m->k_delta * m->k_t, (1.0 + m->delta) * 0.25);
    s = int_law(m, 0.5, 0, 0.3);
    CHECK(s.k_hi == m->k_b && s.k_lo == m->k_b && s.rest == 0.5,
          "int_law elastic = (%g, %g, %g), want (k_b %g, k_b, l0 0.5)", s.k_hi, s.k_lo, s.rest, m->k_b);
    CHECK(s.k_lim == 0.0 && s.lim == HUGE_VAL, "int_law elastic: k_lim %g lim %g, want 0 and HUGE_VAL", s.k_lim, s.lim);
    s = int_law(m, 0.5, 1, 0.3);
    CHECK(s.k_hi == m->k_s && s.k_lo == m->k_b && s.rest == 0.3,
          "int_law plastic = (%g, %g, %g), want (k_s %g, k_b %g, l1 0.3)", s.k_hi, s.k_lo, s.rest, m->k_s, m->k_b);
    CHECK(s.k_lim == 0.0 && s.lim == HUGE_VAL, "int_law plastic: k_lim %g lim %g, want 0 and HUGE_VAL", s.k_lim, s.lim);
}

/* The limit term switches on continuously at lim: energy and force just
 * below and just above it differ by no more than their slopes allow over
 * the gap (2e-9 lim), for random links; and each matches the closed form. */
static void check_limit_continuity(const cloth_material *m)
{
    rng r = rng_seed(0x5EED0004u);
    double worst_e = 0.0, worst_f = 0.0;
    for (int t = 0; t < 50; t++) {
        double l0 = rng_range(&r, 0.05, 1.0), u[3], xi[3], xlo[3], xhi[3], flo[3], fhi[3];
        spring_law s = seq_law(m, l0, 0.0);
        double lim = (1.0 + m->delta) * l0, klim = m->k_delta * m->k_t;
        double dlo = lim * (1.0 - 1e-9), dhi = lim * (1.0 + 1e-9);
        rng_unit_vector(&r, u);
        for (int a = 0; a < 3; a++) {
            xi[a] = rng_range(&r, -1, 1);
            xlo[a] = xi[a] + dlo * u[a];
            xhi[a] = xi[a] + dhi * u[a];
        }
        {
            double wl[3] = {xlo[0] - xi[0], xlo[1] - xi[1], xlo[2] - xi[2]};
            double wh[3] = {xhi[0] - xi[0], xhi[1] - xi[1], xhi[2] - xi[2]};
            dlo = norm3(wl);
            dhi = norm3(wh);
        }
        double elo = oc_spring_energy(xi, xlo, s), ehi = oc_spring_energy(xi, xhi, s);
        oc_spring_eval(xi, xlo, s, 0, flo, NULL);
        oc_spring_eval(xi, xhi, s, 0, fhi, NULL);
        /* closed forms on both sides */
        double elo_x = 0.5 * m->k_t * (dlo - l0) * (dlo - l0);
        double ehi_x = 0.5 * m->k_t * (dhi - l0) * (dhi - l0) + 0.5 * klim * (dhi - lim) * (dhi - lim);
        double fmlo_x = m->k_t * (dlo - l0), fmhi_x = m->k_t * (dhi - l0) + klim * (dhi - lim);
        CHECK_REL(elo, elo_x, 1e-10, 0.0);
        CHECK_REL(ehi, ehi_x, 1e-10, 0.0);
        CHECK_REL(dot3(flo, u), fmlo_x, 1e-10, 0.0);
        CHECK_REL(dot3(fhi, u), fmhi_x, 1e-10, 0.0);
        /* continuity: |E(dhi) - E(dlo)| <= |f| gap, |f(dhi) - f(dlo)| <= (k_t + k_lim) gap (+ rounding) */
        double gap = dhi - dlo, fmax = fmhi_x > fmlo_x ? fmhi_x : fmlo_x;
        double de = fabs(ehi - elo), df;
        {
            double w[3] = {fhi[0] - flo[0], fhi[1] - flo[1], fhi[2] - flo[2]};
            df = norm3(w);
        }
        double tol_e = 1.1 * fmax * gap + 1e-13 * ehi, tol_f = 1.1 * (m->k_t + klim) * gap + 1e-13 * fmax;
        if (de / tol_e > worst_e) worst_e = de / tol_e;
        if (df / tol_f > worst_f) worst_f = df / tol_f;
        CHECK(de <= tol_e, "limit term: energy jumps at lim: E(lim(1-1e-9)) %.17g, E(lim(1+1e-9)) %.17g (tol %.3g)",
              elo, ehi, tol_e);
        CHECK(df <= tol_f, "limit term: force jumps at lim: |f(lim(1+1e-9)) - f(lim(1-1e-9))| %.3g > %.3g", df, tol_f);
    }
    printf("%-32s 50 samples: energy change / allowed %.2f, force change / allowed %.2f\n", "continuity at lim",
           worst_e, worst_f);
}

static void check_link_forces(const cloth_material *m)
{
    rng r = rng_seed(0x5EED0001u);
    const int samples = 200;
    for (int region = 0; region < NREGION; region++) {
        double worst_fd = 0.0, worst_closed = 0.0;
        int failed_before = (int)check_failures();
        for (int t = 0; t < samples; t++) {
            link_case lc;
            double f[3], f_on[3], fexp[3], u[3], g_i[3], g_j[3], err_i[3], err_j[3], e_fd;
            make_case(&r, m, region, &lc);
            for (int a = 0; a < 3; a++) u[a] = (lc.xj[a] - lc.xi[a]) / lc.d;

            /* the law carries the region's k and rest, and its limit
             * term is active exactly in the region past the limit */
            {
                double k_used = lc.d >= lc.law.rest ? lc.law.k_hi : lc.law.k_lo;
                CHECK(k_used == lc.k && lc.law.rest == lc.rest, "%s: law gives k %g rest %g, want k %g rest %g",
                      region_name[region], k_used, lc.law.rest, lc.k, lc.rest);
                CHECK((lc.d > lc.law.lim) == lc.past, "%s: d %g, law's lim %g: the limit term should %sbe active",
                      region_name[region], lc.d, lc.law.lim, lc.past ? "" : "not ");
            }

            /* energy, closed form: 1/2 k (d - rest)^2 [+ 1/2 k_delta k_t (d - lim)^2] */
            {
                double e = oc_spring_energy(lc.xi, lc.xj, lc.law);
                double eexp = 0.5 * lc.k * (lc.d - lc.rest) * (lc.d - lc.rest);
                if (lc.past) eexp += 0.5 * lc.klim * (lc.d - lc.lim) * (lc.d - lc.lim);
                if (!CHECK(fabs(e - eexp) <= 1e-10 * eexp,
                           "%s: energy %.17g, want 1/2 k (d-rest)^2%s = %.17g (d %g rest %g k %g lim %g k_lim %g)",
                           region_name[region], e, lc.past ? " + 1/2 k_lim (d-lim)^2" : "", eexp, lc.d, lc.rest, lc.k,
                           lc.lim, lc.klim))
                    continue;
            }

            /* force, closed form: f_i = +(k (d - rest) [+ k_delta k_t (d - lim)]) u */
            oc_spring_eval(lc.xi, lc.xj, lc.law, 0, f, NULL);
            oc_spring_eval(lc.xi, lc.xj, lc.law, 1, f_on, NULL);
            {
                double fm = lc.k * (lc.d - lc.rest) + (lc.past ? lc.klim * (lc.d - lc.lim) : 0.0);
                for (int a = 0; a < 3; a++) fexp[a] = fm * u[a];
            }
            {
                double e[3] = {f[0] - fexp[0], f[1] - fexp[1], f[2] - fexp[2]};
                double rel = norm3(e) / norm3(fexp);
                if (rel > worst_closed) worst_closed = rel;
                CHECK(rel <= 1e-10, "%s: f_i = (%g %g %g), want (k(d-rest)%s)u = (%g %g %g), rel err %.3g",
                      region_name[region], f[0], f[1], f[2], lc.past ? " + k_lim(d-lim)" : "", fexp[0], fexp[1],
                      fexp[2], rel);
                CHECK(f_on[0] == f[0] && f_on[1] == f[1] && f_on[2] == f[2],
                      "%s: force depends on the definiteness flag: (%g %g %g) vs (%g %g %g)", region_name[region],
                      f_on[0], f_on[1], f_on[2], f[0], f[1], f[2]);
            }

            /* minus the central-difference gradient of the energy, both ends */
            {
                double h = 1e-6 * lc.d;
                for (int a = 0; a < 3; a++) {
                    double p[3], q[3];
                    memcpy(p, lc.xi, sizeof p);
                    memcpy(q, lc.xi, sizeof q);
                    p[a] += h;
                    q[a] -= h;
                    g_i[a] = (oc_spring_energy(p, lc.xj, lc.law) - oc_spring_energy(q, lc.xj, lc.law)) / (2 * h);
                    memcpy(p, lc.xj, sizeof p);
                    memcpy(q, lc.xj, sizeof q);
                    p[a] += h;
                    q[a] -= h;
                    g_j[a] = (oc_spring_energy(lc.xi, p, lc.law) - oc_spring_energy(lc.xi, q, lc.law)) / (2 * h);
                }
                for (int a = 0; a < 3; a++) {
                    err_i[a] = f[a] + g_i[a];  /* f_i = -dE/dx_i */
                    err_j[a] = -f[a] + g_j[a]; /* f_j = -f_i = -dE/dx_j */
                }
                e_fd = (norm3(err_i) > norm3(err_j) ? norm3(err_i) : norm3(err_j)) / norm3(f);
                if (e_fd > worst_fd) worst_fd = e_fd;
                CHECK(e_fd < 1e-6,
                      "%s: f_i = (%.10g %.10g %.10g) but -dE/dx_i = (%.10g %.10g %.10g), "
                      "-dE/dx_j = (%.10g %.10g %.10g): rel err %.3g (d %g rest %g)",
                      region_name[region], f[0], f[1], f[2], -g_i[0], -g_i[1], -g_i[2], -g_j[0], -g_j[1], -g_j[2], e_fd,
                      lc.d, lc.rest);
            }
        }
        printf("%-32s %d samples: worst rel err vs FD gradient %.2e, vs closed form %.2e%s\n", region_name[region],
               samples, worst_fd, worst_closed, check_failures() > failed_before ? "  (FAILURES)" : "");
    }
}

static void check_damper(void)
{
    rng r = rng_seed(0x5EED0002u);
    double worst_f = 0, worst_d = 0;
    for (int t = 0; t < 200; t++) {
        double xi[3], xj[3], vi[3], vj[3], u[3], f[3], D[9], Dfd[9], Dfdi[9], fexp[3], w = 0, dd;
        double c = rng_range(&r, 0.01, 5.0);
        rng_unit_vector(&r, u);
        dd = rng_range(&r, 0.05, 1.0);
        for (int a = 0; a < 3; a++) {
            xi[a] = rng_range(&r, -1, 1);
            xj[a] = xi[a] + dd * u[a];
            vi[a] = rng_range(&r, -2, 2);
            vj[a] = rng_range(&r, -2, 2);
        }
        {
            double x[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
            dd = norm3(x);
            for (int a = 0; a < 3; a++) u[a] = x[a] / dd;
        }
        for (int a = 0; a < 3; a++) w += (vj[a] - vi[a]) * u[a];
        for (int a = 0; a < 3; a++) fexp[a] = c * w * u[a];

        oc_damper_eval(xi, xj, vi, vj, c, f, D);
        {
            double e[3] = {f[0] - fexp[0], f[1] - fexp[1], f[2] - fexp[2]};
            double rel = norm3(e) / (fabs(c) * norm3((double[3]){vj[0] - vi[0], vj[1] - vi[1], vj[2] - vi[2]}));
            if (rel > worst_f) worst_f = rel;
            CHECK(rel <= 1e-12, "damper: f_i = (%g %g %g), want c((vj-vi).u)u = (%g %g %g)", f[0], f[1], f[2], fexp[0],
                  fexp[1], fexp[2]);
        }
        /* D against central differences of the damping force wrt v_j and v_i */
        for (int b = 0; b < 3; b++) {
            double h = 1e-6, p[3], q[3], fp[3], fq[3];
            memcpy(p, vj, sizeof p);
            memcpy(q, vj, sizeof q);
            p[b] += h;
            q[b] -= h;
            oc_damper_eval(xi, xj, vi, p, c, fp, NULL);
            oc_damper_eval(xi, xj, vi, q, c, fq, NULL);
            for (int a = 0; a < 3; a++) Dfd[3 * a + b] = (fp[a] - fq[a]) / (2 * h);
            memcpy(p, vi, sizeof p);
            memcpy(q, vi, sizeof q);
            p[b] += h;
            q[b] -= h;
            oc_damper_eval(xi, xj, p, vj, c, fp, NULL);
            oc_damper_eval(xi, xj, q, vj, c, fq, NULL);
            for (int a = 0; a < 3; a++) Dfdi[3 * a + b] = (fp[a] - fq[a]) / (2 * h);
        }
        {
            double e = 0, ei = 0, ec = 0;
            for (int k = 0; k < 9; k++) {
                double cuu = c * u[k / 3] * u[k % 3];
                e += (D[k] - Dfd[k]) * (D[k] - Dfd[k]);
                ei += (D[k] + Dfdi[k]) * (D[k] + Dfdi[k]);
                ec += (D[k] - cuu) * (D[k] - cuu);
            }
            e = sqrt(e) / c; /* |D|_F = c */
            ei = sqrt(ei) / c;
            ec = sqrt(ec) / c;
            if (e > worst_d) worst_d = e;
            CHECK(e < 1e-6, "damper: D differs from FD of f_i wrt v_j: rel err %.3g", e);
            CHECK(ei < 1e-6, "damper: -D differs from FD of f_i wrt v_i: rel err %.3g", ei);
            CHECK(ec < 1e-12, "damper: D differs from c uu^T: rel err %.3g", ec);
        }
    }
    printf("%-32s 200 samples: worst rel err of f %.2e, of D vs FD %.2e\n", "damper", worst_f, worst_d);
}

/* Cloth level: the damping part of cloth_internal_forces is the sum of link
 * dampers, with c_t on sequential and c_b on interlaced links. */
static void check_cloth_damping(void)
{
    rng r = rng_seed(0x5EED0003u);
    cloth_desc d = cloth_default_desc();
    cloth *c = NULL;
    cloth_error err;
    d.rows = 5;
    d.cols = 6;
    d.material = test_material();
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK && c, "cloth_create: %s", err.message)) return;
    {
        int n = cloth_vertex_count(c);
        double *x = malloc(sizeof(double) * 3 * n), *v = calloc(3 * (size_t)n, sizeof(double));
        double *f0 = malloc(sizeof(double) * 3 * n), *f1 = malloc(sizeof(double) * 3 * n);
        double *fexp = calloc(3 * (size_t)n, sizeof(double));
        double fmax = 0, emax = 0;
        memcpy(x, cloth_positions(c), sizeof(double) * 3 * n);
        for (int k = 0; k < 3 * n; k++) x[k] += rng_range(&r, -0.02, 0.02);
        CHECK(cloth_set_positions(c, x) == CLOTH_OK, "set_positions: %s", cloth_last_error(c));
        CHECK(cloth_set_velocities(c, v) == CLOTH_OK, "set_velocities: %s", cloth_last_error(c));
        CHECK(cloth_internal_forces(c, f0) == CLOTH_OK, "internal_forces: %s", cloth_last_error(c));
        for (int k = 0; k < 3 * n; k++) v[k] = rng_range(&r, -1, 1);
        CHECK(cloth_set_velocities(c, v) == CLOTH_OK, "set_velocities: %s", cloth_last_error(c));
        CHECK(cloth_internal_forces(c, f1) == CLOTH_OK, "internal_forces: %s", cloth_last_error(c));
        for (int t = 0; t < 2; t++) {
            cloth_link_type ty = t == 0 ? CLOTH_SEQUENTIAL : CLOTH_INTERLACED;
            double cc = t == 0 ? d.material.c_t : d.material.c_b;
            for (int e = 0; e < cloth_link_count(c, ty); e++) {
                cloth_link L;
                double fi[3];
                if (cloth_get_link(c, ty, e, &L) != CLOTH_OK) continue;
                oc_damper_eval(x + 3 * L.i, x + 3 * L.j, v + 3 * L.i, v + 3 * L.j, cc, fi, NULL);
                for (int a = 0; a < 3; a++) {
                    fexp[3 * L.i + a] += fi[a];
                    fexp[3 * L.j + a] -= fi[a];
                }
            }
        }
        for (int k = 0; k < 3 * n; k++) {
            double e = fabs((f1[k] - f0[k]) - fexp[k]);
            if (fabs(fexp[k]) > fmax) fmax = fabs(fexp[k]);
            if (e > emax) emax = e;
        }
        CHECK(fmax > 0, "cloth damping forces are all zero");
        CHECK(emax <= 1e-9 * fmax,
              "cloth damping: internal_forces(v) - internal_forces(0) differs from the sum of link "
              "dampers (c_t sequential, c_b interlaced) by %.3g (max %.3g)",
              emax, fmax);
        printf("%-32s max |f(v)-f(0) - sum dampers| = %.2e of %.2e\n", "cloth damping", emax, fmax);
        free(x);
        free(v);
        free(f0);
        free(f1);
        free(fexp);
    }
    cloth_destroy(c);
}

int main(void)
{
    cloth_material m = test_material();
    check_laws(&m);
    check_link_forces(&m);
    check_limit_continuity(&m);
    check_damper();
    check_cloth_damping();
    return check_summary();
}
