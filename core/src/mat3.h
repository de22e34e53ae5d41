/* 3x3 block helpers shared by the step, the solver and the multigrid. */
#ifndef ODECLOTH_MAT3_H
#define ODECLOTH_MAT3_H

#include <math.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

/* the block-row loops below are the solvers' inner loops: always inline,
 * and unrolled (GCC; a row has 8-25 blocks) */
#if defined(__GNUC__)
#define MAT3_INLINE static inline __attribute__((always_inline))
#else
#define MAT3_INLINE static inline
#endif
#if defined(__GNUC__) && !defined(__clang__)
#define MAT3_UNROLL _Pragma("GCC unroll 4")
#else
#define MAT3_UNROLL
#endif

/* y = M x (y may not alias x) */
static inline void mat3vec(const double *M, const double *x, double *y)
{
    y[0] = M[0] * x[0] + M[1] * x[1] + M[2] * x[2];
    y[1] = M[3] * x[0] + M[4] * x[1] + M[5] * x[2];
    y[2] = M[6] * x[0] + M[7] * x[1] + M[8] * x[2];
}

/* C = A B */
static inline void mat3mul(const double *A, const double *B, double *C)
{
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 3
#endif
    for (int r = 0; r < 3; r++)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 3
#endif
        for (int s = 0; s < 3; s++) C[3 * r + s] = A[3 * r] * B[s] + A[3 * r + 1] * B[3 + s] + A[3 * r + 2] * B[6 + s];
}

/* A += s B, element by element (SSE2: two at a time, the same operations) */
/* A = 0 - B: the bits of mat3_axpy(A, B, -1) on a zero A */
static inline void mat3_set_neg(double *A, const double *B)
{
    for (int k = 0; k < 9; k++) A[k] = 0.0 - B[k];
}

static inline void mat3_axpy(double *A, const double *B, double s)
{
#if defined(__SSE2__)
    __m128d sv = _mm_set1_pd(s);
    for (int k = 0; k < 8; k += 2)
        _mm_storeu_pd(A + k, _mm_add_pd(_mm_loadu_pd(A + k), _mm_mul_pd(sv, _mm_loadu_pd(B + k))));
    A[8] += s * B[8];
#else
    for (int k = 0; k < 9; k++) A[k] += s * B[k];
#endif
}

/* o = m^-1 by cofactors; returns the determinant (o untouched if it is zero
 * or not finite). */
static inline double mat3inv(const double *m, double *o)
{
    double c0 = m[4] * m[8] - m[5] * m[7], c1 = m[5] * m[6] - m[3] * m[8], c2 = m[3] * m[7] - m[4] * m[6];
    double det = m[0] * c0 + m[1] * c1 + m[2] * c2;
    if (det == 0.0 || !isfinite(det)) return det;
    double id = 1.0 / det;
    o[0] = c0 * id;
    o[1] = (m[2] * m[7] - m[1] * m[8]) * id;
    o[2] = (m[1] * m[5] - m[2] * m[4]) * id;
    o[3] = c1 * id;
    o[4] = (m[0] * m[8] - m[2] * m[6]) * id;
    o[5] = (m[2] * m[3] - m[0] * m[5]) * id;
    o[6] = c2 * id;
    o[7] = (m[1] * m[6] - m[0] * m[7]) * id;
    o[8] = (m[0] * m[4] - m[1] * m[3]) * id;
    return det;
}

/* ------------------------------------------------------ block-row sums
 * Products of a row of 3x3 blocks with x_col[k], each block summed as mat3vec does and added to
 * (subtracted from) acc block by block: a plain loop's order, so every variant gives the same bits. */

/* A block equal to its transpose bit for bit. */
static inline int mat3_is_sym(const double *B)
{
    return !memcmp(B + 1, B + 3, sizeof *B) && !memcmp(B + 2, B + 6, sizeof *B) && !memcmp(B + 5, B + 7, sizeof *B);
}

/* acc += (row_add) or -= (row_sub) sum B_k x_col[k] */
#define MAT3_ROW(name, op)                                                                                 \
    MAT3_INLINE void name(const double *val, const int *col, int a, int z, const double *x, double acc[3]) \
    {                                                                                                      \
        double a0 = acc[0], a1 = acc[1], a2 = acc[2];                                                      \
        MAT3_UNROLL                                                                                        \
        for (int k = a; k < z; k++) {                                                                      \
            const double *B = val + 9 * (size_t)k, *xj = x + 3 * (size_t)col[k];                           \
            double x0 = xj[0], x1 = xj[1], x2 = xj[2];                                                     \
            a0 op B[0] * x0 + B[1] * x1 + B[2] * x2;                                                       \
            a1 op B[3] * x0 + B[4] * x1 + B[5] * x2;                                                       \
            a2 op B[6] * x0 + B[7] * x1 + B[8] * x2;                                                       \
        }                                                                                                  \
        acc[0] = a0;                                                                                       \
        acc[1] = a1;                                                                                       \
        acc[2] = a2;                                                                                       \
    }
MAT3_ROW(row_add, +=)
MAT3_ROW(row_sub, -=)
#undef MAT3_ROW

/* The same for rows of symmetric blocks: with SSE2 rows 0 and 1 go as one pair, whose column pairs
 * are adjacent in memory for a symmetric block; each lane keeps the scalar order, so the bits match. */
#if defined(__SSE2__)
#define MAT3_ROW_SYM(name, op, vop)                                                                        \
    MAT3_INLINE void name(const double *val, const int *col, int a, int z, const double *x, double acc[3]) \
    {                                                                                                      \
        __m128d a01 = _mm_loadu_pd(acc);                                                                   \
        double a2 = acc[2];                                                                                \
        MAT3_UNROLL                                                                                        \
        for (int k = a; k < z; k++) {                                                                      \
            const double *B = val + 9 * (size_t)k, *xj = x + 3 * (size_t)col[k];                           \
            double x0 = xj[0], x1 = xj[1], x2 = xj[2];                                                     \
            __m128d t = _mm_add_pd(_mm_mul_pd(_mm_loadu_pd(B), _mm_set1_pd(x0)),                           \
                                   _mm_mul_pd(_mm_loadu_pd(B + 3), _mm_set1_pd(x1)));                      \
            t = _mm_add_pd(t, _mm_mul_pd(_mm_loadu_pd(B + 6), _mm_set1_pd(x2)));                           \
            a01 = vop(a01, t);                                                                             \
            a2 op B[6] * x0 + B[7] * x1 + B[8] * x2;                                                       \
        }                                                                                                  \
        _mm_storeu_pd(acc, a01);                                                                           \
        acc[2] = a2;                                                                                       \
    }
MAT3_ROW_SYM(row_add_sym, +=, _mm_add_pd)
MAT3_ROW_SYM(row_sub_sym, -=, _mm_sub_pd)
#undef MAT3_ROW_SYM

/* mat3vec for a symmetric M, the same way (y may not alias x) */
MAT3_INLINE void mat3vec_sym(const double *M, const double *x, double *y)
{
    double x0 = x[0], x1 = x[1], x2 = x[2];
    __m128d t = _mm_add_pd(_mm_mul_pd(_mm_loadu_pd(M), _mm_set1_pd(x0)),
                           _mm_mul_pd(_mm_loadu_pd(M + 3), _mm_set1_pd(x1)));
    t = _mm_add_pd(t, _mm_mul_pd(_mm_loadu_pd(M + 6), _mm_set1_pd(x2)));
    double y2 = M[6] * x0 + M[7] * x1 + M[8] * x2;
    _mm_storeu_pd(y, t);
    y[2] = y2;
}
#else
#define row_add_sym row_add
#define row_sub_sym row_sub
#define mat3vec_sym mat3vec
#endif

/* ----------------- AVX: symmetric rows' sums in 256-bit vectors, chosen at run time, no FMA (same
 * bits); the fourth lane reads one double past a block (matrices are padded). Kernels take a constant
 * flag avx, wrapped twice (MAT3_AVX_FN for 1); mat3_avx() picks (docs/newton.md, "Design notes"). */
#if defined(__SSE2__) && defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__)) && !defined(ODECLOTH_NO_AVX)
#define MAT3_HAVE_AVX 1
#include <immintrin.h>
#define MAT3_AVX_FN __attribute__((target("avx"), flatten))
/* the AVX loops may run here (the CPU and the OS support AVX) */
static inline int mat3_avx(void) { return __builtin_cpu_supports("avx"); }

/* not always_inline: inlined only into MAT3_AVX_FN functions */
#define MAT3_ROW_SYM_AVX(name, vop)                                                                         \
    static inline __attribute__((target("avx"))) void name(const double *val, const int *col, int a, int z, \
                                                           const double *x, double acc[3])                  \
    {                                                                                                       \
        __m256d ac = _mm256_set_pd(0.0, acc[2], acc[1], acc[0]);                                            \
        MAT3_UNROLL                                                                                         \
        for (int k = a; k < z; k++) {                                                                       \
            const double *B = val + 9 * (size_t)k, *xj = x + 3 * (size_t)col[k];                            \
            __m256d t = _mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(B), _mm256_broadcast_sd(xj)),           \
                                      _mm256_mul_pd(_mm256_loadu_pd(B + 3), _mm256_broadcast_sd(xj + 1)));  \
            t = _mm256_add_pd(t, _mm256_mul_pd(_mm256_loadu_pd(B + 6), _mm256_broadcast_sd(xj + 2)));       \
            ac = vop(ac, t);                                                                                \
        }                                                                                                   \
        _mm_storeu_pd(acc, _mm256_castpd256_pd128(ac));                                                     \
        _mm_store_sd(acc + 2, _mm256_extractf128_pd(ac, 1));                                                \
    }
MAT3_ROW_SYM_AVX(row_add_sym_avx, _mm256_add_pd)
MAT3_ROW_SYM_AVX(row_sub_sym_avx, _mm256_sub_pd)
#undef MAT3_ROW_SYM_AVX

#else
#define MAT3_HAVE_AVX 0
#define MAT3_AVX_FN
static inline int mat3_avx(void) { return 0; }
#endif

/* row_add_sym / row_sub_sym, by the AVX loop when avx (a constant in the
 * kernels) is set */
MAT3_INLINE void row_add_symv(int avx, const double *val, const int *col, int a, int z, const double *x, double acc[3])
{
#if MAT3_HAVE_AVX
    if (avx) {
        row_add_sym_avx(val, col, a, z, x, acc);
        return;
    }
#endif
    (void)avx;
    row_add_sym(val, col, a, z, x, acc);
}

MAT3_INLINE void row_sub_symv(int avx, const double *val, const int *col, int a, int z, const double *x, double acc[3])
{
#if MAT3_HAVE_AVX
    if (avx) {
        row_sub_sym_avx(val, col, a, z, x, acc);
        return;
    }
#endif
    (void)avx;
    row_sub_sym(val, col, a, z, x, acc);
}

#endif
