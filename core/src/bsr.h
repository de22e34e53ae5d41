/* A symmetric-pattern sparse matrix of 3x3 blocks in block-CSR form (bsr.c).
 * The pattern is built once from an edge list (the cloth's links) when the
 * cloth is created; the step only rewrites values. */
#ifndef ODECLOTH_BSR_H
#define ODECLOTH_BSR_H

typedef struct bsr {
    int n;        /* block rows (= block columns) */
    int nnzb;     /* stored blocks, diagonal included */
    int *row_ptr; /* n + 1 */
    int *col;     /* nnzb, sorted within each row */
    int *diag;    /* n: index of block (i, i) */
    double *val;  /* 9 * nnzb, each block row-major */
    /* 2n row flags (oc_bsr_check_sym), or NULL: sym[i] = 1 when row i's blocks in val are exactly
     * symmetric as last checked (stale once val changes); sym[n + i] the same for a caller's copy
     * of the values on this pattern (ssor.c's filtered matrix). */
    unsigned char *sym;
} bsr;

/* Pattern: every diagonal block plus (i,j) and (j,i) per edge (duplicates share a block); blk[2e]
 * and blk[2e+1] receive the indices of (ei[e], ej[e]) and (ej[e], ei[e]).
 * Returns 0, or -1 on allocation failure or bad indices (A is then empty). */
int oc_bsr_build(bsr *A, int n, int nedges, const int *ei, const int *ej, int *blk);
/* Index of block (i, j), or -1 if the pattern has none. */
int oc_bsr_find(const bsr *A, int i, int j);
void oc_bsr_free(bsr *A);
void oc_bsr_zero(bsr *A);
/* Zero the diagonal blocks only. */
void oc_bsr_zero_diag(bsr *A);
/* 1 when the edges' blocks (blk, as oc_bsr_build fills it) cover every
 * off-diagonal block exactly once: an assembly may then write them, not add. */
int oc_bsr_edges_own_offdiag(const bsr *A, int nedges, const int *blk);
/* y = A x (x and y of length 3n, distinct). */
void oc_bsr_mul(const bsr *A, const double *x, double *y);
/* y = A x for x zero outside block columns cols[0..m) (cols NULL: all), walking only those
 * columns' rows; needs symmetric blocks with A_ij = A_ji, as the cloth's matrix has. */
void oc_bsr_mul_cols(const bsr *A, const double *x, const int *cols, int m, double *y);
/* Flags (n) of the rows of val (A's pattern) whose blocks are all exactly
 * (bitwise) symmetric; returns how many. */
int oc_bsr_check_sym(const bsr *A, const double *val, unsigned char *flag);
/* y = A x as oc_bsr_mul, bitwise the same, faster on the rows flagged in
 * A->sym (oc_bsr_check_sym(A, A->val, A->sym) must be current; A->sym NULL:
 * oc_bsr_mul). */
void oc_bsr_mul_sym(const bsr *A, const double *x, double *y);
/* y_i = (A x)_i for the block rows rows[0..m) only (y's other rows are not
 * touched), each as oc_bsr_mul computes it. */
void oc_bsr_mul_rows(const bsr *A, const double *x, const int *rows, int m, double *y);
/* Dense copy (3n x 3n, row-major) for tests and small problems. */
void oc_bsr_to_dense(const bsr *A, double *dense);

#endif
