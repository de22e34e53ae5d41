/* bench_heap: a cloth that falls into a heap on the floor, folding onto
 * itself, with the self-collision pass on (odecloth/selfcollision.h).
 *
 * A 1 m square cotton cloth (cloth_material_preset(CLOTH_COTTON), 0.2 kg,
 * N x N nodes, the library's default solver) hangs by a corner, its diagonal
 * vertical and the lowest corner just above a floor (an ODE plane). The held
 * corner is lowered to the floor in 1.2 s while it circles, and let go: the
 * cloth piles onto itself, fold on fold. 2 s at h = 1/60 (dClothStep), the
 * pass applied after every step (and once before, to bind it).
 *
 * Per step (DIR/bench_heap_steps.csv): the step's wall time, the share of it
 * spent in the self-contact barrier inside the step (dClothStepStats'
 * self_contact_seconds_all), the pass after the step, the triangle pairs
 * intersecting after the step (intersections_count), Newton and CG
 * iterations of all the step's solves, substeps, failure. Per run (DIR/bench_heap.csv and a line on
 * stdout): the sums, the largest count of intersecting pairs, the steps with
 * any, and the layers at the heap's thickest point (the most triangles over
 * one point of the floor). With pictures available: DIR/bench_heap_N.png,
 * the heap at the end, and DIR/bench_heap_N_half.png at 0.5 s.
 *
 *   bench_heap [--out DIR] [--grid N] [--self-collision T] [--max-wall S]
 *              [--seconds S] [--turns T] [--swirl R] [--no-images] [--check]
 *
 * --check: no failed step, no intersecting triangle pair after any step, and a
 * heap at the end (HEAP_LAYERS_MIN layers somewhere), so the count is not of a
 * cloth that never met itself.
 *
 * Test physics_heap_no_crossing in test/CMakeLists.txt.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "odecloth/dcloth.h"
#include "odecloth/selfcollision.h"
#include "bench_util.h"
#include "demo.h"
#include "intersections.h"

#define HZ 60.0
#define G 9.81
#define HEAP_FOOT 0.05    /* m, the lower corner above the floor; the held one ends there */
#define HEAP_LOWER_S 1.2  /* s, the held corner lowered to the floor, then let go */
#define HEAP_TURNS 1.5    /* circles the held corner makes meanwhile (--turns) */
#define HEAP_SWIRL 0.1    /* m, their radius (--swirl) */
#define HEAP_LAYERS_MIN 3 /* --check: the fewest layers at the thickest point */
#define LAYER_SAMPLES 100 /* per side, the floor points where layers are counted */
#define IMAGE_W 960
#define IMAGE_H 720

typedef struct options {
    bench_opts b;
    double thickness;    /* m, the pass's; 0: no pass */
    double max_wall;     /* s per run */
    double seconds;      /* simulated */
    double turns, swirl; /* the held corner's circles while lowered, their radius (m) */
    int images;
} options;

typedef struct run {
    int N, steps, failed, dropped, steps_crossing;
    long max_pairs, newton, cg;
    double wall_s, contact_s, pass_s, max_strain;
    int layers;
    const char *status;
} run;

static FILE *g_steps;

/* The cloth hung by its last corner in the x-z plane, the diagonal vertical
 * and the first corner HEAP_FOOT above the floor. */
static int hang(cloth *c, int N)
{
    size_t n3 = 3 * (size_t)N * N;
    double *x = malloc(n3 * sizeof *x), step = 1.0 / (N - 1);
    if (!x) return -1;
    for (int r = 0; r < N; r++)
        for (int k = 0; k < N; k++) {
            double *p = x + 3 * ((size_t)r * N + k), u = k * step, w = r * step;
            p[0] = (u - w) * M_SQRT1_2, p[1] = 0.0, p[2] = HEAP_FOOT + (u + w) * M_SQRT1_2;
        }
    int rc = cloth_set_positions(c, x) == CLOTH_OK ? 0 : -1;
    free(x);
    return rc;
}

/* Where the held corner is at time t: lowered at a steady rate from where it
 * hangs (top) to HEAP_FOOT over HEAP_LOWER_S, circling the vertical through
 * its start o->turns times at radius o->swirl (grown from 0 over the first turn) */
static void held_at(const options *o, double t, const double *top, dReal *at)
{
    double f = fmin(t / HEAP_LOWER_S, 1.0), a = 2.0 * M_PI * o->turns * f;
    double r = o->swirl * fmin(o->turns * f, 1.0);
    at[0] = top[0] + r * sin(a);
    at[1] = top[1] + r * (1.0 - cos(a));
    at[2] = top[2] + f * (HEAP_FOOT - top[2]);
}

/* Whether the floor point (px, py) is inside the xy shadow of triangle t */
static int over(const double *x, const int *t, double px, double py)
{
    const double *a = x + 3 * t[0], *b = x + 3 * t[1], *c = x + 3 * t[2];
    double d1 = (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
    double d2 = (c[0] - b[0]) * (py - b[1]) - (c[1] - b[1]) * (px - b[0]);
    double d3 = (a[0] - c[0]) * (py - c[1]) - (a[1] - c[1]) * (px - c[0]);
    return (d1 > 0 && d2 > 0 && d3 > 0) || (d1 < 0 && d2 < 0 && d3 < 0);
}

/* The most triangles over one of LAYER_SAMPLES^2 points spread over the cloth's xy box */
static int most_layers(const double *x, int nv, const int *tri, int nt)
{
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    for (int i = 0; i < nv; i++)
        for (int a = 0; a < 2; a++) lo[a] = fmin(lo[a], x[3 * i + a]), hi[a] = fmax(hi[a], x[3 * i + a]);
    int *count = calloc((size_t)LAYER_SAMPLES * LAYER_SAMPLES, sizeof *count), most = 0;
    if (!count) return -1;
    double dx = (hi[0] - lo[0]) / LAYER_SAMPLES, dy = (hi[1] - lo[1]) / LAYER_SAMPLES;
    for (int t = 0; t < nt && dx > 0 && dy > 0; t++) {
        const int *tv = tri + 3 * t;
        double bl[2] = {HUGE_VAL, HUGE_VAL}, bh[2] = {-HUGE_VAL, -HUGE_VAL};
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 2; a++) bl[a] = fmin(bl[a], x[3 * tv[k] + a]), bh[a] = fmax(bh[a], x[3 * tv[k] + a]);
        int i0 = (int)fmax(0, ceil((bl[0] - lo[0]) / dx - 0.5));
        int i1 = (int)fmin(LAYER_SAMPLES - 1, (bh[0] - lo[0]) / dx);
        int j0 = (int)fmax(0, ceil((bl[1] - lo[1]) / dy - 0.5));
        int j1 = (int)fmin(LAYER_SAMPLES - 1, (bh[1] - lo[1]) / dy);
        for (int i = i0; i <= i1; i++)
            for (int j = j0; j <= j1; j++)
                if (over(x, tv, lo[0] + (i + 0.5) * dx, lo[1] + (j + 0.5) * dy)) {
                    int *n = count + (size_t)i * LAYER_SAMPLES + j;
                    if (++*n > most) most = *n;
                }
    }
    free(count);
    return most;
}

static void save_picture(const options *o, dSpaceID space, dClothID cl, int N, const char *tag)
{
    if (!o->images || !demo_render_available() || !demo_png_available()) return;
    demo_camera cam = {{1.1, -1.5, 1.0}, {0.0, 0.0, 0.08}, 36};
    demo_image *im = demo_render(&cam, space, &cl, 1, 1, IMAGE_W, IMAGE_H);
    if (!im) return;
    char label[96], path[1024];
    snprintf(label, sizeof label, "heap %dx%d %s", N, N, tag);
    demo_text(im, 12, 12, 3, (const unsigned char[3]){20, 20, 20}, label);
    snprintf(path, sizeof path, "%s/bench_heap_%d%s.png", o->b.out, N, !strcmp(tag, "end") ? "" : "_half");
    if (!demo_png_write(path, im)) printf("wrote %s\n", path);
    demo_image_destroy(im);
}

/* One step: the cloth's, then the pass; its figures into r and the steps' CSV */
static int heap_step(dClothID cl, cloth_self_collision *sc, const int *tri, int nt, int k, run *r)
{
    cloth *core = dClothGetCore(cl);
    double w0 = bench_wall_now();
    cloth_status rc = dClothStep(cl, 1.0 / HZ);
    double w1 = bench_wall_now();
    int ok = rc == CLOTH_OK && !dClothGetStats(cl)->held;
    if (ok && sc && cloth_self_collision_apply(sc, core, NULL) != CLOTH_OK) ok = 0;
    double w2 = bench_wall_now();
    const dClothStepStats *ps = dClothGetStats(cl);
    const cloth_step_stats *st = &ps->core;
    double sc_s = ps->self_contact_seconds_all; /* every solve of the step, as the wall time */
    intersections ix = {0, 0};
    if (intersections_count(cloth_positions(core), cloth_vertex_count(core), tri, nt, &ix, NULL)) ix.pairs = -1;
    r->steps = k + 1;
    r->failed += !ok;
    r->dropped += st->self_contact_dropped;
    r->wall_s += w1 - w0;
    r->pass_s += w2 - w1;
    r->contact_s += sc_s;
    r->newton += ps->newton_all;
    r->cg += ps->cg_all;
    r->max_pairs = ix.pairs > r->max_pairs ? ix.pairs : r->max_pairs;
    r->steps_crossing += ix.pairs != 0;
    r->max_strain = fmax(r->max_strain, cloth_max_strain(core));
    if (g_steps)
        fprintf(g_steps, "%d,%d,%.3f,%.3f,%.4f,%.3f,%ld,%d,%d,%d,%d,%d,%.5f\n", r->N, k, 1e3 * (w1 - w0), 1e3 * sc_s,
                w1 > w0 ? sc_s / (w1 - w0) : 0.0, 1e3 * (w2 - w1), ix.pairs, ps->newton_all, ps->cg_all, st->substeps,
                !ok, st->self_contact_dropped, st->max_strain);
    return ok;
}

static run run_heap(const options *o, int N)
{
    run r = {.N = N, .status = "failed"};
    dWorldID world = dWorldCreate();
    dWorldSetGravity(world, 0, 0, -G);
    dSpaceID space = dHashSpaceCreate(0);
    dCreatePlane(space, 0, 0, 1, 0);
    dClothDesc d = dClothDefaultDesc();
    d.cloth = cloth_default_desc();
    d.cloth.rows = d.cloth.cols = N;
    d.cloth.width = d.cloth.height = 1.0;
    d.cloth.material = cloth_material_preset(CLOTH_COTTON);
    d.cloth.material.density = 0.2;
    dClothID cl = 0;
    cloth_self_collision *sc = NULL;
    cloth_error err = {0};
    int nt = 2 * (N - 1) * (N - 1), *tri = malloc(3 * (size_t)nt * sizeof *tri);
    if (!tri || dClothCreate(world, space, &d, &cl, &err) != CLOTH_OK || hang(dClothGetCore(cl), N) ||
        (o->thickness > 0 && cloth_self_collision_create(dClothGetCore(cl), o->thickness, &sc, &err) != CLOTH_OK)) {
        fprintf(stderr, "bench_heap: %dx%d: %s\n", N, N, err.message[0] ? err.message : "out of memory");
        goto done;
    }
    intersections_grid_triangles(N, N, tri);
    if (sc) cloth_self_collision_apply(sc, dClothGetCore(cl), NULL); /* binds it: the first step has it */
    int held = N * N - 1, total = (int)lround(o->seconds * HZ), half = (int)lround(0.5 * HZ);
    double top[3];
    memcpy(top, cloth_positions(dClothGetCore(cl)) + 3 * held, sizeof top);
    r.status = "ok";
    for (int k = 0; k < total; k++) {
        dReal at[3];
        held_at(o, (k + 1) / HZ, top, at);
        if (k < HEAP_LOWER_S * HZ) dClothPinToWorld(cl, held, at);
        else if (k - 1 < HEAP_LOWER_S * HZ) dClothReleasePin(cl, held);
        heap_step(cl, sc, tri, nt, k, &r);
        if (k + 1 == half) save_picture(o, space, cl, N, "at 0.5 s");
        if (k + 1 < total && r.wall_s + r.pass_s > o->max_wall) {
            r.status = "timeout";
            break;
        }
    }
    if (r.failed && strcmp(r.status, "timeout")) r.status = "failed";
    r.layers = most_layers(cloth_positions(dClothGetCore(cl)), N * N, tri, nt);
    save_picture(o, space, cl, N, "end");
done:
    cloth_self_collision_destroy(sc);
    free(tri);
    if (cl) dClothDestroy(cl);
    dSpaceDestroy(space);
    dWorldDestroy(world);
    return r;
}

static void print_run(FILE *f, const run *r, int csv)
{
    double step = r->wall_s, share = step > 0 ? r->contact_s / step : NAN;
    double all = (r->contact_s + r->pass_s) / (step + r->pass_s);
    fprintf(f,
            csv ? "%d,%d,%.3f,%.3f,%.4f,%.3f,%.4f,%.2f,%.1f,%ld,%d,%d,%d,%d,%.4f,%s\n"
                : "%4d %5d %8.2f %8.2f %6.1f%% %8.2f %6.1f%% %7.2f %7.1f %7ld %6d %6d %5d %6d %7.4f %s\n",
            r->N, r->steps, step, r->contact_s, csv ? share : 100 * share, r->pass_s, csv ? all : 100 * all,
            r->steps ? (double)r->newton / r->steps : NAN, r->steps ? (double)r->cg / r->steps : NAN, r->max_pairs,
            r->steps_crossing, r->failed, r->dropped, r->layers, r->max_strain, r->status);
    fflush(f);
}

static const char usage[] =
    "usage: bench_heap [--out DIR] [--grid N] [--self-collision T] [--max-wall S] [--seconds S]\n"
    "                  [--turns T] [--swirl R] [--no-images] [--check]\n"
    "A 1 m cotton cloth hung by a corner, lowered to the floor while circling and let go: it\n"
    "folds into a heap. 2 s at h = 1/60, the self-collision pass on (N = 41 and 81 unless --grid).\n"
    "--self-collision T  the pass's thickness in m (default 0.005; 0: no pass)\n"
    "--max-wall S  wall-clock budget per run in seconds (default 600): a run past it stops\n"
    "           with status timeout and its figures so far\n"
    "--seconds S  simulated time (default 2)\n"
    "--turns T, --swirl R  circles (default 1.5) and their radius in m (default 0.1) of the held\n"
    "           corner while it is lowered\n"
    "--no-images  no pictures (else DIR/bench_heap_N.png and _half.png when rendering works)\n"
    "--check    exit 1 if a step failed or left intersecting triangle pairs, or the cloth\n"
    "           ends with fewer than 3 layers over every point of the floor (no heap)\n"
    "Writes DIR/bench_heap.csv and DIR/bench_heap_steps.csv (default DIR out/bench).";

/* A number in (lo, hi] from v, or -1 with a message naming the option */
static int parse_number(const char *opt, const char *v, double lo, double hi, double *out)
{
    char *end;
    *out = strtod(v, &end);
    if (end == v || *end || !(*out > lo) || !(*out <= hi)) {
        fprintf(stderr, "bench_heap: %s '%s' must be a number in (%g, %g]\n", opt, v, lo, hi);
        return -1;
    }
    return 0;
}

enum { OPT_NO_IMAGES = BENCH_OWN, OPT_SELF_COLLISION, OPT_MAX_WALL, OPT_TURNS, OPT_SWIRL, OPT_SECONDS };

static const struct option own_options[] = {
    {"no-images", no_argument, NULL, OPT_NO_IMAGES},
    {"self-collision", required_argument, NULL, OPT_SELF_COLLISION},
    {"max-wall", required_argument, NULL, OPT_MAX_WALL},
    {"turns", required_argument, NULL, OPT_TURNS},
    {"swirl", required_argument, NULL, OPT_SWIRL},
    {"seconds", required_argument, NULL, OPT_SECONDS},
    {NULL, 0, NULL, 0},
};

/* This program's own options (bench_take_fn). */
static int take_option(void *ctx, int opt, const char *v)
{
    options *o = ctx;
    int bad = 0;
    switch (opt) {
    case OPT_NO_IMAGES: o->images = 0; break;
    case OPT_SELF_COLLISION:
        bad = !strcmp(v, "0") ? (o->thickness = 0, 0) : parse_number("--self-collision", v, 0, 1, &o->thickness);
        break;
    case OPT_MAX_WALL: bad = parse_number("--max-wall", v, 0, 1e6, &o->max_wall); break;
    case OPT_TURNS: bad = parse_number("--turns", v, 0, 10, &o->turns); break;
    case OPT_SWIRL: bad = parse_number("--swirl", v, 0, 0.5, &o->swirl); break;
    default: /* OPT_SECONDS */ bad = parse_number("--seconds", v, 0, 60, &o->seconds); break;
    }
    return bad ? 2 : 0;
}

/* Fills o from the command line; 0 to go on, -1 after --help, else the exit status. */
static int parse_options(options *o, int argc, char **argv)
{
    int rc = bench_parse(&o->b, own_options, take_option, o, argc, argv);
    return rc < 0 ? 0 : rc ? rc : -1;
}

int main(int argc, char **argv)
{
    options o = {.b = {"bench_heap", usage, "out/bench", 0, 0, 0}, 0.005, 600.0, 2.0, HEAP_TURNS, HEAP_SWIRL, 1};
    int rc = parse_options(&o, argc, argv);
    if (rc) return rc < 0 ? 0 : rc;
    FILE *csv = bench_open_csv(&o.b, "bench_heap");
    if (!csv || !(g_steps = bench_open_csv(&o.b, "bench_heap_steps"))) return 1;
    fputs("N,steps,wall_s,self_contact_s,self_contact_share,pass_s,share_with_pass,newton_per_step,cg_per_step,"
          "max_intersecting_pairs,steps_intersecting,failed_steps,dropped,layers,max_strain,status\n",
          csv);
    fputs("N,step,wall_ms,self_contact_ms,self_contact_share,pass_ms,intersecting_pairs,newton,cg,substeps,failed,"
          "dropped,max_strain\n",
          g_steps);
    printf("heap: %g s at h = 1/%g, self-collision thickness %g m, wall budget %g s per run\n", o.seconds, HZ,
           o.thickness, o.max_wall);
    printf("%4s %5s %8s %8s %7s %8s %7s %7s %7s %7s %6s %6s %5s %6s %7s %s\n", "N", "steps", "wall s", "self s",
           "share", "pass s", "w/pass", "newton", "CG", "pairs", "stepsX", "fail", "drop", "layers", "strain",
           "status");
    dInitODE2(0);
    int grids[2] = {41, 81}, ng = o.b.grid ? 1 : 2, misses = 0;
    if (o.b.grid) grids[0] = o.b.grid;
    for (int g = 0; g < ng; g++) {
        run r = run_heap(&o, grids[g]);
        print_run(stdout, &r, 0);
        print_run(csv, &r, 1);
        misses += r.failed > 0 || r.max_pairs != 0 || r.layers < HEAP_LAYERS_MIN || strcmp(r.status, "ok");
    }
    demo_render_shutdown();
    dCloseODE();
    fclose(csv);
    fclose(g_steps);
    if (o.b.check) printf("check: %s (%d runs missed)\n", misses ? "FAILED" : "passed", misses);
    return o.b.check && misses ? 1 : 0;
}
