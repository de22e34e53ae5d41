/* The multigrid's Galerkin coarse operators (core/src/galerkin.c, through
 * oc_mg_setup) against dense products formed here: on grids of the cloth's link
 * pattern (sequential and interlaced links, odd and even sides) with random
 * symmetric blocks and random constraint filters, every level's matrix must
 * equal W^T F W, with F the level above (level 0: S A S) and W bilinear
 * interpolation computed independently below, to 1e-12 of its largest entry,
 * and be symmetric (exactly where the fine blocks are). A missing
 * contribution, a block added twice or transposed wrongly, or an unfiltered
 * constraint fails it. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "grid_matrix.h"
#include "multigrid.h"

/* the bilinear parents of fine index f on a coarse axis of n nodes */
static int parents(int f, int n, int *p, double *w)
{
    if (f % 2 == 0) {
        p[0] = f / 2, w[0] = 1.0;
        return 1;
    }
    if ((f + 1) / 2 >= n) {
        p[0] = (f - 1) / 2, w[0] = 1.0;
        return 1;
    }
    p[0] = (f - 1) / 2, p[1] = (f + 1) / 2, w[0] = w[1] = 0.5;
    return 2;
}

/* dense W (3 Rf Cf x 3 Rc Cc) */
static void dense_w(int Rf, int Cf, int Rc, int Cc, double *W)
{
    int nc3 = 3 * Rc * Cc;
    memset(W, 0, sizeof *W * 3 * (size_t)Rf * Cf * nc3);
    for (int r = 0; r < Rf; r++)
        for (int c = 0; c < Cf; c++) {
            int pr[2], pc[2];
            double wr[2], wc[2];
            int nr = parents(r, Rc, pr, wr), ncl = parents(c, Cc, pc, wc);
            for (int a = 0; a < nr; a++)
                for (int b = 0; b < ncl; b++)
                    for (int d = 0; d < 3; d++)
                        W[(size_t)(3 * (r * Cf + c) + d) * nc3 + 3 * (pr[a] * Cc + pc[b]) + d] = wr[a] * wc[b];
        }
}

static void dense_of(const bsr *M, double *D)
{
    int n3 = 3 * M->n;
    memset(D, 0, sizeof *D * (size_t)n3 * n3);
    for (int i = 0; i < M->n; i++)
        for (int k = M->row_ptr[i]; k < M->row_ptr[i + 1]; k++)
            for (int r = 0; r < 3; r++)
                for (int s = 0; s < 3; s++)
                    D[(size_t)(3 * i + r) * n3 + 3 * M->col[k] + s] = M->val[9 * (size_t)k + 3 * r + s];
}

/* K = W^T F W, dense: F is nf x nf, W nf x nc */
static void galerkin_dense(const double *F, const double *W, int nf, int nc, double *K)
{
    double *FW = calloc((size_t)nf * nc, sizeof *FW);
    for (int i = 0; i < nf; i++)
        for (int k = 0; k < nf; k++) {
            double f = F[(size_t)i * nf + k];
            if (f != 0.0)
                for (int j = 0; j < nc; j++) FW[(size_t)i * nc + j] += f * W[(size_t)k * nc + j];
        }
    memset(K, 0, sizeof *K * (size_t)nc * nc);
    for (int k = 0; k < nf; k++)
        for (int i = 0; i < nc; i++) {
            double w = W[(size_t)k * nc + i];
            if (w != 0.0)
                for (int j = 0; j < nc; j++) K[(size_t)i * nc + j] += w * FW[(size_t)k * nc + j];
        }
    free(FW);
}

/* |K - M| over the largest |K|; *asym: |M - M^T| over it */
static double compare(const double *K, const bsr *M, double *asym)
{
    int n3 = 3 * M->n;
    double *D = malloc(sizeof *D * (size_t)n3 * n3), big = 0.0, diff = 0.0, as = 0.0;
    dense_of(M, D);
    for (int i = 0; i < n3; i++)
        for (int j = 0; j < n3; j++) {
            big = fmax(big, fabs(K[(size_t)i * n3 + j]));
            diff = fmax(diff, fabs(K[(size_t)i * n3 + j] - D[(size_t)i * n3 + j]));
            as = fmax(as, fabs(D[(size_t)i * n3 + j] - D[(size_t)j * n3 + i]));
        }
    free(D);
    *asym = as / big;
    return diff / big;
}

/* S A S with S_i = I - n n^T (a plane) or 0 (a pin) on the constrained */
static void filtered(const bsr *A, const double *S, const unsigned char *con, double *F)
{
    int n3 = 3 * A->n;
    dense_of(A, F);
    for (int i = 0; i < A->n; i++) {
        if (!con[i]) continue;
        const double *Si = S + 9 * (size_t)i;
        for (int pass = 0; pass < 2; pass++) /* rows, then columns */
            for (int j = 0; j < n3; j++) {
                double *e[3], v[3];
                for (int r = 0; r < 3; r++)
                    e[r] = pass ? &F[(size_t)j * n3 + 3 * i + r] : &F[(size_t)(3 * i + r) * n3 + j];
                for (int r = 0; r < 3; r++) v[r] = *e[r];
                for (int r = 0; r < 3; r++) *e[r] = Si[3 * r] * v[0] + Si[3 * r + 1] * v[1] + Si[3 * r + 2] * v[2];
            }
    }
}

/* sym: every block symmetric and no constraint (the smoother's paired loop
 * needs the coarse blocks exactly symmetric then) */
static void run(int R, int C, int sym, rng *g)
{
    int n = R * C;
    bsr A;
    multigrid mg;
    CHECK(grid_matrix(R, C, &A) == 0, "%dx%d: grid_matrix", R, C);
    random_symmetric(&A, g, sym);
    double *S = calloc(9 * (size_t)n, sizeof *S), *Dinv = calloc(9 * (size_t)n, sizeof *Dinv);
    unsigned char *con = calloc((size_t)n, 1);
    for (int i = 0; i < n; i++) {
        double u[3];
        rng_unit_vector(g, u);
        int kind = !sym && rng_unit(g) < 0.3 ? (rng_unit(g) < 0.5 ? 1 : 2) : 0;
        con[i] = kind != 0;
        for (int r = 0; r < 3; r++)
            for (int s = 0; s < 3; s++) S[9 * i + 3 * r + s] = kind == 2 ? 0.0 : (r == s) - (kind ? u[r] * u[s] : 0.0);
        Dinv[9 * i] = Dinv[9 * i + 4] = Dinv[9 * i + 8] = 1.0;
    }
    CHECK(oc_mg_create(&mg, R, C, &A) == 0, "%dx%d: oc_mg_create", R, C);
    oc_mg_setup(&mg, &A, S, con, Dinv);
    /* the fine operator coarsened is S A S; then each level's own */
    double *F = malloc(sizeof *F * 9 * (size_t)n * n);
    filtered(&A, S, con, F);
    for (int l = 0; l + 1 < mg.nlev; l++) {
        const mg_level *Lf = &mg.lev[l], *Lc = &mg.lev[l + 1];
        int nf = 3 * Lf->n, nc = 3 * Lc->n;
        double asym;
        double *W = malloc(sizeof *W * (size_t)nf * nc), *K = malloc(sizeof *K * (size_t)nc * nc);
        dense_w(Lf->R, Lf->C, Lc->R, Lc->C, W);
        galerkin_dense(F, W, nf, nc, K);
        double e = compare(K, &Lc->M, &asym);
        CHECK(e <= 1e-12, "%dx%d level %d: coarse operator off W^T F W by %.3g of its largest entry", R, C, l + 1, e);
        CHECK(sym ? asym == 0.0 : asym <= 1e-14, "%dx%d level %d: coarse operator asymmetric by %.3g", R, C, l + 1,
              asym);
        printf("%dx%d%s level %d (%dx%d): off W^T F W by %.2e, asymmetric by %.2e\n", R, C, sym ? " sym" : "", l + 1,
               Lc->R, Lc->C, e, asym);
        free(F);
        F = malloc(sizeof *F * (size_t)nc * nc);
        dense_of(&Lc->M, F);
        free(W);
        free(K);
    }
    CHECK(mg.nlev >= 2, "%dx%d: %d levels", R, C, mg.nlev);
    free(F);
    oc_mg_free(&mg);
    oc_bsr_free(&A);
    free(S);
    free(Dinv);
    free(con);
}

int main(void)
{
    rng g = rng_seed(0x6a1e4c1u);
    for (int sym = 0; sym < 2; sym++) {
        run(9, 9, sym, &g);   /* two levels */
        run(17, 17, sym, &g); /* three */
        run(10, 7, sym, &g);  /* even sides: nodes hanging off one parent */
        run(12, 18, sym, &g);
    }
    return check_summary();
}
