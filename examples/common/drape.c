/* The drape-and-remove experiment: see drape.h. */
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include "drape.h"
#include "odecloth/fabric.h"
#include "odecloth/selfcollision.h"
#include "view.h"

#define FLOOR_Z 0.0
#define CLOTH_SIZE 1.0
#define TABLE_SIDE 0.55
#define TABLE_HEIGHT 0.6
#define SPHERE_R 0.25
#define SPHERE_Z 0.55
#define LIFT_Z 1.4
#define UNWRAP 0.97        /* corners' spacing, of the flat spacing, while lifted off */
#define SLACK 0.8          /* corners' spacing while carried */
#define SPREAD_Z 0.35      /* height where the corners are spread out */
#define CARRY_X 1.0        /* the cloth is laid down centred at (CARRY_X, 0) */
#define TWO_CORNER_MOVES 4 /* phases of the two-corner removal before it is laid down */
#define LAY_TIME 3.0       /* s the laying down takes, --short or not */
#define HAND_Z 1.5         /* two-corner removal: hands' height while carrying     */
#define HAND_GAP 0.9       /* their spacing then, of the cloth's width             */
#define HAND_BACK 0.2      /* m, how far back of the cloth's edge they lift it     */
#define HAND_SLACK 0.03    /* slack while laying it down, of the cloth's length      */

static const float table_rgb[3] = {0.55f, 0.40f, 0.28f}, sphere_rgb[3] = {0.60f, 0.62f, 0.68f};

static const int box_indices[36] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                    2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};

dGeomID demo_box_mesh_create(demo_box_mesh *m, dSpaceID space, double lx, double ly, double lz)
{
    /* corner k: bit 0 +x, bit 1 +y, bit 2 +z; faces counter-clockwise from outside */
    for (int k = 0; k < 8; k++) {
        m->v[k][0] = (k & 1 ? 0.5 : -0.5) * lx;
        m->v[k][1] = (k & 2 ? 0.5 : -0.5) * ly;
        m->v[k][2] = (k & 4 ? 0.5 : -0.5) * lz;
    }
    m->data = dGeomTriMeshDataCreate();
    dGeomTriMeshDataBuildDouble(m->data, m->v, 3 * sizeof(double), 8, box_indices, 36, 3 * sizeof(int));
    m->geom = dCreateTriMesh(space, m->data, NULL, NULL, NULL);
    return m->geom;
}

void demo_box_mesh_destroy(demo_box_mesh *m)
{
    if (m->geom) dGeomDestroy(m->geom);
    if (m->data) dGeomTriMeshDataDestroy(m->data);
    m->geom = NULL;
    m->data = NULL;
}

static double collider_top(drape_collider col) { return col == DRAPE_TABLE ? TABLE_HEIGHT : SPHERE_Z + SPHERE_R; }

static void cameras(drape_collider col, demo_camera *draped, demo_camera *after, demo_camera *wide)
{
    double top = collider_top(col);
    *draped = (demo_camera){{1.25, -1.55, top + 0.95}, {0, 0, top - 0.3}, 38};
    *after = (demo_camera){{CARRY_X + 1.05, -1.0, 1.35}, {CARRY_X + 0.05, 0, 0}, 42};
    *wide = (demo_camera){{0.45, -2.6, 1.7}, {0.45, 0, 0.6}, 50};
}

int demo_claim(int ok, const char *fmt, ...)
{
    va_list ap;
    printf("check %s: ", ok ? "ok" : "FAILED");
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    putchar('\n');
    return !ok;
}

/* The corner phases after the drape. Each moves the four corners, by a
 * smoothstep in time, to (cx + scale * ox, scale * oy, z) for the flat
 * corner offsets (ox, oy). */
typedef struct phase {
    const char *name;
    double scale, cx, z;
} phase;

/* What a run carries from step to step. */
typedef struct runner {
    const demo_opts *o;
    const drape_variant *v;
    dWorldID world;
    dSpaceID space;
    dClothID c;
    demo_camera cam_wide;
    demo_metrics run, phase; /* over the whole run, over the current phase */
    int step, total, next_frame, slept;
    demo_box_mesh table;
    cloth_self_collision *self; /* --self-collision, else NULL */
} runner;

static int run_step(runner *R)
{
    if (demo_step(R->o, R->world, &R->c, 1, 1.0 / R->o->hz, R->step)) return -1;
    if (R->self) {
        cloth_self_collision_stats sst;
        if (cloth_self_collision_apply(R->self, dClothGetCore(R->c), &sst) != CLOTH_OK) {
            fprintf(stderr, "%s: step %d: %s\n", R->o->prog, R->step, cloth_last_error(dClothGetCore(R->c)));
            return -1;
        }
        if (R->o->trace && sst.pairs)
            printf("  self-collision: %d pairs separated (%d crossed), closest %.2f mm\n", sst.pairs, sst.crossings,
                   1e3 * sst.closest);
    }
    R->slept += dClothGetStats(R->c)->sleeping;
    demo_track_step(R->c, &R->run);
    demo_track_step(R->c, &R->phase);
    R->step++;
    demo_frame_hook(R->o, R->v->tag, R->step, R->total, &R->next_frame, &R->cam_wide, R->space, &R->c, 1);
    demo_view_frame(R->o, R->v->label, R->step, R->total, &R->cam_wide, R->space, &R->c, 1);
    return 0;
}

static void phase_done(runner *R, const char *name)
{
    if (R->o->trace || R->o->phases) {
        int plastic = 0;
        const cloth *core = dClothGetCore(R->c);
        cloth_link l;
        for (int i = 0; core && cloth_get_link(core, CLOTH_INTERLACED, i, &l) == CLOTH_OK; i++) plastic += l.plastic;
        printf("  phase %-7s to step %5d: max strain %.4f, max penetration %.2f mm, deepest bend %.3f, "
               "plastic links %d\n",
               name, R->step, R->phase.max_strain, 1e3 * R->phase.max_penetration, R->phase.min_bend, plastic);
    }
    memset(&R->phase, 0, sizeof R->phase);
}

/* Step `steps` free of pins (a settle), then measure the cloth into m (the
 * run's extremes so far, its shape now, the wall time since t0) and save the
 * picture <tag>_<what>. */
static int settle_and_capture(runner *R, int steps, const char *what, double t0, const demo_camera *cam,
                              demo_metrics *m, demo_image **pic)
{
    for (int s = 0; s < steps; s++)
        if (run_step(R)) return -1;
    phase_done(R, what);
    *m = R->run;
    m->wall = demo_now() - t0;
    demo_measure_shape(R->c, FLOOR_Z, m);
    char name[120];
    snprintf(name, sizeof name, "%s_%s", R->v->tag, what);
    demo_save_frame(R->o, name, cam, R->space, &R->c, 1, pic);
    return 0;
}

/* Move n pinned vertices from `from` to `to` over `steps`, by a smoothstep
 * in time; `from` ends at `to`. */
static int move_pins(runner *R, const char *name, int n, const int *pin, double (*from)[3], const double (*to)[3],
                     int steps)
{
    for (int s = 1; s <= steps; s++) {
        double w = demo_smoothstep((double)s / steps);
        for (int k = 0; k < n; k++) {
            dReal at[3];
            for (int a = 0; a < 3; a++) at[a] = from[k][a] + w * (to[k][a] - from[k][a]);
            dClothPinToWorld(R->c, pin[k], at);
        }
        if (run_step(R)) return -1;
    }
    phase_done(R, name);
    memcpy(from, to, (size_t)n * sizeof *from);
    return 0;
}

/* Move the four corners to the phase's positions (see phase). */
static int move_corners(runner *R, const phase *ph, const int corner[4], double from[4][3], int steps)
{
    static const double off[4][2] = {{-0.5, -0.5}, {0.5, -0.5}, {-0.5, 0.5}, {0.5, 0.5}};
    double to[4][3];
    for (int k = 0; k < 4; k++) {
        to[k][0] = ph->cx + ph->scale * off[k][0] * CLOTH_SIZE;
        to[k][1] = ph->scale * off[k][1] * CLOTH_SIZE;
        to[k][2] = ph->z;
    }
    return move_pins(R, ph->name, 4, corner, from, (const double(*)[3])to, steps);
}

/* The corners' current positions. */
static void corners_now(const runner *R, const int corner[4], double at[4][3])
{
    const dReal *x = dClothGetPositions(R->c);
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 3; a++) at[k][a] = x[3 * corner[k] + a];
}

/* The drape of a variant folded more than once: lifted off as for the
 * removal, laid back flat over the collider and let go, before each
 * drape after the first. */
static int refold(runner *R, drape_collider col, const int corner[4], int move_steps)
{
    const phase relay[] = {
        {"unwrap", UNWRAP, 0.0, collider_top(col) + 0.02},
        {"lift", UNWRAP, 0.0, LIFT_Z},
        {"relay", 1.0, 0.0, collider_top(col) + 0.05},
    };
    double from[4][3];
    corners_now(R, corner, from);
    for (int p = 0; p < 3; p++)
        if (move_corners(R, &relay[p], corner, from, move_steps)) return -1;
    for (int k = 0; k < 4; k++) dClothReleasePin(R->c, corner[k]);
    return 0;
}

/* The paper's removal: the four corners lifted, carried, spread out to
 * the flat square's corners over the floor and lowered onto it, then let go. */
static int remove_by_four_corners(runner *R, drape_collider col, const int corner[4], double thickness, int steps)
{
    /* the floor corners a thickness above the floor: where a resting vertex is */
    const phase phases[] = {
        {"unwrap", UNWRAP, 0.0, collider_top(col) + 0.02},
        {"lift", UNWRAP, 0.0, LIFT_Z},
        {"gather", SLACK, 0.0, LIFT_Z},
        {"carry", SLACK, CARRY_X, LIFT_Z},
        {"spread", 1.0, CARRY_X, SPREAD_Z},
        {"lower", 1.0, CARRY_X, FLOOR_Z + thickness},
    };
    double from[4][3];
    corners_now(R, corner, from);
    for (int p = 0; p < 6; p++)
        if (move_corners(R, &phases[p], corner, from, steps)) return -1;
    for (int k = 0; k < 4; k++) dClothReleasePin(R->c, corner[k]);
    return 0;
}

/* The removal as a person does it: two corners of one edge taken up, the cloth lifted off, carried
 * clear and lowered till its free edge touches the floor, then laid down walking forward (the held
 * edge tilted 45 degrees ahead and lowered along that line, a little slack). */
static int remove_by_two_corners(runner *R, const int corner[4], double thickness, int steps, int lay_steps)
{
    const double w = 0.5 * CLOTH_SIZE, g = HAND_GAP * w, back = -w - HAND_BACK;
    const double lean = (1.0 - HAND_SLACK) * CLOTH_SIZE * sqrt(0.5); /* held edge over the free one */
    const double stops[][2][3] = {
        {{-g, back, HAND_Z}, {g, back, HAND_Z}},
        {{CARRY_X - g, -w, HAND_Z}, {CARRY_X + g, -w, HAND_Z}},
        {{CARRY_X - w, -w, FLOOR_Z + CLOTH_SIZE}, {CARRY_X + w, -w, FLOOR_Z + CLOTH_SIZE}},
        {{CARRY_X - w, -w + lean, FLOOR_Z + lean}, {CARRY_X + w, -w + lean, FLOOR_Z + lean}},
        {{CARRY_X - w, w, FLOOR_Z + thickness}, {CARRY_X + w, w, FLOOR_Z + thickness}},
    };
    static const char *const names[] = {"lift", "carry", "lower", "lean", "lay"};
    double from[4][3];
    corners_now(R, corner, from);
    for (int p = 0; p <= TWO_CORNER_MOVES; p++)
        if (move_pins(R, names[p], 2, corner, from, stops[p], p == TWO_CORNER_MOVES ? lay_steps : steps)) return -1;
    for (int k = 0; k < 2; k++) dClothReleasePin(R->c, corner[k]);
    return 0;
}

int drape_run(const demo_opts *o, const demo_scene *scene, const drape_variant *v, drape_result *r)
{
    drape_collider col = scene->col;
    memset(r, 0, sizeof *r);
    double settle = o->short_run ? 2.5 : 4.0;
    double move = o->short_run ? 1.0 : 1.5;
    double hold = v->hold > 0.0 ? v->hold : settle;
    int folds = v->folds > 1 ? v->folds : 1;
    dClothDesc d = demo_desc(o);
    r->delta = v->material.delta;
    r->strain_allow = drape_strain_allowance(&d.cloth.solver, r->delta);
    r->thickness = d.thickness;

    runner R = {.o = o, .v = v, .next_frame = 1};
    R.world = dWorldCreate();
    dWorldSetGravity(R.world, 0, 0, -9.81);
    R.space = dHashSpaceCreate(0);
    dCreatePlane(R.space, 0, 0, 1, FLOOR_Z);
    if (col == DRAPE_TABLE && !o->box_table) {
        dGeomID table = demo_box_mesh_create(&R.table, R.space, TABLE_SIDE, TABLE_SIDE, TABLE_HEIGHT);
        dGeomSetPosition(table, 0, 0, FLOOR_Z + TABLE_HEIGHT / 2);
        dGeomSetData(table, (void *)table_rgb);
    } else if (col == DRAPE_TABLE) {
        dGeomID table = dCreateBox(R.space, TABLE_SIDE, TABLE_SIDE, TABLE_HEIGHT);
        dGeomSetPosition(table, 0, 0, FLOOR_Z + TABLE_HEIGHT / 2);
        dGeomSetData(table, (void *)table_rgb);
    } else {
        dGeomID ball = dCreateSphere(R.space, SPHERE_R);
        dGeomSetPosition(ball, 0, 0, SPHERE_Z);
        dGeomSetData(ball, (void *)sphere_rgb);
        double post = SPHERE_Z - SPHERE_R - FLOOR_Z;
        dGeomID stem = dCreateCylinder(R.space, 0.04, post);
        dGeomSetPosition(stem, 0, 0, FLOOR_Z + post / 2);
        dGeomSetData(stem, (void *)sphere_rgb);
    }
    d.cloth.rows = d.cloth.cols = o->grid;
    d.cloth.width = d.cloth.height = CLOTH_SIZE;
    d.cloth.origin[0] = d.cloth.origin[1] = -CLOTH_SIZE / 2;
    d.cloth.origin[2] = collider_top(col) + 0.05;
    d.cloth.material = v->material;
    cloth_error err;
    int rc = -1;
    if (dClothCreate(R.world, R.space, &d, &R.c, &err) != CLOTH_OK) {
        fprintf(stderr, "%s: %s\n", o->prog, err.message);
        goto done;
    }
    if (o->sleep) dClothSetAutoSleep(R.c, 1, 0.01, 10);
    if (o->self_thickness > 0.0 &&
        cloth_self_collision_create(dClothGetCore(R.c), o->self_thickness, &R.self, &err) != CLOTH_OK) {
        fprintf(stderr, "%s: %s\n", o->prog, err.message);
        goto done;
    }
    const int C = o->grid, corner[4] = {0, C - 1, (C - 1) * C, C * C - 1};
    demo_camera cam_draped, cam_after;
    cameras(col, &cam_draped, &cam_after, &R.cam_wide);
    int settle_steps = (int)lround(settle * o->hz), move_steps = (int)lround(move * o->hz);
    int hold_steps = (int)lround(hold * o->hz);
    int lay_steps = (int)lround(LAY_TIME * o->hz);
    int remove_steps = v->removal == DRAPE_REMOVE_TWO_CORNERS ? TWO_CORNER_MOVES * move_steps + lay_steps
                                                              : 6 * move_steps;
    R.total = settle_steps + folds * hold_steps + (folds - 1) * 3 * move_steps + remove_steps;
    double t0 = demo_now();

    for (int f = 1; f < folds; f++) {
        for (int s = 0; s < hold_steps; s++)
            if (run_step(&R)) goto done;
        phase_done(&R, "hold");
        if (refold(&R, col, corner, move_steps)) goto done;
    }
    if (settle_and_capture(&R, hold_steps, scene->tags[0], t0, &cam_draped, &r->draped, &r->pic_draped)) goto done;

    if (v->removal == DRAPE_REMOVE_TWO_CORNERS ? remove_by_two_corners(&R, corner, d.thickness, move_steps, lay_steps)
                                               : remove_by_four_corners(&R, col, corner, d.thickness, move_steps))
        goto done;
    if (settle_and_capture(&R, settle_steps, scene->tags[1], t0, &cam_after, &r->after, &r->pic_after)) goto done;
    rc = 0;
    if (o->sleep)
        printf("%s: slept %d of %d steps (%.0f%%), %.2f s wall\n", v->tag, R.slept, R.step,
               100.0 * R.slept / (R.step > 0 ? R.step : 1), demo_now() - t0);
done:
    if (rc) phase_done(&R, "FAILED");
    cloth_self_collision_destroy(R.self);
    dClothDestroy(R.c);
    demo_box_mesh_destroy(&R.table);
    dSpaceDestroy(R.space);
    dWorldDestroy(R.world);
    return rc;
}

const demo_scene drape_table_scene = {"table",
                                      {"draped", "after removal"},
                                      {"draped", "after"},
                                      DRAPE_TABLE,
                                      drape_run,
                                      DRAPE_BENDING,
                                      1,
                                      1,
                                      0,
                                      DRAPE_GRIP,
                                      1};
const demo_scene drape_sphere_scene = {"sphere",
                                       {"draped", "after removal"},
                                       {"draped", "after"},
                                       DRAPE_SPHERE,
                                       drape_run,
                                       DRAPE_BENDING,
                                       1,
                                       1,
                                       0,
                                       DRAPE_GRIP,
                                       0};

int drape_run_all(const demo_opts *o, const demo_scene *sc, const drape_variant *v, int nv, drape_result *results,
                  const char *sheet, const char *title)
{
    if (nv <= 0 || nv > DEMO_MAX_ALPHAS || demo_make_out_dir(o) || demo_video_check(o)) return -1;
    memset(results, 0, (size_t)nv * sizeof *results); /* what a failed run leaves is freed below */
    if (o->images && (!demo_render_available() || !demo_png_available()))
        printf("%s: no pictures: %s\n", o->prog,
               !demo_render_available() ? demo_render_unavailable_reason()
                                        : "built without libpng (install libpng-dev and rebuild)");
    int rc = 0;
    for (int i = 0; i < nv && !rc; i++) {
        printf("== %s: %s, %s\n", o->prog, v[i].label, sc->name);
        rc = sc->run(o, sc, &v[i], &results[i]);
        if (demo_video_finish(o)) rc = -1;
        if (rc) break;
        for (int k = 0; k < 2; k++) {
            const demo_metrics *m = k ? &results[i].after : &results[i].draped;
            char label[80];
            snprintf(label, sizeof label, "%s %s", v[i].tag, sc->rows[k]);
            demo_print_metrics(stdout, label, m);
            snprintf(label, sizeof label, "%s_%s", v[i].tag, sc->tags[k]);
            if (o->csv && demo_csv_row(o->csv, o->prog, label, v[i].material.alpha, m)) rc = -1;
        }
    }
    if (!rc && results[0].pic_draped) {
        const demo_image **cells = calloc(2 * (size_t)nv, sizeof *cells);
        const char **cols = calloc((size_t)nv, sizeof *cols);
        if (cells && cols) {
            for (int i = 0; i < nv; i++) {
                cells[i] = results[i].pic_draped;
                cells[nv + i] = results[i].pic_after;
                cols[i] = v[i].label;
            }
            demo_image *s = demo_contact_sheet(cells, 2, nv, sc->rows, cols, title);
            char path[1024];
            snprintf(path, sizeof path, "%s/%s.png", o->out, sheet);
            if (!s || demo_png_write(path, s)) rc = -1;
            else printf("wrote %s\n", path);
            demo_image_destroy(s);
        }
        free(cells);
        free(cols);
    }
    for (int i = 0; i < nv; i++) {
        demo_image_destroy(results[i].pic_draped);
        demo_image_destroy(results[i].pic_after);
        results[i].pic_draped = results[i].pic_after = NULL;
    }
    demo_render_shutdown();
    return rc;
}

double drape_strain_allowance(const cloth_solver *sv, double delta)
{
    return sv->nonlinear == CLOTH_NEWTON ? sv->limit_tolerance * (1.0 + delta) : 1e-4;
}

int drape_check_common(const demo_opts *o, const drape_variant *v, const drape_result *r)
{
    (void)o;
    int failed = 0;
    double pen = fmax(r->draped.max_penetration, r->after.max_penetration);
    double strain = fmax(r->draped.max_strain, r->after.max_strain);
    failed += demo_claim(pen < r->thickness, "%s: max penetration %.2f mm < thickness %.1f mm", v->tag, 1e3 * pen,
                         1e3 * r->thickness);
    failed += demo_claim(strain <= r->delta + r->strain_allow, "%s: max strain %.5f <= delta %.3f (+%g)", v->tag,
                         strain, r->delta, r->strain_allow);
    return failed;
}

/* A run's links yielded if its deepest bend reached its alpha. */
static int yielded(double alpha, const drape_result *r)
{
    return alpha > 0.0 && fmin(r->draped.min_bend, r->after.min_bend) <= alpha;
}

int drape_check_alphas(const double *alphas, const drape_result *r, int n, int graded)
{
    int failed = 0, elastic = -1;
    for (int i = 0; i < n; i++)
        if (alphas[i] == 0.0) elastic = i;
    if (elastic >= 0)
        failed += demo_claim(r[elastic].after.crease_deg < DRAPE_FLAT_DEG && r[elastic].after.plastic_links == 0,
                             "alpha 0: residual crease %.3f deg < %.2f deg, plastic links %d = 0",
                             r[elastic].after.crease_deg, DRAPE_FLAT_DEG, r[elastic].after.plastic_links);
    for (int i = 0; i < n; i++) {
        if (alphas[i] == 0.0) continue;
        double bend = fmin(r[i].draped.min_bend, r[i].after.min_bend);
        if (!graded && !yielded(alphas[i], &r[i])) {
            /* no link ever reached alpha l0: the plastic rule never acted,
             * so the run must be the elastic one, to rounding */
            failed += demo_claim(r[i].after.plastic_links == 0 &&
                                     (elastic < 0 || fabs(r[i].after.crease_deg - r[elastic].after.crease_deg) < 1e-9),
                                 "alpha %g: deepest bend d/l0 %.3f never reached alpha, so no plastic link (%d) and "
                                 "the elastic run's crease (%.4f deg)",
                                 alphas[i], bend, r[i].after.plastic_links, r[i].after.crease_deg);
            continue;
        }
        if (elastic >= 0)
            failed += demo_claim(r[i].after.crease_deg >
                                     DRAPE_MORE_FACTOR * r[elastic].after.crease_deg + DRAPE_FLAT_DEG,
                                 "alpha %g (deepest bend %.3f): residual crease %.3f deg > %.1f x alpha 0's "
                                 "+ %.1f deg (%.3f deg)",
                                 alphas[i], bend, r[i].after.crease_deg, DRAPE_MORE_FACTOR, DRAPE_FLAT_DEG,
                                 r[elastic].after.crease_deg);
        for (int j = 0; j < n; j++)
            if (alphas[j] > alphas[i] && (graded || yielded(alphas[j], &r[j])))
                failed += demo_claim(r[j].after.crease_deg > r[i].after.crease_deg,
                                     "residual crease grows with alpha: %.3f deg at %g > %.3f deg at %g",
                                     r[j].after.crease_deg, alphas[j], r[i].after.crease_deg, alphas[i]);
    }
    return failed;
}

int drape_check_draped(const double *alphas, const drape_result *r, int n)
{
    int failed = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            if (alphas[j] > alphas[i])
                failed += demo_claim(r[j].draped.crease_deg > r[i].draped.crease_deg,
                                     "draped crease grows with alpha: %.3f deg at %g > %.3f deg at %g",
                                     r[j].draped.crease_deg, alphas[j], r[i].draped.crease_deg, alphas[i]);
    return failed;
}

drape_removal drape_removal_chosen(const demo_opts *o)
{
    return o->removal == 2 ? DRAPE_REMOVE_TWO_CORNERS : DRAPE_REMOVE_FOUR_CORNERS;
}

int drape_scene_material(const demo_opts *o, const demo_scene *sc, cloth_material *m)
{
    if (demo_material(o, CLOTH_SIZE, sc->fabric, m)) return -1;
    if (!demo_fabric_chosen(o, sc->fabric) && !(o->k_b > 0.0) && sc->k_b > 0.0) m->k_b = sc->k_b;
    if (o->memory < 0) m->plastic_memory = sc->memory;
    /* a remembered crease's pull per length of crease is k_s times the spacing: set it, not k_s */
    double grip = o->crease_grip > 0.0 ? o->crease_grip : demo_fabric_chosen(o, sc->fabric) ? sc->crease_grip : 0.0;
    if (grip > 0.0 && m->plastic_memory) m->k_s = grip * (o->grid - 1) / CLOTH_SIZE;
    return 0;
}

int drape_alpha_main(int argc, char **argv, const char *prog, const char *usage, const demo_scene *sc,
                     const double *default_alphas, int ndefault, const char *title)
{
    demo_opts o;
    int p = demo_begin(&o, prog, usage, argc, argv);
    if (p) return p == 1 ? 0 : 2;
    if (o.selftest) return demo_metrics_selftest() ? 1 : 0;
    double alphas[DEMO_MAX_ALPHAS];
    int n = demo_alphas(&o, default_alphas, ndefault, alphas);
    drape_variant v[DEMO_MAX_ALPHAS];
    drape_result r[DEMO_MAX_ALPHAS];
    memset(v, 0, sizeof v);
    cloth_material m;
    if (drape_scene_material(&o, sc, &m)) return 1;
    for (int i = 0; i < n; i++) {
        v[i].material = m;
        v[i].material.alpha = alphas[i];
        v[i].removal = drape_removal_chosen(&o);
        snprintf(v[i].label, sizeof v[i].label, "alpha %g", alphas[i]);
        snprintf(v[i].tag, sizeof v[i].tag, "alpha%g", alphas[i]);
    }
    if (drape_run_all(&o, sc, v, n, r, prog, title)) return 1;
    if (!o.check) return 0;
    int failed = 0;
    for (int i = 0; i < n; i++) failed += drape_check_common(&o, &v[i], &r[i]);
    failed += drape_check_alphas(alphas, r, n, sc->graded);
    if (sc->draped_graded) failed += drape_check_draped(alphas, r, n);
    printf("%s: %d check(s) failed\n", o.prog, failed);
    return failed ? 1 : 0;
}

int drape_material_variants(const demo_opts *o, drape_variant *v)
{
    int n = o->nalpha ? o->nalpha : 1;
    for (int i = 0; i < n; i++) {
        memset(&v[i], 0, sizeof v[i]);
        v[i].material = cloth_material_preset(o->material);
        if (o->nalpha) v[i].material.alpha = o->alphas[i];
        if (o->k_b > 0.0) v[i].material.k_b = o->k_b;
        if (o->memory >= 0) v[i].material.plastic_memory = o->memory;
        snprintf(v[i].label, sizeof v[i].label, "%s, alpha %g", o->material_name, v[i].material.alpha);
        snprintf(v[i].tag, sizeof v[i].tag, "alpha%g", v[i].material.alpha);
    }
    return n;
}

dClothID demo_hang_cloth(const demo_opts *o, const drape_variant *v, demo_contacts *w, dSpaceID space, dClothDesc *d,
                         drape_result *r)
{
    d->cloth.axis_u[0] = 1, d->cloth.axis_u[1] = 0, d->cloth.axis_u[2] = 0;
    d->cloth.axis_v[0] = 0, d->cloth.axis_v[1] = 0, d->cloth.axis_v[2] = -1;
    d->cloth.material = v->material;
    r->delta = v->material.delta;
    r->strain_allow = drape_strain_allowance(&d->cloth.solver, r->delta);
    r->thickness = d->thickness;
    dClothID c = NULL;
    cloth_error err;
    if (dClothCreate(w->world, space, d, &c, &err) != CLOTH_OK) {
        fprintf(stderr, "%s: %s\n", o->prog, err.message);
        return NULL;
    }
    return c;
}

int demo_scene_step(const demo_opts *o, const drape_variant *v, demo_contacts *w, dSpaceID space, dClothID *c,
                    const demo_camera *cam, double h, int s, int steps, int *next_frame, demo_metrics *run)
{
    dSpaceCollide(space, w, demo_near_callback);
    if (demo_step(o, w->world, c, 1, h, s)) return -1;
    dJointGroupEmpty(w->contacts);
    demo_track_step(*c, run);
    demo_frame_hook(o, v->tag, s + 1, steps, next_frame, cam, space, c, 1);
    demo_view_frame(o, v->label, s + 1, steps, cam, space, c, 1);
    return 0;
}

void demo_scene_free(demo_moment *k, dClothID c, demo_contacts *w, dSpaceID space)
{
    demo_moment_free(k);
    dClothDestroy(c);
    dJointGroupDestroy(w->contacts);
    dSpaceDestroy(space);
    dWorldDestroy(w->world);
}

int drape_material_main(const demo_opts *o, const demo_scene *s, const char *title, drape_report_fn report)
{
    drape_variant v[DEMO_MAX_ALPHAS];
    drape_result r[DEMO_MAX_ALPHAS];
    if (o->fabric || o->crease_grip > 0.0 || o->crease_law > 0.0) {
        fprintf(stderr,
                "%s: --fabric, --crease-grip and --crease-law are drape_table's, drape_sphere's and crumple's; "
                "use --material\n",
                o->prog);
        return 2;
    }
    int n = drape_material_variants(o, v), failed = 0;
    for (int i = 0; i < n; i++) {
        /* one run at a time: what a run keeps for report is the last run's */
        if (drape_run_all(o, s, &v[i], 1, &r[i], s->name, title)) return 1;
        int own = report(o, &v[i], &r[i]);
        if (o->check) failed += drape_check_common(o, &v[i], &r[i]) + own;
    }
    if (o->check) printf("%s: %d check(s) failed\n", s->name, failed);
    return failed ? 1 : 0;
}

int demo_moment_init(demo_moment *k, dClothID c)
{
    k->state = cloth_state_create(dClothGetCore(c));
    k->value = -INFINITY;
    memset(k->body_at, 0, sizeof k->body_at);
    if (!k->state) fprintf(stderr, "out of memory for a cloth state\n");
    return k->state ? 0 : -1;
}

void demo_moment_free(demo_moment *k)
{
    cloth_state_destroy(k->state);
    k->state = NULL;
}

void demo_moment_offer(demo_moment *k, double value, dClothID c, dBodyID b, const demo_metrics *run, double t0,
                       demo_metrics *m)
{
    if (!(value > k->value)) return;
    k->value = value;
    cloth_save(dClothGetCore(c), k->state);
    if (b) memcpy(k->body_at, dBodyGetPosition(b), sizeof k->body_at);
    *m = *run;
    m->wall = demo_now() - t0;
    demo_measure_shape(c, 0.0, m);
}

void demo_moment_finish(const demo_opts *o, const demo_scene *sc, const drape_variant *v, demo_moment *k, dClothID c,
                        dBodyID b, dSpaceID space, const demo_camera *cam, const demo_metrics *run, double t0,
                        drape_result *r)
{
    r->after = *run;
    r->after.wall = demo_now() - t0;
    demo_measure_shape(c, 0.0, &r->after);
    char name[120];
    snprintf(name, sizeof name, "%s_%s", v->tag, sc->tags[1]);
    demo_save_frame(o, name, cam, space, &c, 1, &r->pic_after);
    cloth_restore(dClothGetCore(c), k->state);
    if (b) dBodySetPosition(b, k->body_at[0], k->body_at[1], k->body_at[2]);
    snprintf(name, sizeof name, "%s_%s", v->tag, sc->tags[0]);
    demo_save_frame(o, name, cam, space, &c, 1, &r->pic_draped);
}
