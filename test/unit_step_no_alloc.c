/* Unit: a step allocates nothing. Every work array is sized when the cloth
 * (or its self-contact pass) is created, so cloth_step never calls malloc,
 * calloc or realloc: a game stepping at 60 Hz gets no allocator latency and no
 * failure from memory mid-run. The test counts the allocator's calls made
 * inside cloth_step (it defines malloc and its kin over glibc's, which the
 * static core library then calls) in scenes that take every path of the step:
 *   1. Newton (the default: multigrid), backward Euler and BDF2: a 41x41
 *      cloth falling onto contact planes under its lower half, two corners
 *      pinned, air drag, tension plasticity and plasticity in time on,
 *      landing and sliding;
 *   2. the linearised step with block Jacobi and with SSOR;
 *   3. a rigid body solved with the cloth, holding two corners;
 *   4. Newton with self-contact's barrier bound (cloth_self_collision_apply
 *      after each step): a cloth folded over itself, 30 steps, then the same
 *      30 steps again from the saved start: its pair lists and broadphase grow
 *      to what the scene needs (geometrically) in the first run and hold it.
 * Asserted: no allocation in any step of scenes 1-3, from the first, nor in
 * scene 4's second run after its first two steps (the restored start may ask
 * its lists for a little more than the first run did). Under
 * AddressSanitizer the allocator is its own: not run. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "odecloth/selfcollision.h"
#include "check.h"
#include "sanitizer.h"

#define WARMUP 2

static long allocations; /* calls while counting */
static int counting;

#if !defined(ODECLOTH_ASAN) && defined(__GLIBC__)
extern void *__libc_malloc(size_t n);
extern void *__libc_calloc(size_t m, size_t n);
extern void *__libc_realloc(void *p, size_t n);

void *malloc(size_t n)
{
    allocations += counting;
    return __libc_malloc(n);
}

void *calloc(size_t m, size_t n)
{
    allocations += counting;
    return __libc_calloc(m, n);
}

void *realloc(void *p, size_t n)
{
    allocations += counting;
    return __libc_realloc(p, n);
}
#define COUNTS 1
#else
#define COUNTS 0
#endif

/* Steps c `steps` times at h (with self-contact's pass s after each, if any): the allocations
 * of the steps after the warm-up, asserted zero; the warm-up's are printed */
static void count_steps(const char *scene, cloth *c, cloth_self_collision *s, int steps, double h, int warmup)
{
    long warm = 0, after = 0;
    int failed = 0;
    for (int k = 0; k < steps; k++) {
        allocations = 0;
        counting = 1;
        cloth_status st = cloth_step(c, h, NULL);
        if (s && st == CLOTH_OK) st = cloth_self_collision_apply(s, c, NULL);
        counting = 0;
        failed += st != CLOTH_OK;
        if (k < warmup) warm += allocations;
        else after += allocations;
    }
    printf("%s: %d steps, %ld allocations in the first %d, %ld after\n", scene, steps, warm, warmup, after);
    CHECK(failed == 0, "%s: %d steps failed (%s)", scene, failed, cloth_last_error(c));
    CHECK(after == 0, "%s: %ld allocations in steps after the first %d", scene, after, warmup);
}

static cloth *make(int n, cloth_method method, cloth_nonlinear nl, cloth_precond pc)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = n;
    d.solver.method = method;
    d.solver.nonlinear = nl;
    d.solver.precond = pc;
    d.material.alpha = 0.8;
    d.material.tension_yield = 0.5 * d.material.delta;
    d.material.tension_set = 0.5;
    d.material.tau_set = 0.05;
    d.material.tau_recover = 0.5;
    cloth *c = NULL;
    cloth_error err;
    if (cloth_create(&d, &c, &err) != CLOTH_OK) {
        CHECK(0, "cloth_create: %s", err.message);
        return NULL;
    }
    const double *x = cloth_positions(c);
    cloth_pin(c, 0, x);
    cloth_pin(c, n - 1, x + 3 * (n - 1));
    cloth_air air = {{1.0, 0.0, 0.0}, 0.5, 0.1};
    cloth_set_air(c, &air);
    return c;
}

/* Contact planes 2 cm under the lower half's vertices, set before each step as a plugin does */
static void contacts(cloth *c)
{
    const double up[3] = {0.0, 0.0, 1.0}, *x = cloth_positions(c);
    int n = cloth_vertex_count(c);
    for (int i = n / 2; i < n; i++) {
        cloth_constraint k;
        if (cloth_get_constraint(c, i, &k) == CLOTH_OK && k.ndof == 3) continue;
        double p[3] = {x[3 * i], x[3 * i + 1], 0.98};
        cloth_set_contact(c, i, up, p);
    }
}

static void scene_methods(void)
{
    const cloth_method m[2] = {CLOTH_BACKWARD_EULER, CLOTH_BDF2};
    const cloth_nonlinear nl[3] = {CLOTH_NEWTON, CLOTH_LINEARIZED, CLOTH_LINEARIZED};
    const cloth_precond pc[3] = {CLOTH_PRECOND_AUTO, CLOTH_PRECOND_BLOCK_JACOBI, CLOTH_PRECOND_SSOR};
    const char *names[3] = {"Newton", "linearised, block Jacobi", "linearised, SSOR"};
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 2; b++) {
            cloth *c = make(41, m[b], nl[a], pc[a]);
            if (!c) continue;
            char scene[96];
            snprintf(scene, sizeof scene, "%s, %s", names[a], b ? "BDF2" : "backward Euler");
            long warm = 0, after = 0;
            for (int k = 0; k < 40; k++) { /* the planes reset before each step, as a plugin's are */
                contacts(c);
                allocations = 0;
                counting = 1;
                CHECK(cloth_step(c, 1.0 / 60, NULL) == CLOTH_OK, "%s, step %d: %s", scene, k, cloth_last_error(c));
                counting = 0;
                if (k < WARMUP) warm += allocations;
                else after += allocations;
            }
            printf("%s: 40 steps, %ld allocations in the first %d, %ld after\n", scene, warm, WARMUP, after);
            CHECK(warm + after == 0, "%s: %ld allocations in its steps", scene, warm + after);
            cloth_destroy(c);
        }
}

static void scene_body(void)
{
    cloth *c = make(21, CLOTH_BACKWARD_EULER, CLOTH_NEWTON, CLOTH_PRECOND_AUTO);
    if (!c) return;
    cloth_body b = {.mass = 0.1, .inertia = {1e-3, 0, 0, 0, 1e-3, 0, 0, 0, 1e-3}, .com = {0.5, 0.0, 1.0}};
    CHECK(cloth_set_bodies(c, &b, 1) == CLOTH_OK, "cloth_set_bodies: %s", cloth_last_error(c));
    CHECK(cloth_hold_by_body(c, 0, 0) == CLOTH_OK && cloth_hold_by_body(c, 20, 0) == CLOTH_OK, "cloth_hold_by_body: %s",
          cloth_last_error(c));
    count_steps("a body solved with the cloth", c, NULL, 30, 1.0 / 60, 0);
    cloth_destroy(c);
}

/* A 21x21 cloth hung by one edge over a bar falls onto itself: self-contact's barrier acts */
static void scene_self_contact(void)
{
    cloth *c = make(21, CLOTH_BACKWARD_EULER, CLOTH_NEWTON, CLOTH_PRECOND_AUTO);
    if (!c) return;
    cloth_release_all(c);
    int n = cloth_rows(c);
    double *x = malloc(3 * sizeof(double) * (size_t)n * (size_t)n);
    if (!x) {
        cloth_destroy(c);
        return;
    }
    memcpy(x, cloth_positions(c), 3 * sizeof(double) * (size_t)n * (size_t)n);
    for (int r = 0; r < n; r++) /* the far half folded up over the near one, 2 cm above it */
        for (int q = n / 2 + 1; q < n; q++) {
            double *p = x + 3 * (r * n + q), *m = x + 3 * (r * n + (n - 1 - q));
            p[0] = m[0];
            p[2] = m[2] + 0.02 * (q - n / 2) / (n / 2);
        }
    cloth_set_positions(c, x);
    free(x);
    cloth_self_collision *s = NULL;
    cloth_error err;
    CHECK(cloth_self_collision_create(c, 0.005, &s, &err) == CLOTH_OK, "self-collision: %s", err.message);
    for (int r = 0; r < n; r++) { /* the fold's bottom layer rests on planes */
        const double up[3] = {0.0, 0.0, 1.0};
        double p[3] = {0.0, 0.0, cloth_positions(c)[2]};
        for (int q = 0; q <= n / 2; q++) cloth_set_contact(c, r * n + q, up, p);
    }
    cloth_state *start = cloth_state_create(c);
    if (s && start && cloth_save(c, start) == CLOTH_OK) {
        /* its pair lists grow to what the fold needs; run again, they hold it */
        long grown = 0;
        for (int k = 0; k < 30; k++) {
            allocations = 0;
            counting = 1;
            if (cloth_step(c, 1.0 / 60, NULL) == CLOTH_OK) cloth_self_collision_apply(s, c, NULL);
            counting = 0;
            grown += allocations;
        }
        printf("self-contact's barrier, first run: %ld allocations (its lists growing)\n", grown);
        CHECK(cloth_restore(c, start) == CLOTH_OK, "cloth_restore");
        count_steps("self-contact's barrier, the same steps again", c, s, 30, 1.0 / 60, WARMUP);
    }
    cloth_state_destroy(start);
    cloth_self_collision_destroy(s);
    cloth_destroy(c);
}

int main(void)
{
    if (!COUNTS) {
        printf("the allocator is not glibc's (or AddressSanitizer's): not counted\n");
        return 0;
    }
    scene_methods();
    scene_body();
    scene_self_contact();
    return check_summary();
}
