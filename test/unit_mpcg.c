/* Unit: the modified PCG (oc_mpcg_solve) against a dense direct solve.
 *
 * The constrained problem MPCG solves (Baraff-Witkin 1998 sec. 5.3) is:
 * find x with (I - S) x = z and S (A x - b) = 0, S the per-vertex filter
 * (projector onto the free directions). Writing x = z + Q y, with Q an
 * orthonormal basis of the free directions of every vertex (S = Q Q^T), this
 * is the reduced SPD system
 *     (Q^T A Q) y = Q^T (b - A z),
 * which this test builds densely and solves by Cholesky, independently of
 * the code under test.
 *
 * Small random SPD block-sparse systems (a grid graph with diagonals; random
 * non-symmetric off-diagonal blocks B with (j,i) = B^T; diagonal blocks made
 * strictly diagonally dominant, then a random symmetric diagonal scaling so
 * the preconditioner matters), with each constraint kind: free (S = I),
 * pin (S = 0), plane (S = I - n n^T), line (S = d d^T), and a mix; each with
 * both preconditioners (3x3 blocks: inverse of S A_ii S + (I - S); scalar
 * Jacobi) through oc_mpcg_solve, and scalar Jacobi as a function through
 * oc_mpcg_solve_pc with the block-weighted stopping norm, and through oc_mpcg_run
 * with the list of constrained vertices (only those filtered; block Jacobi
 * and scalar Jacobi), which is how the step calls it; each with and without
 * a warm-start guess. Asserted:
 *   - the relative error of x against the dense solution <= 1e-8 at
 *     tolerance 1e-10 (the reduced systems here have condition numbers of a
 *     few hundred at most in the preconditioned norm);
 *   - the true relative residual |S (b - A x)|_P / |S (b - A z)|_P in the
 *     solver's stopping norm, recomputed here, is <= 2 tol, and the reported
 *     residual <= tol;
 *   - the constrained components equal z: bitwise for pins, and to
 *     1e-15 max(1, |x_i|, |guess_i|) for planes and lines (a plane's filter
 *     I - n n^T is not an exact projector in floating point, so n . S y is a
 *     rounding of n . y, not zero; the warm guess carries garbage of size 10
 *     in the constrained directions, which the filter must remove);
 *   - iterations <= the number of free unknowns (exact-arithmetic CG bound)
 *     and a warm start 1e-7 from the solution needs fewer iterations than cold;
 *   - everything constrained: x == z bitwise, 0 iterations, no failure;
 *   - a matrix that is not positive definite (-A, and A shifted to be
 *     indefinite with a positive diagonal): MPCG reports CG_INDEFINITE, or
 *     its x solves the system (1e-6); never success with a wrong x.
 * Through a real cloth (5 x 5, a pin, a plane and a line, tolerance 1e-12):
 * one step of each method lands the constrained components of the new
 * positions on the targets to 1e-12 m, and for the implicit methods the
 * step's dv agrees (1e-10 relative) with the dense reduced solve of the
 * step's own A, b, z (left in the cloth's workspace, internal.h). Also on a
 * 9 x 9 cloth with each preconditioner (block, Jacobi, multigrid).
 * A landing (pins moved far, z large, against a small b): with
 * mpcg_problem.ref_floor the solve leaves at most 2 tol of |S b|_P, which
 * without it (tol of |S (b - A z)|_P) it does not; a floor above the
 * landing's reference changes nothing.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "mpcg.h"
#include "mat3.h"
#include "bsr.h"
#include "check.h"

enum { FREE = 0, PIN = 1, PLANE = 2, LINE = 3 };

/* ------------------------------------------------------------ dense tools */

/* In-place Cholesky of the m x m SPD matrix a (lower triangle); 0 or -1. */
static int cholesky(double *a, int m)
{
    for (int j = 0; j < m; j++) {
        double s = a[j * m + j];
        for (int k = 0; k < j; k++) s -= a[j * m + k] * a[j * m + k];
        if (!(s > 0.0)) return -1;
        a[j * m + j] = sqrt(s);
        for (int i = j + 1; i < m; i++) {
            double t = a[i * m + j];
            for (int k = 0; k < j; k++) t -= a[i * m + k] * a[j * m + k];
            a[i * m + j] = t / a[j * m + j];
        }
    }
    return 0;
}

static void cholesky_solve(const double *l, int m, double *y)
{
    for (int i = 0; i < m; i++) {
        double t = y[i];
        for (int k = 0; k < i; k++) t -= l[i * m + k] * y[k];
        y[i] = t / l[i * m + i];
    }
    for (int i = m - 1; i >= 0; i--) {
        double t = y[i];
        for (int k = i + 1; k < m; k++) t -= l[k * m + i] * y[k];
        y[i] = t / l[i * m + i];
    }
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Orthonormal basis of the free directions of one vertex: returns the count
 * (0..3) and fills q (3 vectors of 3). kind/axis as the constraint. */
static int free_basis(int kind, const double axis[3], double q[3][3])
{
    if (kind == FREE) {
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) q[a][b] = a == b;
        return 3;
    }
    if (kind == PIN) return 0;
    if (kind == LINE) {
        memcpy(q[0], axis, 3 * sizeof(double));
        return 1;
    }
    /* plane: two unit vectors orthogonal to the normal (Gram-Schmidt) */
    int m = 0;
    for (int e = 0; e < 3 && m < 2; e++) {
        double v[3] = {0, 0, 0};
        v[e] = 1.0;
        double p = dot3(v, axis);
        for (int a = 0; a < 3; a++) v[a] -= p * axis[a];
        for (int k = 0; k < m; k++) {
            double pk = dot3(v, q[k]);
            for (int a = 0; a < 3; a++) v[a] -= pk * q[k][a];
        }
        double nv = sqrt(dot3(v, v));
        if (nv < 0.3) continue;
        for (int a = 0; a < 3; a++) q[m][a] = v[a] / nv;
        m++;
    }
    return m;
}

/* Dense reference: x = z + Q y with (Q^T A Q) y = Q^T (b - A z). dense is
 * the N x N matrix, kinds/axes per vertex. Returns 0, or -1 if the reduced
 * matrix is not SPD. m_out: the number of free unknowns. */
static int dense_reference(int n, const double *dense, const double *b, const double *z, const int *kinds,
                           const double *axes, double *x, int *m_out)
{
    int N = 3 * n;
    double *Q = calloc((size_t)N * N, sizeof *Q); /* N x m, column-major by free unknown */
    int m = 0;
    for (int i = 0; i < n; i++) {
        double q[3][3];
        int k = free_basis(kinds[i], axes + 3 * i, q);
        for (int c = 0; c < k; c++, m++)
            for (int a = 0; a < 3; a++) Q[(size_t)m * N + 3 * i + a] = q[c][a];
    }
    *m_out = m;
    double *r = malloc((size_t)N * sizeof *r), *AQ = malloc((size_t)N * (m ? m : 1) * sizeof *AQ);
    double *red = malloc((size_t)(m ? m : 1) * (m ? m : 1) * sizeof *red), *y = malloc((size_t)(m ? m : 1) * sizeof *y);
    int rc = 0;
    for (int i = 0; i < N; i++) {
        double t = b[i];
        for (int j = 0; j < N; j++) t -= dense[(size_t)i * N + j] * z[j];
        r[i] = t;
    }
    for (int c = 0; c < m; c++)
        for (int i = 0; i < N; i++) {
            double t = 0;
            for (int j = 0; j < N; j++) t += dense[(size_t)i * N + j] * Q[(size_t)c * N + j];
            AQ[(size_t)c * N + i] = t;
        }
    for (int a = 0; a < m; a++) {
        double t = 0;
        for (int i = 0; i < N; i++) t += Q[(size_t)a * N + i] * r[i];
        y[a] = t;
        for (int c = 0; c < m; c++) {
            double s = 0;
            for (int i = 0; i < N; i++) s += Q[(size_t)a * N + i] * AQ[(size_t)c * N + i];
            red[a * m + c] = s;
        }
    }
    /* symmetrise the rounding */
    for (int a = 0; a < m; a++)
        for (int c = 0; c < a; c++) red[a * m + c] = red[c * m + a] = 0.5 * (red[a * m + c] + red[c * m + a]);
    if (m > 0 && cholesky(red, m) != 0) rc = -1;
    if (rc == 0 && m > 0) cholesky_solve(red, m, y);
    for (int i = 0; i < N; i++) {
        double t = z[i];
        for (int c = 0; c < m; c++) t += Q[(size_t)c * N + i] * y[c];
        x[i] = t;
    }
    free(Q);
    free(r);
    free(AQ);
    free(red);
    free(y);
    return rc;
}

/* filter block S of one vertex */
static void filter_block(int kind, const double axis[3], double S[9])
{
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double nn = axis[a] * axis[b];
            S[3 * a + b] = kind == FREE ? (a == b) : kind == PIN ? 0.0 : kind == PLANE ? (a == b) - nn : nn;
        }
}

/* Preconditioner blocks: block = inverse of S A_ii S + (I - S); else scalar
 * Jacobi 1 / A_ii[a][a]. */
static void make_precond(const bsr *A, const double *S, int block, double *P)
{
    for (int i = 0; i < A->n; i++) {
        const double *Aii = A->val + 9 * (size_t)A->diag[i], *Si = S + 9 * (size_t)i;
        double *Pi = P + 9 * (size_t)i;
        memset(Pi, 0, 9 * sizeof *Pi);
        if (block) {
            double SA[9], M[9];
            for (int r = 0; r < 3; r++)
                for (int s = 0; s < 3; s++) {
                    double t = 0;
                    for (int k = 0; k < 3; k++) t += Si[3 * r + k] * Aii[3 * k + s];
                    SA[3 * r + s] = t;
                }
            for (int r = 0; r < 3; r++)
                for (int s = 0; s < 3; s++) {
                    double t = 0;
                    for (int k = 0; k < 3; k++) t += SA[3 * r + k] * Si[3 * k + s];
                    M[3 * r + s] = t + ((r == s) - Si[3 * r + s]);
                }
            double det = mat3inv(M, Pi);
            if (det != 0.0 && isfinite(det)) continue;
            memset(Pi, 0, 9 * sizeof *Pi);
        }
        for (int a = 0; a < 3; a++) Pi[4 * a] = 1.0 / Aii[4 * a];
    }
}

/* A preconditioner function for oc_mpcg_solve_pc: s = P r blockwise. */
typedef struct jac_ctx {
    int n;
    const double *P;
} jac_ctx;

static void jac_apply(void *ctx, const double *r, double *s)
{
    const jac_ctx *j = ctx;
    oc_filter_apply(j->n, j->P, r, s);
}

/* |S v|_P^2 with P the preconditioner blocks */
static double pnorm2(int n, const double *S, const double *P, const double *v)
{
    double s = 0;
    for (int i = 0; i < n; i++) {
        double sv[3], pv[3];
        for (int a = 0; a < 3; a++) sv[a] = dot3(S + 9 * i + 3 * a, v + 3 * i);
        for (int a = 0; a < 3; a++) pv[a] = dot3(P + 9 * i + 3 * a, sv);
        s += dot3(sv, pv);
    }
    return s;
}

/* ----------------------------------------------------- random SPD system */

typedef struct sys {
    int n, N;
    bsr A;
    double *dense;
} sys;

/* An R x C grid graph with both diagonals per cell. */
static void make_system(sys *s, int R, int C, rng *g)
{
    int n = R * C, ne = 0;
    int *ei = malloc(sizeof(int) * 4 * n), *ej = malloc(sizeof(int) * 4 * n);
    for (int r = 0; r < R; r++)
        for (int c = 0; c < C; c++) {
            int i = r * C + c;
            if (c + 1 < C) {
                ei[ne] = i;
                ej[ne++] = i + 1;
            }
            if (r + 1 < R) {
                ei[ne] = i;
                ej[ne++] = i + C;
            }
            if (r + 1 < R && c + 1 < C) {
                ei[ne] = i;
                ej[ne++] = i + C + 1;
            }
            if (r + 1 < R && c > 0) {
                ei[ne] = i;
                ej[ne++] = i + C - 1;
            }
        }
    int *blk = malloc(sizeof(int) * 2 * ne);
    CHECK(oc_bsr_build(&s->A, n, ne, ei, ej, blk) == 0, "oc_bsr_build failed");
    s->n = n;
    s->N = 3 * n;
    double *rowabs = calloc(3 * (size_t)n, sizeof *rowabs);
    for (int e = 0; e < ne; e++) {
        double *B = s->A.val + 9 * (size_t)blk[2 * e], *BT = s->A.val + 9 * (size_t)blk[2 * e + 1];
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) {
                double v = rng_range(g, -1.0, 1.0);
                B[3 * a + b] = v;
                BT[3 * b + a] = v;
                rowabs[3 * ei[e] + a] += fabs(v);
                rowabs[3 * ej[e] + b] += fabs(v);
            }
    }
    for (int i = 0; i < n; i++) {
        double *D = s->A.val + 9 * (size_t)s->A.diag[i];
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < a; b++) {
                double v = rng_range(g, -0.5, 0.5);
                D[3 * a + b] = D[3 * b + a] = v;
                rowabs[3 * i + a] += fabs(v);
                rowabs[3 * i + b] += fabs(v);
            }
        for (int a = 0; a < 3; a++) D[4 * a] = rowabs[3 * i + a] + rng_range(g, 0.05, 1.0);
    }
    /* symmetric diagonal scaling D A D keeps A SPD and spreads its scales */
    double *sc = malloc(sizeof(double) * 3 * n);
    for (int k = 0; k < 3 * n; k++) sc[k] = exp(rng_range(g, -1.5, 1.5));
    for (int i = 0; i < n; i++)
        for (int k = s->A.row_ptr[i]; k < s->A.row_ptr[i + 1]; k++) {
            int j = s->A.col[k];
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++) s->A.val[9 * (size_t)k + 3 * a + b] *= sc[3 * i + a] * sc[3 * j + b];
        }
    s->dense = malloc(sizeof(double) * (size_t)s->N * s->N);
    oc_bsr_to_dense(&s->A, s->dense);
    /* oc_bsr_to_dense must agree with oc_bsr_mul (used by the reference) */
    {
        double *v = malloc(sizeof(double) * s->N), *y1 = malloc(sizeof(double) * s->N), e = 0, m = 0;
        for (int k = 0; k < s->N; k++) v[k] = rng_range(g, -1, 1);
        oc_bsr_mul(&s->A, v, y1);
        for (int i = 0; i < s->N; i++) {
            double t = 0;
            for (int j = 0; j < s->N; j++) t += s->dense[(size_t)i * s->N + j] * v[j];
            if (fabs(t - y1[i]) > e) e = fabs(t - y1[i]);
            if (fabs(t) > m) m = fabs(t);
        }
        CHECK(e <= 1e-14 * m, "oc_bsr_mul vs oc_bsr_to_dense: max diff %.3g (scale %.3g)", e, m);
        free(v);
        free(y1);
    }
    free(sc);
    free(rowabs);
    free(ei);
    free(ej);
    free(blk);
}

static void free_system(sys *s)
{
    oc_bsr_free(&s->A);
    free(s->dense);
}

/* ------------------------------------------------------------------ cases */

static const char *kind_name[] = {"free", "pin", "plane", "line"};

/* mix: -1 = random mix of all kinds, else every constrained vertex of that
 * kind (about a third of the vertices; the rest free). */
static void run_case(const sys *s, int mix, rng *g, int *iters_out)
{
    int n = s->n, N = s->N;
    int *kinds = malloc(sizeof(int) * n);
    double *axes = calloc(3 * (size_t)n, sizeof *axes), *S = malloc(sizeof(double) * 9 * n);
    double *z = calloc((size_t)N, sizeof *z), *b = malloc(sizeof(double) * N), *xref = malloc(sizeof(double) * N);
    double *P = malloc(sizeof(double) * 9 * n), *x = malloc(sizeof(double) * N);
    double *w = malloc(sizeof(double) * 8 * N), *r = malloc(sizeof(double) * N);
    double *guess = malloc(sizeof(double) * N), *Pjac = malloc(sizeof(double) * 9 * n);
    char name[64];

    for (int i = 0; i < n; i++) {
        if (mix < 0) kinds[i] = (int)(rng_u64(g) % 4);
        else kinds[i] = mix == FREE ? FREE : (rng_unit(g) < 0.35 ? mix : FREE);
        rng_unit_vector(g, axes + 3 * i);
        filter_block(kinds[i], axes + 3 * i, S + 9 * i);
        /* z = (I - S) t for a random t: a target in the constrained directions */
        double t[3];
        for (int a = 0; a < 3; a++) t[a] = rng_range(g, -1, 1);
        for (int a = 0; a < 3; a++) z[3 * i + a] = t[a] - dot3(S + 9 * i + 3 * a, t);
    }
    for (int k = 0; k < N; k++) b[k] = rng_range(g, -1, 1);
    int m;
    int ok = dense_reference(n, s->dense, b, z, kinds, axes, xref, &m);
    snprintf(name, sizeof name, "%s", mix < 0 ? "mixed" : kind_name[mix]);
    CHECK(ok == 0, "%s: reduced reference matrix not SPD", name);
    double xscale = 0;
    for (int k = 0; k < N; k++) xscale = fmax(xscale, fabs(xref[k]));

    /* the constrained vertices, for oc_mpcg_run's filter list */
    int *con = malloc(sizeof(int) * n), ncon = 0;
    for (int i = 0; i < n; i++)
        if (kinds[i] != FREE) con[ncon++] = i;
    /* variant 0: oc_mpcg_solve, block preconditioner (also the norm); 1: oc_mpcg_solve, scalar Jacobi (also the norm);
     * 2: oc_mpcg_solve_pc, scalar Jacobi as a function, block-weighted norm; 3 and 4, as the step calls it: oc_mpcg_run
     * with the list of constrained vertices (filtering only those), block Jacobi (pc NULL) or scalar as a function */
    for (int var = 0; var < 5; var++) {
        make_precond(&s->A, S, var != 1, P); /* the norm's blocks (and oc_mpcg_solve's preconditioner) */
        make_precond(&s->A, S, 0, Pjac);
        jac_ctx jc = {n, Pjac};
        const char *pcnames[] = {"block", "jacobi", "pc-jacobi", "run-block", "run-jacobi"}, *pc = pcnames[var];
        mpcg_problem prob = {.A = &s->A,
                             .b = b,
                             .S = S,
                             .z = z,
                             .Dinv = P,
                             .con = con,
                             .ncon = ncon,
                             .pc = var == 4 ? jac_apply : NULL,
                             .ctx = &jc,
                             .tol = 1e-10,
                             .max_iter = 10 * N};
        int cold_it = -1;
        for (int warm = 0; warm <= 1; warm++) {
            const double tol = 1e-10;
            /* warm: the reference plus a 1e-7 perturbation in every direction,
             * and garbage in the constrained directions (to be ignored) */
            for (int k = 0; k < N; k++) x[k] = warm ? xref[k] + 1e-7 * xscale * rng_range(g, -1, 1) : 0.0;
            if (warm)
                for (int i = 0; i < n; i++) {
                    double t[3];
                    for (int a = 0; a < 3; a++) t[a] = 10.0 * rng_range(g, -1, 1);
                    for (int a = 0; a < 3; a++) x[3 * i + a] += t[a] - dot3(S + 9 * i + 3 * a, t);
                }
            memcpy(guess, x, sizeof(double) * N);
            mpcg_result res = var < 2    ? oc_mpcg_solve(&s->A, b, S, z, P, tol, 10 * N, x, w)
                              : var == 2 ? oc_mpcg_solve_pc(&s->A, b, S, z, P, jac_apply, &jc, tol, 10 * N, x, w)
                                         : oc_mpcg_run(&prob, x, w);
            CHECK(res.failure == CLOTH_FAIL_NONE, "%s/%s/%s: failure %d", name, pc, warm ? "warm" : "cold",
                  (int)res.failure);
            double e = 0, xr = 0;
            for (int k = 0; k < N; k++) {
                e = fmax(e, fabs(x[k] - xref[k]));
                xr = fmax(xr, fabs(xref[k]));
            }
            if (getenv("MPCG_VERBOSE"))
                printf("  %s/%s/%s: rel err %.2e, %d it\n", name, pc, warm ? "warm" : "cold", e / xr, res.iterations);
            CHECK(e <= 1e-8 * xr, "%s/%s/%s: |x - x_dense|_max = %.3g, relative %.3g > 1e-8 (m = %d, %d it)", name, pc,
                  warm ? "warm" : "cold", e, e / xr, m, res.iterations);
            /* the true residual in the solver's norm, recomputed */
            oc_bsr_mul(&s->A, x, r);
            for (int k = 0; k < N; k++) r[k] = b[k] - r[k];
            double num = pnorm2(n, S, P, r);
            oc_bsr_mul(&s->A, z, r);
            for (int k = 0; k < N; k++) r[k] = b[k] - r[k];
            double den = pnorm2(n, S, P, r);
            double true_res = sqrt(num / den);
            CHECK(true_res <= 2 * tol, "%s/%s/%s: true relative residual %.3g > 2 tol", name, pc,
                  warm ? "warm" : "cold", true_res);
            CHECK(res.residual <= tol, "%s/%s/%s: reported residual %.3g > tol", name, pc, warm ? "warm" : "cold",
                  res.residual);
            CHECK(res.iterations <= m, "%s/%s/%s: %d iterations > %d free unknowns", name, pc, warm ? "warm" : "cold",
                  res.iterations, m);
            /* constraints hold */
            double worst = 0;
            int pin_exact = 1;
            for (int i = 0; i < n; i++) {
                const double *xi = x + 3 * i, *zi = z + 3 * i, *ax = axes + 3 * i;
                double d[3] = {xi[0] - zi[0], xi[1] - zi[1], xi[2] - zi[2]};
                /* rounding scale: the largest vector the filter was applied to */
                double sc = fmax(1.0, fmax(sqrt(dot3(xi, xi)), sqrt(dot3(guess + 3 * i, guess + 3 * i)))), err = 0;
                if (kinds[i] == PIN) {
                    pin_exact &= memcmp(xi, zi, 3 * sizeof(double)) == 0;
                } else if (kinds[i] == PLANE) {
                    err = fabs(dot3(ax, d));
                } else if (kinds[i] == LINE) {
                    double p = dot3(ax, d);
                    double o[3] = {d[0] - p * ax[0], d[1] - p * ax[1], d[2] - p * ax[2]};
                    err = sqrt(dot3(o, o));
                }
                worst = fmax(worst, err / sc);
            }
            CHECK(pin_exact, "%s/%s/%s: a pinned vertex's x differs from z", name, pc, warm ? "warm" : "cold");
            CHECK(worst <= 1e-15, "%s/%s/%s: constrained components off z by %.3g (relative) > 1e-15", name, pc,
                  warm ? "warm" : "cold", worst);
            if (!warm) {
                cold_it = res.iterations;
                iters_out[var] = res.iterations;
            } else {
                CHECK(res.iterations < cold_it, "%s/%s: warm start %d iterations >= cold %d", name, pc, res.iterations,
                      cold_it);
            }
        }
    }
    free(kinds);
    free(axes);
    free(S);
    free(z);
    free(b);
    free(xref);
    free(P);
    free(x);
    free(w);
    free(r);
    free(guess);
    free(Pjac);
    free(con);
}

/* Not positive definite: MPCG must report CLOTH_FAIL_CG_INDEFINITE, or else
 * return the solution of the system (CG may run through an indefinite
 * matrix without meeting p^T A p <= 0; then its answer is still A x = b).
 * What it must never do is report success with a wrong x. Two matrices from
 * the SPD one: -A (negative definite, every diagonal block negative
 * definite), and A - sigma I with sigma the largest shift keeping every
 * diagonal entry positive (times 0.999), which the dense Cholesky confirms
 * indefinite. No constraints (S = I), z = 0. */
static void not_definite(const sys *s, rng *g)
{
    int n = s->n, N = s->N;
    bsr B = s->A; /* same pattern, own values */
    B.val = malloc(sizeof(double) * 9 * (size_t)s->A.nnzb);
    double *S = calloc(9 * (size_t)n, sizeof *S), *z = calloc((size_t)N, sizeof *z), *b = malloc(sizeof(double) * N);
    double *P = malloc(sizeof(double) * 9 * n), *x = malloc(sizeof(double) * N), *w = malloc(sizeof(double) * 8 * N);
    double *dense = malloc(sizeof(double) * (size_t)N * N), *xref = malloc(sizeof(double) * N);
    int *kinds = calloc((size_t)n, sizeof *kinds);
    double *axes = calloc((size_t)N, sizeof *axes);
    for (int i = 0; i < n; i++) S[9 * i] = S[9 * i + 4] = S[9 * i + 8] = 1.0;
    for (int k = 0; k < N; k++) b[k] = rng_range(g, -1, 1);
    double dmin = INFINITY;
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) dmin = fmin(dmin, s->A.val[9 * (size_t)s->A.diag[i] + 4 * a]);
    for (int kind = 0; kind < 2; kind++) {
        const char *name = kind == 0 ? "-A" : "A - sigma I";
        for (size_t k = 0; k < 9 * (size_t)s->A.nnzb; k++) B.val[k] = kind == 0 ? -s->A.val[k] : s->A.val[k];
        if (kind == 1)
            for (int i = 0; i < n; i++)
                for (int a = 0; a < 3; a++) B.val[9 * (size_t)B.diag[i] + 4 * a] -= 0.999 * dmin;
        oc_bsr_to_dense(&B, dense);
        int m;
        if (dense_reference(n, dense, b, z, kinds, axes, xref, &m) == 0) {
            printf("%s: positive definite after all (Cholesky succeeded); case skipped\n", name);
            continue;
        }
        /* the reference by Gaussian elimination would do, but the contract
         * only needs: a reported success must satisfy A x = b */
        for (int pcv = 0; pcv < 2; pcv++) {
            make_precond(&B, S, pcv == 0, P);
            memset(x, 0, sizeof(double) * N);
            mpcg_result res = oc_mpcg_solve(&B, b, S, z, P, 1e-10, 10 * N, x, w);
            double num = 0, den = 0;
            oc_bsr_mul(&B, x, w);
            for (int k = 0; k < N; k++) {
                num += (b[k] - w[k]) * (b[k] - w[k]);
                den += b[k] * b[k];
            }
            double rel = sqrt(num / den);
            printf("%s, %s preconditioner: failure %d (%s), %d iterations, |b - A x| / |b| = %.3g\n", name,
                   pcv == 0 ? "block" : "jacobi", (int)res.failure, cloth_failure_string(res.failure), res.iterations,
                   rel);
            CHECK(res.failure == CLOTH_FAIL_CG_INDEFINITE || (res.failure == CLOTH_FAIL_NONE && rel <= 1e-6),
                  "%s, %s preconditioner: failure %d (%s) with |b - A x| / |b| = %.3g: neither reported nor solved",
                  name, pcv == 0 ? "block" : "jacobi", (int)res.failure, cloth_failure_string(res.failure), rel);
        }
    }
    free(B.val);
    free(S);
    free(z);
    free(b);
    free(P);
    free(x);
    free(w);
    free(dense);
    free(xref);
    free(kinds);
    free(axes);
}

/* Every vertex pinned: x = z exactly, nothing to iterate. */
static void all_constrained(const sys *s, rng *g)
{
    int n = s->n, N = s->N;
    double *S = calloc(9 * (size_t)n, sizeof *S), *z = malloc(sizeof(double) * N), *b = malloc(sizeof(double) * N);
    double *P = malloc(sizeof(double) * 9 * n), *x = malloc(sizeof(double) * N), *w = malloc(sizeof(double) * 8 * N);
    for (int k = 0; k < N; k++) {
        z[k] = rng_range(g, -1, 1);
        b[k] = rng_range(g, -1, 1);
    }
    for (int block = 1; block >= 0; block--) {
        make_precond(&s->A, S, block, P);
        for (int var = 0; var < 2; var++) {
            jac_ctx jc = {n, P};
            for (int k = 0; k < N; k++) x[k] = rng_range(g, -1, 1); /* a guess, to be ignored */
            mpcg_result res = var == 0 ? oc_mpcg_solve(&s->A, b, S, z, P, 1e-10, 100, x, w)
                                       : oc_mpcg_solve_pc(&s->A, b, S, z, P, jac_apply, &jc, 1e-10, 100, x, w);
            CHECK(res.failure == CLOTH_FAIL_NONE, "all pinned: failure %d", (int)res.failure);
            CHECK(res.iterations == 0, "all pinned: %d iterations, expected 0", res.iterations);
            CHECK(memcmp(x, z, sizeof(double) * N) == 0, "all pinned: x differs from z");
        }
    }
    free(S);
    free(z);
    free(b);
    free(P);
    free(x);
    free(w);
}

/* A landing: pinned vertices moved far (z large) against a small b. With
 * ref_floor set, the reference is no more than |S b|^2 (nor less than the
 * floor), so the solve leaves no more than tol of the residual before the
 * landing; without it, tol of the landing's own |S (b - A z)|, which here
 * is far more. A floor above the landing's reference changes nothing. */
static void landing_reference(const sys *s, rng *g)
{
    int n = s->n, N = s->N;
    double *buf = calloc(19 * (size_t)N, sizeof *buf); /* S, P (3N each), z, b, x, r, Az (N each), w (8N) */
    double *S = buf, *P = S + 3 * N, *z = P + 3 * N, *b = z + N, *x = b + N, *r = x + N, *Az = r + N, *w = Az + N;
    const double axis[3] = {0, 0, 1}, tol = 1e-3;
    for (int i = 0; i < n; i++) {
        int pin = i % 3 == 0;
        filter_block(pin ? PIN : FREE, axis, S + 9 * i);
        for (int a = 0; a < 3; a++) z[3 * i + a] = pin ? rng_range(g, -1e3, 1e3) : 0.0;
    }
    for (int k = 0; k < N; k++) b[k] = rng_range(g, -1, 1);
    make_precond(&s->A, S, 1, P);
    oc_bsr_mul(&s->A, z, Az);
    for (int k = 0; k < N; k++) r[k] = b[k] - Az[k];
    double before = pnorm2(n, S, P, b), landing = pnorm2(n, S, P, r);
    CHECK(landing > 1e4 * before, "the test's premise: the landing's residual %.3g against %.3g before", landing,
          before);
    double left[3];
    int iters[3];
    const double floors[3] = {0.0, 1e-300, 1e3 * landing};
    for (int v = 0; v < 3; v++) {
        mpcg_problem pr = {&s->A, b, S, z, P, NULL, 0, NULL, NULL, tol, 10 * N, NULL, floors[v], 0, 0.0, NULL, 0};
        memset(x, 0, sizeof(double) * N);
        mpcg_result res = oc_mpcg_run(&pr, x, w);
        CHECK(res.failure == CLOTH_FAIL_NONE, "landing (floor %g): failure %d", floors[v], (int)res.failure);
        oc_bsr_mul(&s->A, x, r);
        for (int k = 0; k < N; k++) r[k] = b[k] - r[k];
        left[v] = sqrt(pnorm2(n, S, P, r));
        iters[v] = res.iterations;
    }
    printf("landing: residual left %.3g (no cap, %d iterations), %.3g (capped, %d), %.3g (floor above, %d); "
           "before the landing %.3g\n",
           left[0], iters[0], left[1], iters[1], left[2], iters[2], sqrt(before));
    CHECK(left[1] <= 2 * tol * sqrt(before), "capped: %.3g left, over 2 tol of %.3g", left[1], sqrt(before));
    CHECK(left[0] > 2 * tol * sqrt(before), "uncapped: %.3g left, within 2 tol of %.3g (the cap untested)", left[0],
          sqrt(before));
    CHECK(iters[2] == iters[0] && left[2] == left[0], "a floor above the landing's reference changed the solve");
    free(buf);
}

/* The error stop (abs_err2, mass): a pinned third, tolerance 1e-10; the
 * stop at a tenth of the full solve's size |x - z|_M (masses 0.5-2) must
 * end sooner, within that tenth of the full solve in the mass norm. */
static void error_stop(const sys *s, rng *g)
{
    int n = s->n, N = s->N;
    double *buf = calloc(19 * (size_t)N, sizeof *buf); /* S, P (3N each), z, b, x, y, m (N each), w (8N) */
    double *S = buf, *P = S + 3 * N, *z = P + 3 * N, *b = z + N, *x = b + N, *y = x + N, *m = y + N;
    double *w = m + N;
    const double axis[3] = {0, 0, 1};
    for (int i = 0; i < n; i++) {
        filter_block(i % 3 == 0 ? PIN : FREE, axis, S + 9 * i);
        m[i] = rng_range(g, 0.5, 2.0);
    }
    for (int k = 0; k < N; k++) b[k] = rng_range(g, -1, 1);
    make_precond(&s->A, S, 1, P);
    mpcg_problem pr = {&s->A, b, S, z, P, NULL, 0, NULL, NULL, 1e-10, 10 * N, NULL, 0.0, 0, 0.0, m, 0};
    mpcg_result full = oc_mpcg_run(&pr, x, w);
    double size = 0.0, err = 0.0;
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) size += m[i] * x[3 * i + a] * x[3 * i + a];
    pr.abs_err2 = 0.01 * size;
    mpcg_result part = oc_mpcg_run(&pr, y, w);
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) err += m[i] * (y[3 * i + a] - x[3 * i + a]) * (y[3 * i + a] - x[3 * i + a]);
    printf("error stop at a tenth of the size: %d iterations against %d, error %.3g of the size\n", part.iterations,
           full.iterations, sqrt(err / size));
    CHECK(full.failure == CLOTH_FAIL_NONE && part.failure == CLOTH_FAIL_NONE, "failures %d, %d", (int)full.failure,
          (int)part.failure);
    CHECK(part.iterations < full.iterations, "the error stop did not shorten the solve (%d iterations)",
          part.iterations);
    CHECK(err <= pr.abs_err2, "stopped %.3g of the size from the solution, over the tenth asked", sqrt(err / size));
    free(buf);
}

/* ---------------------------------------------------------- a real cloth */

static void cloth_case(cloth_method method, cloth_precond precond, int R, rng *g)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = CLOTH_LINEARIZED; /* the linearised step's one linear solve is tested */
    d.rows = d.cols = R;
    d.solver.method = method;
    d.solver.precond = precond;
    d.solver.cg_tolerance = 1e-12;
    d.solver.cg_max_iterations = 10000;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) return;
    int n = cloth_vertex_count(c), N = 3 * n;
    const double *x = cloth_positions(c);
    const char *mnames[] = {"BE", "explicit", "symplectic", "BDF2"},
               *pnames[] = {"block", "jacobi", "multigrid", "ssor"};
    char mname[64];
    snprintf(mname, sizeof mname, "%s/%s/%dx%d", mnames[method], pnames[precond], R, R);

    /* BDF2: take one (backward Euler) step first so the checked step is BDF2 */
    if (method == CLOTH_BDF2) CHECK(cloth_step(c, 1.0 / 60, NULL) == CLOTH_OK, "BDF2 first step");

    cloth_constraint k[3];
    memset(k, 0, sizeof k);
    int verts[3] = {0, R - 1, R * R - 3};
    int ndof[3] = {3, 1, 2};
    for (int q = 0; q < 3; q++) {
        k[q].vertex = verts[q];
        k[q].ndof = ndof[q];
        rng_unit_vector(g, k[q].axis);
        for (int a = 0; a < 3; a++) k[q].target[a] = x[3 * verts[q] + a] + rng_range(g, -0.004, 0.004);
        CHECK(cloth_set_constraint(c, &k[q]) == CLOTH_OK, "set_constraint: %s", cloth_last_error(c));
        CHECK(cloth_get_constraint(c, verts[q], &k[q]) == CLOTH_OK, "get_constraint"); /* normalised axis */
    }
    cloth_step_stats st;
    cloth_status s = cloth_step(c, 1.0 / 60, &st);
    CHECK(s == CLOTH_OK, "%s: cloth_step: %s", mname, cloth_last_error(c));
    x = cloth_positions(c);
    for (int q = 0; q < 3; q++) {
        const double *xi = x + 3 * verts[q], *ax = k[q].axis;
        double dd[3] = {xi[0] - k[q].target[0], xi[1] - k[q].target[1], xi[2] - k[q].target[2]};
        double e;
        if (ndof[q] == 3) e = sqrt(dot3(dd, dd));
        else if (ndof[q] == 1) e = fabs(dot3(dd, ax));
        else {
            double p = dot3(dd, ax);
            double o[3] = {dd[0] - p * ax[0], dd[1] - p * ax[1], dd[2] - p * ax[2]};
            e = sqrt(dot3(o, o));
        }
        CHECK(e <= 1e-12, "%s: %s constraint on vertex %d: constrained components off target by %.3g m", mname,
              ndof[q] == 3   ? "pin"
              : ndof[q] == 1 ? "plane"
                             : "line",
              verts[q], e);
    }

    if (method == CLOTH_BACKWARD_EULER || method == CLOTH_BDF2) {
        /* the step's own linear system (left in the workspace), solved densely */
        int *kinds = calloc((size_t)n, sizeof *kinds);
        double *axes = calloc((size_t)N, sizeof *axes), *dense = malloc(sizeof(double) * N * N);
        double *xr = malloc(sizeof(double) * N);
        for (int q = 0; q < 3; q++) {
            kinds[verts[q]] = ndof[q] == 3 ? PIN : ndof[q] == 1 ? PLANE : LINE;
            memcpy(axes + 3 * verts[q], k[q].axis, 3 * sizeof(double));
        }
        oc_bsr_to_dense(&c->A, dense);
        int m;
        CHECK(dense_reference(n, dense, c->b, c->z, kinds, axes, xr, &m) == 0, "%s: cloth's reduced A not SPD", mname);
        double e = 0, sc = 0;
        for (int i = 0; i < N; i++) {
            e = fmax(e, fabs(c->dv[i] - xr[i]));
            sc = fmax(sc, fabs(xr[i]));
        }
        if (getenv("MPCG_VERBOSE")) printf("  cloth %s: dv rel err %.2e, %d it\n", mname, e / sc, st.iterations);
        CHECK(e <= 1e-10 * sc, "%s: step dv vs dense reduced solve: max diff %.3g (scale %.3g, %d CG it)", mname, e, sc,
              st.iterations);
        free(kinds);
        free(axes);
        free(dense);
        free(xr);
    }
    cloth_destroy(c);
}

int main(void)
{
    rng g = rng_seed(0x6d706367u);
    const int grids[][2] = {{3, 4}, {4, 5}, {6, 6}};
    for (size_t t = 0; t < sizeof grids / sizeof grids[0]; t++) {
        sys s;
        make_system(&s, grids[t][0], grids[t][1], &g);
        for (int mix = -1; mix <= LINE; mix++) {
            int it[5] = {0, 0, 0, 0, 0};
            run_case(&s, mix, &g, it);
            printf("grid %dx%d %-6s: cold iterations block %d, jacobi %d, pc-jacobi %d, run-block %d, run-jacobi %d\n",
                   grids[t][0], grids[t][1], mix < 0 ? "mixed" : kind_name[mix], it[0], it[1], it[2], it[3], it[4]);
        }
        all_constrained(&s, &g);
        rng gl = rng_seed(0x6c616e64u + (unsigned)t); /* its own draws: the other cases' stay as they were */
        landing_reference(&s, &gl);
        error_stop(&s, &gl);
        if (t == 0) not_definite(&s, &g);
        free_system(&s);
    }
    for (int m = CLOTH_BACKWARD_EULER; m <= CLOTH_BDF2; m++)
        cloth_case((cloth_method)m, CLOTH_PRECOND_BLOCK_JACOBI, 5, &g);
    for (int p = CLOTH_PRECOND_BLOCK_JACOBI; p <= CLOTH_PRECOND_SSOR; p++) {
        cloth_case(CLOTH_BACKWARD_EULER, (cloth_precond)p, 9, &g);
        cloth_case(CLOTH_BDF2, (cloth_precond)p, 9, &g);
    }
    return check_summary();
}
