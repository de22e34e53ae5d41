/* Block-CSR matrix of 3x3 blocks with a pattern fixed at creation. */
#include <stdlib.h>
#include <string.h>
#include "bsr.h"
#include "mat3.h"

void oc_bsr_free(bsr *A)
{
    free(A->row_ptr);
    free(A->col);
    free(A->diag);
    free(A->val);
    free(A->sym);
    memset(A, 0, sizeof *A);
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Index of block (i, j), or -1. Rows are short (<= 17 blocks for a cloth),
 * so a linear scan is as fast as a bisection. */
int oc_bsr_find(const bsr *A, int i, int j)
{
    for (int k = A->row_ptr[i]; k < A->row_ptr[i + 1]; k++)
        if (A->col[k] == j) return k;
    return -1;
}

int oc_bsr_build(bsr *A, int n, int nedges, const int *ei, const int *ej, int *blk)
{
    memset(A, 0, sizeof *A);
    if (n <= 0 || nedges < 0) return -1;
    for (int e = 0; e < nedges; e++)
        if (ei[e] < 0 || ei[e] >= n || ej[e] < 0 || ej[e] >= n || ei[e] == ej[e]) return -1;

    int *count = calloc((size_t)n + 1, sizeof *count);
    if (!count) return -1;
    for (int i = 0; i < n; i++) count[i] = 1; /* the diagonal */
    for (int e = 0; e < nedges; e++) {
        count[ei[e]]++;
        count[ej[e]]++;
    }
    size_t upper = (size_t)n + 2 * (size_t)nedges; /* before removing duplicates */
    A->n = n;
    A->row_ptr = malloc(((size_t)n + 1) * sizeof *A->row_ptr);
    A->col = malloc(upper * sizeof *A->col);
    A->diag = malloc((size_t)n * sizeof *A->diag);
    int *fill = malloc((size_t)n * sizeof *fill);
    if (!A->row_ptr || !A->col || !A->diag || !fill) goto fail;

    A->row_ptr[0] = 0;
    for (int i = 0; i < n; i++) A->row_ptr[i + 1] = A->row_ptr[i] + count[i];
    for (int i = 0; i < n; i++) {
        fill[i] = A->row_ptr[i];
        A->col[fill[i]++] = i;
    }
    for (int e = 0; e < nedges; e++) {
        A->col[fill[ei[e]]++] = ej[e];
        A->col[fill[ej[e]]++] = ei[e];
    }
    /* sort each row and squeeze out duplicate edges */
    int out = 0;
    for (int i = 0; i < n; i++) {
        int lo = A->row_ptr[i], hi = A->row_ptr[i + 1];
        qsort(A->col + lo, (size_t)(hi - lo), sizeof *A->col, cmp_int);
        A->row_ptr[i] = out;
        for (int k = lo; k < hi; k++)
            if (k == lo || A->col[k] != A->col[k - 1]) A->col[out++] = A->col[k];
    }
    A->row_ptr[n] = out;
    A->nnzb = out;
    A->val = calloc(9 * (size_t)out + 1, sizeof *A->val); /* + the AVX rows' padding double (mat3.h) */
    A->sym = calloc(2 * (size_t)n, 1);
    if (!A->val || !A->sym) goto fail;
    for (int i = 0; i < n; i++) A->diag[i] = oc_bsr_find(A, i, i);
    for (int e = 0; e < nedges; e++) {
        blk[2 * e] = oc_bsr_find(A, ei[e], ej[e]);
        blk[2 * e + 1] = oc_bsr_find(A, ej[e], ei[e]);
    }
    free(count);
    free(fill);
    return 0;
fail:
    free(count);
    free(fill);
    oc_bsr_free(A);
    return -1;
}

void oc_bsr_zero(bsr *A) { memset(A->val, 0, 9 * (size_t)A->nnzb * sizeof *A->val); }

void oc_bsr_zero_diag(bsr *A)
{
    for (int i = 0; i < A->n; i++) memset(A->val + 9 * (size_t)A->diag[i], 0, 9 * sizeof *A->val);
}

int oc_bsr_edges_own_offdiag(const bsr *A, int nedges, const int *blk)
{
    unsigned char *hits = calloc((size_t)A->nnzb + 1, 1);
    if (!hits) return 0;
    for (int k = 0; k < 2 * nedges; k++)
        if (hits[blk[k]] < 2) hits[blk[k]]++;
    int own = 1;
    for (int i = 0; i < A->n && own; i++)
        for (int k = A->row_ptr[i]; k < A->row_ptr[i + 1]; k++) own = own && (k == A->diag[i] || hits[k] == 1);
    free(hits);
    return own;
}

void oc_bsr_mul(const bsr *A, const double *x, double *y)
{
    for (int i = 0; i < A->n; i++) {
        double y0 = 0.0, y1 = 0.0, y2 = 0.0;
        for (int k = A->row_ptr[i]; k < A->row_ptr[i + 1]; k++) {
            const double *B = A->val + 9 * (size_t)k;
            const double *xj = x + 3 * (size_t)A->col[k];
            y0 += B[0] * xj[0] + B[1] * xj[1] + B[2] * xj[2];
            y1 += B[3] * xj[0] + B[4] * xj[1] + B[5] * xj[2];
            y2 += B[6] * xj[0] + B[7] * xj[1] + B[8] * xj[2];
        }
        y[3 * i] = y0;
        y[3 * i + 1] = y1;
        y[3 * i + 2] = y2;
    }
}

int oc_bsr_check_sym(const bsr *A, const double *val, unsigned char *flag)
{
    int count = 0;
    for (int i = 0; i < A->n; i++) {
        int s = 1;
        for (int k = A->row_ptr[i]; k < A->row_ptr[i + 1] && s; k++) s = mat3_is_sym(val + 9 * (size_t)k);
        flag[i] = (unsigned char)s;
        count += s;
    }
    return count;
}

void oc_bsr_mul_sym(const bsr *A, const double *x, double *y)
{
    if (!A->sym) {
        oc_bsr_mul(A, x, y);
        return;
    }
    for (int i = 0; i < A->n; i++) {
        double acc[3] = {0.0, 0.0, 0.0};
        if (A->sym[i]) row_add_sym(A->val, A->col, A->row_ptr[i], A->row_ptr[i + 1], x, acc);
        else row_add(A->val, A->col, A->row_ptr[i], A->row_ptr[i + 1], x, acc);
        y[3 * i] = acc[0];
        y[3 * i + 1] = acc[1];
        y[3 * i + 2] = acc[2];
    }
}

void oc_bsr_mul_rows(const bsr *A, const double *x, const int *rows, int m, double *y)
{
    for (int a = 0; a < m; a++) {
        int i = rows[a];
        double acc[3] = {0.0, 0.0, 0.0};
        row_add(A->val, A->col, A->row_ptr[i], A->row_ptr[i + 1], x, acc);
        y[3 * (size_t)i] = acc[0];
        y[3 * (size_t)i + 1] = acc[1];
        y[3 * (size_t)i + 2] = acc[2];
    }
}

void oc_bsr_mul_cols(const bsr *A, const double *x, const int *cols, int m, double *y)
{
    if (!cols) {
        oc_bsr_mul(A, x, y);
        return;
    }
    memset(y, 0, 3 * (size_t)A->n * sizeof *y);
    for (int a = 0; a < m; a++) {
        int j = cols[a];
        const double *xj = x + 3 * (size_t)j;
        for (int k = A->row_ptr[j]; k < A->row_ptr[j + 1]; k++) {
            const double *B = A->val + 9 * (size_t)k; /* A_ji = A_ij */
            double *yi = y + 3 * (size_t)A->col[k];
            yi[0] += B[0] * xj[0] + B[1] * xj[1] + B[2] * xj[2];
            yi[1] += B[3] * xj[0] + B[4] * xj[1] + B[5] * xj[2];
            yi[2] += B[6] * xj[0] + B[7] * xj[1] + B[8] * xj[2];
        }
    }
}

void oc_bsr_to_dense(const bsr *A, double *dense)
{
    size_t N = 3 * (size_t)A->n;
    memset(dense, 0, N * N * sizeof *dense);
    for (int i = 0; i < A->n; i++)
        for (int k = A->row_ptr[i]; k < A->row_ptr[i + 1]; k++)
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++)
                    dense[(3 * (size_t)i + a) * N + 3 * (size_t)A->col[k] + b] = A->val[9 * (size_t)k + 3 * a + b];
}
