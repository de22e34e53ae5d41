#define _POSIX_C_SOURCE 199309L
/* drape_pinned: the core on its own. A 1 m cotton cloth, horizontal, pinned at
 * two adjacent corners, falls and swings under gravity; the program prints
 * the step statistics as it goes and a summary at the end.
 *
 *   drape_pinned [--grid N] [--hz F] [--seconds T] [--alpha A] [--method be|bdf2|symplectic|explicit]
 *
 * A short run is a smoke test (every step must succeed):
 * Test demo_drape_pinned in test/CMakeLists.txt.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "odecloth/cloth.h"
#include "common/cli.h"

static void usage(void)
{
    puts("usage: drape_pinned [--grid N] [--hz F] [--seconds T] [--alpha A]\n"
         "                    [--method be|bdf2|symplectic|explicit] [--precond block|jacobi|mg|ssor]\n"
         "A cotton cloth of N x N nodes (default 21), 1 m square, pinned at two\n"
         "adjacent corners, falls from horizontal for T seconds (default 3) at F\n"
         "steps per second (default 60). Prints energies, CG iterations, strain\n"
         "and plastic links.");
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv)
{
    cloth_desc d = cloth_default_desc();
    double hz = 60.0, seconds = 3.0;
    static const struct option options[] = {
        {"help", no_argument, NULL, 'h'},         {"grid", required_argument, NULL, 'g'},
        {"hz", required_argument, NULL, 'z'},     {"seconds", required_argument, NULL, 's'},
        {"alpha", required_argument, NULL, 'a'},  {"precond", required_argument, NULL, 'p'},
        {"method", required_argument, NULL, 'm'}, {NULL, 0, NULL, 0},
    };
    cli_start();
    for (;;) {
        const char *o = NULL;
        int opt = cli_next(argc, argv, options, &o);
        const char *v = optarg;
        if (opt == CLI_END) break;
        if (opt == 'h') {
            usage();
            return 0;
        } else if (opt == 'g') {
            d.rows = d.cols = atoi(v);
        } else if (opt == 'z') {
            hz = atof(v);
        } else if (opt == 's') {
            seconds = atof(v);
        } else if (opt == 'a') {
            d.material.alpha = atof(v);
        } else if (opt == 'p') {
            if (!strcmp(v, "block")) d.solver.precond = CLOTH_PRECOND_BLOCK_JACOBI;
            else if (!strcmp(v, "jacobi")) d.solver.precond = CLOTH_PRECOND_JACOBI;
            else if (!strcmp(v, "mg")) d.solver.precond = CLOTH_PRECOND_MULTIGRID;
            else if (!strcmp(v, "ssor")) d.solver.precond = CLOTH_PRECOND_SSOR;
            else {
                fprintf(stderr, "drape_pinned: unknown preconditioner '%s'\n", v);
                return 2;
            }
        } else if (opt == 'm') {
            if (!strcmp(v, "be")) d.solver.method = CLOTH_BACKWARD_EULER;
            else if (!strcmp(v, "bdf2")) d.solver.method = CLOTH_BDF2;
            else if (!strcmp(v, "symplectic")) d.solver.method = CLOTH_SYMPLECTIC_EULER;
            else if (!strcmp(v, "explicit")) d.solver.method = CLOTH_EXPLICIT_EULER;
            else {
                fprintf(stderr, "drape_pinned: unknown method '%s'\n", v);
                return 2;
            }
        } else {
            fprintf(stderr, "drape_pinned: unknown or incomplete option '%s' (try --help)\n", o);
            return 2;
        }
    }
    if (!(hz > 0.0) || !(seconds > 0.0)) {
        fprintf(stderr, "drape_pinned: --hz and --seconds must be > 0\n");
        return 2;
    }
    cloth *c;
    cloth_error err;
    if (cloth_create(&d, &c, &err) != CLOTH_OK) {
        fprintf(stderr, "drape_pinned: %s\n", err.message);
        return 1;
    }
    const double *x = cloth_positions(c);
    int pins[2] = {0, d.cols - 1};
    for (int k = 0; k < 2; k++) cloth_pin(c, pins[k], x + 3 * pins[k]);

    double h = 1.0 / hz;
    int steps = (int)(seconds * hz + 0.5);
    long iters = 0;
    double t0 = now();
    printf("%d x %d cotton cloth, alpha %.2f, h = 1/%g s, %s\n", d.rows, d.cols, d.material.alpha, hz,
           d.solver.method == CLOTH_BACKWARD_EULER     ? "backward Euler + MPCG"
           : d.solver.method == CLOTH_BDF2             ? "BDF2 + MPCG"
           : d.solver.method == CLOTH_SYMPLECTIC_EULER ? "symplectic Euler"
                                                       : "explicit Euler");
    printf("%7s %10s %10s %10s %6s %10s %8s %8s\n", "t (s)", "kinetic J", "elastic J", "grav J", "CG it", "residual",
           "strain", "plastic");
    for (int s = 1; s <= steps; s++) {
        cloth_step_stats st;
        if (cloth_step(c, h, &st) != CLOTH_OK) {
            fprintf(stderr, "drape_pinned: step %d failed: %s\n", s, cloth_last_error(c));
            cloth_destroy(c);
            return 1;
        }
        iters += st.iterations;
        if (s % (int)(hz / 4 > 1 ? hz / 4 : 1) == 0 || s == steps)
            printf("%7.3f %10.3e %10.3e %10.4f %6d %10.2e %8.4f %8d\n", s * h, st.energy.kinetic, st.energy.elastic,
                   st.energy.gravitational, st.iterations, st.residual, st.max_strain, st.plastic_links);
    }
    double wall = now() - t0;
    double f[3], fsum[3] = {0, 0, 0};
    for (int k = 0; k < 2; k++) {
        cloth_constraint_force(c, pins[k], f);
        for (int a = 0; a < 3; a++) fsum[a] += f[a];
    }
    double mass = 0.0;
    for (int i = 0; i < cloth_vertex_count(c); i++) mass += cloth_masses(c)[i];
    printf("\n%d steps in %.3f s wall (%.0f steps/s), %.1f CG iterations per step\n", steps, wall, steps / wall,
           (double)iters / steps);
    printf("pin forces sum (%.4f, %.4f, %.4f) N; cloth weight %.4f N\n", fsum[0], fsum[1], fsum[2], mass * 9.81);
    double zmin = x[2];
    for (int i = 0; i < cloth_vertex_count(c); i++)
        if (x[3 * i + 2] < zmin) zmin = x[3 * i + 2];
    printf("lowest point z = %.4f m (pins at z = %.4f m), max strain %.4f (limit %.2f)\n", zmin, x[2],
           cloth_max_strain(c), d.material.delta);
    cloth_destroy(c);
    return 0;
}
