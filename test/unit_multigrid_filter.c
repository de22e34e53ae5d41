/* The multigrid V-cycle (core/src/multigrid.c) keeps the constrained
 * directions out of its output. On grids of the cloth's link pattern with a
 * positive definite random matrix and plane constraints of random normals
 * (and pins), the preconditioner's output s = V(S r) at a constrained vertex
 * i must lie in S_i's range: |(I - S_i) s_i| within a few rounding units of
 * |s_i|, as far as S_i = I - n n^T is a projector in floating point. A
 * smoother whose D_i^-1 leaks into the constrained directions (its rounding
 * amplified by the block's condition) fails it; the modified PCG then
 * stalls at tight tolerances. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "grid_matrix.h"
#include "mat3.h"
#include "multigrid.h"

/* A positive definite: random symmetric blocks, the diagonal blocks made dominant
 * with a condition of about `cond` within each (a stiff link along a random axis) */
static void definite(bsr *A, rng *g, double cond)
{
    random_symmetric(A, g, 0);
    for (int i = 0; i < A->n; i++) {
        double off = 0.0, u[3], *D = A->val + 9 * (size_t)A->diag[i];
        for (int k = A->row_ptr[i]; k < A->row_ptr[i + 1]; k++)
            if (k != A->diag[i])
                for (int e = 0; e < 9; e++) off += fabs(A->val[9 * (size_t)k + e]);
        rng_unit_vector(g, u);
        for (int r = 0; r < 3; r++)
            for (int s = 0; s < 3; s++) D[3 * r + s] += (r == s ? off : 0.0) + cond * off * u[r] * u[s];
    }
}

/* S_i: a plane of random normal (60%), a pin (10%) or free; Dinv_i = (S A_ii S + I - S)^-1 */
static void constraints(const bsr *A, rng *g, double *S, unsigned char *con, double *Dinv)
{
    for (int i = 0; i < A->n; i++) {
        double u[3], x = rng_unit(g), *Si = S + 9 * (size_t)i, T[9], M[9];
        int kind = x < 0.6 ? 1 : x < 0.7 ? 2 : 0;
        rng_unit_vector(g, u);
        con[i] = kind != 0;
        for (int r = 0; r < 3; r++)
            for (int s = 0; s < 3; s++) Si[3 * r + s] = kind == 2 ? 0.0 : (r == s) - (kind ? u[r] * u[s] : 0.0);
        mat3mul(Si, A->val + 9 * (size_t)A->diag[i], T);
        mat3mul(T, Si, M);
        for (int r = 0; r < 3; r++)
            for (int s = 0; s < 3; s++) M[3 * r + s] += (r == s) - Si[3 * r + s];
        mat3inv(M, Dinv + 9 * (size_t)i);
    }
}

static void run(int R, int C, double cond, rng *g)
{
    int n = R * C;
    bsr A;
    multigrid mg;
    double *S = malloc(9 * sizeof *S * (size_t)n), *Dinv = malloc(9 * sizeof *Dinv * (size_t)n);
    double *r = malloc(3 * sizeof *r * (size_t)n), *s = malloc(3 * sizeof *s * (size_t)n);
    unsigned char *con = malloc((size_t)n);
    int ok = CHECK(S && Dinv && r && s && con, "out of memory") && CHECK(grid_matrix(R, C, &A) == 0, "grid_matrix");
    if (!ok || !CHECK(oc_mg_create(&mg, R, C, &A) == 0, "%dx%d: oc_mg_create", R, C)) {
        if (ok) oc_bsr_free(&A);
        free(S), free(Dinv), free(r), free(s), free(con);
        return;
    }
    definite(&A, g, cond);
    constraints(&A, g, S, con, Dinv);
    oc_mg_setup(&mg, &A, S, con, Dinv);
    double worst = 0.0;
    for (int trial = 0; trial < 4; trial++) {
        for (int i = 0; i < n; i++) {
            double v[3];
            for (int k = 0; k < 3; k++) v[k] = rng_range(g, -1.0, 1.0);
            mat3vec(S + 9 * (size_t)i, v, r + 3 * i);
        }
        oc_mg_apply(&mg, r, s);
        for (int i = 0; i < n; i++) {
            if (!con[i]) continue;
            const double *si = s + 3 * i, *Si = S + 9 * (size_t)i;
            double p[3], e = 0.0, m = 0.0;
            mat3vec(Si, si, p);
            for (int k = 0; k < 3; k++) {
                e += (si[k] - p[k]) * (si[k] - p[k]);
                m += si[k] * si[k];
            }
            if (m > 0.0) worst = fmax(worst, sqrt(e / m));
        }
    }
    printf("%dx%d, diagonal blocks' condition about %g: constrained part of the V-cycle's output %.2e of it\n", R, C,
           cond, worst);
    /* S_i = I - n n^T in floating point is a projector to a few ulp (|S^2 - S| about 4 eps): 16 eps */
    CHECK(worst <= 16 * DBL_EPSILON, "%dx%d cond %g: the V-cycle's output leaks %.3g into constrained directions", R, C,
          cond, worst);
    oc_mg_free(&mg);
    oc_bsr_free(&A);
    free(S), free(Dinv), free(r), free(s), free(con);
}

int main(void)
{
    rng g = rng_seed(0x5f17e3u);
    run(9, 9, 1e2, &g);
    run(17, 17, 1e4, &g);
    run(12, 18, 1e6, &g);
    return check_summary();
}
