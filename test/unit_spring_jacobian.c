/* Unit: the link stiffness blocks and the definiteness rule (paper eq. 5, 14,
 * section 3.2), and the whole cloth's forces against its energy.
 *
 * Single links (oc_spring_eval), for each link type and region:
 *   - definiteness = 0: K = df_i/dx_j equals the central difference of
 *     oc_spring_eval's f_i wrt x_j, and -K equals that wrt x_i (norm-wise
 *     relative error over the 3x3 block < 1e-6, floor 1e-3 k);
 *     K = k uu^T + k (1 - rest/d)(I - uu^T): eigenvalues k, k(1-rest/d) twice.
 *     Sequential links past the elongation limit lim = (1 + delta) l0 (test
 *     material: delta 0.07, k_delta 37): K = (k_t + k_delta k_t) uu^T +
 *     (fe/d)(I - uu^T), fe = k_t (d - l0) + k_delta k_t (d - lim): eigenvalues
 *     k_t + k_delta k_t along u and fe/d twice across. The tension region
 *     stays below the limit (d/l0 in (1.001, 1 + 0.99 delta)).
 *   - definiteness = 1: K symmetric and positive semidefinite (eigenvalues
 *     >= -1e-12 |K|), so the link's 6x6 block [[-K, K], [K, -K]] is negative
 *     semidefinite; stretched links (d >= rest) are unchanged by the rule;
 *     compressed links keep exactly k uu^T (eigenvalues k, 0, 0), down to
 *     d = 0.05 rest.
 *   - the rule matters: a compressed link with the rule off has the negative
 *     eigenvalue k (1 - rest/d).
 * The Newton step's form (oc_spring_eval_predicted), for each region, with u0
 * the link's direction turned by up to 0.2 rad: f_i = -dE/dx_i and
 * K = df_i/dx_j (-K wrt x_i) by central differences (rel. 1e-6), K
 * symmetric positive semidefinite; with u0 = u, f_i equals oc_spring_eval's.
 * Whole cloth: on a random state with zero velocities, plastic links of
 * both kinds (d > l1 and d < l1; alpha = 1, plastic state frozen) and
 * sequential links past the elongation limit,
 * cloth_internal_forces = -grad cloth_energies().elastic by central
 * differences through cloth_set_positions; the elastic energy equals the sum
 * of oc_spring_energy over the links with the laws of their current regions; and
 * evaluating energies does not change the plastic state.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "check.h"

enum {
    SEQ_TENSION,
    SEQ_PAST_LIMIT,
    SEQ_COMPRESSION,
    INT_ELASTIC_STRETCH,
    INT_ELASTIC_COMPRESSION,
    INT_SPREAD,
    INT_PLASTIC_COMPRESSION,
    NREGION
};
static const char *region_name[NREGION] = {"sequential tension",
                                           "sequential past the limit",
                                           "sequential compression",
                                           "interlaced elastic stretched",
                                           "interlaced elastic compressed",
                                           "interlaced plastic spreading",
                                           "interlaced plastic compression"};

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double norm3(const double a[3]) { return sqrt(dot3(a, a)); }
static double fro9(const double *A)
{
    double s = 0;
    for (int k = 0; k < 9; k++) s += A[k] * A[k];
    return sqrt(s);
}

/* Eigenvalues of a symmetric 3x3 matrix (row-major) by cyclic Jacobi
 * rotations, sorted ascending. */
static void sym3_eigenvalues(const double S[9], double ev[3])
{
    double a[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) a[i][j] = 0.5 * (S[3 * i + j] + S[3 * j + i]);
    for (int sweep = 0; sweep < 100; sweep++) {
        double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        double scale = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2] + off;
        if (off <= 1e-34 * scale || off == 0.0) break;
        for (int p = 0; p < 2; p++)
            for (int q = p + 1; q < 3; q++) {
                double theta, t, cs, sn;
                if (a[p][q] == 0.0) continue;
                theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
                t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1));
                cs = 1 / sqrt(t * t + 1);
                sn = t * cs;
                /* A <- J^T A J, J the rotation in the (p, q) plane */
                for (int k = 0; k < 3; k++) {
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = cs * akp - sn * akq;
                    a[k][q] = sn * akp + cs * akq;
                }
                for (int k = 0; k < 3; k++) {
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = cs * apk - sn * aqk;
                    a[q][k] = sn * apk + cs * aqk;
                }
            }
    }
    ev[0] = a[0][0];
    ev[1] = a[1][1];
    ev[2] = a[2][2];
    for (int i = 0; i < 2; i++)
        for (int j = i + 1; j < 3; j++)
            if (ev[j] < ev[i]) {
                double t = ev[i];
                ev[i] = ev[j];
                ev[j] = t;
            }
}

static cloth_material test_material(void)
{
    cloth_material m = cloth_material_preset(CLOTH_COTTON);
    m.k_t = 3100.0;
    m.k_c = 73.0;
    m.k_b = 2.3;
    m.k_s = 11.7;
    m.alpha = 0.8;
    m.delta = 0.07;   /* not a preset's */
    m.k_delta = 37.0; /* not a preset's */
    return m;
}

typedef struct link_case {
    double xi[3], xj[3], d, u[3];
    spring_law law;
    double k, rest;   /* expected stiffness and rest length in this region */
    double klim, lim; /* expected limit term: k_delta k_t past (1 + delta) l0; 0 elsewhere */
} link_case;

/* lo/hi bound d/rest for the compressed regions so tests can ask for strong
 * compression. */
static void make_case(rng *r, const cloth_material *m, int region, double squeeze_lo, link_case *lc)
{
    double l0 = rng_range(r, 0.05, 1.0), l1, d;
    lc->klim = 0.0;
    lc->lim = HUGE_VAL;
    switch (region) {
    case SEQ_TENSION: /* below the elongation limit */
        lc->law = seq_law(m, l0, 0.0), lc->k = m->k_t, lc->rest = l0;
        d = l0 * rng_range(r, 1.001, 1.0 + 0.99 * m->delta);
        break;
    case SEQ_PAST_LIMIT:
        lc->law = seq_law(m, l0, 0.0), lc->k = m->k_t, lc->rest = l0;
        lc->klim = m->k_delta * m->k_t, lc->lim = (1.0 + m->delta) * l0;
        d = l0 * rng_range(r, 1.0 + 1.01 * m->delta, 1.5);
        break;
    case SEQ_COMPRESSION:
        lc->law = seq_law(m, l0, 0.0), lc->k = m->k_c, lc->rest = l0;
        d = l0 * rng_range(r, squeeze_lo, 0.99);
        break;
    case INT_ELASTIC_STRETCH:
        lc->law = int_law(m, l0, 0, 0.0), lc->k = m->k_b, lc->rest = l0;
        d = l0 * rng_range(r, 1.01, 1.5);
        break;
    case INT_ELASTIC_COMPRESSION:
        lc->law = int_law(m, l0, 0, 0.0), lc->k = m->k_b, lc->rest = l0;
        d = l0 * rng_range(r, squeeze_lo, 0.99); /* e.g. alpha = 0 */
        break;
    case INT_SPREAD:
        l1 = l0 * rng_range(r, 0.2, 0.75);
        lc->law = int_law(m, l0, 1, l1), lc->k = m->k_s, lc->rest = l1;
        d = rng_range(r, 1.01 * l1, 0.79 * l0);
        break;
    default:
        l1 = l0 * rng_range(r, 0.2, 0.75);
        lc->law = int_law(m, l0, 1, l1), lc->k = m->k_b, lc->rest = l1;
        d = l1 * rng_range(r, squeeze_lo, 0.99);
        break;
    }
    rng_unit_vector(r, lc->u);
    for (int a = 0; a < 3; a++) {
        lc->xi[a] = rng_range(r, -1, 1);
        lc->xj[a] = lc->xi[a] + d * lc->u[a];
    }
    {
        double x[3] = {lc->xj[0] - lc->xi[0], lc->xj[1] - lc->xi[1], lc->xj[2] - lc->xi[2]};
        lc->d = norm3(x);
        for (int a = 0; a < 3; a++) lc->u[a] = x[a] / lc->d;
    }
}

/* df_i/dx_j (wrt = 1) or df_i/dx_i (wrt = 0) by central differences. */
static void fd_block(const link_case *lc, int wrt, double J[9])
{
    double h = 1e-6 * lc->d;
    for (int b = 0; b < 3; b++) {
        double xp[3], xm[3], fp[3], fm[3];
        memcpy(xp, wrt ? lc->xj : lc->xi, sizeof xp);
        memcpy(xm, wrt ? lc->xj : lc->xi, sizeof xm);
        xp[b] += h;
        xm[b] -= h;
        if (wrt) {
            oc_spring_eval(lc->xi, xp, lc->law, 0, fp, NULL);
            oc_spring_eval(lc->xi, xm, lc->law, 0, fm, NULL);
        } else {
            oc_spring_eval(xp, lc->xj, lc->law, 0, fp, NULL);
            oc_spring_eval(xm, lc->xj, lc->law, 0, fm, NULL);
        }
        for (int a = 0; a < 3; a++) J[3 * a + b] = (fp[a] - fm[a]) / (2 * h);
    }
}

static void check_link_jacobians(const cloth_material *m)
{
    rng r = rng_seed(0x5EED0101u);
    const int samples = 200;
    for (int region = 0; region < NREGION; region++) {
        double worst = 0, worst_ev = 0;
        int compressed_region = region == SEQ_COMPRESSION || region == INT_ELASTIC_COMPRESSION ||
                                region == INT_PLASTIC_COMPRESSION;
        long failed_before = check_failures();
        for (int t = 0; t < samples; t++) {
            link_case lc;
            double f[3], K[9], Kon[9], Jj[9], Ji[9], ev[3], evon[3], nK, e_j = 0, e_i = 0;
            /* half the compressed samples strongly compressed (down to 0.05) */
            make_case(&r, m, region, (t & 1) ? 0.05 : 0.5, &lc);
            oc_spring_eval(lc.xi, lc.xj, lc.law, 0, f, K);
            oc_spring_eval(lc.xi, lc.xj, lc.law, 1, f, Kon);
            fd_block(&lc, 1, Jj);
            fd_block(&lc, 0, Ji);
            nK = fro9(K);
            for (int k = 0; k < 9; k++) {
                e_j += (K[k] - Jj[k]) * (K[k] - Jj[k]);
                e_i += (-K[k] - Ji[k]) * (-K[k] - Ji[k]);
            }
            {
                double den = nK > 1e-3 * lc.k ? nK : 1e-3 * lc.k;
                e_j = sqrt(e_j) / den;
                e_i = sqrt(e_i) / den;
            }
            if (e_j > worst) worst = e_j;
            if (e_i > worst) worst = e_i;
            CHECK(e_j < 1e-6,
                  "%s: K = df_i/dx_j (rule off) vs FD: rel err %.3g (d/rest %g)\n"
                  "  K  = [%g %g %g; %g %g %g; %g %g %g]\n  FD = [%g %g %g; %g %g %g; %g %g %g]",
                  region_name[region], e_j, lc.d / lc.rest, K[0], K[1], K[2], K[3], K[4], K[5], K[6], K[7], K[8], Jj[0],
                  Jj[1], Jj[2], Jj[3], Jj[4], Jj[5], Jj[6], Jj[7], Jj[8]);
            CHECK(e_i < 1e-6, "%s: -K vs FD of f_i wrt x_i (rule off): rel err %.3g", region_name[region], e_i);

            /* the law's limit term (seq_law: k_delta k_t past (1 + delta) l0) */
            if (region == SEQ_PAST_LIMIT || region == SEQ_TENSION)
                CHECK(fabs(lc.law.k_lim - m->k_delta * m->k_t) <= 1e-15 * m->k_delta * m->k_t &&
                          fabs(lc.law.lim - (1.0 + m->delta) * lc.rest) <= 1e-15 * lc.rest,
                      "%s: seq_law's k_lim %.17g lim %.17g, want k_delta k_t %.17g, (1 + delta) l0 %.17g",
                      region_name[region], lc.law.k_lim, lc.law.lim, m->k_delta * m->k_t, (1.0 + m->delta) * lc.rest);

            /* rule off: eigenvalues fe/d (twice, across u) and k + k_lim
             * (along u), fe = k (d - rest) + k_lim (d - lim) past the limit;
             * below it fe/d = k (1 - rest/d) */
            sym3_eigenvalues(K, ev);
            {
                int past = lc.d > lc.lim;
                double kl = past ? lc.klim : 0.0;
                double fe = lc.k * (lc.d - lc.rest) + (past ? lc.klim * (lc.d - lc.lim) : 0.0);
                double lt = fe / lc.d, ka = lc.k + kl, want[3];
                CHECK(past == (region == SEQ_PAST_LIMIT), "%s: d/lim %g: sampled on the wrong side of the limit",
                      region_name[region], lc.d / lc.lim);
                want[0] = lt < ka ? lt : ka;
                want[1] = lt;
                want[2] = lt < ka ? ka : lt;
                for (int a = 0; a < 3; a++) {
                    double e = fabs(ev[a] - want[a]) / nK;
                    if (e > worst_ev) worst_ev = e;
                    CHECK(e < 1e-9, "%s: rule off, eigenvalue %d = %.12g, want %.12g (k %g, k_lim %g, rest/d %g)",
                          region_name[region], a, ev[a], want[a], lc.k, kl, lc.rest / lc.d);
                }
                /* and the along-u eigenvector is u: u^T K u = k + k_lim */
                {
                    double Ku[3];
                    for (int a = 0; a < 3; a++)
                        Ku[a] = K[3 * a] * lc.u[0] + K[3 * a + 1] * lc.u[1] + K[3 * a + 2] * lc.u[2];
                    double w[3] = {Ku[0] - ka * lc.u[0], Ku[1] - ka * lc.u[1], Ku[2] - ka * lc.u[2]};
                    double e = norm3(w) / nK;
                    CHECK(e < 1e-12, "%s: K u != (k + k_lim) u: rel err %.3g (k + k_lim %g)", region_name[region], e,
                          ka);
                }
                if (compressed_region)
                    CHECK(ev[0] < 0,
                          "%s: compressed link (d/rest %g) with the rule off should have a "
                          "negative eigenvalue k(1-rest/d) = %g, got %g",
                          region_name[region], lc.d / lc.rest, lt, ev[0]);
            }

            /* rule on: symmetric, PSD; unchanged when stretched; k uu^T when compressed */
            {
                double nKon = fro9(Kon), asym = 0, diff = 0, diffuu = 0;
                for (int a = 0; a < 3; a++)
                    for (int b = 0; b < 3; b++) {
                        double kuu = lc.k * lc.u[a] * lc.u[b];
                        asym = fmax(asym, fabs(Kon[3 * a + b] - Kon[3 * b + a]));
                        diff = fmax(diff, fabs(Kon[3 * a + b] - K[3 * a + b]));
                        diffuu = fmax(diffuu, fabs(Kon[3 * a + b] - kuu));
                    }
                CHECK(asym <= 1e-14 * nKon, "%s: K (rule on) not symmetric: %.3g", region_name[region], asym);
                sym3_eigenvalues(Kon, evon);
                CHECK(evon[0] >= -1e-12 * nKon,
                      "%s: K (rule on) has eigenvalue %.6g < 0 (d/rest %g): the link's 6x6 stiffness "
                      "is not negative semidefinite",
                      region_name[region], evon[0], lc.d / lc.rest);
                if (!compressed_region)
                    CHECK(diff <= 1e-14 * nKon, "%s: the rule changed a stretched link's K by %.3g",
                          region_name[region], diff);
                else {
                    CHECK(diffuu <= 1e-12 * lc.k,
                          "%s: rule on, compressed: K differs from k uu^T by %.3g "
                          "(k %g, d/rest %g)",
                          region_name[region], diffuu, lc.k, lc.d / lc.rest);
                    CHECK(fabs(evon[2] - lc.k) <= 1e-10 * lc.k && fabs(evon[0]) <= 1e-10 * lc.k &&
                              fabs(evon[1]) <= 1e-10 * lc.k,
                          "%s: rule on, compressed: eigenvalues %g %g %g, want 0 0 %g", region_name[region], evon[0],
                          evon[1], evon[2], lc.k);
                }
            }
        }
        printf("%-32s %d samples: worst rel err of K vs FD %.2e, eigenvalues %.2e%s\n", region_name[region], samples,
               worst, worst_ev, check_failures() > failed_before ? "  (FAILURES)" : "");
    }
}

/* ----------------------------------------------------- whole cloth vs energy */

typedef struct link_snapshot {
    int plastic;
    double l1;
} link_snapshot;

static void snapshot_links(const cloth *c, link_snapshot *s)
{
    int n = cloth_link_count(c, CLOTH_INTERLACED);
    for (int e = 0; e < n; e++) {
        cloth_link L;
        cloth_get_link(c, CLOTH_INTERLACED, e, &L);
        s[e].plastic = L.plastic;
        s[e].l1 = L.plastic ? L.l1 : 0.0;
    }
}

static void check_cloth_gradient(void)
{
    rng r = rng_seed(0x5EED0102u);
    cloth_desc d = cloth_default_desc();
    cloth *c = NULL;
    cloth_error err;
    int n, n_int, nplastic, above = 0, below = 0, past_limit = 0;
    double *x0, *x, *f, *g, *v, spacing;
    link_snapshot *s0, *s1;

    d.rows = 6;
    d.cols = 7;
    d.width = 0.6;
    d.height = 0.5;
    d.material = test_material();
    d.material.alpha = 1.0; /* any compression of an interlaced link is plastic */
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK && c, "cloth_create: %s", err.message)) return;
    n = cloth_vertex_count(c);
    n_int = cloth_link_count(c, CLOTH_INTERLACED);
    spacing = d.width / (d.cols - 1);
    x0 = malloc(sizeof(double) * 3 * n);
    x = malloc(sizeof(double) * 3 * n);
    f = malloc(sizeof(double) * 3 * n);
    g = malloc(sizeof(double) * 3 * n);
    v = calloc(3 * (size_t)n, sizeof(double));
    s0 = malloc(sizeof *s0 * (size_t)n_int);
    s1 = malloc(sizeof *s1 * (size_t)n_int);

    /* state A: the rest grid with random offsets; update the plastic state there */
    memcpy(x0, cloth_positions(c), sizeof(double) * 3 * n);
    for (int k = 0; k < 3 * n; k++) x0[k] += rng_range(&r, -0.2, 0.2) * spacing;
    CHECK(cloth_set_positions(c, x0) == CLOTH_OK, "set_positions: %s", cloth_last_error(c));
    nplastic = cloth_update_plastic(c);
    CHECK(nplastic > 0 && nplastic < n_int, "want some but not all interlaced links plastic, got %d of %d", nplastic,
          n_int);
    /* state B: move again, without updating the plastic state, so plastic
     * links sit on both sides of l1 (k_s above, k_b below) */
    for (int k = 0; k < 3 * n; k++) x0[k] += rng_range(&r, -0.05, 0.05) * spacing;
    CHECK(cloth_set_positions(c, x0) == CLOTH_OK, "set_positions: %s", cloth_last_error(c));
    CHECK(cloth_set_velocities(c, v) == CLOTH_OK, "set_velocities: %s", cloth_last_error(c));
    snapshot_links(c, s0);

    /* energy = sum of link energies with the laws of their regions */
    {
        cloth_desc cd = cloth_get_desc(c);
        double e_sum = 0, e = cloth_energies(c).elastic;
        for (int t = 0; t < 2; t++) {
            cloth_link_type ty = t ? CLOTH_INTERLACED : CLOTH_SEQUENTIAL;
            for (int k = 0; k < cloth_link_count(c, ty); k++) {
                cloth_link L;
                spring_law law;
                cloth_get_link(c, ty, k, &L);
                law = t ? int_law(&cd.material, L.rest, L.plastic, L.l1) : seq_law(&cd.material, L.rest, 0.0);
                e_sum += oc_spring_energy(x0 + 3 * L.i, x0 + 3 * L.j, law);
                if (!t) {
                    double dd[3] = {x0[3 * L.j] - x0[3 * L.i], x0[3 * L.j + 1] - x0[3 * L.i + 1],
                                    x0[3 * L.j + 2] - x0[3 * L.i + 2]};
                    if (norm3(dd) > (1.0 + cd.material.delta) * L.rest) past_limit++;
                }
                if (t && L.plastic) {
                    double dd[3] = {x0[3 * L.j] - x0[3 * L.i], x0[3 * L.j + 1] - x0[3 * L.i + 1],
                                    x0[3 * L.j + 2] - x0[3 * L.i + 2]};
                    if (norm3(dd) > L.l1) above++;
                    else below++;
                }
            }
        }
        CHECK(above > 0 && below > 0, "want plastic links with d > l1 and d < l1, got %d and %d", above, below);
        CHECK(past_limit > 0, "want sequential links past the elongation limit (their k_delta term), got none");
        CHECK(fabs(e - e_sum) <= 1e-12 * e_sum,
              "cloth_energies().elastic = %.17g but the sum of link energies is %.17g", e, e_sum);
    }

    CHECK(cloth_internal_forces(c, f) == CLOTH_OK, "internal_forces: %s", cloth_last_error(c));
    {
        double h = 1e-6 * spacing, err2 = 0, f2 = 0, fmax = 0, emax = 0;
        memcpy(x, x0, sizeof(double) * 3 * n);
        for (int k = 0; k < 3 * n; k++) {
            double ep, em;
            x[k] = x0[k] + h;
            cloth_set_positions(c, x);
            ep = cloth_energies(c).elastic;
            x[k] = x0[k] - h;
            cloth_set_positions(c, x);
            em = cloth_energies(c).elastic;
            x[k] = x0[k];
            g[k] = (ep - em) / (2 * h);
        }
        cloth_set_positions(c, x0);
        for (int k = 0; k < 3 * n; k++) {
            double e = f[k] + g[k];
            err2 += e * e;
            f2 += f[k] * f[k];
            if (fabs(f[k]) > fmax) fmax = fabs(f[k]);
            if (fabs(e) > emax) emax = fabs(e);
        }
        CHECK(f2 > 0, "internal forces all zero on a deformed cloth");
        CHECK(sqrt(err2) <= 1e-6 * sqrt(f2),
              "cloth_internal_forces vs -grad elastic energy: |err| %.3g, |f| %.3g (rel %.3g)", sqrt(err2), sqrt(f2),
              sqrt(err2 / f2));
        CHECK(emax <= 1e-6 * fmax, "cloth_internal_forces vs -grad elastic energy: max component err %.3g of %.3g",
              emax, fmax);
        printf("%-32s %d plastic (%d above l1, %d below), %d sequential past the limit: rel err of forces vs "
               "-grad E %.2e\n",
               "whole cloth", nplastic, above, below, past_limit, sqrt(err2 / f2));
    }
    snapshot_links(c, s1);
    {
        int changed = 0;
        for (int e = 0; e < n_int; e++)
            if (s0[e].plastic != s1[e].plastic || s0[e].l1 != s1[e].l1) changed++;
        CHECK(changed == 0, "set_positions/energies/internal_forces changed the plastic state of %d links", changed);
    }
    free(x0);
    free(x);
    free(f);
    free(g);
    free(v);
    free(s0);
    free(s1);
    cloth_destroy(c);
}

/* E (what = 0), f_i[a] (1) of oc_spring_eval_predicted with x_i (wrt 0) or
 * x_j (wrt 1) moved by e along axis b */
static double predicted_at(const link_case *lc, const double *u0, int wrt, int b, double e, int what, int a)
{
    double xi[3], xj[3], f[3];
    memcpy(xi, lc->xi, sizeof xi);
    memcpy(xj, lc->xj, sizeof xj);
    (wrt ? xj : xi)[b] += e;
    double E = oc_spring_eval_predicted(xi, xj, u0, lc->law, 0.0, f, NULL, NULL);
    return what ? f[a] : E;
}

static void check_predicted_links(const cloth_material *m)
{
    rng r = rng_seed(0x5EED0202u);
    double worst = 0.0;
    for (int region = 0; region < NREGION; region++)
        for (int t = 0; t < 200; t++) {
            link_case lc;
            make_case(&r, m, region, (t & 1) ? 0.05 : 0.5, &lc);
            double u0[3], w[3], f[3], K[9], fp[3], Kp[9], ev[3], h = 1e-6 * lc.d;
            rng_unit_vector(&r, w);
            for (int a = 0; a < 3; a++) u0[a] = lc.u[a] + 0.2 * rng_unit(&r) * w[a];
            double n0 = norm3(u0);
            for (int a = 0; a < 3; a++) u0[a] /= n0;
            oc_spring_eval_predicted(lc.xi, lc.xj, u0, lc.law, 0.0, f, K, NULL);
            double nK = fmax(fro9(K), 1e-3 * lc.k), nf = fmax(norm3(f), 1e-3 * lc.k * lc.d), eg = 0.0, ek = 0.0;
            for (int b = 0; b < 3; b++) {
                double g = (predicted_at(&lc, u0, 0, b, h, 0, 0) - predicted_at(&lc, u0, 0, b, -h, 0, 0)) / (2 * h);
                eg = fmax(eg, fabs(f[b] + g) / nf);
                for (int a = 0; a < 3; a++) {
                    double dj = (predicted_at(&lc, u0, 1, b, h, 1, a) - predicted_at(&lc, u0, 1, b, -h, 1, a)) /
                                (2 * h);
                    double di = (predicted_at(&lc, u0, 0, b, h, 1, a) - predicted_at(&lc, u0, 0, b, -h, 1, a)) /
                                (2 * h);
                    ek = fmax(ek, fmax(fabs(K[3 * a + b] - dj), fabs(K[3 * a + b] + di)) / nK);
                }
            }
            worst = fmax(worst, fmax(eg, ek));
            CHECK(eg < 1e-6 && ek < 1e-6, "%s, predicted: f vs -dE/dx_i %.3g, K vs FD %.3g (d/rest %g)",
                  region_name[region], eg, ek, lc.d / lc.rest);
            sym3_eigenvalues(K, ev);
            CHECK(ev[0] >= -1e-12 * nK && fabs(K[1] - K[3]) + fabs(K[2] - K[6]) + fabs(K[5] - K[7]) <= 1e-12 * nK,
                  "%s, predicted: K not symmetric semidefinite (eigenvalue %g)", region_name[region], ev[0]);
            oc_spring_eval_predicted(lc.xi, lc.xj, lc.u, lc.law, 0.0, fp, Kp, NULL);
            oc_spring_eval(lc.xi, lc.xj, lc.law, 0, f, NULL);
            CHECK(norm3((double[3]){fp[0] - f[0], fp[1] - f[1], fp[2] - f[2]}) <= 1e-12 * nf,
                  "%s, predicted along u: force differs from oc_spring_eval's", region_name[region]);
        }
    printf("predicted-direction form, %d regions: worst rel err of f, K vs FD %.2e\n", NREGION, worst);
}

/* oc_spring_eval_predicted's slack weight w: a slack link's K gains exactly
 * w k_hi u u^T (so it stays symmetric semidefinite), a taut one's nothing;
 * the energy and force are unchanged */
static void check_slack_stiffen(const cloth_material *m)
{
    spring_law s = seq_law(m, 0.1, 0.0);
    const double xi[3] = {0.01, -0.02, 0.03}, dir[3] = {0.6, 0.0, 0.8}, u0[3] = {0.0, 0.6, 0.8};
    for (int taut = 0; taut < 2; taut++) {
        double len = taut ? 0.1 : 0.097, xj[3], K0[9], K[9], f0[3], f[3], w = 0.1;
        for (int r = 0; r < 3; r++) xj[r] = xi[r] + len * dir[r];
        int slack = -1;
        double E0 = oc_spring_eval_predicted(xi, xj, u0, s, 0.0, f0, K0, NULL);
        double E = oc_spring_eval_predicted(xi, xj, u0, s, w, f, K, &slack);
        double err = fabs(E - E0);
        for (int r = 0; r < 3; r++) err = fmax(err, fabs(f[r] - f0[r]));
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                err = fmax(err, fabs(K[3 * a + b] - K0[3 * a + b] - (taut ? 0.0 : w * s.k_hi * dir[a] * dir[b])));
        CHECK(slack == !taut && err <= 1e-12 * s.k_hi, "slack stiffening (%s): slack %d, off by %g",
              taut ? "at rest length" : "slack", slack, err);
    }
}

int main(void)
{
    cloth_material m = test_material();
    check_link_jacobians(&m);
    check_predicted_links(&m);
    check_slack_stiffen(&m);
    check_cloth_gradient();
    return check_summary();
}
