/* Unit: the Newton step's self-contact (core/src/self_contact.h) against
 * brute force over every pair: the barrier's energy and its pairs within
 * the thickness, with its candidate list kept, grown and rebuilt; the share of an
 * update short of the first touch; and a flat sheet's work. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "internal.h"
#include "ccd.h"
#include "self_contact.h"

#define N 9       /* vertices per side */
#define H 0.05    /* grid step, m */
#define D 0.02    /* thickness, m */
#define CFAC 0.01 /* dx/dv */
#define NV (N * N)
#define NT (2 * (N - 1) * (N - 1))

static int tri[3 * NT];
static unsigned long seed = 12345;

static double jitter(double a)
{
    seed = seed * 6364136223846793005ul + 1442695040888963407ul;
    return a * ((double)(seed >> 11) / 9007199254740992.0 * 2.0 - 1.0);
}

static void triangles(void)
{
    int t = 0;
    for (int r = 0; r + 1 < N; r++)
        for (int q = 0; q + 1 < N; q++, t += 2) {
            int a = r * N + q, b = a + 1, c = a + N, d = c + 1;
            const int k[6] = {a, b, d, a, d, c};
            memcpy(tri + 3 * t, k, sizeof k);
        }
}

/* The sheet folded at row N / 2: the upper rows over the lower ones, gap apart, shifted by a third of a step */
static void fold(double *x, double gap)
{
    for (int r = 0; r < N; r++)
        for (int q = 0; q < N; q++) {
            double *p = x + 3 * (r * N + q);
            int top = r > N / 2;
            p[0] = q * H + (top ? H / 3.0 : 0.0) + jitter(0.1 * D);
            p[1] = (top ? N - 1 - r + 0.5 : r) * H + jitter(0.1 * D);
            p[2] = (top ? gap : 0.0) + jitter(0.1 * D);
        }
}

/* Brute force in the list's order: every vertex against every triangle not its own, then
 * every edge against every later edge sharing no vertex; the energy, *active the pairs within D */
static double brute_energy(const int *edges, int ne, const double *x, double kappa, int *active)
{
    double E[2] = {0.0, 0.0};
    *active = 0;
    for (int kind = 0; kind < 2; kind++)
        for (int a = 0; a < (kind ? ne : NV); a++)
            for (int b = kind ? a + 1 : 0; b < (kind ? ne : NT); b++) {
                int v[4];
                if (kind) {
                    const int vv[4] = {edges[2 * a], edges[2 * a + 1], edges[2 * b], edges[2 * b + 1]};
                    memcpy(v, vv, sizeof v);
                    if (v[0] == v[2] || v[0] == v[3] || v[1] == v[2] || v[1] == v[3]) continue;
                } else {
                    const int vv[4] = {a, tri[3 * b], tri[3 * b + 1], tri[3 * b + 2]};
                    memcpy(v, vv, sizeof v);
                    if (a == v[1] || a == v[2] || a == v[3]) continue;
                }
                double y[12], c[4], n[3] = {0.0, 0.0, 0.0};
                for (int k = 0; k < 4; k++) memcpy(y + 3 * k, x + 3 * v[k], 3 * sizeof *y);
                oc_ccd_pair_weights(kind, y, c);
                for (int k = 0; k < 4; k++)
                    for (int r = 0; r < 3; r++) n[r] += c[k] * y[3 * k + r];
                double d = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                if (!(d < D) || !(d > 1e-9 * D)) continue;
                E[kind] -= kappa * (d - D) * (d - D) * log(d / D);
                ++*active;
            }
    return E[0] + E[1];
}

/* The edges as self_contact lists them: each once, ends ascending, sorted */
static int edge_list(int *edges)
{
    int ne = 0;
    for (int a = 0; a < NV; a++)
        for (int b = a + 1; b < NV; b++)
            for (int t = 0; t < NT; t++) {
                int ha = 0, hb = 0;
                for (int k = 0; k < 3; k++) ha += tri[3 * t + k] == a, hb += tri[3 * t + k] == b;
                if (ha && hb) {
                    edges[2 * ne] = a;
                    edges[2 * ne + 1] = b;
                    ne++;
                    break;
                }
            }
    return ne;
}

/* The first touch over x0 -> x1 of every pair, brute force; HUGE_VAL none */
static double brute_touch(const int *edges, int ne, const double *x0, const double *x1)
{
    double first = HUGE_VAL, eta = 1e-3 * D;
    for (int kind = 0; kind < 2; kind++)
        for (int a = 0; a < (kind ? ne : NV); a++)
            for (int b = kind ? a + 1 : 0; b < (kind ? ne : NT); b++) {
                int v[4] = {kind ? edges[2 * a] : a, kind ? edges[2 * a + 1] : tri[3 * b],
                            kind ? edges[2 * b] : tri[3 * b + 1], kind ? edges[2 * b + 1] : tri[3 * b + 2]};
                int shared = kind ? v[0] == v[2] || v[0] == v[3] || v[1] == v[2] || v[1] == v[3]
                                  : a == v[1] || a == v[2] || a == v[3];
                if (shared) continue;
                double y0[12], y1[12];
                for (int k = 0; k < 4; k++) {
                    memcpy(y0 + 3 * k, x0 + 3 * v[k], 3 * sizeof *y0);
                    memcpy(y1 + 3 * k, x1 + 3 * v[k], 3 * sizeof *y1);
                }
                ccd_hit hit;
                if (kind ? oc_ccd_edge_edge(y0, y1, eta, &hit) : oc_ccd_point_triangle(y0, y1, eta, &hit))
                    first = fmin(first, hit.t);
            }
    return first;
}

static cloth *sheet(void)
{
    cloth_desc d = cloth_default_desc();
    cloth_error err;
    cloth *c = NULL;
    d.rows = d.cols = N;
    d.width = d.height = (N - 1) * H;
    CHECK(cloth_create(&d, &c, &err) == CLOTH_OK && c, "cloth_create: %s", err.message);
    return c;
}

/* The folded sheet: energy and pairs within D as brute force finds them, with the
 * list rebuilt, kept over a small move and rebuilt over a large one */
static void case_fold(cloth *c)
{
    static double x[3 * NV], y[3 * NV];
    static int edges[2 * 3 * NT];
    int ne = edge_list(edges), active;
    self_contact *s = oc_self_contact_create(NV, NT, tri, D);
    if (!CHECK(s != NULL, "oc_self_contact_create")) return;
    oc_self_contact_begin(s, c, CFAC);
    double mt = 0.0;
    for (int i = 0; i < NV; i++) mt += c->mass[i];
    double kappa = mt / NV / (CFAC * CFAC * (2.0 * log(2.0) + 5.0));
    /* the layers 1.5 D apart (rebuild), brought to 0.6 D by moves within the list's regions
     * (kept), then jittered by 3 D (rebuild) */
    fold(x, 1.5 * D);
    const long rebuilt[3] = {1, 0, 1};
    for (int m = 0; m < 3; m++) {
        for (int i = 0; i < NV; i++)
            for (int r = 0; r < 3; r++) {
                double toward = m == 1 && r == 2 ? (i / N > N / 2 ? -0.45 * D : 0.45 * D) : 0.0;
                y[3 * i + r] = x[3 * i + r] + toward + jitter(m == 0 ? 0.0 : m == 1 ? 0.04 * D : 3.0 * D);
            }
        long before = oc_self_contact_get_work(s).rebuilds;
        double E = oc_self_contact_eval(s, y, CFAC, NULL, NULL), Eb = brute_energy(edges, ne, y, kappa, &active);
        self_contact_work w = oc_self_contact_get_work(s);
        CHECK(m == 0 || active > 50, "move %d: the fold has %d pairs within D", m, active);
        CHECK(w.active == active, "move %d: %d pairs within D, brute force %d", m, w.active, active);
        CHECK_REL(E, Eb, 1e-12, 0.0);
        CHECK(w.rebuilds - before == rebuilt[m], "move %d: %ld rebuilds, not %ld", m, w.rebuilds - before, rebuilt[m]);
        int all = NV * NT + ne * (ne - 1) / 2;
        CHECK(w.candidates < all / 2, "move %d: %d candidates of all %d pairs", m, w.candidates, all);
        memcpy(x, y, sizeof x);
    }
    /* back and forth between the last position and one within the regions but more than the close
     * pairs' slack from it (whatever common translation): one close list made, then both kept and used
     * again; then the last moved rigidly by more than the slack, its list kept; energy as brute force */
    static double z[3 * NV];
    memcpy(y, x, sizeof y);
    for (int i = N * (N / 2 + 1); i < NV; i++) y[3 * i + 2] += 0.6 * D;
    for (int i = 0; i < 3 * NV; i++) z[i] = x[i] + 0.5 * D;
    for (int k = 0; k < 5; k++) {
        const double *at = k == 4 ? z : k % 2 ? y : x;
        long before = oc_self_contact_get_work(s).relisted;
        double E = oc_self_contact_eval(s, at, CFAC, NULL, NULL), Eb = brute_energy(edges, ne, at, kappa, &active);
        self_contact_work w = oc_self_contact_get_work(s);
        CHECK(w.relisted - before == (k == 1), "back and forth %d: %ld close lists made", k, w.relisted - before);
        CHECK(w.active == active, "back and forth %d: %d pairs within D, brute force %d", k, w.active, active);
        CHECK_REL(E, Eb, 1e-12, 0.0);
    }
    /* a corner vertex moved out of its region, 0.3 D over the centroid of a far triangle: the list
     * grown for it, not rebuilt, and still all pairs within D */
    for (int k = 0; k < 2; k++) {
        const int *t = tri + 3 * (NT - 1 - 2 * k);
        memcpy(y, x, sizeof y);
        for (int r = 0; r < 3; r++)
            y[3 * k + r] = (x[3 * t[0] + r] + x[3 * t[1] + r] + x[3 * t[2] + r]) / 3.0 + (r == 2 ? 0.3 * D : 0.0);
        self_contact_work w0 = oc_self_contact_get_work(s);
        double E = oc_self_contact_eval(s, y, CFAC, NULL, NULL), Eb = brute_energy(edges, ne, y, kappa, &active);
        self_contact_work w = oc_self_contact_get_work(s);
        CHECK(w.rebuilds == w0.rebuilds && w.extended == w0.extended + 1, "one out: %ld rebuilds, %ld grown",
              w.rebuilds - w0.rebuilds, w.extended - w0.extended);
        CHECK(w.active == active && w.candidates > w0.candidates,
              "one out: %d pairs within D (brute force %d), "
              "%d candidates from %d",
              w.active, active, w.candidates, w0.candidates);
        CHECK_REL(E, Eb, 1e-12, 0.0);
        memcpy(x, y, sizeof x);
    }
    /* the top layer pushed through the bottom: swept through the list (its regions hold the path shifted
     * by a common translation: kept), through a list made again, and far (swept directly, no list); then
     * a rigid lift */
    const char *how[3] = {"within the regions", "near", "far"};
    const double push[3] = {-1.5, -2.5, -40.0};
    for (int k = 0; k < 3; k++) {
        memcpy(y, x, sizeof y);
        for (int i = 0; i < NV; i++) y[3 * i + 2] += i / N > N / 2 ? push[k] * D : 0.0;
        long before = oc_self_contact_get_work(s).rebuilds;
        double first = brute_touch(edges, ne, x, y), share = oc_self_contact_max_step(s, x, y);
        CHECK(first < 1.0 && share == 0.5 * first, "pushed %s: share %.17g, brute force's first touch %.17g", how[k],
              share, first);
        CHECK(oc_self_contact_get_work(s).rebuilds - before == (k == 1), "pushed %s: %ld rebuilds", how[k],
              oc_self_contact_get_work(s).rebuilds - before);
    }
    for (int i = 0; i < NV; i++) y[3 * i + 2] = x[3 * i + 2] + 0.5;
    CHECK(oc_self_contact_max_step(s, x, y) == 1.0 && brute_touch(edges, ne, x, y) == HUGE_VAL, "a rigid lift");
    oc_self_contact_destroy(s);
}

/* A flat sheet, tilted: nothing within D, and no pair's distance computed */
static void case_flat(cloth *c)
{
    static double x[3 * NV];
    self_contact *s = oc_self_contact_create(NV, NT, tri, D);
    if (!CHECK(s != NULL, "oc_self_contact_create")) return;
    oc_self_contact_begin(s, c, CFAC);
    for (int r = 0; r < N; r++)
        for (int q = 0; q < N; q++) {
            double u = q * H, v = r * H, *p = x + 3 * (r * N + q);
            p[0] = 0.8 * u + 0.36 * v;
            p[1] = 0.6 * u - 0.48 * v;
            p[2] = 0.8 * v;
        }
    double E = oc_self_contact_eval(s, x, CFAC, NULL, NULL);
    self_contact_work w = oc_self_contact_get_work(s);
    CHECK(E == 0.0 && w.active == 0, "flat: energy %g, %d pairs within D", E, w.active);
    CHECK(w.tested == 0, "flat: %d pairs' distances computed", w.tested);
    CHECK(oc_self_contact_max_step(s, x, x) == 1.0, "flat, at rest: the whole update");
    oc_self_contact_destroy(s);
}

/* A flat square grid's nearest pairs sharing no vertex are parallel cell diagonals H / sqrt(2)
 * apart (cloth_self_collision_create's limit): a thickness just over it acts at rest, just under not */
static void case_flat_gap(cloth *c)
{
    static double x[3 * NV];
    for (int i = 0; i < NV; i++) {
        x[3 * i] = (i % N) * H;
        x[3 * i + 1] = (i / N) * H;
        x[3 * i + 2] = 0.0;
    }
    for (int over = 0; over < 2; over++) {
        double t = (over ? 1.01 : 0.99) * H / sqrt(2.0);
        self_contact *s = oc_self_contact_create(NV, NT, tri, t);
        if (!CHECK(s != NULL, "oc_self_contact_create")) return;
        oc_self_contact_begin(s, c, CFAC);
        double E = oc_self_contact_eval(s, x, CFAC, NULL, NULL);
        self_contact_work w = oc_self_contact_get_work(s);
        if (over) CHECK(E > 0.0 && w.active > 0, "thickness 1.01 H / sqrt 2: energy %g, %d pairs at rest", E, w.active);
        else CHECK(E == 0.0 && w.active == 0, "thickness 0.99 H / sqrt 2: energy %g, %d pairs at rest", E, w.active);
        oc_self_contact_destroy(s);
    }
}

int main(void)
{
    triangles();
    cloth *c = sheet();
    if (c) {
        case_fold(c);
        case_flat(c);
        case_flat_gap(c);
    }
    cloth_destroy(c);
    return check_summary();
}
