/* Unit: the elongation limit's multipliers through the state setters.
 *
 * A 9 x 9 cotton cloth under Newton, its top row pinned, hangs under 81 g
 * until links sit at the limit, held by multipliers. Asserted: some
 * multiplier is positive; cloth_set_velocities (the same velocities) keeps
 * every one bit for bit, as does cloth_set_vertex with a velocity alone;
 * cloth_set_positions (the same positions) drops them all.
 */
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"
#include "internal.h"

#define N 9

/* the largest multiplier, and whether all equal those in ref */
static double largest(const cloth *c, const double *ref, int *same)
{
    double m = 0.0;
    *same = 1;
    for (int e = 0; e < c->n_seq; e++) {
        if (c->st.lim_shift[e] > m) m = c->st.lim_shift[e];
        if (ref && c->st.lim_shift[e] != ref[e]) *same = 0;
    }
    return m;
}

int main(void)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = N;
    d.gravity[2] = -81.0 * 9.81;
    d.solver.nonlinear = CLOTH_NEWTON;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) return check_summary();
    const double *x = cloth_positions(c);
    for (int k = 0; k < N; k++) cloth_pin(c, k, x + 3 * k);
    int ok = 1;
    for (int s = 0; s < 30 && ok; s++) ok = CHECK(cloth_step(c, 1.0 / 60, NULL) == CLOTH_OK, "step %d", s);
    int n = cloth_vertex_count(c), same;
    double *ref = malloc((size_t)c->n_seq * sizeof *ref), *v = malloc(3 * (size_t)n * sizeof *v);
    memcpy(ref, c->st.lim_shift, (size_t)c->n_seq * sizeof *ref);
    double top = largest(c, NULL, &same);
    CHECK(top > 0.0, "no link held by a multiplier (largest %g)", top);
    memcpy(v, cloth_velocities(c), 3 * (size_t)n * sizeof *v);
    cloth_set_velocities(c, v);
    largest(c, ref, &same);
    CHECK(same, "cloth_set_velocities changed the multipliers");
    cloth_set_vertex(c, n - 1, NULL, v + 3 * (n - 1));
    largest(c, ref, &same);
    CHECK(same, "cloth_set_vertex with a velocity alone changed the multipliers");
    double *xs = malloc(3 * (size_t)n * sizeof *xs);
    memcpy(xs, cloth_positions(c), 3 * (size_t)n * sizeof *xs);
    cloth_set_positions(c, xs);
    top = largest(c, NULL, &same);
    CHECK(top == 0.0, "cloth_set_positions kept a multiplier of %g", top);
    free(ref);
    free(v);
    free(xs);
    cloth_destroy(c);
    return check_summary();
}
