/* What the scripted demos (examples/drape_table.c and friends) share: an
 * option parser, an RGB image with a PNG writer, a small bitmap font and a
 * contact-sheet composer, an offscreen OpenGL renderer (OSMesa) of a cloth
 * and the geoms of an ODE space, an OBJ writer, and the metrics every demo
 * prints (residual crease, wrinkles, plastic links, penetration, strain).
 * The --view window (GLFW) is view.h's; it draws with the renderer's code.
 *
 * Without OSMesa or libpng at build time everything still builds:
 * demo_render_available() / demo_png_available() say so, and the demos
 * print their metrics only, with a message saying why there are no pictures.
 */
#ifndef ODECLOTH_EXAMPLES_DEMO_H
#define ODECLOTH_EXAMPLES_DEMO_H

#include <stdio.h>
#include "odecloth/dcloth.h"

/* ---------------------------------------------------------------- options */

#define DEMO_MAX_ALPHAS 8

typedef struct demo_opts {
    const char *prog; /* program name, for messages            */
    double alphas[DEMO_MAX_ALPHAS];
    int nalpha;       /* 0: the demo's default list            */
    int material_set; /* --material given                      */
    cloth_preset material;
    const char *material_name;
    int fabric; /* --fabric: 1 + the cloth_fabric_kind, derived
                                     for the grid's spacing; 0 = none given */
    const char *fabric_name;
    double self_thickness; /* --self-collision T: m, cloth against itself
                                     (odecloth/selfcollision.h); 0 = off       */
    double k_b;            /* --bending K: N/m, replaces the preset's
                                     interlaced stiffness k_b (0: the preset's) */
    double crease_grip;    /* --crease-grip G: N, with plastic memory a
                                     crease's pull k_s = G / spacing (0: the demo's) */
    double crease_law;     /* --crease-law S: N, material.k_crease = 2 S /
                                     spacing (0: the demo's)                */
    int removal;           /* --removal: 1 four corners (the paper's),
                                     2 two corners (a person's); 0 = the demo's */
    int memory;            /* --memory 0|1: material.plastic_memory
                                     (-1: the demo's default)               */
    int grid;              /* nodes per side (--grid N)             */
    double hz;             /* steps per second                      */
    int hz_set;            /* --steps-per-second given              */
    const char *out;       /* directory for pictures and OBJ files  */
    int obj;               /* --obj: an OBJ per saved frame          */
    int frames;            /* --frames K: K extra evenly spaced frames */
    int check;             /* --check: assert the demo's claims      */
    int short_run;         /* --short: a shorter timeline            */
    const char *csv;       /* --csv FILE: append one row per run      */
    int smooth;            /* display subdivision levels (0-3)       */
    int width, height;     /* picture size in pixels                 */
    int images;            /* 0 with --no-images                     */
    int trace;             /* --trace: print every step's stats      */
    int phases;            /* --phases: a line per scripted phase    */
    int box_table;         /* --box-table: the table as a dBox       */
    int selftest;          /* --selftest: check the metrics, exit    */
    int sleep;             /* --sleep: dClothSetAutoSleep (1 cm/s, 10 steps) */
    int solver;            /* --solver: 0 the library's default, else
                                     1 + the cloth_nonlinear chosen           */
    int view;              /* --view: a live window (view.h)         */
    int view_frames;       /* --view-frames N: close it after N frames
                                     (0: when the user closes it)          */
    int video;             /* --video: each run as <out>/<tag>.mp4    */
} demo_opts;

/* Defaults: grid 21, 60 steps/s, out "out/<prog>", smooth 1, 400 x 300,
 * cotton. Parses argv; on --help prints the common options after `usage`
 * and returns 1 (exit 0); on a bad option or value prints why and returns 2
 * (exit 2); else 0. No other side effect. */
int demo_parse(demo_opts *o, const char *prog, const char *usage, int argc, char **argv);
/* What a demo's main calls: demo_parse, and when it returns 0 ODE's
 * initialisation (dInitODE2, with dCloseODE at exit). Same returns. */
int demo_begin(demo_opts *o, const char *prog, const char *usage, int argc, char **argv);
/* The fabric in use (1 + cloth_fabric_kind; 0: the --material preset):
 * --fabric, else none if --material was given, else the demo's default. */
int demo_fabric_chosen(const demo_opts *o, int fabric_default);
/* Its name ("cotton"), "" for 0. */
const char *demo_fabric_name(int fabric);
/* The material the options ask for, a square cloth of `size` m, o->grid nodes a side: the fabric
 * derived for that spacing (cloth_fabric_material), else the --material preset; then --bending and
 * --memory. 0, or -1 with the reason printed (a grid too fine for the fabric). */
int demo_material(const demo_opts *o, double size, int fabric_default, cloth_material *out);
/* The plugin's default descriptor with the demo's --solver applied. */
dClothDesc demo_desc(const demo_opts *o);
/* The alphas asked for, or the defaults given (n of them). */
int demo_alphas(const demo_opts *o, const double *defaults, int n, double *out);
/* Create o->out (and its parents); 0 on success, else prints why. */
int demo_make_out_dir(const demo_opts *o);
/* Seconds on a monotonic clock. */
double demo_now(void);
/* 3t^2 - 2t^3 on [0, 1], clamped: the scripted motions' easing. */
double demo_smoothstep(double t);

/* ------------------------------------------------------------------ image */

typedef struct demo_image {
    int w, h;
    unsigned char *rgb; /* 3 bytes a pixel, row 0 at the top */
} demo_image;

demo_image *demo_image_create(int w, int h, const unsigned char bg[3]); /* NULL on no memory */
void demo_image_destroy(demo_image *im);
int demo_png_available(void);
/* 0 on success; else prints why (no libpng, cannot open, ...) and returns -1. */
int demo_png_write(const char *path, const demo_image *im);
/* Text in the labels' font (font.c), its capitals 7 * scale pixels tall
 * with their top at y, starting at x; clipped to the image. Returns the
 * width (0 without a font: no labels, said once on stderr). */
int demo_text(demo_image *im, int x, int y, int scale, const unsigned char rgb[3], const char *s);
int demo_text_width(int scale, const char *s);
/* Copy src into dst with its top-left at (x, y), clipped. */
void demo_blit(demo_image *dst, const demo_image *src, int x, int y);
/* A grid of rows x cols cells (cells[r * cols + c], NULL: blank) with a
 * title, column labels on top and row labels on the left. NULL on no memory. */
demo_image *demo_contact_sheet(const demo_image *const *cells, int rows, int cols, const char *const *row_labels,
                               const char *const *col_labels, const char *title);

/* --------------------------------------------------------------- renderer */

typedef struct demo_camera {
    double eye[3], target[3]; /* z up */
    double fov_deg;           /* vertical field of view */
} demo_camera;

/* A geom whose data is this pointer is not drawn (a plate between the
 * camera and the cloth, say). */
extern const float demo_geom_hidden[3];
/* The direction toward the key light (world, z up, not normalised): the
 * pictures' shadows fall away from it. */
extern const double demo_key_light[3];

int demo_render_available(void);
/* Why pictures are not available ("" if they are). */
const char *demo_render_unavailable_reason(void);
/* Render the cloths and every geom of `space` (plane, box, sphere, capsule,
 * cylinder, trimesh; placeable geoms follow their bodies) into a new image
 * of w x h. smooth: display-only subdivision levels of the cloth mesh (an
 * interpolating four-point scheme on the grid: the simulated vertices stay
 * where they are). NULL (and a message) if rendering is unavailable. */
demo_image *demo_render(const demo_camera *cam, dSpaceID space, dClothID *cloths, int ncloths, int smooth, int w,
                        int h);
/* Free the offscreen context (at exit; harmless if none). */
void demo_render_shutdown(void);
/* What demo_render draws, into the caller's current OpenGL context (the
 * --view window, view.c): clears a w x h viewport and draws the geoms and
 * the cloths from cam. Only in builds with OpenGL (OSMesa or GLFW). 0, or
 * -1 on no memory (printed). */
int demo_draw_scene(const demo_camera *cam, dSpaceID space, dClothID *cloths, int ncloths, int smooth, int w, int h);

/* ---------------------------------------------------------------- metrics */

typedef struct demo_metrics {
    double crease_deg;      /* mean |dihedral angle| over interior edges, deg  */
    double crease_max_deg;  /* largest |dihedral angle|, deg                   */
    double height;          /* m, highest vertex above the floor (z = floor)   */
    int plastic_links;      /* interlaced links in the plastic region           */
    int wrinkles;           /* ridges: see demo_wrinkles                        */
    double max_penetration; /* m, over the whole run (plugin stats)            */
    double deepest_point;   /* m, over the run: max_penetration_all (plugin stats) */
    double max_strain;      /* over the whole run (core stats, after limiting)  */
    double min_bend;        /* deepest bend over the run: smallest d / l0 of an
                              interlaced link (a link yields at d / l0 <= alpha) */
    double wall;            /* s                                                */
    int steps;
} demo_metrics;

/* Mean and max absolute dihedral angle (degrees) over the interior edges of
 * the cloth's triangles (the angle between the two triangles' normals). */
void demo_crease(dClothID c, double *mean_deg, double *max_deg);
/* Wrinkle count: a wrinkle is a connected set of interior edges (joined
 * through shared vertices) each bent by more than threshold_deg and holding
 * at least min_edges edges; isolated kinks are not counted. */
int demo_wrinkles(dClothID c, double threshold_deg, int min_edges);
#define DEMO_WRINKLE_DEG 10.0
#define DEMO_WRINKLE_MIN_EDGES 3
/* Fill the shape metrics of m (crease, height, plastic links, wrinkles)
 * from the cloth as it is now; floor_z is the floor's height. */
void demo_measure_shape(dClothID c, double floor_z, demo_metrics *m);
/* Smallest d / l0 over the interlaced links now. */
double demo_deepest_bend(dClothID c);
/* Fold one step's stats into the run's extremes. */
void demo_track_step(dClothID c, demo_metrics *m);
void demo_print_metrics(FILE *f, const char *label, const demo_metrics *m);
/* Append a CSV row (with a header when the file is new); 0 on success. */
int demo_csv_row(const char *path, const char *demo, const char *label, double alpha, const demo_metrics *m);

/* The crease, wrinkle and bend metrics on a cloth folded by a known angle,
 * against closed forms (metrics.c says which); prints, returns failures. */
int demo_metrics_selftest(void);

/* Write the cloth as a Wavefront OBJ (positions, normals, triangles). */
int demo_write_obj(const char *path, dClothID c);

/* Save what a frame needs: a PNG (when rendering works and o->images) and
 * an OBJ (o->obj), named <out>/<name>.png / .obj. Prints what it wrote.
 * If keep is non-NULL the rendered image is returned through it (the caller
 * frees it), for a contact sheet. Returns 0, or -1 on a write error. */
int demo_save_frame(const demo_opts *o, const char *name, const demo_camera *cam, dSpaceID space, dClothID *cloths,
                    int n, demo_image **keep);

/* --frames K: after step `step` (1-based) of `total`, save frame *next
 * (<tag>_frameNNN) when the run has reached it; K frames evenly spaced.
 * Also --video's hook (demo_video_hook). */
void demo_frame_hook(const demo_opts *o, const char *tag, int step, int total, int *next, const demo_camera *cam,
                     dSpaceID space, dClothID *cloths, int n);

/* ------------------------------------------------------------------ video */

/* --video (video.c): every run of a demo recorded, from the camera of its
 * --frames, as <out>/<tag>.mp4 through ffmpeg (found on PATH). */
int demo_video_fps(void); /* frames per simulated second */
/* Before the runs: 0 if --video is not asked for or can be done; else
 * prints why not (no OSMesa, no ffmpeg on PATH) and returns -1. */
int demo_video_check(const demo_opts *o);
/* After step `step` (1-based) of `total`: the frames due by then. Step 1
 * (or a new tag) starts a recording, step total ends it. */
void demo_video_hook(const demo_opts *o, const char *tag, int step, int total, const demo_camera *cam, dSpaceID space,
                     dClothID *cloths, int n);
/* After a run: ends a recording still open (a run that failed); -1 if any
 * recording failed since the last call (each said why), else 0. */
int demo_video_finish(const demo_opts *o);

/* -------------------------------------------------------------- stepping */

/* The user's own collisions between bodies and geoms (the cloth's are the
 * plugin's): pass as dSpaceCollide(space, &ctx, demo_near_callback) before
 * a step and dJointGroupEmpty(ctx.contacts) after it. */
typedef struct demo_contacts {
    dWorldID world;
    dJointGroupID contacts;
    double mu, bounce;
} demo_contacts;
void demo_near_callback(void *ctx, dGeomID a, dGeomID b);

/* One step of the world and its cloths; on failure (a cloth held after a
 * failed solve included) prints the plugin's message (with the demo's name
 * and the step number) and returns -1. */
int demo_step(const demo_opts *o, dWorldID world, dClothID *cloths, int n, double h, int step);

#endif
