/* Physics: an elongation limit the pins make infeasible, under Newton.
 *
 * A 9 x 5 cotton cloth (1 m x 0.5 m, no plasticity, zero gravity) whose
 * left and right columns are pinned 5% further apart than its width, laid
 * out stretched and at rest: every horizontal link sits 2% past the
 * elongation limit whatever the step does. The limit's multiplier cannot
 * shorten such a link; it would only grow. Asserted over 20 steps of 1/60 s:
 *   - every step succeeds, with at most 3 rounds of the limit's multipliers;
 *   - the pins hold the plain law (the k_delta stiffening, no multiplier):
 *     the constraint forces on the right column balance the library's own
 *     internal forces there (cloth_internal_forces) to 1e-3 of them, where
 *     a multiplier left in would add its own pull.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define COLS 9
#define ROWS 5
#define STRETCH 1.05

int main(void)
{
    cloth_desc d = cloth_default_desc();
    d.rows = ROWS;
    d.cols = COLS;
    d.width = 1.0;
    d.height = 0.5;
    d.gravity[2] = 0.0;
    d.material.alpha = 0.0;
    d.solver.nonlinear = CLOTH_NEWTON;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) return check_summary();
    int n = cloth_vertex_count(c);
    double *x0 = malloc(3 * (size_t)n * sizeof *x0), *f = malloc(3 * (size_t)n * sizeof *f);
    memcpy(x0, cloth_positions(c), 3 * (size_t)n * sizeof *x0);
    for (int i = 0; i < n; i++) x0[3 * i] = d.origin[0] + STRETCH * (x0[3 * i] - d.origin[0]);
    cloth_set_positions(c, x0);
    for (int r = 0; r < ROWS; r++) {
        cloth_pin(c, r * COLS, x0 + 3 * (r * COLS));
        cloth_pin(c, r * COLS + COLS - 1, x0 + 3 * (r * COLS + COLS - 1));
    }
    int worst_rounds = 0, ok = 1;
    for (int s = 0; s < 20 && ok; s++) {
        cloth_step_stats st;
        ok = CHECK(cloth_step(c, 1.0 / 60, &st) == CLOTH_OK, "step %d: %s", s, cloth_last_error(c));
        if (st.limit_updates > worst_rounds) worst_rounds = st.limit_updates;
    }
    printf("max strain %.4f (limit %.2f), most multiplier rounds in a step %d\n", cloth_max_strain(c), d.material.delta,
           worst_rounds);
    CHECK(worst_rounds <= 3, "%d rounds of the multipliers in a step", worst_rounds);
    cloth_internal_forces(c, f);
    double fc = 0.0, fi = 0.0;
    for (int r = 0; r < ROWS; r++) {
        double g[3];
        int i = r * COLS + COLS - 1;
        cloth_constraint_force(c, i, g);
        fc += g[0];
        fi += f[3 * i];
    }
    printf("right column: constraint force x %.6g N, internal force x %.6g N\n", fc, fi);
    CHECK(fi < 0.0, "the stretched cloth pulls the right column inwards (%g N)", fi);
    CHECK(fabs(fc + fi) <= 1e-3 * fabs(fi), "the pins' force %g N against the plain law's %g N", fc, fi);
    free(x0);
    free(f);
    cloth_destroy(c);
    return check_summary();
}
