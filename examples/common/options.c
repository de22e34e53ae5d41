/* The option parser every demo shares. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include "cli.h"
#include "demo.h"

static const char common_usage[] =
    "common options:\n"
    "  --alpha A[,B...]       plastic yield ratio(s) in [0, 1], one run each\n"
    "  --material NAME        cotton | wool | elastic (Table 1 presets, per-link springs)\n"
    "  --fabric NAME          cotton | wool | silk | denim | polyester: a fabric in physical\n"
    "                         units (odecloth/fabric.h), its springs derived for the grid's\n"
    "                         spacing (drape_table, drape_sphere, crumple; docs/demos.md)\n"
    "  --bending K            interlaced (bending) stiffness k_b in N/m, (0, 10000], in place\n"
    "                         of the preset's (cotton 20, wool 10; drape_table,\n"
    "                         drape_sphere and fabrics' table default to 0.05); drapes,\n"
    "                         press, fabrics, curtain, trampoline\n"
    "  --memory 0|1           plastic memory (material.plastic_memory): 1 keeps an opened\n"
    "                         link plastic with its l1 (drape_table, drape_sphere and\n"
    "                         fabrics' table: 1 by default; crumple, fabrics' press,\n"
    "                         curtain, trampoline: 0)\n"
    "  --crease-grip G        N, (0, 100]: a remembered crease's pull, k_s = G / the grid's\n"
    "                         spacing (the same at every grid; drape_table, drape_sphere;\n"
    "                         with --fabric and plastic memory on: 0.04 by default)\n"
    "  --crease-law S         N m/m per radian, (0, 100]: the crease law (material.k_crease\n"
    "                         = 4 S / the grid's spacing): a set kept within the yield angle\n"
    "                         2 acos(alpha) of each fold, resisting unfolding with S per length\n"
    "                         of crease (drape_table, drape_sphere, crumple)\n"
    "  --removal four|two     drape_table, drape_sphere, fabrics: the cloth taken off by its\n"
    "                         four corners, spread flat over the floor and lowered (the\n"
    "                         paper's; default), or by two corners and laid down free edge\n"
    "                         first, as a person does\n"
    "  --self-collision T     drape_table, drape_sphere: keep the cloth's vertices T m (0, 0.1]\n"
    "                         from its own triangles after each step (off by default); T must\n"
    "                         be under 0.707 of a cell's side (refused otherwise)\n"
    "  --solver S             linearized | newton: how the implicit steps solve their equations\n"
    "                         (solver.nonlinear; default: the library's)\n"
    "  --grid N               nodes per side, 3..161 (default 21)\n"
    "  --steps-per-second F   steps per simulated second, 10..10000 (default 60; curtain 240)\n"
    "  --out DIR              where pictures and OBJ files go (default out/<demo>)\n"
    "  --obj                  also write an OBJ of the cloth for every saved frame\n"
    "  --frames K             also save K evenly spaced frames over each run (default 0)\n"
    "  --smooth L             display-only subdivision levels of the cloth, 0..3 (default 1)\n"
    "  --size WxH             picture size in pixels (default 400x300)\n"
    "  --no-images            metrics only\n"
    "  --video                also record each run as <out>/<run>.mp4 (alpha0.5.mp4, cotton.mp4),\n"
    "                         30 frames per simulated second at --size, through ffmpeg\n"
    "                         (make video; without ffmpeg on PATH the demo says so, exit 1)\n"
    "  --csv FILE             append the metrics of each run to FILE\n"
    "  --phases               print each phase's largest strain and penetration, deepest\n"
    "                         bend (smallest d / l0) and plastic links at its end\n"
    "  --trace                print every step's statistics (and --phases)\n"
    "  --box-table            drape_table, fabrics, crumple: tables and plates as ODE's box\n"
    "                         geom (vertex and box triangle contacts) instead of a\n"
    "                         triangle mesh (the press then sinks into a plate: README)\n"
    "  --sleep                let a cloth at rest sleep (dClothSetAutoSleep: RMS speed under\n"
    "                         1 cm/s for 10 steps); drape_table, drape_sphere print the saving\n"
    "  --view                 watch the run in a window (GLFW + OpenGL) when there is a display:\n"
    "                         left-drag rotates, right-drag or scroll zooms, middle-drag pans;\n"
    "                         space pauses / resumes, n or . steps once while paused, f runs\n"
    "                         as fast as it can (else in real time), r resets the camera, s\n"
    "                         saves the window as <out>/view_NNN.png, q or Esc closes it (the\n"
    "                         demo then runs on headless); each run's end waits for space.\n"
    "                         No display: says so and runs headless. Same results either way\n"
    "  --view-frames N        --view for scripted runs: draw every step, close the window after\n"
    "                         N frames and write the last as <out>/view.png (no pauses)\n"
    "  --short                a shorter timeline (what --check uses in CTest)\n"
    "  --check                assert the demo's claims on its own metrics (exit 1 if not)\n"
    "  --selftest             check the crease / wrinkle / bend metrics on a folded cloth\n"
    "                         against closed forms, and exit\n"
    "  --help                 this text\n";

static int bad(const demo_opts *o, const char *opt, const char *val, const char *why)
{
    fprintf(stderr, "%s: %s '%s': %s (try --help)\n", o->prog, opt, val ? val : "", why);
    return 2;
}

/* A finite number filling the whole string. */
static int parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end || errno || !isfinite(v)) return -1;
    *out = v;
    return 0;
}

static int parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || *end || errno || v < lo || v > hi) return -1;
    *out = (int)v;
    return 0;
}

static int parse_alphas(demo_opts *o, const char *s)
{
    char buf[256];
    if (strlen(s) >= sizeof buf) return -1;
    strcpy(buf, s);
    o->nalpha = 0;
    for (char *t = buf;;) { /* comma-separated; an empty item is an error */
        char *comma = strchr(t, ',');
        if (comma) *comma = '\0';
        double a;
        if (o->nalpha == DEMO_MAX_ALPHAS || parse_double(t, &a) || a < 0.0 || a > 1.0) return -1;
        o->alphas[o->nalpha++] = a;
        if (!comma) return 0;
        t = comma + 1;
    }
}

const char *demo_fabric_name(int fabric)
{
    static const char *const names[] = {"cotton", "wool", "silk", "denim", "polyester"};
    return fabric >= 1 && fabric <= 5 ? names[fabric - 1] : "";
}

static int parse_fabric(const char *s, int *fabric)
{
    for (int f = 1; *demo_fabric_name(f); f++)
        if (!strcmp(s, demo_fabric_name(f))) {
            *fabric = f;
            return 0;
        }
    return -1;
}

enum {
    OPT_OBJ = 256,
    OPT_CHECK,
    OPT_SHORT,
    OPT_NO_IMAGES,
    OPT_TRACE,
    OPT_PHASES,
    OPT_BOX_TABLE,
    OPT_SELFTEST,
    OPT_SLEEP,
    OPT_VIEW,
    OPT_VIDEO,
    OPT_ALPHA,
    OPT_MATERIAL,
    OPT_FABRIC,
    OPT_SELF_COLLISION,
    OPT_CREASE_GRIP,
    OPT_CREASE_LAW,
    OPT_REMOVAL,
    OPT_MEMORY,
    OPT_BENDING,
    OPT_SOLVER,
    OPT_GRID,
    OPT_HZ,
    OPT_OUT,
    OPT_FRAMES,
    OPT_VIEW_FRAMES,
    OPT_SMOOTH,
    OPT_SIZE,
    OPT_CSV,
};

static const struct option options[] = {
    {"help", no_argument, NULL, 'h'},
    {"obj", no_argument, NULL, OPT_OBJ},
    {"check", no_argument, NULL, OPT_CHECK},
    {"short", no_argument, NULL, OPT_SHORT},
    {"no-images", no_argument, NULL, OPT_NO_IMAGES},
    {"trace", no_argument, NULL, OPT_TRACE},
    {"phases", no_argument, NULL, OPT_PHASES},
    {"box-table", no_argument, NULL, OPT_BOX_TABLE},
    {"selftest", no_argument, NULL, OPT_SELFTEST},
    {"sleep", no_argument, NULL, OPT_SLEEP},
    {"view", no_argument, NULL, OPT_VIEW},
    {"video", no_argument, NULL, OPT_VIDEO},
    {"alpha", required_argument, NULL, OPT_ALPHA},
    {"material", required_argument, NULL, OPT_MATERIAL},
    {"fabric", required_argument, NULL, OPT_FABRIC},
    {"self-collision", required_argument, NULL, OPT_SELF_COLLISION},
    {"crease-grip", required_argument, NULL, OPT_CREASE_GRIP},
    {"crease-law", required_argument, NULL, OPT_CREASE_LAW},
    {"removal", required_argument, NULL, OPT_REMOVAL},
    {"memory", required_argument, NULL, OPT_MEMORY},
    {"bending", required_argument, NULL, OPT_BENDING},
    {"solver", required_argument, NULL, OPT_SOLVER},
    {"grid", required_argument, NULL, OPT_GRID},
    {"steps-per-second", required_argument, NULL, OPT_HZ},
    {"hz", required_argument, NULL, OPT_HZ},
    {"out", required_argument, NULL, OPT_OUT},
    {"frames", required_argument, NULL, OPT_FRAMES},
    {"view-frames", required_argument, NULL, OPT_VIEW_FRAMES},
    {"smooth", required_argument, NULL, OPT_SMOOTH},
    {"size", required_argument, NULL, OPT_SIZE},
    {"csv", required_argument, NULL, OPT_CSV},
    {NULL, 0, NULL, 0},
};

/* A flag (an option without a value): 1 if opt is one, else 0. */
static int take_flag(demo_opts *o, int opt)
{
    switch (opt) {
    case OPT_OBJ: o->obj = 1; return 1;
    case OPT_CHECK: o->check = 1; return 1;
    case OPT_SHORT: o->short_run = 1; return 1;
    case OPT_NO_IMAGES: o->images = 0; return 1;
    case OPT_TRACE: o->trace = o->phases = 1; return 1;
    case OPT_PHASES: o->phases = 1; return 1;
    case OPT_BOX_TABLE: o->box_table = 1; return 1;
    case OPT_SELFTEST: o->selftest = 1; return 1;
    case OPT_SLEEP: o->sleep = 1; return 1;
    case OPT_VIEW: o->view = 1; return 1;
    case OPT_VIDEO: o->video = 1; return 1;
    default: return 0;
    }
}

/* An option with the value v; opt_name is how it was spelled (for messages).
 * 0 taken, 2 refused (message printed). */
static int take_value(demo_opts *o, int opt, const char *opt_name, const char *v)
{
    switch (opt) {
    case OPT_ALPHA:
        if (parse_alphas(o, v)) return bad(o, opt_name, v, "want up to 8 numbers in [0, 1], comma-separated");
        break;
    case OPT_MATERIAL:
        o->material_set = 1;
        o->material_name = v;
        if (!strcmp(v, "cotton")) o->material = CLOTH_COTTON;
        else if (!strcmp(v, "wool")) o->material = CLOTH_WOOL;
        else if (!strcmp(v, "elastic")) o->material = CLOTH_ELASTIC;
        else return bad(o, opt_name, v, "want cotton, wool or elastic");
        break;
    case OPT_FABRIC:
        if (parse_fabric(v, &o->fabric)) return bad(o, opt_name, v, "want cotton, wool, silk, denim or polyester");
        o->fabric_name = v;
        break;
    case OPT_SELF_COLLISION:
        if (parse_double(v, &o->self_thickness) || !(o->self_thickness > 0.0) || o->self_thickness > 0.1)
            return bad(o, opt_name, v, "want a thickness in (0, 0.1] m");
        break;
    case OPT_CREASE_GRIP:
        if (parse_double(v, &o->crease_grip) || !(o->crease_grip > 0.0) || o->crease_grip > 100.0)
            return bad(o, opt_name, v, "want a number in (0, 100] N");
        break;
    case OPT_CREASE_LAW:
        if (parse_double(v, &o->crease_law) || !(o->crease_law > 0.0) || o->crease_law > 100.0)
            return bad(o, opt_name, v, "want a number in (0, 100] N m/m per radian");
        break;
    case OPT_REMOVAL:
        if (!strcmp(v, "four")) o->removal = 1;
        else if (!strcmp(v, "two")) o->removal = 2;
        else return bad(o, opt_name, v, "want two or four");
        break;
    case OPT_MEMORY:
        if (!strcmp(v, "0")) o->memory = 0;
        else if (!strcmp(v, "1")) o->memory = 1;
        else return bad(o, opt_name, v, "want 0 or 1");
        break;
    case OPT_BENDING:
        if (parse_double(v, &o->k_b) || !(o->k_b > 0.0) || o->k_b > 1e4)
            return bad(o, opt_name, v, "want a number in (0, 10000]");
        break;
    case OPT_SOLVER:
        if (!strcmp(v, "linearized")) o->solver = 1 + CLOTH_LINEARIZED;
        else if (!strcmp(v, "newton")) o->solver = 1 + CLOTH_NEWTON;
        else return bad(o, opt_name, v, "want linearized or newton");
        break;
    case OPT_GRID:
        if (parse_int(v, 3, 161, &o->grid)) return bad(o, opt_name, v, "want a whole number in 3..161");
        break;
    case OPT_HZ:
        if (parse_double(v, &o->hz) || o->hz < 10.0 || o->hz > 10000.0)
            return bad(o, opt_name, v, "want a number in 10..10000");
        o->hz_set = 1;
        break;
    case OPT_OUT:
        if (!*v) return bad(o, opt_name, v, "empty directory name");
        o->out = v;
        break;
    case OPT_FRAMES:
        if (parse_int(v, 0, 1000, &o->frames)) return bad(o, opt_name, v, "want a whole number in 0..1000");
        break;
    case OPT_VIEW_FRAMES:
        if (parse_int(v, 1, 1000000, &o->view_frames)) return bad(o, opt_name, v, "want a whole number in 1..1000000");
        o->view = 1;
        break;
    case OPT_SMOOTH:
        if (parse_int(v, 0, 3, &o->smooth)) return bad(o, opt_name, v, "want 0, 1, 2 or 3");
        break;
    case OPT_SIZE: {
        int w, h;
        char tail;
        if (sscanf(v, "%dx%d%c", &w, &h, &tail) != 2 || w < 32 || h < 32 || w > 4096 || h > 4096)
            return bad(o, opt_name, v, "want WxH, each 32..4096");
        o->width = w;
        o->height = h;
        break;
    }
    case OPT_CSV:
        if (!*v) return bad(o, opt_name, v, "empty file name");
        o->csv = v;
        break;
    }
    return 0;
}

static void set_defaults(demo_opts *o, const char *prog)
{
    static char out_default[256];
    memset(o, 0, sizeof *o);
    o->memory = -1;
    o->prog = prog;
    o->material = CLOTH_COTTON;
    o->material_name = "cotton";
    o->grid = 21;
    o->hz = 60.0;
    snprintf(out_default, sizeof out_default, "out/%s", prog);
    o->out = out_default;
    o->smooth = 1;
    o->width = 400;
    o->height = 300;
    o->images = 1;
}

int demo_parse(demo_opts *o, const char *prog, const char *usage, int argc, char **argv)
{
    set_defaults(o, prog);
    cli_start();
    for (;;) {
        const char *arg = NULL;
        int opt = cli_next(argc, argv, options, &arg);
        if (opt == CLI_END) break;
        if (opt == 'h') {
            fputs(usage, stdout);
            fputs(common_usage, stdout);
            return 1;
        }
        if (opt == CLI_OPERAND || (opt == CLI_UNKNOWN && strncmp(arg, "--", 2)))
            return bad(o, "argument", arg, "not an option");
        if (opt == CLI_UNKNOWN) return bad(o, "unknown option", arg, "not one of the options");
        if (opt == CLI_NO_VALUE) return bad(o, arg, NULL, "needs a value");
        if (take_flag(o, opt)) continue;
        /* the option as spelled, without an =value */
        char name[32];
        snprintf(name, sizeof name, "%.*s", (int)strcspn(arg, "="), arg);
        if (take_value(o, opt, name, optarg)) return 2;
    }
    if (o->fabric && o->material_set)
        return bad(o, "--fabric", o->fabric_name, "give --material or --fabric, not both");
    return 0;
}

dClothDesc demo_desc(const demo_opts *o)
{
    dClothDesc d = dClothDefaultDesc();
    if (o->solver) d.cloth.solver.nonlinear = (cloth_nonlinear)(o->solver - 1);
    return d;
}

int demo_begin(demo_opts *o, const char *prog, const char *usage, int argc, char **argv)
{
    int p = demo_parse(o, prog, usage, argc, argv);
    if (p == 0) {
        dInitODE2(0);
        atexit(dCloseODE);
    }
    return p;
}

int demo_alphas(const demo_opts *o, const double *defaults, int n, double *out)
{
    if (o->nalpha) {
        memcpy(out, o->alphas, (size_t)o->nalpha * sizeof *out);
        return o->nalpha;
    }
    memcpy(out, defaults, (size_t)n * sizeof *out);
    return n;
}

int demo_make_out_dir(const demo_opts *o)
{
    char path[1024];
    if (snprintf(path, sizeof path, "%s", o->out) >= (int)sizeof path) {
        fprintf(stderr, "%s: --out path too long\n", o->prog);
        return -1;
    }
    for (char *p = path + 1;; p++) {
        if (*p == '/' || !*p) {
            char c = *p;
            *p = '\0';
            if (mkdir(path, 0777) && errno != EEXIST) {
                fprintf(stderr, "%s: cannot create %s: %s\n", o->prog, path, strerror(errno));
                return -1;
            }
            *p = c;
            if (!c) break;
        }
    }
    return 0;
}

double demo_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int demo_step(const demo_opts *o, dWorldID world, dClothID *cloths, int n, double h, int step)
{
    int held = 0;
    cloth_status s = dClothWorldStep(world, cloths, n, h, 0);
    for (int i = 0; s == CLOTH_OK && i < n; i++) held += dClothGetStats(cloths[i])->held;
    if (s == CLOTH_OK && !held) {
        for (int i = 0; o->trace && i < n; i++) {
            const dClothStepStats *st = dClothGetStats(cloths[i]);
            printf("step %5d cloth %d: CG %3d  strain %.5f  limited %3d  contacts %3d (sticking %3d, "
                   "triangles %3d)  resolves %d  penetration %.2f mm  plastic %4d  kinetic %.3e J\n",
                   step, i, st->core.iterations, st->core.max_strain, st->core.strain_limited, st->contacts,
                   st->sticking, st->triangle_contacts, st->resolves, 1e3 * st->max_penetration, st->core.plastic_links,
                   st->core.energy.kinetic);
        }
        return 0;
    }
    for (int i = 0; i < n; i++) {
        const char *e = dClothGetLastError(cloths[i]);
        if (*e) fprintf(stderr, "%s: step %d failed: %s\n", o->prog, step, e);
    }
    return -1;
}

double demo_smoothstep(double t)
{
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return t * t * (3 - 2 * t);
}

void demo_near_callback(void *ctx, dGeomID a, dGeomID b)
{
    demo_contacts *w = ctx;
    dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
    if (!ba && !bb) return; /* static against static */
    dContact ct[4];
    int n = dCollide(a, b, 4, &ct[0].geom, sizeof ct[0]);
    for (int i = 0; i < n; i++) {
        ct[i].surface.mode = dContactBounce;
        ct[i].surface.mu = w->mu;
        ct[i].surface.bounce = w->bounce;
        ct[i].surface.bounce_vel = 0.1;
        dJointID j = dJointCreateContact(w->world, w->contacts, &ct[i]);
        dJointAttach(j, ba, bb);
    }
}
