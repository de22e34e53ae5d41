/* The press-and-release experiment (examples/crumple.c describes it): a
 * hanging cloth squeezed by a rising bar and two closing plates, released. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "drape.h"
#include "view.h"

#define TOP_Z 1.3       /* m, the top plate's underside; the cloth hangs from it */
#define PLATE_T 0.04    /* m, plate thickness */
#define PLATE_W 1.2     /* m, along x */
#define PLATE_D 0.04    /* m, along y: bars, so the side plates can close past them */
#define GAP 0.08        /* m, between the plates when pressed */
#define SIDE_H 1.1      /* m, height of the side plates */
#define SIDE_OPEN 0.45  /* m, their inner faces' distance from the cloth's plane, open */
#define SIDE_SHUT 0.03  /* m, and shut */
#define RIPPLE 0.01     /* m, initial out-of-plane ripple */
#define SLIDE 1.4       /* m, how far the bottom plate slides away along x once it lets go */
#define OPEN_LENGTH 0.9 /* m, the plates' gap once they open again (the cloth is 1 m) */

static const float plate_rgb[3] = {0.45f, 0.52f, 0.60f}, side_rgb[3] = {0.70f, 0.74f, 0.78f};

/* The script, by phase: the bottom bar rises (press), the side plates
 * close (squash), both hold, the side plates open, the bottom bar goes back
 * down (pull), lets go of the cloth and slides away, and the cloth hangs. */
enum { PRESS, SQUASH, HOLD, OPEN, PULL, LETGO, HANG, NPHASE };

/* Where the script has the bottom plate's top face (z) and the side
 * plates' inner faces (|y|) at time t. */
static void plates_at(const double *dur, double t, double *bottom, double *side, double *slide)
{
    double start[NPHASE + 1] = {0};
    for (int p = 0; p < NPHASE; p++) start[p + 1] = start[p] + dur[p];
    double lo = TOP_Z - 1.0, hi = TOP_Z - GAP;
    *bottom = lo + (hi - lo) * demo_smoothstep(t / dur[PRESS]);
    *side = SIDE_OPEN + (SIDE_SHUT - SIDE_OPEN) * demo_smoothstep((t - start[SQUASH]) / dur[SQUASH]);
    if (t > start[OPEN]) *side = SIDE_SHUT + (SIDE_OPEN - SIDE_SHUT) * demo_smoothstep((t - start[OPEN]) / dur[OPEN]);
    if (t > start[PULL]) *bottom = hi + (TOP_Z - OPEN_LENGTH - hi) * demo_smoothstep((t - start[PULL]) / dur[PULL]);
    *slide = t > start[LETGO] ? SLIDE * demo_smoothstep((t - start[LETGO]) / dur[LETGO]) : 0.0;
}

/* Whether segment [a, b] (relative to the box's centre) passes through the
 * axis-aligned box of half sides e with neither end inside it. */
static int through_box(const double *a, const double *b, const double e[3])
{
    double t0 = 0.0, t1 = 1.0;
    int ina = 1, inb = 1;
    for (int k = 0; k < 3; k++) {
        ina = ina && fabs(a[k]) < e[k];
        inb = inb && fabs(b[k]) < e[k];
    }
    for (int k = 0; k < 3 && !ina && !inb && t0 <= t1; k++) {
        double d = b[k] - a[k];
        if (d == 0.0) {
            if (fabs(a[k]) >= e[k]) return 0;
            continue;
        }
        double u0 = (-e[k] - a[k]) / d, u1 = (e[k] - a[k]) / d;
        t0 = fmax(t0, fmin(u0, u1));
        t1 = fmin(t1, fmax(u0, u1));
    }
    return !ina && !inb && t0 <= t1;
}

/* How many sequential links of the C x C cloth pass through the unrotated
 * kinematic bar: those with an end in the bottom row never, those with an
 * end in the top row only if `top` (a link through the top bar's edge). */
static int links_through_bar(dClothID c, int C, dBodyID bar, int top)
{
    const double e[3] = {PLATE_W / 2, PLATE_D / 2, PLATE_T / 2};
    const dReal *p = dBodyGetPosition(bar), *x = dClothGetPositions(c);
    const cloth *core = dClothGetCore(c);
    int n = 0;
    for (int k = 0, nl = cloth_link_count(core, CLOTH_SEQUENTIAL); k < nl; k++) {
        cloth_link L;
        cloth_get_link(core, CLOTH_SEQUENTIAL, k, &L);
        if ((!top && L.i < C) || L.j >= (C - 1) * C) continue;
        double a[3], b[3];
        for (int r = 0; r < 3; r++) a[r] = x[3 * L.i + r] - p[r], b[r] = x[3 * L.j + r] - p[r];
        n += through_box(a, b, e);
    }
    return n;
}

/* Link-steps through a bar, the steps with any, the most at once, the first */
typedef struct threading {
    int sum, steps, most, first;
} threading;

static void threading_add(threading *t, int m, int step)
{
    t->sum += m;
    t->steps += m > 0;
    if (m > t->most) t->most = m;
    if (m > 0 && t->first < 0) t->first = step;
}

static void threading_print(const char *tag, const char *bar, const threading *t)
{
    printf("%-8s links through the %s: %d link-steps in %d steps (at most %d at once, the first at step %d)\n", tag,
           bar, t->sum, t->steps, t->most, t->first);
}

static int press_run(const demo_opts *o, const demo_scene *sc, const drape_variant *v, drape_result *r)
{
    memset(r, 0, sizeof *r);
    const double h = 1.0 / o->hz;
    /* --short shortens the final hang only: pressing faster than this
     * fails steps (the squeezed cloth overstretches) */
    const double dur[NPHASE] = {2.0, 2.0, 0.5, 0.8, 2.5, 1.0, o->short_run ? 2.5 : 4.0};
    int n_pressed = (int)lround((dur[PRESS] + dur[SQUASH] + dur[HOLD]) * o->hz);
    int n_letgo = n_pressed + (int)lround((dur[OPEN] + dur[PULL]) * o->hz);
    int n_total = n_letgo + (int)lround((dur[LETGO] + dur[HANG]) * o->hz);
    dWorldID world = dWorldCreate();
    dWorldSetGravity(world, 0, 0, -9.81);
    dSpaceID space = dHashSpaceCreate(0);
    /* 0 top, 1 bottom (horizontal); 2 at -y, 3 at +y (upright) */
    dBodyID plate[4];
    dGeomID pg[4];
    demo_box_mesh mesh[4];
    memset(mesh, 0, sizeof mesh);
    const double size[4][3] = {{PLATE_W, PLATE_D, PLATE_T},
                               {PLATE_W, PLATE_D, PLATE_T},
                               {PLATE_W, PLATE_T, SIDE_H},
                               {PLATE_W, PLATE_T, SIDE_H}};
    for (int k = 0; k < 4; k++) {
        plate[k] = dBodyCreate(world);
        dBodySetKinematic(plate[k]);
        dGeomID g = o->box_table ? dCreateBox(space, size[k][0], size[k][1], size[k][2])
                                 : demo_box_mesh_create(&mesh[k], space, size[k][0], size[k][1], size[k][2]);
        dGeomSetBody(g, plate[k]);
        pg[k] = g;
        /* the plate between the camera and the cloth is not drawn */
        dGeomSetData(g, (void *)(k < 2 ? plate_rgb : k == 2 ? demo_geom_hidden : side_rgb));
    }
    double bottom, side, slide;
    plates_at(dur, 0, &bottom, &side, &slide);
    dBodySetPosition(plate[0], 0, 0, TOP_Z + PLATE_T / 2);
    dBodySetPosition(plate[1], 0, 0, bottom - PLATE_T / 2);
    dBodySetPosition(plate[2], 0, -(side + PLATE_T / 2), TOP_Z - SIDE_H / 2);
    dBodySetPosition(plate[3], 0, side + PLATE_T / 2, TOP_Z - SIDE_H / 2);
    dClothDesc d = demo_desc(o);
    d.cloth.rows = d.cloth.cols = o->grid;
    /* hanging: rows run down from the top plate, columns along x */
    d.cloth.origin[0] = -0.5;
    d.cloth.origin[1] = 0;
    d.cloth.origin[2] = TOP_Z - d.thickness;
    d.cloth.axis_u[0] = 1, d.cloth.axis_u[1] = 0, d.cloth.axis_u[2] = 0;
    d.cloth.axis_v[0] = 0, d.cloth.axis_v[1] = 0, d.cloth.axis_v[2] = -1;
    d.cloth.height = 1.0 - 2 * d.thickness;
    d.cloth.material = v->material;
    d.mu = 0.0; /* smooth plates: the squeezed cloth slides along them */
    r->delta = v->material.delta;
    r->strain_allow = drape_strain_allowance(&d.cloth.solver, r->delta);
    r->thickness = d.thickness;
    dClothID c = NULL;
    cloth_error err;
    int rc = -1;
    if (dClothCreate(world, space, &d, &c, &err) != CLOTH_OK) {
        fprintf(stderr, "%s: %s\n", o->prog, err.message);
        goto done;
    }
    /* The mesh plates give vertex contacts only: with their triangle tests
     * on, as with ODE's box plates (--box-table), the cloth squashed between
     * them fails a step (docs/demos.md) */
    for (int k = 0; k < 4 && !o->box_table; k++) dClothSetTriangleTests(c, pg[k], 0);
    /* a small out-of-plane ripple (3 half waves down the cloth, 1 cm), so
     * the squeezed cloth buckles into an accordion rather than folding
     * flat in its own plane */
    const int C = o->grid;
    double *x0 = malloc(3 * (size_t)C * C * sizeof *x0);
    if (!x0) {
        fprintf(stderr, "%s: out of memory\n", o->prog);
        goto done;
    }
    memcpy(x0, dClothGetPositions(c), 3 * (size_t)C * C * sizeof *x0);
    for (int row = 0; row < C; row++)
        for (int col = 0; col < C; col++) x0[3 * (row * C + col) + 1] += RIPPLE * sin(3 * M_PI * row / (C - 1));
    cloth_set_positions(dClothGetCore(c), x0);
    free(x0);
    /* the top row held by the top plate, the bottom row by the bottom one */
    const dReal *x = dClothGetPositions(c);
    for (int col = 0; col < C; col++)
        for (int k = 0; k < 2; k++) {
            int i = k ? (C - 1) * C + col : col;
            const dReal *p = dBodyGetPosition(plate[k]);
            dReal local[3] = {x[3 * i] - p[0], x[3 * i + 1] - p[1], x[3 * i + 2] - p[2]};
            dClothPinToBody(c, i, plate[k], local);
        }
    const demo_camera cam = {{0.9, -1.7, 1.15}, {0, 0, 0.8}, 40};
    demo_metrics run = {0};
    int next_frame = 1;
    threading bar = {0, 0, 0, -1}, top = {0, 0, 0, -1};
    double t0 = demo_now();
    for (int s = 0; s < n_total; s++) {
        /* the plates' velocities for this step: to where the script has
         * them at its end (ODE moves kinematic bodies by their velocity) */
        if (s == n_letgo) dClothReleaseBody(c, plate[1]); /* the bottom row hangs free */
        plates_at(dur, (s + 1) * h, &bottom, &side, &slide);
        const dReal *pb = dBodyGetPosition(plate[1]);
        dBodySetLinearVel(plate[1], (slide - pb[0]) / h, 0, (bottom - PLATE_T / 2 - pb[2]) / h);
        for (int k = 2; k < 4; k++) {
            double y = (k == 2 ? -1 : 1) * (side + PLATE_T / 2);
            dBodySetLinearVel(plate[k], 0, (y - dBodyGetPosition(plate[k])[1]) / h, 0);
        }
        if (demo_step(o, world, &c, 1, h, s)) goto done;
        demo_track_step(c, &run);
        if (s < n_letgo) { /* while the bar holds the cloth */
            threading_add(&bar, links_through_bar(c, C, plate[1], 0), s + 1);
            threading_add(&top, links_through_bar(c, C, plate[0], 1), s + 1);
        }
        demo_frame_hook(o, v->tag, s + 1, n_total, &next_frame, &cam, space, &c, 1);
        demo_view_frame(o, v->label, s + 1, n_total, &cam, space, &c, 1);
        if (s + 1 == n_pressed || s + 1 == n_total) {
            int last = s + 1 == n_total;
            demo_metrics *m = last ? &r->after : &r->draped;
            *m = run;
            m->wall = demo_now() - t0;
            demo_measure_shape(c, 0.0, m);
            char name[120];
            snprintf(name, sizeof name, "%s_%s", v->tag, sc->tags[last]);
            demo_save_frame(o, name, &cam, space, &c, 1, last ? &r->pic_after : &r->pic_draped);
        }
    }
    threading_print(v->tag, "bar", &bar);
    threading_print(v->tag, "top bar", &top);
    rc = 0;
done:
    dClothDestroy(c);
    for (int k = 0; k < 4; k++) demo_box_mesh_destroy(&mesh[k]);
    dSpaceDestroy(space);
    dWorldDestroy(world);
    return rc;
}

const demo_scene press_scene =
    {"plates", {"pressed", "released"}, {"pressed", "released"}, DRAPE_TABLE, press_run, 0.0, 0, 0, 0, 0.0, 0};
