/* Unit: no hidden global state. Four cloths (different sizes, methods and
 * preconditioners, pins, plastic links, retries on) are stepped 100 times
 * each, first one after the other, then all at once in four threads
 * started together at a barrier, each thread's cloth created, stepped and
 * destroyed inside it. Asserted: every cloth's final positions and
 * velocities are bitwise those of its sequential run (a static or global
 * buffer, a shared workspace or a non-reentrant call in the core would show
 * as a difference or as a crash under the sanitizers). Repeated 3 times. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

#define NJOB 4
#define STEPS 100

typedef struct job {
    int rows, cols;
    cloth_method method;
    cloth_precond precond;
    double *x, *v; /* out: final state */
    int n, failed;
    pthread_barrier_t *start;
} job;

static void *run(void *arg)
{
    job *j = arg;
    cloth_desc d = cloth_default_desc();
    d.rows = j->rows;
    d.cols = j->cols;
    d.solver.method = j->method;
    d.solver.precond = j->precond;
    d.solver.max_substep_halvings = 2;
    d.material.alpha = 0.95;
    cloth *c = NULL;
    if (j->start) pthread_barrier_wait(j->start);
    if (cloth_create(&d, &c, NULL) != CLOTH_OK) {
        j->failed = -1;
        return NULL;
    }
    int n = cloth_vertex_count(c);
    const double *x = cloth_positions(c);
    double p[3];
    memcpy(p, x + 3 * (d.cols - 1), sizeof p);
    cloth_pin(c, 0, x);
    for (int s = 0; s < STEPS; s++) {
        p[2] += 0.002; /* lift one corner */
        cloth_pin(c, d.cols - 1, p);
        if (cloth_step(c, 1.0 / 90, NULL) != CLOTH_OK) j->failed++;
    }
    j->n = n;
    j->x = malloc(3 * (size_t)n * sizeof *j->x);
    j->v = malloc(3 * (size_t)n * sizeof *j->v);
    memcpy(j->x, cloth_positions(c), 3 * (size_t)n * sizeof *j->x);
    memcpy(j->v, cloth_velocities(c), 3 * (size_t)n * sizeof *j->v);
    cloth_destroy(c);
    return NULL;
}

static void setup(job *jobs)
{
    const job proto[NJOB] = {
        {11, 9, CLOTH_BACKWARD_EULER, CLOTH_PRECOND_BLOCK_JACOBI, NULL, NULL, 0, 0, NULL},
        {9, 13, CLOTH_BDF2, CLOTH_PRECOND_MULTIGRID, NULL, NULL, 0, 0, NULL},
        {15, 7, CLOTH_BACKWARD_EULER, CLOTH_PRECOND_SSOR, NULL, NULL, 0, 0, NULL},
        {9, 9, CLOTH_BDF2, CLOTH_PRECOND_JACOBI, NULL, NULL, 0, 0, NULL},
    };
    memcpy(jobs, proto, sizeof proto);
}

int main(void)
{
    job seq[NJOB];
    setup(seq);
    for (int k = 0; k < NJOB; k++) {
        run(&seq[k]);
        CHECK(seq[k].failed == 0, "sequential job %d: %d failed steps", k, seq[k].failed);
    }
    for (int rep = 0; rep < 3; rep++) {
        job par[NJOB];
        pthread_t th[NJOB];
        pthread_barrier_t bar;
        setup(par);
        pthread_barrier_init(&bar, NULL, NJOB);
        for (int k = 0; k < NJOB; k++) {
            par[k].start = &bar;
            CHECK(pthread_create(&th[k], NULL, run, &par[k]) == 0, "pthread_create");
        }
        for (int k = 0; k < NJOB; k++) pthread_join(th[k], NULL);
        pthread_barrier_destroy(&bar);
        for (int k = 0; k < NJOB; k++) {
            size_t n3 = 3 * (size_t)seq[k].n;
            CHECK(par[k].failed == 0 && par[k].n == seq[k].n, "threaded job %d: %d failed steps", k, par[k].failed);
            if (par[k].x && seq[k].x)
                CHECK(memcmp(par[k].x, seq[k].x, n3 * sizeof(double)) == 0 &&
                          memcmp(par[k].v, seq[k].v, n3 * sizeof(double)) == 0,
                      "round %d, job %d: stepped in a thread beside others, the cloth differs from its sequential run",
                      rep, k);
            free(par[k].x);
            free(par[k].v);
        }
    }
    printf("%d cloths x %d steps, in %d threads at once (3 rounds) and one after the other: %s\n", NJOB, STEPS, NJOB,
           check_failed_ == 0 ? "bitwise equal" : "DIFFERENT");
    for (int k = 0; k < NJOB; k++) {
        free(seq[k].x);
        free(seq[k].v);
    }
    return check_summary();
}
