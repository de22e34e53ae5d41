/* Unit: the default preconditioner, CLOTH_PRECOND_AUTO.
 *
 * A 21x21 cloth hung by two corners, 20 steps: under Newton the default
 * takes bitwise the steps of CLOTH_PRECOND_MULTIGRID chosen by name (the
 * same positions, CG and Newton iterations), and the linearised step those
 * of CLOTH_PRECOND_BLOCK_JACOBI. A cloth made linearised and switched to
 * Newton by cloth_set_solver gets the multigrid too. A 3 x 5000 grid, which
 * does not coarsen (too many nodes for its dense level) and is refused the
 * multigrid by name, is made with the default and under Newton takes the
 * steps of block Jacobi (3 steps).
 */
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define STEPS 20

typedef struct run {
    int ok, cg, newton, n;
    double x[3 * 21 * 21];
} run;

static cloth *make(int rows, int cols, cloth_nonlinear how, cloth_precond pc)
{
    cloth_desc d = cloth_default_desc();
    d.rows = rows;
    d.cols = cols;
    d.width = 0.05 * (cols - 1);
    d.height = 0.05 * (rows - 1);
    d.solver.nonlinear = how;
    d.solver.precond = pc;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create %dx%d precond %d: %s", rows, cols, (int)pc, err.message))
        return NULL;
    cloth_pin(c, 0, cloth_positions(c));
    cloth_pin(c, cols - 1, cloth_positions(c) + 3 * (cols - 1));
    return c;
}

/* k steps of c (destroyed), the positions kept when they fit */
static run steps(cloth *c, int k)
{
    run r;
    memset(&r, 0, sizeof r);
    if (!c) return r;
    r.ok = 1;
    for (int s = 0; s < k && r.ok; s++) {
        cloth_step_stats st;
        r.ok = cloth_step(c, 1.0 / 60, &st) == CLOTH_OK;
        r.cg += st.iterations;
        r.newton += st.newton;
    }
    r.n = cloth_vertex_count(c);
    if (3 * r.n <= (int)(sizeof r.x / sizeof r.x[0])) memcpy(r.x, cloth_positions(c), 3 * (size_t)r.n * sizeof *r.x);
    CHECK(r.ok, "a step failed: %s", cloth_last_error(c));
    cloth_destroy(c);
    return r;
}

static int same(const run *a, const run *b)
{
    return a->ok && b->ok && a->cg == b->cg && a->newton == b->newton && a->n == b->n &&
           memcmp(a->x, b->x, sizeof a->x) == 0;
}

static void square_grid(void)
{
    CHECK(cloth_default_desc().solver.precond == CLOTH_PRECOND_AUTO, "the default is not CLOTH_PRECOND_AUTO");
    run a = steps(make(21, 21, CLOTH_NEWTON, CLOTH_PRECOND_AUTO), STEPS);
    run m = steps(make(21, 21, CLOTH_NEWTON, CLOTH_PRECOND_MULTIGRID), STEPS);
    run j = steps(make(21, 21, CLOTH_NEWTON, CLOTH_PRECOND_BLOCK_JACOBI), STEPS);
    printf("21x21, Newton: auto %d CG, multigrid %d, block Jacobi %d\n", a.cg, m.cg, j.cg);
    CHECK(same(&a, &m), "Newton: auto is not multigrid (CG %d against %d)", a.cg, m.cg);
    CHECK(a.cg < j.cg, "Newton: multigrid took no fewer CG iterations than block Jacobi (%d, %d)", a.cg, j.cg);
    run al = steps(make(21, 21, CLOTH_LINEARIZED, CLOTH_PRECOND_AUTO), STEPS);
    run jl = steps(make(21, 21, CLOTH_LINEARIZED, CLOTH_PRECOND_BLOCK_JACOBI), STEPS);
    CHECK(same(&al, &jl), "linearised: auto is not block Jacobi (CG %d against %d)", al.cg, jl.cg);
    cloth *c = make(21, 21, CLOTH_LINEARIZED, CLOTH_PRECOND_AUTO);
    if (c) {
        cloth_solver s = cloth_get_desc(c).solver;
        s.nonlinear = CLOTH_NEWTON;
        CHECK(cloth_set_solver(c, &s) == CLOTH_OK, "switched to Newton: %s", cloth_last_error(c));
        run sw = steps(c, STEPS);
        CHECK(same(&sw, &m), "switched to Newton: auto is not multigrid (CG %d against %d)", sw.cg, m.cg);
    }
}

static void thin_grid(void)
{
    cloth_desc d = cloth_default_desc();
    d.rows = 3;
    d.cols = 5000;
    d.solver.precond = CLOTH_PRECOND_MULTIGRID;
    d.solver.nonlinear = CLOTH_NEWTON;
    cloth *c = NULL;
    cloth_error err;
    CHECK(cloth_create(&d, &c, &err) == CLOTH_EINVAL && c == NULL, "3 x 5000 with multigrid by name made");
    run a = steps(make(3, 5000, CLOTH_NEWTON, CLOTH_PRECOND_AUTO), 3);
    run j = steps(make(3, 5000, CLOTH_NEWTON, CLOTH_PRECOND_BLOCK_JACOBI), 3);
    printf("3 x 5000, Newton: auto %d CG, block Jacobi %d\n", a.cg, j.cg);
    CHECK(a.ok && j.ok && a.cg == j.cg && a.newton == j.newton, "3 x 5000, Newton: auto took %d CG against %d", a.cg,
          j.cg);
}

int main(void)
{
    square_grid();
    thin_grid();
    return check_summary();
}
