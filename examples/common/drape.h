/* The drape-and-remove experiment of the paper (section 5, Fig. 7-9), shared
 * by drape_table, drape_sphere and fabrics.
 *
 * A square cloth (1 m, --grid N nodes a side) falls from 5 cm above a
 * collider standing on a floor plane (a table 0.55 x 0.55, 0.6 high; or a
 * sphere of radius 0.25 on a thin post, its top at 0.8 m) and settles for
 * 4 s ("draped"). Then a scripted timeline, with the four corners pinned to
 * world points moved every step (each phase 1.5 s, a smoothstep in time):
 *   unwrap  corners to 97% of the flat square's corners, 2 cm above the top
 *   lift    straight up to 1.4 m (the cloth comes off as a shallow dish)
 *   gather  corners drawn in to 80% of the flat spacing (slack for carrying)
 *   carry   1 m sideways, clear of the collider
 *   spread  corners to the flat square's corners, 0.35 m up
 *   lower   corners onto the floor (a thickness above it)
 * then the corners are released and the cloth settles for 4 s ("after
 * removal"). --removal two takes it off as a person does instead: two
 * corners of one edge lifted 0.9 m apart to 1.5 m, carried clear, lowered
 * till the free edge touches the floor, tilted 45 degrees ahead and laid
 * down along that line (3 s, with 3% slack), then let go.
 * --short: 2.5 s settles and 1 s phases. A variant may set the
 * drape's own length (hold) and drape more than once (folds): before each
 * drape after the first the cloth is lifted off (unwrap, lift) and laid
 * back flat 5 cm over the collider (relay), then let go.
 *
 * The table is a triangle mesh (the paper's own collision: cloth vertices
 * against the body's triangles, and here the triangles against the cloth's
 * too). With ODE's box geom (--box-table: vertex plus libccd triangle
 * contacts) the drape is clean and the cloth lifts off over the box's edges
 * at the elongation limit (strain 0.0300 at cotton's k_b; CTest
 * demo_drape_table_box).
 *
 * Material (drape_table, drape_sphere; drape_alpha_main): cotton (Table 1)
 * with two changes, each overridable: bending k_b DRAPE_BENDING (--bending)
 * in place of the preset's 20 N/m, and plastic memory on (--memory,
 * material.plastic_memory). k_b 20 never bends a link below d/l0 0.89 here
 * (no crease at alpha 0.5 or 0.8); real light cotton at this 5 cm spacing
 * is estimated at 0.005-0.02 N/m (docs/demos.md); 0.05 is the softest
 * tried that keeps penetration well under the thickness (docs/demos.md).
 * Memory lets a crease that the spread
 * opens re-form once let go (the paper's "creases remain even after a brief
 * covering"); with the paper's per-step rule the spread erases them all.
 * --fabric NAME takes the fabric in physical units instead (no k_b
 * override); with memory a crease's pull is then set per length of crease,
 * k_s = crease_grip / spacing (--crease-grip), as k_s alone is not the same at every grid. */
#define DRAPE_FLAT_DEG 0.5    /* alpha 0: mean residual crease below this   */
#define DRAPE_MORE_FACTOR 1.5 /* "clearly more": by this factor             */
#define DRAPE_BENDING 0.05    /* k_b N/m of drape_table / drape_sphere      */
#define DRAPE_GRIP 0.04       /* N: crease_grip of drape_table / drape_sphere */
#ifndef ODECLOTH_EXAMPLES_DRAPE_H
#define ODECLOTH_EXAMPLES_DRAPE_H

#include "demo.h"

/* A box as a triangle mesh (12 triangles) centred on its geom's position:
 * what the demos use for tables and plates (the press between ODE box plates
 * still fails a step, README). The vertices live here, as ODE keeps
 * pointers to them. */
typedef struct demo_box_mesh {
    double v[8][3];
    dTriMeshDataID data;
    dGeomID geom;
} demo_box_mesh;
dGeomID demo_box_mesh_create(demo_box_mesh *m, dSpaceID space, double lx, double ly, double lz);
void demo_box_mesh_destroy(demo_box_mesh *m); /* the geom and its data */

typedef enum drape_collider { DRAPE_TABLE, DRAPE_SPHERE } drape_collider;

typedef enum drape_removal {
    DRAPE_REMOVE_FOUR_CORNERS = 0, /* the paper's: spread flat by four corners, lowered */
    DRAPE_REMOVE_TWO_CORNERS       /* a person's: by two corners, laid down edge first  */
} drape_removal;

typedef struct drape_variant {
    char label[48]; /* column label ("alpha 0.5", "wool")      */
    char tag[48];   /* file name part ("alpha0.5", "wool")     */
    cloth_material material;
    double hold;           /* s the cloth stays draped before removal
                                (drape_run; 0: the scene's settle)       */
    int folds;             /* drape_run: drapes before the removal, each
                                after the first lifted off and laid back
                                flat over the collider (0 or 1: once)   */
    drape_removal removal; /* drape_run: how the cloth is taken off    */
} drape_variant;

typedef struct drape_result {
    demo_metrics draped;                /* at the end of the drape (first picture)  */
    demo_metrics after;                 /* settled after removal (second picture)   */
    double delta;                       /* the material's elongation limit          */
    double strain_allow;                /* past delta, what the step guarantees      */
    double thickness;                   /* m                                        */
    demo_image *pic_draped, *pic_after; /* NULL without pictures         */
} drape_result;

/* A two-picture experiment run per variant: drape and removal here; the
 * crumple demo's press and release too. */
typedef struct demo_scene demo_scene;
struct demo_scene {
    const char *name;    /* "table", ...                                     */
    const char *rows[2]; /* picture labels: "draped", "after removal"        */
    const char *tags[2]; /* file and CSV names: "draped", "after"            */
    drape_collider col;  /* for drape_run                                    */
    /* 0 on success, -1 if a step failed (message printed) */
    int (*run)(const demo_opts *o, const demo_scene *s, const drape_variant *v, drape_result *r);
    /* drape_alpha_main's material, unless --fabric / --material / --bending / --memory say otherwise */
    double k_b; /* N/m bending in place of the preset's (not a fabric's); 0 = the preset's */
    int memory; /* material.plastic_memory                              */
    /* drape_check_alphas: 1 = every alpha > 0 must crease clearly more than
     * alpha 0 and less than every larger alpha (the paper's graded claim);
     * 0 = a run that never yielded may instead equal the elastic run */
    int graded;
    int fabric;         /* drape_alpha_main: 1 + the cloth_fabric_kind by default; 0 = the --material preset */
    double crease_grip; /* N: with a fabric and plastic memory, k_s = crease_grip / spacing (0: the fabric's) */
    int draped_graded;  /* drape_alpha_main: 1 = drape_check_draped too */
};

/* The drape-and-remove run of one variant (a demo_scene's run). */
int drape_run(const demo_opts *o, const demo_scene *s, const drape_variant *v, drape_result *r);
extern const demo_scene drape_table_scene, drape_sphere_scene;
/* The press-and-release run (examples/crumple.c, common/press.c). */
extern const demo_scene press_scene;

/* Run every variant, print the metrics, write the contact sheet
 * <out>/<sheet>.png (columns: variants; rows: the scene's two pictures) and
 * the CSV rows. results has nv entries; the pictures are freed. 0, or -1
 * on a failure. */
int drape_run_all(const demo_opts *o, const demo_scene *s, const drape_variant *v, int nv, drape_result *results,
                  const char *sheet, const char *title);

/* What a step guarantees past the elongation limit delta, in strain: the
 * projection's rounding (1e-4), or Newton's limit_tolerance of the limit. */
double drape_strain_allowance(const cloth_solver *sv, double delta);

/* The claims common to every drape: no vertex past the thickness into a
 * body (max penetration < thickness) and max strain within delta plus the
 * step's allowance. Prints each; returns the number failed. */
int drape_check_common(const demo_opts *o, const drape_variant *v, const drape_result *r);

/* The paper's claim on runs that differ only in alpha (alphas[i] -> r[i]):
 *  - alpha 0 leaves a near-flat cloth: mean crease < DRAPE_FLAT_DEG, no
 *    plastic link;
 *  - every run with alpha > 0 leaves clearly more crease than alpha 0
 *    (DRAPE_MORE_FACTOR times it + DRAPE_FLAT_DEG), and less than every
 *    larger alpha;
 *  - unless graded (the scene's flag): a run whose links never yielded (its
 *    deepest bend d / l0 stayed above its alpha) may instead be the elastic
 *    run: no plastic link, and the same residual crease as alpha 0 to 1e-9
 *    deg (the plastic rule never acted), and is left out of the ordering.
 * Prints each; returns the number failed. */
int drape_check_alphas(const double *alphas, const drape_result *r, int n, int graded);

/* The removal --removal asks for; four corners (the paper's) by default. */
drape_removal drape_removal_chosen(const demo_opts *o);

/* Graded while draped: every larger alpha's mean crease at the end of the
 * drape above every smaller one's. Prints each; returns the number failed. */
int drape_check_draped(const double *alphas, const drape_result *r, int n);

/* The scene's material as drape_alpha_main runs it: the options' (demo_material)
 * with the scene's fabric as default, its k_b on a --material preset without
 * --bending, and its memory without --memory. 0, or -1 (message printed). */
int drape_scene_material(const demo_opts *o, const demo_scene *sc, cloth_material *m);

/* main() of drape_table and drape_sphere: one variant per alpha (the
 * --material preset otherwise; defaults when no --alpha), the sheet <prog>.png,
 * and with --check the common claims and drape_check_alphas. Returns the
 * exit status. */
int drape_alpha_main(int argc, char **argv, const char *prog, const char *usage, const demo_scene *s,
                     const double *default_alphas, int ndefault, const char *title);

/* Variants for the one-material demos (trampoline, curtain): the
 * --material preset, once per --alpha, or once at its own alpha. Returns n. */
int drape_material_variants(const demo_opts *o, drape_variant *v);

/* main() of the one-material demos (trampoline, curtain, flag) after
 * demo_begin: each variant run alone, the sheet <scene name>.png; report
 * prints a run's figures and returns how many of its own claims failed
 * (checked only with --check); the common claims are added. Exit status. */
typedef int (*drape_report_fn)(const demo_opts *o, const drape_variant *v, const drape_result *r);
int drape_material_main(const demo_opts *o, const demo_scene *s, const char *title, drape_report_fn report);

/* One step of a one-cloth scene at step s of steps: ODE contacts, the cloth
 * and the world (demo_step), then the run's metrics, frames and live view.
 * 0, or -1 if the step failed (message printed). */
int demo_scene_step(const demo_opts *o, const drape_variant *v, demo_contacts *w, dSpaceID space, dClothID *c,
                    const demo_camera *cam, double h, int s, int steps, int *next_frame, demo_metrics *run);
/* A cloth hanging from its first row (columns along x, rows down -z) at
 * the variant's material, created from d in w's world and space; r gets
 * its delta and thickness. NULL if refused (message printed). */
dClothID demo_hang_cloth(const demo_opts *o, const drape_variant *v, demo_contacts *w, dSpaceID space, dClothDesc *d,
                         drape_result *r);
/* The moment of a run worth a picture besides its end (the deepest sag, the
 * widest swing): the cloth's state, a body's position (b may be NULL: no
 * body), the metrics then. */
typedef struct demo_moment {
    cloth_state *state;
    dReal body_at[3];
    double value; /* the largest offered so far */
} demo_moment;
int demo_moment_init(demo_moment *k, dClothID c); /* -1 on no memory */
void demo_moment_free(demo_moment *k);
/* Keep this moment if value is the largest yet: the cloth's state, b's
 * position, and `run` (the metrics so far, wall time since t0, the cloth's
 * shape now) into *m. */
void demo_moment_offer(demo_moment *k, double value, dClothID c, dBodyID b, const demo_metrics *run, double t0,
                       demo_metrics *m);
/* At the end of a run: r->after = run (shape now, wall since t0), its
 * picture <tag>_<tags[1]>; then the kept moment put back (cloth and body)
 * and its picture <tag>_<tags[0]>. */
void demo_moment_finish(const demo_opts *o, const demo_scene *sc, const drape_variant *v, demo_moment *k, dClothID c,
                        dBodyID b, dSpaceID space, const demo_camera *cam, const demo_metrics *run, double t0,
                        drape_result *r);

/* The scene's teardown: the kept moment, the cloth, the contact group, the
 * space and the world. */
void demo_scene_free(demo_moment *k, dClothID c, demo_contacts *w, dSpaceID space);

/* Print a check line ("check ok" / "check FAILED") and return !ok. */
int demo_claim(int ok, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

#endif
