/* Physics: the accuracy-driven controller (cloth_adaptive_*, core/src/adaptive.c)
 * on three scenes unlike the swing and sphere it is tuned on
 * (examples/bench_workprecision.c, k_t 200 N/m). Elastic cotton, 1 m square,
 * 0.2 kg, 15x15, damping 2.5x the preset's as on the chart (x sqrt(10) at k_t
 * 20000 N/m: the same damping ratio):
 *   flag:  hanging, pinned along its top edge, settled, in a wind across it
 *          as per-vertex forces, 2 + 4 sin(2 pi (u / 0.5 m - 2 Hz t)) m/s^2,
 *          a wave travelling along it (held over each 1/60 s frame); 0.75 s;
 *   box:   horizontal, dropped 0.1 m onto a box 2 x 0.3 x 0.5 m (it folds
 *          over two edges); core only: before each step a vertex whose
 *          predicted position x + h v is inside gets a frictionless plane
 *          constraint on the nearest face; 0.5 s;
 *   stiff: k_t 20000 N/m, hanging from its two top corners, settled, then
 *          plucked across (up to 1 m/s at the bottom, a half sine along the
 *          width); 0.5 s.
 * The lengths and the damping keep the scenes predictable: with the preset's
 * damping, fixed steps of 1/30720 and 1/61440 s stop converging after
 * 1/6-1/2 s, the stiff scene before 1/6 s (with k_c = k_t it converges: links
 * ringing about their rest length, where the stiffness jumps k_c -> k_t).
 *
 * Reference: symplectic Euler at 1/61440 s; its RMS difference to 1/30720 s
 * must be under a tenth of the smallest request. Errors: RMS over vertices
 * and samples (every 1/12 s). At tolerances 1e-2, 3e-3, 1e-3 m/s: error /
 * requested <= 1.5 (against the RMS of tolerance * t over the samples), no
 * sample over 2 tolerance * t; at 3e-3 and 1e-3 the controller's work
 * within 2x of the cheapest fixed-step run, of the method it used in most
 * frames, at or under its error (step rates sqrt(2) apart). Work is counted
 * in cloth_step calls, the shadow's included, not timed: CPU time is printed
 * for reading only (timings belong in the benchmarks).
 * The flag again with backward Euler solved by Newton's method: the controller
 * must bound Newton's residual as it bounds the CG's, or its error misses.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "odecloth/cloth.h"
#include "check.h"

#define FPS 60
#define SAMPLE_FRAMES 5 /* a sample every 1/12 s */
#define MAXSAMP 12
#define GRID 15
#define NV (GRID * GRID)
#define PI 3.14159265358979323846

enum { FLAG, BOX, STIFF, NSCENES };
static const char *scene_name[NSCENES] = {"flag", "box", "stiff"};
static const int scene_frames[NSCENES] = {45, 30, 30};
static const double box_c[3] = {0.0, 0.05, 0.25}, box_e[3] = {1.0, 0.15, 0.25}; /* centre, half extents */
static double *start_x[NSCENES]; /* the hanging scenes' settled starts (3n) */

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int nsamp(int scene) { return scene_frames[scene] / SAMPLE_FRAMES; }
static double sample_time(int k) { return (k + 1) * (double)SAMPLE_FRAMES / FPS; }

static cloth_nonlinear nonlinear = CLOTH_LINEARIZED; /* how backward Euler's steps are solved */

static cloth *new_cloth(int scene, cloth_method m, double cg_tol, double damping)
{
    cloth_desc d = cloth_default_desc();
    d.solver.nonlinear = nonlinear;
    d.rows = d.cols = GRID;
    d.material = cloth_material_preset(CLOTH_ELASTIC);
    if (scene == STIFF) d.material.k_t = 20000.0;
    d.material.c_t *= damping;
    d.material.c_b *= damping;
    d.solver.method = m;
    d.solver.cg_tolerance = cg_tol;
    d.solver.cg_max_iterations = 20000;
    d.solver.max_substep_halvings = 0; /* the method as it is: a failed step is a failure */
    if (scene == BOX) {
        d.origin[2] = box_c[2] + box_e[2] + 0.1;
    } else { /* hanging: rows go down from z = 1 */
        d.axis_v[1] = 0.0;
        d.axis_v[2] = -1.0;
    }
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "cloth_create: %s", err.message)) exit(1);
    const double *x = cloth_positions(c);
    for (int i = 0; i < GRID; i++) /* the top row: all of it (flag), its corners (stiff) */
        if (scene == FLAG || (scene == STIFF && (i == 0 || i == GRID - 1))) cloth_pin(c, i, x + 3 * i);
    return c;
}

/* A hanging scene's start: 3 s of backward Euler at 100x the damping. */
static void settle(int scene)
{
    cloth *c = new_cloth(scene, CLOTH_BACKWARD_EULER, 1e-10, 100.0);
    for (int s = 0; s < 360; s++)
        if (!CHECK(cloth_step(c, 1.0 / 120, NULL) == CLOTH_OK, "settling: %s", cloth_last_error(c))) exit(1);
    start_x[scene] = malloc(3 * NV * sizeof(double));
    memcpy(start_x[scene], cloth_positions(c), 3 * NV * sizeof(double));
    cloth_destroy(c);
}

static cloth *make_cloth(int scene, cloth_method m, double cg_tol)
{
    cloth *c = new_cloth(scene, m, cg_tol, scene == STIFF ? 2.5 * sqrt(10.0) : 2.5);
    if (scene == BOX) return c;
    double v[3 * NV] = {0};
    if (scene == STIFF)
        for (int i = 0; i < NV; i++) v[3 * i + 1] = (i / GRID) / (GRID - 1.0) * sin(PI * (i % GRID) / (GRID - 1.0));
    if (!CHECK(cloth_set_positions(c, start_x[scene]) == CLOTH_OK && cloth_set_velocities(c, v) == CLOTH_OK,
               "start: %s", cloth_last_error(c)))
        exit(1);
    return c;
}

/* The flag's wind over frame f, held at its value mid-frame. */
static void set_wind(cloth *c, int f)
{
    const double t = (f + 0.5) / FPS, *m = cloth_masses(c);
    double force[3 * NV] = {0};
    for (int i = 0; i < NV; i++) {
        double u = (i % GRID) / (GRID - 1.0);
        force[3 * i + 1] = m[i] * (2.0 + 4.0 * sin(2.0 * PI * (u / 0.5 - 2.0 * t)));
    }
    cloth_set_external_forces(c, force);
}

/* The box: a plane constraint on the nearest face for each vertex whose
 * predicted end position is inside; the others released. Also the
 * controller's callback. */
static int box_contacts(cloth *c, double h, void *user)
{
    (void)user;
    const double *x = cloth_positions(c), *v = cloth_velocities(c);
    for (int i = 0; i < NV; i++) {
        double p[3], depth = HUGE_VAL;
        int face = -1;
        for (int a = 0; a < 3 && face > -2; a++) {
            p[a] = x[3 * i + a] + h * v[3 * i + a] - box_c[a];
            double d = box_e[a] - fabs(p[a]);
            if (d <= 0.0) face = -2;
            else if (d < depth) depth = d, face = a;
        }
        if (face < 0) {
            cloth_release(c, i);
            continue;
        }
        cloth_constraint k;
        memset(&k, 0, sizeof k);
        k.vertex = i;
        k.ndof = 1;
        k.axis[face] = p[face] > 0.0 ? 1.0 : -1.0;
        for (int a = 0; a < 3; a++) k.target[a] = box_c[a] + (a == face ? box_e[a] * k.axis[a] : p[a]);
        cloth_set_constraint(c, &k);
    }
    return 0;
}

typedef struct result {
    int failed;
    double cpu;                 /* s, CPU time of the run */
    double x[MAXSAMP * 3 * NV]; /* positions at the samples */
    double sym;                 /* controller: share of frames stepped by symplectic Euler */
    double substeps;            /* controller: mean substeps per frame */
    long steps;                 /* cloth_step calls (the controller's: every attempt and the shadow's) */
    double estimate[MAXSAMP];   /* controller: its global estimate at the samples, m */
} result;

/* A run of the scene into r: fixed steps of 1 / hz (hz a multiple of FPS)
 * by method m (backward Euler at CG tolerance 1e-3, the default), or (tol > 0)
 * the controller at tol m/s. */
static void run(int scene, cloth_method m, double hz, double tol, result *r)
{
    memset(r, 0, sizeof *r);
    cloth *c = make_cloth(scene, m, m == CLOTH_BACKWARD_EULER ? 1e-3 : 1e-10);
    cloth_adaptive *a = NULL;
    if (tol > 0.0) {
        cloth_adaptive_desc ad = cloth_adaptive_default_desc();
        ad.tolerance = tol;
        if (scene == BOX) ad.before_substep = box_contacts;
        cloth_error err;
        if (!CHECK(cloth_adaptive_create(c, &ad, &a, &err) == CLOTH_OK, "adaptive: %s", err.message)) exit(1);
    }
    const long per_frame = a ? 0 : lround(hz / FPS);
    double t0 = cpu_now();
    for (int f = 0; f < scene_frames[scene] && !r->failed; f++) {
        if (scene == FLAG) set_wind(c, f);
        if (a) {
            cloth_adaptive_stats st;
            r->failed = cloth_adaptive_frame(a, c, 1.0 / FPS, &st) != CLOTH_OK;
            r->sym += (st.method == CLOTH_SYMPLECTIC_EULER) / (double)scene_frames[scene];
            r->substeps += st.substeps / (double)scene_frames[scene];
            r->steps += st.steps;
            if ((f + 1) % SAMPLE_FRAMES == 0) r->estimate[f / SAMPLE_FRAMES] = st.global_estimate;
        }
        for (long k = 0; k < per_frame && !r->failed; k++) {
            if (scene == BOX) box_contacts(c, 1.0 / hz, NULL);
            r->failed = cloth_step(c, 1.0 / hz, NULL) != CLOTH_OK;
            r->steps++;
        }
        if ((f + 1) % SAMPLE_FRAMES == 0)
            memcpy(r->x + (f / SAMPLE_FRAMES) * 3 * NV, cloth_positions(c), 3 * NV * sizeof(double));
    }
    r->cpu = cpu_now() - t0;
    cloth_adaptive_destroy(a);
    cloth_destroy(c);
}

/* RMS over vertices of x - ref at sample k */
static double sample_error(const double *x, const double *ref, int k)
{
    double s = 0.0;
    for (int i = 3 * NV * k; i < 3 * NV * (k + 1); i++) s += (x[i] - ref[i]) * (x[i] - ref[i]);
    return sqrt(s / NV);
}

/* RMS over vertices and samples; NaN if the run failed */
static double run_error(int scene, const result *r, const double *ref)
{
    double s = 0.0;
    for (int k = 0; k < nsamp(scene); k++) s += pow(sample_error(r->x, ref, k), 2);
    return r->failed ? NAN : sqrt(s / nsamp(scene));
}

/* A fixed-step series of one method on one scene: rates FPS round(2^(j/2)),
 * a factor sqrt(2) apart, run as far as they were needed. */
typedef struct series {
    cloth_method m;
    int n; /* runs so far */
    double hz[24], err[24], cpu[24];
    long steps[24];
} series;

/* The series' cheapest run with error at most e (the lowest rate), running
 * further rates as needed: its index, or -1 if none up to 1/30720 s
 * reaches it. */
static int fixed_run(int scene, series *S, double e, const double *ref, result *r)
{
    for (int j = 0;; j++) {
        if (j == S->n) {
            double hz = FPS * round(pow(2.0, 0.5 * (j + (S->m == CLOTH_SYMPLECTIC_EULER ? 8 : 0))));
            if (hz > 30720) return -1;
            S->hz[j] = hz;
            run(scene, S->m, hz, 0.0, r);
            S->cpu[j] = r->cpu;
            S->steps[j] = r->steps;
            S->err[j] = run_error(scene, r, ref);
            S->n++;
            printf("    %s fixed 1/%-6.0f error %.3g m, %ld steps, %.3f CPU s\n",
                   S->m == CLOTH_BACKWARD_EULER ? "backward Euler" : "symplectic Euler", hz, S->err[j], S->steps[j],
                   S->cpu[j]);
        }
        if (S->err[j] <= e) return j; /* not over e, nor blown up */
    }
}

/* error / requested for the controller's run r at tol: RMS over the samples
 * (as the chart measures it), and the worst sample into *worst */
static double request_ratio(int sc, const result *r, const double *ref, double tol, double *worst)
{
    double req = 0.0;
    *worst = 0.0;
    for (int k = 0; k < nsamp(sc); k++) {
        req += pow(tol * sample_time(k), 2) / nsamp(sc);
        *worst = fmax(*worst, sample_error(r->x, ref, k) / (tol * sample_time(k)));
    }
    return run_error(sc, r, ref) / sqrt(req);
}

/* One scene: its reference, checked; the controller at each tolerance. */
static void scene_checks(int sc, result *ref, result *r)
{
    const double tols[] = {1e-2, 3e-3, 1e-3};
    run(sc, CLOTH_SYMPLECTIC_EULER, 30720, 0.0, r);
    run(sc, CLOTH_SYMPLECTIC_EULER, 61440, 0.0, ref);
    double change = run_error(sc, r, ref->x), worst, req_min = 0.0;
    for (int k = 0; k < nsamp(sc); k++) req_min += pow(1e-3 * sample_time(k), 2) / nsamp(sc);
    req_min = sqrt(req_min);
    CHECK(change < 0.1 * req_min, "%s: reference change %g m not under a tenth of the smallest request %g m",
          scene_name[sc], change, req_min);
    printf("%s, %.2g s: reference symplectic Euler 1/61440 s (%.2f CPU s); at 1/30720 it differs by %.3g m RMS\n",
           scene_name[sc], scene_frames[sc] / (double)FPS, ref->cpu, change);
    series S[2] = {{CLOTH_BACKWARD_EULER, 0, {0}, {0}, {0}, {0}}, {CLOTH_SYMPLECTIC_EULER, 0, {0}, {0}, {0}, {0}}};
    for (int t = 0; t < 3; t++) {
        run(sc, CLOTH_BACKWARD_EULER, 0, tols[t], r);
        double cpu = r->cpu;
        double e = run_error(sc, r, ref->x), q = request_ratio(sc, r, ref->x, tols[t], &worst), g = 0.0;
        for (int k = 0; k < nsamp(sc); k++) g += r->estimate[k] * r->estimate[k] / nsamp(sc);
        printf("  tol %-6g error %.3g m, %.3g of requested (worst sample %.3g); %.1f substeps per frame, "
               "%.0f%% symplectic, %ld steps, %.3f CPU s; global estimate %.2f of the error\n",
               tols[t], e, q, worst, r->substeps, 100 * r->sym, r->steps, cpu, sqrt(g) / e);
        CHECK(!r->failed && q <= 1.5, "%s tol %g: error %g m, %.2f of requested", scene_name[sc], tols[t], e, q);
        CHECK(!r->failed && worst <= 2.0, "%s tol %g: a sample at %.2f of requested", scene_name[sc], tols[t], worst);
        if (t == 0 || r->failed) continue;
        long steps = r->steps;
        series *F = &S[r->sym >= 0.5];
        int j = fixed_run(sc, F, e, ref->x, r);
        if (!CHECK(j >= 0, "%s tol %g: no fixed-step run reaches its error %g m", scene_name[sc], tols[t], e)) continue;
        printf("  tol %-6g %ld steps, %.2fx the cheapest fixed-step run at or under its error (%ld); CPU %.2fx\n",
               tols[t], steps, steps / (double)F->steps[j], F->steps[j], cpu / F->cpu[j]);
        CHECK(steps <= 2 * F->steps[j], "%s tol %g: %ld steps, over twice the fixed steps' %ld", scene_name[sc],
              tols[t], steps, F->steps[j]);
    }
}

int main(void)
{
    result *ref = malloc(sizeof *ref), *r = malloc(sizeof *r);
    if (!ref || !r) return 1;
    settle(FLAG);
    settle(STIFF);
    for (int sc = 0; sc < NSCENES; sc++) scene_checks(sc, ref, r);
    nonlinear = CLOTH_NEWTON;
    printf("backward Euler by Newton's method:\n");
    scene_checks(FLAG, ref, r);
    free(ref);
    free(r);
    free(start_x[FLAG]);
    free(start_x[STIFF]);
    return check_summary();
}
