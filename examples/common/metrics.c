/* The figures every demo prints: crease (dihedral angles), wrinkles, height,
 * plastic links, penetration and strain over the run; CSV rows, OBJ files
 * and saved frames. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "demo.h"

/* An interior edge: the two triangles that share it. */
typedef struct edge {
    int a, b;   /* vertices, a < b */
    int t0, t1; /* triangles */
} edge;

typedef struct half {
    int a, b, t;
} half;

static int half_cmp(const void *p, const void *q)
{
    const half *x = p, *y = q;
    if (x->a != y->a) return x->a < y->a ? -1 : 1;
    if (x->b != y->b) return x->b < y->b ? -1 : 1;
    return (x->t > y->t) - (x->t < y->t);
}

/* The interior edges of the cloth's triangle mesh and the angle (degrees)
 * each is bent by; *n their number. NULL on no memory (n = 0). */
static edge *interior_edges(dClothID c, double **angle, int *n)
{
    int nt = dClothGetTriangleCount(c);
    const int *tri = dClothGetTriangles(c);
    const dReal *x = dClothGetPositions(c);
    half *h = malloc(3 * (size_t)nt * sizeof *h);
    edge *e = malloc(3 * (size_t)nt * sizeof *e);
    double *tn = malloc(3 * (size_t)nt * sizeof *tn);
    *n = 0;
    *angle = NULL;
    if (!h || !e || !tn) goto fail;
    for (int t = 0; t < nt; t++) {
        const int *v = tri + 3 * t;
        for (int k = 0; k < 3; k++) {
            int a = v[k], b = v[(k + 1) % 3];
            h[3 * t + k] = (half){a < b ? a : b, a < b ? b : a, t};
        }
        double e1[3], e2[3], *nn = tn + 3 * t;
        for (int k = 0; k < 3; k++) {
            e1[k] = x[3 * v[1] + k] - x[3 * v[0] + k];
            e2[k] = x[3 * v[2] + k] - x[3 * v[0] + k];
        }
        nn[0] = e1[1] * e2[2] - e1[2] * e2[1];
        nn[1] = e1[2] * e2[0] - e1[0] * e2[2];
        nn[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double l = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
        for (int k = 0; k < 3; k++) nn[k] = l > 0 ? nn[k] / l : 0;
    }
    qsort(h, 3 * (size_t)nt, sizeof *h, half_cmp);
    for (int i = 0; i + 1 < 3 * nt; i++)
        if (h[i].a == h[i + 1].a && h[i].b == h[i + 1].b) {
            e[(*n)++] = (edge){h[i].a, h[i].b, h[i].t, h[i + 1].t};
            i++;
        }
    *angle = malloc((size_t)(*n > 0 ? *n : 1) * sizeof **angle);
    if (!*angle) goto fail;
    for (int i = 0; i < *n; i++) {
        const double *p = tn + 3 * e[i].t0, *q = tn + 3 * e[i].t1;
        double cx = p[1] * q[2] - p[2] * q[1], cy = p[2] * q[0] - p[0] * q[2], cz = p[0] * q[1] - p[1] * q[0];
        (*angle)[i] = atan2(sqrt(cx * cx + cy * cy + cz * cz), p[0] * q[0] + p[1] * q[1] + p[2] * q[2]) * 180 / M_PI;
    }
    free(h);
    free(tn);
    return e;
fail:
    fprintf(stderr, "metrics: out of memory\n");
    free(h);
    free(e);
    free(tn);
    *n = 0;
    return NULL;
}

void demo_crease(dClothID c, double *mean_deg, double *max_deg)
{
    double *ang;
    int n;
    edge *e = interior_edges(c, &ang, &n);
    double sum = 0, mx = 0;
    for (int i = 0; i < n; i++) {
        sum += ang[i];
        if (ang[i] > mx) mx = ang[i];
    }
    *mean_deg = n ? sum / n : 0;
    *max_deg = mx;
    free(e);
    free(ang);
}

static int find_root(int *parent, int v)
{
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
}

int demo_wrinkles(dClothID c, double threshold_deg, int min_edges)
{
    double *ang;
    int n, nv = dClothGetVertexCount(c), count = 0;
    edge *e = interior_edges(c, &ang, &n);
    int *parent = malloc((size_t)nv * sizeof *parent), *edges = calloc((size_t)nv, sizeof *edges);
    if (e && parent && edges) {
        for (int v = 0; v < nv; v++) parent[v] = v;
        for (int i = 0; i < n; i++)
            if (ang[i] > threshold_deg) parent[find_root(parent, e[i].a)] = find_root(parent, e[i].b);
        for (int i = 0; i < n; i++)
            if (ang[i] > threshold_deg) edges[find_root(parent, e[i].a)]++;
        for (int v = 0; v < nv; v++) count += parent[v] == v && edges[v] >= min_edges;
    }
    free(e);
    free(ang);
    free(parent);
    free(edges);
    return count;
}

void demo_measure_shape(dClothID c, double floor_z, demo_metrics *m)
{
    demo_crease(c, &m->crease_deg, &m->crease_max_deg);
    m->wrinkles = demo_wrinkles(c, DEMO_WRINKLE_DEG, DEMO_WRINKLE_MIN_EDGES);
    const dReal *x = dClothGetPositions(c);
    double top = -INFINITY;
    for (int i = 0; i < dClothGetVertexCount(c); i++)
        if (x[3 * i + 2] > top) top = x[3 * i + 2];
    m->height = top - floor_z;
    const cloth *core = dClothGetCore(c);
    m->plastic_links = 0;
    for (int i = 0; i < cloth_link_count(core, CLOTH_INTERLACED); i++) {
        cloth_link l;
        if (cloth_get_link(core, CLOTH_INTERLACED, i, &l) == CLOTH_OK) m->plastic_links += l.plastic;
    }
}

double demo_deepest_bend(dClothID c)
{
    const cloth *core = dClothGetCore(c);
    const double *x = cloth_positions(core);
    double lo = INFINITY;
    for (int i = 0; i < cloth_link_count(core, CLOTH_INTERLACED); i++) {
        cloth_link l;
        if (cloth_get_link(core, CLOTH_INTERLACED, i, &l) != CLOTH_OK) continue;
        double d2 = 0;
        for (int k = 0; k < 3; k++) d2 += (x[3 * l.i + k] - x[3 * l.j + k]) * (x[3 * l.i + k] - x[3 * l.j + k]);
        if (sqrt(d2) / l.rest < lo) lo = sqrt(d2) / l.rest;
    }
    return lo;
}

void demo_track_step(dClothID c, demo_metrics *m)
{
    const dClothStepStats *st = dClothGetStats(c);
    double bend = demo_deepest_bend(c);
    if (m->steps == 0 || bend < m->min_bend) m->min_bend = bend;
    if (st->max_penetration > m->max_penetration) m->max_penetration = st->max_penetration;
    if (st->max_penetration_all > m->deepest_point) m->deepest_point = st->max_penetration_all;
    if (st->core.max_strain > m->max_strain) m->max_strain = st->core.max_strain;
    m->steps++;
}

void demo_print_metrics(FILE *f, const char *label, const demo_metrics *m)
{
    fprintf(f,
            "%-22s crease %6.2f deg (max %5.1f)  height %.3f m  plastic links %4d  wrinkles %3d  "
            "max penetration %.2f mm (deepest point %.2f)  max strain %.4f  deepest bend %.3f  wall %.1f s\n",
            label, m->crease_deg, m->crease_max_deg, m->height, m->plastic_links, m->wrinkles, 1e3 * m->max_penetration,
            1e3 * m->deepest_point, m->max_strain, m->min_bend, m->wall);
}

int demo_csv_row(const char *path, const char *demo, const char *label, double alpha, const demo_metrics *m)
{
    FILE *probe = fopen(path, "r");
    int fresh = !probe;
    if (probe) fclose(probe);
    FILE *f = fopen(path, "a");
    if (!f) {
        fprintf(stderr, "%s: cannot open for appending: %s\n", path, strerror(errno));
        return -1;
    }
    if (fresh)
        fprintf(f, "demo,label,alpha,crease_deg,crease_max_deg,height_m,plastic_links,wrinkles,"
                   "max_penetration_m,max_strain,deepest_bend,wall_s,steps,deepest_point_m\n");
    fprintf(f, "%s,%s,%g,%.4f,%.3f,%.5f,%d,%d,%.6g,%.6f,%.4f,%.3f,%d,%.6g\n", demo, label, alpha, m->crease_deg,
            m->crease_max_deg, m->height, m->plastic_links, m->wrinkles, m->max_penetration, m->max_strain, m->min_bend,
            m->wall, m->steps, m->deepest_point);
    if (fclose(f)) {
        fprintf(stderr, "%s: write failed: %s\n", path, strerror(errno));
        return -1;
    }
    return 0;
}

int demo_write_obj(const char *path, dClothID c)
{
    int nv = dClothGetVertexCount(c), nt = dClothGetTriangleCount(c);
    const dReal *x = dClothGetPositions(c);
    const int *tri = dClothGetTriangles(c);
    dReal *n = malloc(3 * (size_t)nv * sizeof *n);
    FILE *f = n ? fopen(path, "w") : NULL;
    if (!f) {
        fprintf(stderr, "%s: %s\n", path, n ? strerror(errno) : "out of memory");
        free(n);
        return -1;
    }
    dClothGetNormals(c, n);
    fprintf(f, "# odecloth cloth, %d vertices, %d triangles\n", nv, nt);
    for (int i = 0; i < nv; i++) fprintf(f, "v %.6f %.6f %.6f\n", x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    for (int i = 0; i < nv; i++) fprintf(f, "vn %.5f %.5f %.5f\n", n[3 * i], n[3 * i + 1], n[3 * i + 2]);
    for (int t = 0; t < nt; t++) {
        const int *v = tri + 3 * t;
        fprintf(f, "f %d//%d %d//%d %d//%d\n", v[0] + 1, v[0] + 1, v[1] + 1, v[1] + 1, v[2] + 1, v[2] + 1);
    }
    free(n);
    if (fclose(f)) {
        fprintf(stderr, "%s: write failed: %s\n", path, strerror(errno));
        return -1;
    }
    return 0;
}

int demo_save_frame(const demo_opts *o, const char *name, const demo_camera *cam, dSpaceID space, dClothID *cloths,
                    int n, demo_image **keep)
{
    char path[1024];
    int rc = 0;
    if (keep) *keep = NULL;
    if (o->obj)
        for (int i = 0; i < n; i++) {
            if (n > 1) snprintf(path, sizeof path, "%s/%s_%d.obj", o->out, name, i);
            else snprintf(path, sizeof path, "%s/%s.obj", o->out, name);
            if (demo_write_obj(path, cloths[i])) rc = -1;
            else printf("  wrote %s\n", path);
        }
    if (!o->images || !demo_render_available() || !demo_png_available()) return rc;
    demo_image *im = demo_render(cam, space, cloths, n, o->smooth, o->width, o->height);
    if (!im) return -1;
    snprintf(path, sizeof path, "%s/%s.png", o->out, name);
    if (demo_png_write(path, im)) rc = -1;
    else printf("  wrote %s\n", path);
    if (keep) *keep = im;
    else demo_image_destroy(im);
    return rc;
}

void demo_frame_hook(const demo_opts *o, const char *tag, int step, int total, int *next, const demo_camera *cam,
                     dSpaceID space, dClothID *cloths, int n)
{
    demo_video_hook(o, tag, step, total, cam, space, cloths, n);
    if (!o->frames || (long)step * o->frames < (long)*next * total) return;
    char name[120];
    snprintf(name, sizeof name, "%s_frame%03d", tag, (*next)++);
    demo_save_frame(o, name, cam, space, cloths, n, NULL);
}

/* The metrics against closed forms: a flat 21 x 21 cloth folded along its
 * middle column by a bend of theta (both halves turned up by theta / 2).
 * The R - 1 edges on the fold are bent by theta, every other interior edge
 * by 0, so the mean crease is theta (R - 1) / (interior edges), counted
 * here from the grid (R(C-1) + C(R-1) + (R-1)(C-1) edges, 2(R-1) + 2(C-1)
 * of them on the boundary); the max is theta; the fold is one wrinkle when
 * theta > DEMO_WRINKLE_DEG, none below; the deepest bend is the interlaced
 * link straddling the fold at right angles: d / l0 = cos(theta / 2).
 * Returns the number of failures (printed). */
int demo_metrics_selftest(void)
{
    dWorldID world = dWorldCreate();
    dClothDesc d = dClothDefaultDesc();
    const int R = d.cloth.rows, C = d.cloth.cols, c0 = C / 2;
    const double s = d.cloth.width / (C - 1);
    dClothID c = NULL;
    cloth_error err;
    int failed = 0;
    double *x = malloc(3 * (size_t)R * C * sizeof *x);
    if (!x || dClothCreate(world, 0, &d, &c, &err) != CLOTH_OK) {
        fprintf(stderr, "selftest: %s\n", x ? err.message : "out of memory");
        free(x);
        dWorldDestroy(world);
        return 1;
    }
    const double thetas[3] = {60.0, 5.0, 0.0};
    for (int k = 0; k < 3; k++) {
        double th = thetas[k] * M_PI / 180;
        for (int r = 0; r < R; r++)
            for (int col = 0; col < C; col++) {
                double u = (col - c0) * s, *p = x + 3 * (r * C + col);
                p[0] = u * cos(th / 2);
                p[1] = r * s;
                p[2] = fabs(u) * sin(th / 2);
            }
        cloth_set_positions(dClothGetCore(c), x);
        double mean, mx;
        demo_crease(c, &mean, &mx);
        int interior = R * (C - 1) + C * (R - 1) + (R - 1) * (C - 1) - 2 * (R - 1) - 2 * (C - 1);
        double want_mean = thetas[k] * (R - 1) / interior;
        int wrinkles = demo_wrinkles(c, DEMO_WRINKLE_DEG, DEMO_WRINKLE_MIN_EDGES);
        double bend = demo_deepest_bend(c);
        int ok = fabs(mean - want_mean) < 1e-9 && fabs(mx - thetas[k]) < 1e-9 &&
                 wrinkles == (thetas[k] > DEMO_WRINKLE_DEG) && fabs(bend - cos(th / 2)) < 1e-12;
        printf("selftest %s: fold %g deg: mean crease %.12f (closed form %.12f), max %.12f, wrinkles %d, "
               "deepest bend %.15f (cos(theta/2) = %.15f)\n",
               ok ? "ok" : "FAILED", thetas[k], mean, want_mean, mx, wrinkles, bend, cos(th / 2));
        failed += !ok;
    }
    free(x);
    dClothDestroy(c);
    dWorldDestroy(world);
    return failed;
}
