/* Unit: the step's matrix assembly writes each link's off-diagonal blocks
 * instead of zeroing the matrix and adding them (core/src/assembly.h).
 *
 * 1. oc_bsr_edges_own_offdiag: a grid's links (sequential and interlaced) own
 *    every off-diagonal block; a duplicated edge or an extra block in the
 *    pattern does not.
 * 2. A cloth on the written path steps bitwise like its twin forced onto the
 *    zero-and-add path, for the linearised and the Newton step, with pins, a
 *    plane, external forces and air drag (which adds into the same blocks).
 */
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "bsr.h"
#include "internal.h"
#include "check.h"

static void ownership(void)
{
    /* a path 0-1-2 and the chord 0-2 */
    int ei[4] = {0, 1, 0, 0}, ej[4] = {1, 2, 2, 1}, blk[8];
    bsr A;
    CHECK(oc_bsr_build(&A, 3, 3, ei, ej, blk) == 0, "oc_bsr_build");
    CHECK(oc_bsr_edges_own_offdiag(&A, 3, blk) == 1, "distinct edges own their blocks");
    oc_bsr_free(&A);
    CHECK(oc_bsr_build(&A, 3, 4, ei, ej, blk) == 0, "oc_bsr_build with a duplicate");
    CHECK(oc_bsr_edges_own_offdiag(&A, 4, blk) == 0, "a duplicated edge shares its block");
    /* the pattern holds the chord, the edge list handed over does not */
    CHECK(oc_bsr_edges_own_offdiag(&A, 2, blk) == 0, "a block no edge writes");
    oc_bsr_free(&A);
}

static cloth *make(cloth_nonlinear nl, int own, rng *g)
{
    cloth_desc d = cloth_default_desc();
    d.rows = 9;
    d.cols = 8;
    d.solver.nonlinear = nl;
    cloth *c = NULL;
    CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK && c, "cloth_create");
    CHECK(c->links_own_blocks == 1, "a grid's links own its off-diagonal blocks");
    c->links_own_blocks = own;
    int n = cloth_vertex_count(c);
    double *x = malloc(3 * (size_t)n * sizeof *x), *f = malloc(3 * (size_t)n * sizeof *f);
    memcpy(x, cloth_positions(c), 3 * (size_t)n * sizeof *x);
    for (int k = 0; k < 3 * n; k++) {
        x[k] += rng_range(g, -0.01, 0.01);
        f[k] = rng_range(g, -0.02, 0.02);
    }
    cloth_set_positions(c, x);
    cloth_set_external_forces(c, f);
    cloth_pin(c, 0, x);
    cloth_pin(c, d.cols - 1, x + 3 * (d.cols - 1));
    cloth_constraint k = {.vertex = n - 1, .ndof = 1, .axis = {0.0, 0.0, 1.0}};
    memcpy(k.target, x + 3 * (n - 1), sizeof k.target);
    cloth_set_constraint(c, &k);
    cloth_air air = {{1.0, 0.5, 0.0}, 0.8, 0.1};
    cloth_set_air(c, &air);
    free(x);
    free(f);
    return c;
}

static void twins(cloth_nonlinear nl)
{
    rng g1 = rng_seed(0x61737331u), g2 = rng_seed(0x61737331u);
    cloth *a = make(nl, 1, &g1), *b = make(nl, 0, &g2);
    size_t n3 = 3 * (size_t)cloth_vertex_count(a);
    int same = 1, ok = 1;
    for (int s = 0; s < 30; s++) {
        cloth_step_stats sa, sb;
        ok = ok && cloth_step(a, 1.0 / 60.0, &sa) == CLOTH_OK && cloth_step(b, 1.0 / 60.0, &sb) == CLOTH_OK;
        same = same && !memcmp(cloth_positions(a), cloth_positions(b), n3 * sizeof(double)) &&
               !memcmp(cloth_velocities(a), cloth_velocities(b), n3 * sizeof(double));
    }
    CHECK(ok, "%s: every step succeeds", nl == CLOTH_NEWTON ? "newton" : "linearized");
    CHECK(same, "%s: written blocks step bitwise as zeroed-and-added ones",
          nl == CLOTH_NEWTON ? "newton" : "linearized");
    cloth_destroy(a);
    cloth_destroy(b);
}

int main(void)
{
    ownership();
    twins(CLOTH_LINEARIZED);
    twins(CLOTH_NEWTON);
    return check_summary();
}
