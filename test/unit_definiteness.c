/* Unit: the definiteness rule (paper sec. 3.2) keeps the implicit system
 * positive definite, and without it the modified PCG reports non-positive
 * curvature instead of returning a wrong answer.
 *
 * A link's stiffness block is K = k uu^T + k (1 - l/d)(I - uu^T); the
 * transverse eigenvalue k (1 - l/d) is negative when the link is compressed
 * (d < l). The scene: a 9 x 9 cotton cloth whose positions are the rest
 * grid shrunk to half size in its plane (every link at d = l/2, transverse
 * eigenvalue -k) plus a random out-of-plane jitter of 1% of the spacing,
 * at rest, no gravity, h = 1/60, no constraints. Then
 * A = M - h D - h^2 df/dx has out-of-plane diagonal entries m - h^2 sum k
 * over the vertex's links (interior: 0.0031 - 0.111 - 0.044 kg, from the 8
 * sequential links at k_c = 50 N/m and 8 interlaced at k_b = 20 N/m): A is
 * indefinite, and so is every one of its 3x3 diagonal blocks.
 *
 * A second scene, shrunk to 0.8 with h = 1/240, keeps 77 of the 81 3x3
 * diagonal blocks of A positive definite (and the initial residual's norm
 * positive) while A itself stays indefinite (its checkerboard out-of-plane
 * modes), so the failure has to be found inside the CG iteration (with this
 * core: after 2 iterations) rather than from the norm's weights up front.
 *
 * Asserted, for both scenes:
 *   - rule off, for backward Euler and BDF2 (whose first step is BE), and
 *     each preconditioner: cloth_step returns CLOTH_ESTEP, stats.failure ==
 *     CLOTH_FAIL_CG_INDEFINITE (the stats of cloth_last_stats too), and the
 *     state is unchanged (cloth_state_diff == 0 against a state saved
 *     before); should a step report success anyway, its dv must solve the
 *     step's system (|b - A dv| <= 1e-2 |b|), or it returned a wrong answer;
 *   - rule off: the assembled matrix (c->A after the failing step; the step
 *     assembles before it solves) has a negative eigenvalue, computed here
 *     by a cyclic Jacobi eigen-solver on oc_bsr_to_dense;
 *   - rule on, same scene: CLOTH_OK, failure NONE, |b - A dv| <= 1e-2 |b|
 *     (tolerance 1e-3 in the solver's block-diagonal norm), and the
 *     assembled matrix is positive definite with smallest eigenvalue >= the
 *     smallest lumped mass (with the rule every link adds h^2 k uu^T +
 *     h c uu^T, positive semi-definite, to M), largest <= Gershgorin's bound;
 *   - the Jacobi eigen-solver itself, on the rule-on matrix: the
 *     eigenvalues sum to the trace (1e-12) and the smallest one, used as a
 *     shift, makes a Cholesky factorisation of A - (lambda_min - eps) I
 *     succeed and of A - (lambda_min + eps) I fail.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "internal.h"
#include "bsr.h"
#include "check.h"

#define GRID 9

/* Eigenvalues of the symmetric m x m matrix a (destroyed) by cyclic Jacobi
 * rotations, into ev (unsorted). */
static void jacobi_eigen(double *a, int m, double *ev)
{
    for (int sweep = 0; sweep < 100; sweep++) {
        double off = 0, diag = 0;
        for (int i = 0; i < m; i++) {
            diag += a[i * m + i] * a[i * m + i];
            for (int j = i + 1; j < m; j++) off += a[i * m + j] * a[i * m + j];
        }
        if (off <= 1e-30 * diag) break;
        for (int p = 0; p < m; p++)
            for (int q = p + 1; q < m; q++) {
                double apq = a[p * m + q];
                if (fabs(apq) < 1e-300) continue;
                double theta = (a[q * m + q] - a[p * m + p]) / (2 * apq);
                double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1));
                double cs = 1 / sqrt(t * t + 1), sn = t * cs;
                for (int k = 0; k < m; k++) { /* columns p, q */
                    double akp = a[k * m + p], akq = a[k * m + q];
                    a[k * m + p] = cs * akp - sn * akq;
                    a[k * m + q] = sn * akp + cs * akq;
                }
                for (int k = 0; k < m; k++) { /* rows p, q */
                    double apk = a[p * m + k], aqk = a[q * m + k];
                    a[p * m + k] = cs * apk - sn * aqk;
                    a[q * m + k] = sn * apk + cs * aqk;
                }
            }
    }
    for (int i = 0; i < m; i++) ev[i] = a[i * m + i];
}

/* 0 if the symmetric matrix a - shift I has a Cholesky factor, else -1. */
static int cholesky_ok(const double *a, int m, double shift)
{
    double *l = malloc(sizeof(double) * (size_t)m * m);
    int rc = 0;
    memcpy(l, a, sizeof(double) * (size_t)m * m);
    for (int i = 0; i < m; i++) l[i * m + i] -= shift;
    for (int j = 0; j < m && rc == 0; j++) {
        double s = l[j * m + j];
        for (int k = 0; k < j; k++) s -= l[j * m + k] * l[j * m + k];
        if (!(s > 0)) {
            rc = -1;
            break;
        }
        l[j * m + j] = sqrt(s);
        for (int i = j + 1; i < m; i++) {
            double t = l[i * m + j];
            for (int k = 0; k < j; k++) t -= l[i * m + k] * l[j * m + k];
            l[i * m + j] = t / l[j * m + j];
        }
    }
    free(l);
    return rc;
}

typedef struct spectrum {
    double lmin, lmax, trace, sum, gersh_lo, gersh_hi, asym;
} spectrum;

static spectrum analyse(const cloth *c, double **dense_out)
{
    int N = 3 * c->n;
    double *A = malloc(sizeof(double) * (size_t)N * N), *a = malloc(sizeof(double) * (size_t)N * N);
    double *ev = malloc(sizeof(double) * N);
    oc_bsr_to_dense(&c->A, A);
    spectrum sp = {INFINITY, -INFINITY, 0, 0, INFINITY, -INFINITY, 0};
    for (int i = 0; i < N; i++) {
        double r = 0;
        for (int j = 0; j < N; j++) {
            if (j != i) r += fabs(A[i * N + j]);
            sp.asym = fmax(sp.asym, fabs(A[i * N + j] - A[j * N + i]));
        }
        sp.trace += A[i * N + i];
        sp.gersh_lo = fmin(sp.gersh_lo, A[i * N + i] - r);
        sp.gersh_hi = fmax(sp.gersh_hi, A[i * N + i] + r);
    }
    memcpy(a, A, sizeof(double) * (size_t)N * N);
    jacobi_eigen(a, N, ev);
    for (int i = 0; i < N; i++) {
        sp.lmin = fmin(sp.lmin, ev[i]);
        sp.lmax = fmax(sp.lmax, ev[i]);
        sp.sum += ev[i];
    }
    free(a);
    free(ev);
    if (dense_out) *dense_out = A;
    else free(A);
    return sp;
}

/* the compressed, jittered scene */
static cloth *make_scene(cloth_method method, cloth_precond precond, int rule, double scale)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = CLOTH_LINEARIZED; /* the linearised step's rule is tested */
    d.rows = d.cols = GRID;
    d.gravity[0] = d.gravity[1] = d.gravity[2] = 0.0;
    d.solver.method = method;
    d.solver.precond = precond;
    d.solver.definiteness_rule = rule;
    d.solver.max_substep_halvings = 0; /* the single step's own failure is what is checked */
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) return NULL;
    int n = cloth_vertex_count(c);
    double *x = malloc(sizeof(double) * 3 * n), ctr[3] = {0, 0, 0};
    memcpy(x, cloth_positions(c), sizeof(double) * 3 * n);
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) ctr[a] += x[3 * i + a] / n;
    rng g = rng_seed(0xdef1u);
    double spacing = d.width / (GRID - 1);
    for (int i = 0; i < n; i++) {
        /* the cloth lies in the xy plane (default axes): shrink x, y; jitter z */
        for (int a = 0; a < 2; a++) x[3 * i + a] = ctr[a] + scale * (x[3 * i + a] - ctr[a]);
        x[3 * i + 2] += 0.01 * spacing * rng_range(&g, -1, 1);
    }
    CHECK(cloth_set_positions(c, x) == CLOTH_OK, "set_positions: %s", cloth_last_error(c));
    free(x);
    return c;
}

/* The relative 2-norm residual |S (b - A dv)| / |S b| of the step's own
 * system (no constraints here, S = I): a step that reports success must have
 * solved it. */
static double step_residual(const cloth *c)
{
    int N = 3 * c->n;
    double *r = malloc(sizeof(double) * N), num = 0, den = 0;
    oc_bsr_mul(&c->A, c->dv, r);
    for (int k = 0; k < N; k++) {
        num += (c->b[k] - r[k]) * (c->b[k] - r[k]);
        den += c->b[k] * c->b[k];
    }
    free(r);
    return den > 0 ? sqrt(num / den) : sqrt(num);
}

int main(void)
{
    const char *mname[] = {"BE", "", "", "BDF2"}, *pname[] = {"block", "jacobi", "multigrid", "ssor"};
    const cloth_method methods[] = {CLOTH_BACKWARD_EULER, CLOTH_BDF2};
    /* scene 0: the rest grid at half size, h = 1/60: every diagonal block of A is itself indefinite (m - h^2 sum k
     * < 0 out of plane); scene 1: at 0.8 size, h = 1/240: 77 of 81 diagonal blocks positive definite, A still
     * indefinite (its checkerboard out-of-plane modes), found inside the CG iteration. */
    const double scales[2] = {0.5, 0.8}, hs[2] = {1.0 / 60, 1.0 / 240};
    for (int sc = 0; sc < 2; sc++)
        for (int mi = 0; mi < 2; mi++)
            for (int p = CLOTH_PRECOND_BLOCK_JACOBI; p <= CLOTH_PRECOND_SSOR; p++) {
                cloth_method m = methods[mi];
                double h = hs[sc];
                char name[64];
                snprintf(name, sizeof name, "scene %d (x%.1f, h = 1/%.0f) %s/%s", sc, scales[sc], 1 / h, mname[m],
                         pname[p]);
                /* rule off: indefinite, reported, rolled back */
                cloth *c = make_scene(m, (cloth_precond)p, 0, scales[sc]);
                if (!c) continue;
                cloth_state *before = cloth_state_create(c), *after = cloth_state_create(c);
                cloth_save(c, before);
                cloth_step_stats st;
                cloth_status s = cloth_step(c, h, &st);
                cloth_save(c, after);
                CHECK(s == CLOTH_ESTEP, "%s rule off: cloth_step returned %d (%s), expected CLOTH_ESTEP", name, (int)s,
                      cloth_status_string(s));
                CHECK(st.failure == CLOTH_FAIL_CG_INDEFINITE, "%s rule off: failure %d (%s), expected CG_INDEFINITE",
                      name, (int)st.failure, cloth_failure_string(st.failure));
                CHECK(cloth_last_stats(c)->failure == CLOTH_FAIL_CG_INDEFINITE, "%s rule off: last_stats failure %d",
                      name, (int)cloth_last_stats(c)->failure);
                double diff = cloth_state_diff(before, after);
                CHECK(diff == 0.0, "%s rule off: state changed by the step (diff %.3g)", name, diff);
                if (s == CLOTH_OK) {
                    double res = step_residual(c);
                    CHECK(res <= 1e-2,
                          "%s rule off: the step reported success after %d CG iterations (residual %.3g) "
                          "but |b - A dv| / |b| = %.3g: a wrong answer",
                          name, st.iterations, st.residual, res);
                }
                if (m == CLOTH_BACKWARD_EULER && p == CLOTH_PRECOND_BLOCK_JACOBI) {
                    spectrum sp = analyse(c, NULL);
                    printf("%s rule off: A's eigenvalues in [%.6g, %.6g] (Gershgorin [%.4g, %.4g]); "
                           "step status %d, failure %d, %d CG iterations\n",
                           name, sp.lmin, sp.lmax, sp.gersh_lo, sp.gersh_hi, (int)s, (int)st.failure, st.iterations);
                    CHECK(sp.asym <= 1e-15 * sp.gersh_hi, "%s rule off: A not symmetric (%.3g)", name, sp.asym);
                    CHECK(sp.lmin < 0, "%s rule off: smallest eigenvalue of A %.6g is not negative", name, sp.lmin);
                }
                cloth_state_destroy(before);
                cloth_state_destroy(after);
                cloth_destroy(c);

                /* rule on: definite, converges */
                c = make_scene(m, (cloth_precond)p, 1, scales[sc]);
                if (!c) continue;
                s = cloth_step(c, h, &st);
                CHECK(s == CLOTH_OK, "%s rule on: cloth_step: %s", name, cloth_last_error(c));
                CHECK(st.failure == CLOTH_FAIL_NONE, "%s rule on: failure %d (%s)", name, (int)st.failure,
                      cloth_failure_string(st.failure));
                CHECK(st.residual <= cloth_get_desc(c).solver.cg_tolerance, "%s rule on: residual %.3g", name,
                      st.residual);
                if (s == CLOTH_OK) {
                    double res = step_residual(c);
                    CHECK(res <= 1e-2, "%s rule on: |b - A dv| / |b| = %.3g after a successful step", name, res);
                }
                if (m == CLOTH_BACKWARD_EULER && p == CLOTH_PRECOND_BLOCK_JACOBI) {
                    double *A;
                    int N = 3 * c->n;
                    double mmin = INFINITY;
                    for (int i = 0; i < c->n; i++) mmin = fmin(mmin, cloth_masses(c)[i]);
                    spectrum sp = analyse(c, &A);
                    printf("%s rule on: A's eigenvalues in [%.6g, %.6g] (Gershgorin [%.4g, %.4g]), "
                           "smallest mass %.6g; %d CG iterations\n",
                           name, sp.lmin, sp.lmax, sp.gersh_lo, sp.gersh_hi, mmin, st.iterations);
                    CHECK(sp.asym <= 1e-15 * sp.gersh_hi, "%s rule on: A not symmetric (%.3g)", name, sp.asym);
                    CHECK(sp.lmin >= mmin * (1 - 1e-9), "%s rule on: smallest eigenvalue %.9g < smallest mass %.9g",
                          name, sp.lmin, mmin);
                    CHECK(sp.lmax <= sp.gersh_hi * (1 + 1e-12), "%s rule on: largest eigenvalue %.9g > Gershgorin %.9g",
                          name, sp.lmax, sp.gersh_hi);
                    /* the eigen-solver, checked */
                    CHECK_REL(sp.sum, sp.trace, 1e-12, 0);
                    double eps = 1e-6 * sp.lmin;
                    CHECK(cholesky_ok(A, N, sp.lmin - eps) == 0, "%s: A - (lambda_min - eps) I not positive definite",
                          name);
                    CHECK(cholesky_ok(A, N, sp.lmin + eps) != 0,
                          "%s: A - (lambda_min + eps) I positive definite: lambda_min %.9g is not the smallest", name,
                          sp.lmin);
                    free(A);
                }
                cloth_destroy(c);
            }
    return check_summary();
}
