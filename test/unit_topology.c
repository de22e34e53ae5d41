/* Unit: the grid's topology, rest geometry and masses (paper section 3.1).
 *
 * For R x C grids (3x3, 3x4, 4x3, 3x7, 8x5, 21x21, 40x33), with the default
 * axes and with skewed, unnormalised axes:
 *   - cloth_rows/cols/vertex_count are R, C, R C;
 *   - link counts match the closed forms
 *       sequential R(C-1) + (R-1)C + 2(R-1)(C-1)
 *       interlaced R(C-2) + (R-2)C + 2(R-2)(C-2);
 *   - every link has i < j, joins a sequential (|dr|,|dc| <= 1) or interlaced
 *     ((0,2), (2,0), (2,+-2)) neighbour pair, and every such pair appears
 *     exactly once (no duplicates, none missing);
 *   - every rest length equals the distance of the rest grid positions;
 *   - vertex (r, c) starts at origin + c w/(C-1) u + r h/(R-1) v, u = axis_u
 *     normalised, v = axis_v made orthogonal to u and normalised;
 *   - velocities start at zero and no link starts plastic (cotton, alpha 0.8);
 *   - masses are positive and sum to density * width * height.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* offsets (dr, dc) with dr >= 0 of the sequential and interlaced pairs */
static const int seq_off[4][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};
static const int int_off[4][2] = {{0, 2}, {2, -2}, {2, 0}, {2, 2}};

static void check_grid(int R, int C, int skew)
{
    cloth_desc d = cloth_default_desc();
    cloth *c = NULL;
    cloth_error err;
    double u[3], v[3];
    long failed_before = check_failures();
    d.rows = R;
    d.cols = C;
    d.width = 0.9 + 0.01 * C;
    d.height = 0.7 + 0.02 * R;
    if (skew) {
        double un[3] = {1, 1, 0}, vn[3] = {0, 1, 1};
        memcpy(d.axis_u, un, sizeof un);
        memcpy(d.axis_v, vn, sizeof vn);
        d.origin[0] = 0.3;
        d.origin[1] = -1.2;
        d.origin[2] = 2.5;
        d.material.density = 0.37;
    }
    /* the expected frame */
    {
        double nu = sqrt(dot3(d.axis_u, d.axis_u)), p, nv;
        for (int a = 0; a < 3; a++) u[a] = d.axis_u[a] / nu;
        p = dot3(d.axis_v, u);
        for (int a = 0; a < 3; a++) v[a] = d.axis_v[a] - p * u[a];
        nv = sqrt(dot3(v, v));
        for (int a = 0; a < 3; a++) v[a] /= nv;
    }
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK && c, "%dx%d: cloth_create: %s", R, C, err.message)) return;
    CHECK(cloth_rows(c) == R && cloth_cols(c) == C && cloth_vertex_count(c) == R * C,
          "%dx%d: rows %d cols %d vertices %d", R, C, cloth_rows(c), cloth_cols(c), cloth_vertex_count(c));
    {
        int n = R * C;
        const double *x = cloth_positions(c), *vel = cloth_velocities(c), *m = cloth_masses(c);
        int nseq = cloth_link_count(c, CLOTH_SEQUENTIAL), nint = cloth_link_count(c, CLOTH_INTERLACED);
        int want_seq = R * (C - 1) + (R - 1) * C + 2 * (R - 1) * (C - 1);
        int want_int = R * (C - 2) + (R - 2) * C + 2 * (R - 2) * (C - 2);
        double scale = d.width + d.height + sqrt(dot3(d.origin, d.origin));
        double maxpos = 0, maxv = 0, total = 0;
        int nonpos = 0;

        CHECK(nseq == want_seq, "%dx%d: %d sequential links, want %d", R, C, nseq, want_seq);
        CHECK(nint == want_int, "%dx%d: %d interlaced links, want %d", R, C, nint, want_int);

        /* rest positions */
        for (int r = 0; r < R; r++)
            for (int cc = 0; cc < C; cc++) {
                int i = r * C + cc;
                for (int a = 0; a < 3; a++) {
                    double want = d.origin[a] + cc * d.width / (C - 1) * u[a] + r * d.height / (R - 1) * v[a];
                    double e = fabs(x[3 * i + a] - want);
                    if (e > maxpos) maxpos = e;
                }
            }
        CHECK(maxpos <= 1e-13 * scale, "%dx%d%s: rest positions off the expected grid by %.3g", R, C,
              skew ? " (skewed axes)" : "", maxpos);
        for (int k = 0; k < 3 * n; k++)
            if (fabs(vel[k]) > maxv) maxv = fabs(vel[k]);
        CHECK(maxv == 0.0, "%dx%d: initial velocities not zero (%g)", R, C, maxv);

        /* masses */
        for (int i = 0; i < n; i++) {
            total += m[i];
            if (!(m[i] > 0)) nonpos++;
        }
        CHECK(nonpos == 0, "%dx%d: %d masses not positive", R, C, nonpos);
        CHECK_REL(total, d.material.density * d.width * d.height, 1e-12, 0.0);

        /* links: each neighbour pair exactly once, rest = distance at rest */
        for (int t = 0; t < 2; t++) {
            cloth_link_type ty = t ? CLOTH_INTERLACED : CLOTH_SEQUENTIAL;
            const int(*off)[2] = t ? int_off : seq_off;
            int count = t ? nint : nseq;
            unsigned char *seen = calloc(4 * (size_t)n, 1);
            int bad_order = 0, bad_pair = 0, dup = 0, bad_rest = 0, plastic = 0, missing = 0, bad_get = 0;
            for (int e = 0; e < count; e++) {
                cloth_link L;
                int ri, ci, rj, cj, k;
                double dd[3], len;
                if (cloth_get_link(c, ty, e, &L) != CLOTH_OK) {
                    bad_get++;
                    continue;
                }
                if (!(L.i < L.j) || L.i < 0 || L.j >= n) {
                    bad_order++;
                    continue;
                }
                ri = L.i / C, ci = L.i % C, rj = L.j / C, cj = L.j % C;
                for (k = 0; k < 4; k++)
                    if (rj - ri == off[k][0] && cj - ci == off[k][1]) break;
                if (k == 4) {
                    bad_pair++;
                    if (bad_pair <= 3)
                        CHECK(0, "%dx%d: %s link %d joins (%d,%d)-(%d,%d), not a %s neighbour pair", R, C,
                              t ? "interlaced" : "sequential", e, ri, ci, rj, cj, t ? "skip-one" : "immediate");
                    continue;
                }
                if (seen[4 * L.i + k]++) dup++;
                for (int a = 0; a < 3; a++) dd[a] = x[3 * L.j + a] - x[3 * L.i + a];
                len = sqrt(dot3(dd, dd));
                if (!(fabs(L.rest - len) <= 1e-12 * len)) bad_rest++;
                if (L.plastic) plastic++;
            }
            /* every pair inside the grid must have been seen */
            for (int r = 0; r < R; r++)
                for (int cc = 0; cc < C; cc++)
                    for (int k = 0; k < 4; k++) {
                        int r2 = r + off[k][0], c2 = cc + off[k][1];
                        if (r2 < R && c2 >= 0 && c2 < C && !seen[4 * (r * C + cc) + k]) missing++;
                    }
            CHECK(bad_get == 0, "%dx%d: cloth_get_link failed on %d valid indices", R, C, bad_get);
            CHECK(bad_order == 0, "%dx%d: %d %s links without 0 <= i < j < n", R, C, bad_order,
                  t ? "interlaced" : "sequential");
            CHECK(bad_pair == 0, "%dx%d: %d %s links join wrong pairs", R, C, bad_pair,
                  t ? "interlaced" : "sequential");
            CHECK(dup == 0, "%dx%d: %d duplicate %s links", R, C, dup, t ? "interlaced" : "sequential");
            CHECK(missing == 0, "%dx%d: %d %s neighbour pairs have no link", R, C, missing,
                  t ? "interlaced" : "sequential");
            CHECK(bad_rest == 0, "%dx%d: %d %s rest lengths differ from the rest distance", R, C, bad_rest,
                  t ? "interlaced" : "sequential");
            CHECK(plastic == 0, "%dx%d: %d %s links plastic at rest (cotton, alpha 0.8)", R, C, plastic,
                  t ? "interlaced" : "sequential");
            free(seen);
        }
        printf("%2dx%-2d %-7s: %4d sequential, %4d interlaced links, mass %.6g kg%s\n", R, C,
               skew ? "skewed" : "default", nseq, nint, total, check_failures() > failed_before ? "  (FAILURES)" : "");
    }
    cloth_destroy(c);
}

int main(void)
{
    static const int grids[][2] = {{3, 3}, {3, 4}, {4, 3}, {3, 7}, {8, 5}, {21, 21}, {40, 33}};
    for (size_t g = 0; g < sizeof grids / sizeof grids[0]; g++) {
        check_grid(grids[g][0], grids[g][1], 0);
        check_grid(grids[g][0], grids[g][1], 1);
    }
    /* the closed forms at the paper's size, spelled out */
    {
        cloth_desc d = cloth_default_desc();
        cloth *c = NULL;
        CHECK(d.rows == 21 && d.cols == 21, "default desc is %dx%d, want 21x21", d.rows, d.cols);
        if (cloth_create(&d, &c, NULL) == CLOTH_OK) {
            CHECK(cloth_link_count(c, CLOTH_SEQUENTIAL) == 1640, "21x21: %d sequential links, want 1640",
                  cloth_link_count(c, CLOTH_SEQUENTIAL));
            CHECK(cloth_link_count(c, CLOTH_INTERLACED) == 1520, "21x21: %d interlaced links, want 1520",
                  cloth_link_count(c, CLOTH_INTERLACED));
        } else CHECK(0, "cloth_create(default desc) failed");
        cloth_destroy(c);
    }
    return check_summary();
}
