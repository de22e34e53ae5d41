/* Cloth triangles against a trimesh: each mesh triangle a prism (a convex
 * shape) tested against the cloth triangles near it, found in a hash grid
 * of the cloth's triangles. */
#include <ccd/ccd.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "dcloth_internal.h"
#include "body_motion.h"
#include "geom_triangles.h"
#include "mesh_contacts.h"
#include "triangle_query.h"

/* A mesh triangle as a convex prism: the triangle and its copy moved inward by a depth. A flat
 * triangle has no inside, so the least separating translation may point into the mesh; the prism's
 * makes it point out of the face, and at a closed mesh's convex edge two prisms meet as the solid would. */
typedef struct prism_shape {
    double p[6][3]; /* world frame */
} prism_shape;

static void prism_support(const void *obj, const ccd_vec3_t *dir, ccd_vec3_t *out)
{
    const prism_shape *s = obj;
    const double *d = dir->v;
    int best = 0;
    double bd = -INFINITY;
    for (int k = 0; k < 6; k++) {
        double e = s->p[k][0] * d[0] + s->p[k][1] * d[1] + s->p[k][2] * d[2];
        if (e > bd) bd = e, best = k;
    }
    for (int k = 0; k < 3; k++) out->v[k] = s->p[best][k];
}

static void prism_center(const void *obj, ccd_vec3_t *out)
{
    const prism_shape *s = obj;
    for (int k = 0; k < 3; k++) {
        double m = 0.0;
        for (int a = 0; a < 6; a++) m += s->p[a][k];
        out->v[k] = m / 6.0;
    }
}

static int edge_order(const void *pa, const void *pb)
{
    const struct mesh_edge *a = pa, *b = pb;
    for (int k = 0; k < 3; k++) {
        if (a->a[k] != b->a[k]) return a->a[k] < b->a[k] ? -1 : 1;
    }
    for (int k = 0; k < 3; k++) {
        if (a->b[k] != b->b[k]) return a->b[k] < b->b[k] ? -1 : 1;
    }
    return 0;
}

/* Fetch the mesh's nt triangles (world frame) into c->mesh.v and flag each edge convex (the neighbour
 * turns away below this face's plane) or open (none); flat and concave are 0. Edges are matched by
 * their ends' coordinates (ODE transforms shared corners alike). Returns -1 when out of memory. */
static int mesh_fetch(dClothID c, dGeomID g, int nt)
{
    if (nt > c->mesh.cap) {
        double *v = realloc(c->mesh.v, 9 * (size_t)nt * sizeof *v);
        if (v) c->mesh.v = v;
        unsigned char *f = v ? realloc(c->mesh.convex, 3 * (size_t)nt) : NULL;
        if (f) c->mesh.convex = f;
        struct mesh_edge *e = f ? realloc(c->mesh.edges, 3 * (size_t)nt * sizeof *e) : NULL;
        if (e) c->mesh.edges = e;
        if (!e) return -1;
        c->mesh.cap = nt;
    }
    int ne = 0;
    dcloth_geom_triangles(g, dTriMeshClass, nt, c->mesh.v);
    for (int j = 0; j < nt; j++) {
        const double *t = c->mesh.v + 9 * j;
        int finite = 1;
        for (int r = 0; r < 3; r++) finite = finite && isfinite(t[r]) && isfinite(t[3 + r]) && isfinite(t[6 + r]);
        for (int k = 0; k < 3; k++) c->mesh.convex[3 * j + k] = 1; /* open until a neighbour is found */
        /* a triangle with a coordinate not finite (mesh_contacts skips it)
         * is not sorted: NaN makes the order inconsistent */
        if (!finite) continue;
        for (int k = 0; k < 3; k++) {
            struct mesh_edge *m = c->mesh.edges + ne++;
            const double *p0 = t + 3 * k, *p1 = t + 3 * ((k + 1) % 3);
            int swap = 0;
            for (int r = 0; r < 3; r++)
                if (p0[r] != p1[r]) {
                    swap = p1[r] < p0[r];
                    break;
                }
            memcpy(m->a, swap ? p1 : p0, sizeof m->a);
            memcpy(m->b, swap ? p0 : p1, sizeof m->b);
            m->tri = j;
            m->e = k;
        }
    }
    qsort(c->mesh.edges, (size_t)ne, sizeof *c->mesh.edges, edge_order);
    for (int i = 0; i + 1 < ne; i++) {
        struct mesh_edge *m = c->mesh.edges + i, *o = m + 1;
        if (edge_order(m, o) != 0) continue;
        /* m's triangle against o's far corner, and o's against m's */
        for (int s = 0; s < 2; s++) {
            const struct mesh_edge *x = s ? o : m, *y = s ? m : o;
            const double *t = c->mesh.v + 9 * x->tri, *u = c->mesh.v + 9 * y->tri + 3 * ((y->e + 2) % 3);
            double e1[3], e2[3], f[3], d[3];
            for (int r = 0; r < 3; r++) {
                e1[r] = t[3 + r] - t[r];
                e2[r] = t[6 + r] - t[r];
                d[r] = u[r] - t[r];
            }
            f[0] = e1[1] * e2[2] - e1[2] * e2[1];
            f[1] = e1[2] * e2[0] - e1[0] * e2[2];
            f[2] = e1[0] * e2[1] - e1[1] * e2[0];
            double fl = sqrt(dcloth_dot3(f, f)), el = sqrt(dcloth_dot3(e1, e1) + dcloth_dot3(e2, e2));
            /* below the plane by more than rounding of the mesh's size */
            c->mesh.convex[3 * x->tri + x->e] = fl > 0.0 && dcloth_dot3(f, d) / fl < -1e-9 * el;
        }
        i++;
    }
    return 0;
}

/* The cloth's triangles, each box grown as triangle_query grows it, hashed by the cubic cells (side:
 * the largest box) they overlap, at most 8 each, so a mesh triangle's prism tests only nearby ones.
 * Returns -1 when out of memory; the cell side and origin in s and lo, the size in cells in dim. */
static long long cell_key(const long long i[3], const long long dim[3])
{
    return i[0] + dim[0] * (i[1] + dim[1] * i[2]);
}

static int bucket(long long key, int nbuck)
{
    unsigned long long h = (unsigned long long)key * 0x9E3779B97F4A7C15ull;
    return (int)(h >> 32) & (nbuck - 1);
}

/* Cloth triangle k's box for the step's start tests: grown as triangle_query grows it */
static int start_bounds(dClothID c, const struct convex_query *q, int k, double h, double span, double b[6])
{
    const double *x = cloth_positions(c->core), *v = cloth_velocities(c->core);
    const int *p = c->tri + 3 * k;
    double sweep = 0.0;
    for (int a = 0; a < 3; a++) sweep = fmax(sweep, dcloth_relative_speed(q->body, x + 3 * p[a], v + 3 * p[a]));
    double reach = h * sweep;
    if (!(reach <= span)) reach = span;
    double r = q->surf->thickness * (1.0 + DCLOTH_CONTACT_MARGIN) + reach;
    for (int a = 0; a < 3; a++) {
        b[2 * a] = fmin(x[3 * p[0] + a], fmin(x[3 * p[1] + a], x[3 * p[2] + a])) - r;
        b[2 * a + 1] = fmax(x[3 * p[0] + a], fmax(x[3 * p[1] + a], x[3 * p[2] + a])) + r;
    }
    return 1;
}

static int start_test(dClothID c, struct convex_query *q, int k, double h, ccd_t *ccd, ccd_t *fine)
{
    return dcloth_triangle_query(c, q, k, h, ccd, fine);
}

/* Returns how many cloth triangles bounds gave a box, or -1 (out of memory, or boxes not finite) */
static int grid_build(dClothID c, const convex_query *q, double h, double geom_span, dcloth_tri_bounds bounds,
                      double *s, double lo[3], long long dim[3])
{
    int nt = c->ntri, in = 0;
    if (8 * nt > c->mesh.grid_cap) {
        int cap = 8 * nt, nb = 1;
        while (nb < 2 * cap) nb *= 2;
        double *bx = realloc(c->mesh.grid_box, 6 * (size_t)nt * sizeof *bx);
        if (bx) c->mesh.grid_box = bx;
        int *st = bx ? realloc(c->mesh.grid_stamp, (size_t)nt * sizeof *st) : NULL;
        if (st) c->mesh.grid_stamp = st;
        int *hd = st ? realloc(c->mesh.grid_head, (size_t)nb * sizeof *hd) : NULL;
        if (hd) c->mesh.grid_head = hd;
        int *nx = hd ? realloc(c->mesh.grid_next, (size_t)cap * sizeof *nx) : NULL;
        if (nx) c->mesh.grid_next = nx;
        int *tr = nx ? realloc(c->mesh.grid_tri, (size_t)cap * sizeof *tr) : NULL;
        if (tr) c->mesh.grid_tri = tr;
        long long *ky = tr ? realloc(c->mesh.grid_key, (size_t)cap * sizeof *ky) : NULL;
        if (ky) c->mesh.grid_key = ky;
        if (!ky) return -1;
        c->mesh.grid_cap = cap;
        c->mesh.grid_nbuck = nb;
    }
    double side = 0.0, hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = INFINITY;
        hi[a] = -INFINITY;
    }
    for (int k = 0; k < nt; k++) {
        double *b = c->mesh.grid_box + 6 * k;
        c->mesh.grid_stamp[k] = 0;
        if (!bounds(c, q, k, h, geom_span, b)) {
            b[0] = INFINITY, b[1] = -INFINITY; /* empty: left out of the grid */
            continue;
        }
        in++;
        for (int a = 0; a < 3; a++) {
            side = fmax(side, b[2 * a + 1] - b[2 * a]);
            lo[a] = fmin(lo[a], b[2 * a]);
            hi[a] = fmax(hi[a], b[2 * a + 1]);
        }
    }
    if (!in) return 0;
    if (!(side > 0.0) || !isfinite(side)) return -1;
    /* at most ~1e6 cells a side: a larger span (a cloth flung far) uses
     * larger cells */
    for (int a = 0; a < 3; a++) side = fmax(side, (hi[a] - lo[a]) * 1e-6);
    if (!isfinite(side)) return -1; /* coordinates near overflow */
    *s = side;
    for (int a = 0; a < 3; a++) dim[a] = (long long)((hi[a] - lo[a]) / side) + 1;
    for (int b = 0; b < c->mesh.grid_nbuck; b++) c->mesh.grid_head[b] = -1;
    int n = 0;
    for (int k = 0; k < nt; k++) {
        const double *b = c->mesh.grid_box + 6 * k;
        if (!(b[0] <= b[1])) continue;
        long long i0[3], i1[3], i[3];
        for (int a = 0; a < 3; a++) {
            i0[a] = (long long)((b[2 * a] - lo[a]) / side);
            i1[a] = (long long)((b[2 * a + 1] - lo[a]) / side);
            if (i1[a] >= dim[a]) i1[a] = dim[a] - 1;
        }
        for (i[2] = i0[2]; i[2] <= i1[2]; i[2]++)
            for (i[1] = i0[1]; i[1] <= i1[1]; i[1]++)
                for (i[0] = i0[0]; i[0] <= i1[0]; i[0]++) {
                    if (n == c->mesh.grid_cap) return -1; /* rounding gave a box 3 cells: never seen */
                    long long key = cell_key(i, dim);
                    int bk = bucket(key, c->mesh.grid_nbuck);
                    c->mesh.grid_key[n] = key;
                    c->mesh.grid_tri[n] = k;
                    c->mesh.grid_next[n] = c->mesh.grid_head[bk];
                    c->mesh.grid_head[bk] = n++;
                }
    }
    return in;
}

/* A trimesh's triangles as prisms (prism_shape), each against the cloth triangles near it
 * (grid_build); a prism half as deep as the triangle's shortest edge and the mesh's least side,
 * at most MESH_PRISM_DEPTH thicknesses (tuning.h). Triangles of zero area are skipped. */
int dcloth_mesh_contacts(dClothID c, convex_query *q, double h, ccd_t *ccd, ccd_t *fine)
{
    return dcloth_mesh_pairs(c, q, h, ccd, fine, start_bounds, start_test);
}

int dcloth_mesh_pairs(dClothID c, convex_query *q, double h, ccd_t *ccd, ccd_t *fine, dcloth_tri_bounds bounds,
                      dcloth_pair_test test)
{
    int nt = dGeomTriMeshGetTriangleCount(q->g), hits = 0;
    dReal gb[6];
    dGeomGetAABB(q->g, gb);
    double gbox[6], s, lo[3];
    long long dim[3];
    for (int a = 0; a < 6; a++) gbox[a] = gb[a];
    /* out of memory: vertex contacts only */
    if (nt <= 0 || mesh_fetch(c, q->g, nt) || grid_build(c, q, h, dcloth_diagonal(gbox), bounds, &s, lo, dim) <= 0)
        return 0;
    /* the mesh's box in its own frame: its least side bounds the prisms */
    const dReal *o = dGeomGetPosition(q->g), *R = dGeomGetRotation(q->g);
    double llo[3] = {INFINITY, INFINITY, INFINITY}, lhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int m = 0; m < 3 * nt; m++) {
        const double *x = c->mesh.v + 3 * m;
        double d[3] = {x[0] - o[0], x[1] - o[1], x[2] - o[2]};
        for (int k = 0; k < 3; k++) {
            double l = R[k] * d[0] + R[4 + k] * d[1] + R[8 + k] * d[2]; /* R^T d */
            llo[k] = fmin(llo[k], l);
            lhi[k] = fmax(lhi[k], l);
        }
    }
    double least = fmin(lhi[0] - llo[0], fmin(lhi[1] - llo[1], lhi[2] - llo[2]));
    prism_shape ps;
    q->shape = &ps;
    q->support = prism_support;
    q->center = prism_center;
    ccd->support1 = fine->support1 = prism_support;
    ccd->center1 = fine->center1 = prism_center;
    for (int j = 0; j < nt; j++) {
        const double *a = c->mesh.v + 9 * j, *b = a + 3, *e = a + 6;
        double u[3], w[3], nrm[3];
        for (int r = 0; r < 3; r++) {
            u[r] = b[r] - a[r];
            w[r] = e[r] - a[r];
        }
        nrm[0] = u[1] * w[2] - u[2] * w[1];
        nrm[1] = u[2] * w[0] - u[0] * w[2];
        nrm[2] = u[0] * w[1] - u[1] * w[0];
        double area2 = sqrt(dcloth_dot3(nrm, nrm));
        if (!(area2 > 0.0) || !isfinite(area2)) continue;
        double lmin = sqrt(fmin(dcloth_dot3(u, u),
                                fmin(dcloth_dot3(w, w), (e[0] - b[0]) * (e[0] - b[0]) + (e[1] - b[1]) * (e[1] - b[1]) +
                                                            (e[2] - b[2]) * (e[2] - b[2]))));
        double depth = fmin(fmin(0.5 * lmin, 0.5 * least), MESH_PRISM_DEPTH * q->surf->thickness);
        for (int r = 0; r < 3; r++) {
            nrm[r] /= area2;
            ps.p[0][r] = a[r];
            ps.p[1][r] = b[r];
            ps.p[2][r] = e[r];
            for (int k = 0; k < 3; k++) ps.p[3 + k][r] = ps.p[k][r] - depth * nrm[r];
        }
        for (int r = 0; r < 3; r++) {
            q->aabb[2 * r] = q->aabb[2 * r + 1] = ps.p[0][r];
            for (int k = 1; k < 6; k++) {
                q->aabb[2 * r] = fmin(q->aabb[2 * r], ps.p[k][r]);
                q->aabb[2 * r + 1] = fmax(q->aabb[2 * r + 1], ps.p[k][r]);
            }
        }
        q->span = dcloth_diagonal(q->aabb);
        q->face = nrm;
        q->convex = c->mesh.convex + 3 * j;
        for (int k = 0; k < 3; k++) {
            const double *p0 = ps.p[k], *p1 = ps.p[(k + 1) % 3];
            double d[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]}, *o = q->out[k];
            o[0] = d[1] * nrm[2] - d[2] * nrm[1];
            o[1] = d[2] * nrm[0] - d[0] * nrm[2];
            o[2] = d[0] * nrm[1] - d[1] * nrm[0];
            double ol = sqrt(dcloth_dot3(o, o));
            for (int r = 0; r < 3; r++) o[r] = ol > 0.0 ? o[r] / ol : 0.0;
        }
        long long i0[3], i1[3], i[3];
        for (int a = 0; a < 3; a++) {
            double top = (double)(dim[a] - 1);
            i0[a] = (long long)fmin(top, fmax(0.0, floor((q->aabb[2 * a] - lo[a]) / s)));
            i1[a] = (long long)fmin(top, fmax(-1.0, floor((q->aabb[2 * a + 1] - lo[a]) / s)));
        }
        for (i[2] = i0[2]; i[2] <= i1[2]; i[2]++)
            for (i[1] = i0[1]; i[1] <= i1[1]; i[1]++)
                for (i[0] = i0[0]; i[0] <= i1[0]; i[0]++) {
                    long long key = cell_key(i, dim);
                    for (int e = c->mesh.grid_head[bucket(key, c->mesh.grid_nbuck)]; e >= 0; e = c->mesh.grid_next[e]) {
                        int k = c->mesh.grid_tri[e];
                        if (c->mesh.grid_key[e] != key || c->mesh.grid_stamp[k] == j + 1) continue;
                        c->mesh.grid_stamp[k] = j + 1;
                        const double *b = c->mesh.grid_box + 6 * k;
                        if (b[1] < q->aabb[0] || b[0] > q->aabb[1] || b[3] < q->aabb[2] || b[2] > q->aabb[3] ||
                            b[5] < q->aabb[4] || b[4] > q->aabb[5])
                            continue;
                        hits += test(c, q, k, h, ccd, fine);
                    }
                }
    }
    return hits;
}
