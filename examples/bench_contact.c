/* bench_contact: what contacts cost per step (make bench).
 *
 * A cotton cloth (1 m square, 0.2 kg) released touching (6 mm above) the top of a
 * static collider and let settle for 2 s (h = 1/60 up to 41x41, 1/240 above), on: a sphere (radius
 * 0.3 m), a box (0.6 x 0.6 x 0.4 m) and a trimesh sphere of about 1000
 * triangles (radius 0.3 m), with its triangle tests on (the default) and
 * off (trimesh-vtx: dClothSetTriangleTests and dClothSetEdgeTests, vertex
 * contacts only; trimesh-link and box-link: triangle tests off, the links'
 * tests against the edges on). For each grid and collider: the median wall time
 * per step spent finding contacts (broadphase + vertex tests + triangle tests),
 * the median whole dClothStep, the contact share, and the contacts per step.
 * Writes DIR/bench_contact.csv and, with gnuplot, DIR/bench_contact.png.
 *
 *   bench_contact [--out DIR] [--grids 21,81] [--seconds T] */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "odecloth/dcloth.h"
#include "common/cli.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    if (n <= 0) return NAN;
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return v[n / 2];
}

/* A UV sphere of radius r with `rings` latitude bands and `segs` longitude
 * segments: 2 segs (rings - 1) triangles, wound outward. */
typedef struct mesh {
    double *v;
    dTriIndex *idx;
    int nv, nt;
} mesh;

static int uv_sphere(mesh *m, double r, int rings, int segs)
{
    m->nv = 2 + (rings - 1) * segs;
    m->nt = 2 * segs * (rings - 1);
    m->v = malloc(3 * (size_t)m->nv * sizeof *m->v);
    m->idx = malloc(3 * (size_t)m->nt * sizeof *m->idx);
    if (!m->v || !m->idx) return -1;
    double *v = m->v;
    v[0] = 0, v[1] = 0, v[2] = r; /* north pole 0, south pole nv-1 */
    for (int i = 1; i < rings; i++)
        for (int j = 0; j < segs; j++) {
            double th = M_PI * i / rings, ph = 2 * M_PI * j / segs;
            double *p = v + 3 * (1 + (i - 1) * segs + j);
            p[0] = r * sin(th) * cos(ph), p[1] = r * sin(th) * sin(ph), p[2] = r * cos(th);
        }
    int s = m->nv - 1;
    v[3 * s] = 0, v[3 * s + 1] = 0, v[3 * s + 2] = -r;
    dTriIndex *t = m->idx;
    for (int j = 0; j < segs; j++) {
        int a = 1 + j, b = 1 + (j + 1) % segs;
        *t++ = 0, *t++ = (dTriIndex)a, *t++ = (dTriIndex)b;
    }
    for (int i = 1; i + 1 < rings; i++)
        for (int j = 0; j < segs; j++) {
            int a = 1 + (i - 1) * segs + j, b = 1 + (i - 1) * segs + (j + 1) % segs, c = a + segs, d = b + segs;
            *t++ = (dTriIndex)a, *t++ = (dTriIndex)c, *t++ = (dTriIndex)d;
            *t++ = (dTriIndex)a, *t++ = (dTriIndex)d, *t++ = (dTriIndex)b;
        }
    for (int j = 0; j < segs; j++) {
        int a = 1 + (rings - 2) * segs + j, b = 1 + (rings - 2) * segs + (j + 1) % segs;
        *t++ = (dTriIndex)s, *t++ = (dTriIndex)b, *t++ = (dTriIndex)a;
    }
    return 0;
}

typedef struct result {
    double contact_ms, step_ms, contacts, tri_contacts, edge_contacts;
    int steps, failed;
} result;

static result run(int N, int kind, double seconds, double hz, const mesh *sph)
{
    result r = {0};
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dGeomID g;
    dTriMeshDataID td = 0;
    double top;
    if (kind == 0) {
        g = dCreateSphere(sp, 0.3);
        top = 0.6;
    } else if (kind == 1 || kind == 5) {
        g = dCreateBox(sp, 0.6, 0.6, 0.4);
        top = 0.4;
    } else {
        td = dGeomTriMeshDataCreate();
        dGeomTriMeshDataBuildDouble(td, sph->v, 3 * sizeof(double), sph->nv, sph->idx, 3 * sph->nt,
                                    3 * sizeof(dTriIndex));
        g = dCreateTriMesh(sp, td, 0, 0, 0);
        top = 0.6;
    }
    dGeomSetPosition(g, 0, 0, kind == 1 || kind == 5 ? 0.2 : 0.3);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = N;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.5;
    d.cloth.origin[2] = top + 0.006; /* released touching: see the note on impacts in docs/contacts.md */
    dClothID c;
    cloth_error err;
    if (dClothCreate(w, sp, &d, &c, &err) != CLOTH_OK) {
        fprintf(stderr, "bench_contact: %s\n", err.message);
        r.failed = 1;
    } else {
        if (kind >= 3) dClothSetTriangleTests(c, g, 0); /* vertex contacts, and the links' tests but in 3 */
        if (kind == 3) dClothSetEdgeTests(c, g, 0);
        int steps = (int)(seconds * hz + 0.5);
        double *tc = malloc((size_t)steps * sizeof *tc), *ts = malloc((size_t)steps * sizeof *ts);
        long nc = 0, ntc = 0, nec = 0;
        for (int s = 0; s < steps && tc && ts; s++) {
            if (dClothWorldStep(w, &c, 1, 1.0 / hz, 0) != CLOTH_OK || dClothGetStats(c)->held) {
                fprintf(stderr, "bench_contact: %dx%d step %d: %s\n", N, N, s, dClothGetLastError(c));
                r.failed = 1;
                break;
            }
            const dClothStepStats *st = dClothGetStats(c);
            tc[s] = 1e3 * st->seconds_contacts;
            ts[s] = 1e3 * st->seconds_total;
            nc += st->contacts;
            ntc += st->triangle_contacts;
            nec += st->edge_contacts;
            r.steps = s + 1;
        }
        r.contact_ms = median(tc, r.steps);
        r.step_ms = median(ts, r.steps);
        r.contacts = r.steps ? (double)nc / r.steps : 0.0;
        r.tri_contacts = r.steps ? (double)ntc / r.steps : 0.0;
        r.edge_contacts = r.steps ? (double)nec / r.steps : 0.0;
        free(tc);
        free(ts);
        dClothDestroy(c);
    }
    dSpaceDestroy(sp);
    if (td) dGeomTriMeshDataDestroy(td);
    dWorldDestroy(w);
    return r;
}

int main(int argc, char **argv)
{
    const char *out = "out/bench";
    int grids[8] = {21, 81}, ng = 2;
    double seconds = 2.0;
    static const struct option options[] = {
        {"help", no_argument, NULL, 'h'},
        {"out", required_argument, NULL, 'o'},
        {"seconds", required_argument, NULL, 's'},
        {"grids", required_argument, NULL, 'g'},
        {NULL, 0, NULL, 0},
    };
    cli_start();
    for (;;) {
        const char *arg = NULL;
        int opt = cli_next(argc, argv, options, &arg);
        char *v = optarg;
        if (opt == CLI_END) break;
        if (opt == 'h') {
            puts("usage: bench_contact [--out DIR] [--grids 21,81] [--seconds T]\n"
                 "Contact cost per step of a cloth settling on a sphere, a box and a\n"
                 "1000-triangle trimesh. Writes DIR/bench_contact.csv and .png.");
            return 0;
        } else if (opt == 'o') {
            out = v;
        } else if (opt == 's') {
            seconds = atof(v);
        } else if (opt == 'g') {
            ng = 0;
            for (char *s = v; *s && ng < 8;) {
                grids[ng] = (int)strtol(s, &s, 10);
                if (grids[ng] < 3) {
                    fprintf(stderr, "bench_contact: grid sizes must be >= 3\n");
                    return 2;
                }
                ng++;
                if (*s == ',') s++;
                else break;
            }
        } else {
            fprintf(stderr, "bench_contact: unknown or incomplete option '%s' (try --help)\n", arg);
            return 2;
        }
    }
    if (!(seconds > 0.0)) {
        fprintf(stderr, "bench_contact: --seconds must be > 0\n");
        return 2;
    }
    mesh sph;
    if (uv_sphere(&sph, 0.3, 21, 25) != 0) { /* 2 * 25 * 20 = 1000 triangles */
        fprintf(stderr, "bench_contact: out of memory\n");
        return 1;
    }
    char path[1024];
    snprintf(path, sizeof path, "mkdir -p '%s'", out);
    if (system(path) != 0) {
        fprintf(stderr, "bench_contact: cannot create %s\n", out);
        return 1;
    }
    snprintf(path, sizeof path, "%s/bench_contact.csv", out);
    FILE *csv = fopen(path, "w");
    if (!csv) {
        fprintf(stderr, "bench_contact: cannot write %s: %s\n", path, strerror(errno));
        return 1;
    }
    dInitODE2(0);
    const char *names[6] = {"sphere", "box", "trimesh1000", "trimesh-vtx", "trimesh-link", "box-link"};
    fprintf(csv, "grid,collider,hz,steps,contact_ms,step_ms,contact_share,contacts,triangle_contacts,failed,"
                 "edge_contacts\n");
    printf("%-8s %-12s %-6s %12s %10s %7s %9s %9s %9s\n", "grid", "collider", "h", "contacts ms", "step ms", "share",
           "contacts", "tri", "link");
    for (int gi = 0; gi < ng; gi++)
        for (int k = 0; k < 6; k++) {
            /* h = 1/60 up to 41x41; finer cloths drape off the collider at
             * 1/240 (at 1/60 an 81x81 skirt swings several link lengths per
             * step and the one-Newton-step solve overstretches it) */
            double hz = grids[gi] <= 41 ? 60.0 : 240.0;
            result r = run(grids[gi], k, seconds, hz, &sph);
            double share = r.step_ms > 0 ? r.contact_ms / r.step_ms : NAN;
            printf("%3dx%-4d %-12s 1/%-4.0f %12.3f %10.3f %6.1f%% %9.1f %9.1f %9.1f %s\n", grids[gi], grids[gi],
                   names[k], hz, r.contact_ms, r.step_ms, 100 * share, r.contacts, r.tri_contacts, r.edge_contacts,
                   r.failed ? "FAILED" : "");
            fflush(stdout);
            fprintf(csv, "%d,%s,%.0f,%d,%.4f,%.4f,%.4f,%.1f,%.1f,%d,%.1f\n", grids[gi], names[k], hz, r.steps,
                    r.contact_ms, r.step_ms, share, r.contacts, r.tri_contacts, r.failed, r.edge_contacts);
        }
    fclose(csv);
    dCloseODE();
    free(sph.v);
    free(sph.idx);

    snprintf(path, sizeof path, "%s/bench_contact.gp", out);
    FILE *gp = fopen(path, "w");
    if (!gp) return 0;
    fprintf(gp,
            "set terminal pngcairo size 900,480 font ',10'\n"
            "set output '%s/bench_contact.png'\n"
            "set datafile separator ','\n"
            "set title 'odecloth: contact cost per step (median ms), cloth settling on a collider (h 1/60; 81x81: "
            "1/240)'\n"
            "set style data histograms\nset style histogram clustered gap 1\nset style fill solid 0.8 border -1\n"
            "set logscale y\nset grid ytics\nset ylabel 'ms per step'\nset key left top\n"
            "plot '%s/bench_contact.csv' every ::1 using 5:xticlabels(sprintf('%%dx%%d %%s', $1, $1, strcol(2))) "
            "title 'finding contacts', '' every ::1 using 6 title 'whole step'\n",
            out, out);
    fclose(gp);
    snprintf(path, sizeof path, "gnuplot '%s/bench_contact.gp'", out);
    if (system(path) != 0) fprintf(stderr, "bench_contact: gnuplot failed; the CSV is in %s\n", out);
    else printf("wrote %s/bench_contact.csv and %s/bench_contact.png\n", out, out);
    return 0;
}
