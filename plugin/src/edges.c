/* The cloth's links against the edges and corners of boxes, trimeshes and
 * convexes without triangle tests: vertex contacts let an edge narrower than
 * the spacing pass between two vertices (docs/contacts.md). */
#include <ccd/ccd.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "dcloth_internal.h"
#include "body_motion.h"
#include "contact_offers.h"
#include "edges.h"
#include "epa_side.h"
#include "geom_support.h"
#include "geom_triangles.h"

static void sub3(const double *a, const double *b, double *r)
{
    for (int k = 0; k < 3; k++) r[k] = a[k] - b[k];
}

/* Squared distance from p to triangle (a, b, c) (Voronoi regions of the corners, edges and face). */
static double point_triangle(const double *p, const double *a, const double *b, const double *c)
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    sub3(b, a, ab), sub3(c, a, ac), sub3(p, a, ap);
    double d1 = dcloth_dot3(ab, ap), d2 = dcloth_dot3(ac, ap), u = 0.0, w = 0.0;
    sub3(p, b, bp);
    double d3 = dcloth_dot3(ab, bp), d4 = dcloth_dot3(ac, bp);
    sub3(p, c, cp);
    double d5 = dcloth_dot3(ab, cp), d6 = dcloth_dot3(ac, cp);
    double va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
    if (d1 <= 0.0 && d2 <= 0.0) {
        u = 0.0, w = 0.0;
    } else if (d3 >= 0.0 && d4 <= d3) {
        u = 1.0, w = 0.0;
    } else if (d6 >= 0.0 && d5 <= d6) {
        u = 0.0, w = 1.0;
    } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        u = d1 / (d1 - d3), w = 0.0;
    } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        u = 0.0, w = d2 / (d2 - d6);
    } else if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6)), u = 1.0 - w;
    } else {
        double den = 1.0 / (va + vb + vc);
        u = vb * den, w = vc * den;
    }
    double d[3];
    for (int k = 0; k < 3; k++) d[k] = p[k] - (a[k] + u * ab[k] + w * ac[k]);
    return dcloth_dot3(d, d);
}

static double clamp01(double x) { return x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x; }

/* Squared distance between segments [p1, q1] and [p2, q2]; c1 and c2 the nearest points. */
static double segment_segment(const double *p1, const double *q1, const double *p2, const double *q2, double c1[3],
                              double c2[3])
{
    double s, d1[3], d2[3], r[3];
    sub3(q1, p1, d1), sub3(q2, p2, d2), sub3(p1, p2, r);
    double a = dcloth_dot3(d1, d1), e = dcloth_dot3(d2, d2), f = dcloth_dot3(d2, r), t;
    if (a <= 0.0 && e <= 0.0) {
        s = 0.0, t = 0.0;
    } else if (a <= 0.0) {
        s = 0.0, t = clamp01(f / e);
    } else {
        double cc = dcloth_dot3(d1, r);
        if (e <= 0.0) {
            t = 0.0, s = clamp01(-cc / a);
        } else {
            double b = dcloth_dot3(d1, d2), den = a * e - b * b;
            s = den > 0.0 ? clamp01((b * f - cc * e) / den) : 0.0;
            t = (b * s + f) / e;
            if (t < 0.0) t = 0.0, s = clamp01(-cc / a);
            else if (t > 1.0) t = 1.0, s = clamp01((b - cc) / a);
        }
    }
    double d[3];
    for (int k = 0; k < 3; k++) {
        c1[k] = p1[k] + s * d1[k];
        c2[k] = p2[k] + t * d2[k];
        d[k] = c1[k] - c2[k];
    }
    return dcloth_dot3(d, d);
}

/* Whether segment [a, b] meets triangle t (its boundary included). */
static int segment_meets(const double *a, const double *b, const double *t)
{
    double e1[3], e2[3], d[3], pv[3], tv[3], qv[3];
    sub3(t + 3, t, e1), sub3(t + 6, t, e2), sub3(b, a, d);
    pv[0] = d[1] * e2[2] - d[2] * e2[1], pv[1] = d[2] * e2[0] - d[0] * e2[2], pv[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = dcloth_dot3(e1, pv);
    if (det == 0.0) return 0; /* parallel: the edge tests measure it */
    double inv = 1.0 / det;
    sub3(a, t, tv);
    double u = dcloth_dot3(tv, pv) * inv;
    if (u < 0.0 || u > 1.0) return 0;
    qv[0] = tv[1] * e1[2] - tv[2] * e1[1], qv[1] = tv[2] * e1[0] - tv[0] * e1[2], qv[2] = tv[0] * e1[1] - tv[1] * e1[0];
    double v = dcloth_dot3(d, qv) * inv, s = dcloth_dot3(e2, qv) * inv;
    return v >= 0.0 && u + v <= 1.0 && s >= 0.0 && s <= 1.0;
}

/* The geom's triangles, world frame, into c->edge.tri (9 each) with their
 * boxes (6 each); how many, or -1 when memory ran out. */
static int fetch_triangles(dClothID c, dGeomID g, int cls)
{
    int nt = dcloth_geom_triangle_count(g, cls);
    if (nt > c->edge.cap) {
        double *p = realloc(c->edge.tri, 15 * (size_t)nt * sizeof *p);
        if (!p) return -1;
        c->edge.tri = p;
        c->edge.cap = nt;
    }
    double *tb = c->edge.tri, *box = c->edge.tri + 9 * (size_t)nt;
    dcloth_geom_triangles(g, cls, nt, tb);
    for (int j = 0; j < nt; j++)
        for (int r = 0; r < 3; r++) {
            const double *t = tb + 9 * j;
            box[6 * j + 2 * r] = fmin(t[r], fmin(t[3 + r], t[6 + r]));
            box[6 * j + 2 * r + 1] = fmax(t[r], fmax(t[3 + r], t[6 + r]));
        }
    return nt;
}

/* The fetched triangles bucketed in a uniform grid over their box, cells
 * of a triangle's mean size (at most EDGE_GRID_DIM a side), so a link meets only
 * the triangles near it. */
typedef struct tri_grid {
    double lo[3], cell;
    int dim[3], nt;
    const int *start, *ent; /* CSR: cell k's triangles ent[start[k] .. start[k + 1]) */
} tri_grid;

static int ensure(int **p, int *cap, int n)
{
    if (n <= *cap) return 0;
    int *q = realloc(*p, (size_t)n * sizeof *q);
    if (!q) return -1;
    *p = q;
    *cap = n;
    return 0;
}

/* the cell range [c0, c1] a box (lo, hi) covers, clamped to the grid */
static void cell_range(const tri_grid *gr, const double *lo, const double *hi, int c0[3], int c1[3])
{
    for (int k = 0; k < 3; k++) {
        double a = floor((lo[k] - gr->lo[k]) / gr->cell), b = floor((hi[k] - gr->lo[k]) / gr->cell);
        c0[k] = !(a > 0.0) ? 0 : a >= gr->dim[k] ? gr->dim[k] - 1 : (int)a; /* NaN: 0 */
        c1[k] = !(b > 0.0) ? 0 : b >= gr->dim[k] ? gr->dim[k] - 1 : (int)b;
    }
}

/* Bucket the nt fetched triangles (their boxes after the coordinates) into
 * gr; -1 when memory ran out. */
static int grid_build(dClothID c, int nt, tri_grid *gr)
{
    const double *box = c->edge.tri + 9 * (size_t)nt;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, size = 0.0;
    for (int j = 0; j < nt; j++) {
        double e = 0.0;
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], box[6 * j + 2 * k]);
            hi[k] = fmax(hi[k], box[6 * j + 2 * k + 1]);
            e = fmax(e, box[6 * j + 2 * k + 1] - box[6 * j + 2 * k]);
        }
        size += e / nt;
    }
    double ext = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    gr->cell = fmax(size, ext / EDGE_GRID_DIM);
    if (!(gr->cell > 0.0) || !isfinite(gr->cell) || !isfinite(ext)) gr->cell = INFINITY;
    long long ncell = 1;
    for (int k = 0; k < 3; k++) {
        double d = isfinite(gr->cell) ? floor((hi[k] - lo[k]) / gr->cell) + 1.0 : 1.0;
        gr->dim[k] = d > EDGE_GRID_DIM ? EDGE_GRID_DIM : (int)d;
        gr->lo[k] = isfinite(lo[k]) ? lo[k] : 0.0;
        ncell *= gr->dim[k];
    }
    if (!isfinite(gr->cell)) gr->cell = 1.0; /* one cell */
    gr->nt = nt;
    if (ensure(&c->edge.start, &c->edge.start_cap, (int)ncell + 1) < 0) return -1;
    int *start = c->edge.start;
    memset(start, 0, ((size_t)ncell + 1) * sizeof *start);
    for (int pass = 0; pass < 2; pass++) {
        for (int j = 0; j < nt; j++) {
            const double *bx = box + 6 * j;
            double blo[3] = {bx[0], bx[2], bx[4]}, bhi[3] = {bx[1], bx[3], bx[5]};
            int c0[3], c1[3];
            cell_range(gr, blo, bhi, c0, c1);
            for (int z = c0[2]; z <= c1[2]; z++)
                for (int y = c0[1]; y <= c1[1]; y++)
                    for (int x = c0[0]; x <= c1[0]; x++) {
                        int k = x + gr->dim[0] * (y + gr->dim[1] * z);
                        if (pass) c->edge.ent[start[k]++] = j;
                        else start[k + 1]++;
                    }
        }
        if (pass) break;
        for (long long k = 0; k < ncell; k++) start[k + 1] += start[k];
        if (ensure(&c->edge.ent, &c->edge.ent_cap, start[ncell] > 0 ? start[ncell] : 1) < 0) return -1;
    }
    for (long long k = ncell; k > 0; k--) start[k] = start[k - 1]; /* the fill moved each start to the next */
    start[0] = 0;
    gr->start = start;
    gr->ent = c->edge.ent;
    if (ensure(&c->edge.stamp, &c->edge.stamp_cap, nt) < 0) return -1;
    if (nt > 0) memset(c->edge.stamp, 0, (size_t)nt * sizeof *c->edge.stamp);
    return 0;
}

/* Link [a, b] against gr's triangles within reach r: 1 if its middle is
 * nearer than its ends, or if `tie`, ties with the nearer and is nearer than
 * the other (*d2, p on the link, q on the geom); 0 if not, -1 if it meets it. */
static int link_query(const dClothID c, const tri_grid *gr, int stamp, int tie, const double *a, const double *b,
                      double r, double *d2, double p[3], double q[3])
{
    const double *tb = c->edge.tri, *box = c->edge.tri + 9 * (size_t)gr->nt;
    double lo[3], hi[3], end_a = INFINITY, end_b = INFINITY, mid = INFINITY;
    int c0[3], c1[3];
    for (int k = 0; k < 3; k++) lo[k] = fmin(a[k], b[k]) - r, hi[k] = fmax(a[k], b[k]) + r;
    cell_range(gr, lo, hi, c0, c1);
    for (int z = c0[2]; z <= c1[2]; z++)
        for (int y = c0[1]; y <= c1[1]; y++)
            for (int x = c0[0]; x <= c1[0]; x++) {
                int k = x + gr->dim[0] * (y + gr->dim[1] * z);
                for (int m = gr->start[k]; m < gr->start[k + 1]; m++) {
                    int j = gr->ent[m];
                    const double *bx = box + 6 * j, *t = tb + 9 * j;
                    if (c->edge.stamp[j] == stamp || bx[1] < lo[0] || bx[0] > hi[0] || bx[3] < lo[1] || bx[2] > hi[1] ||
                        bx[5] < lo[2] || bx[4] > hi[2])
                        continue;
                    c->edge.stamp[j] = stamp;
                    if (segment_meets(a, b, t)) return -1;
                    double ea = point_triangle(a, t, t + 3, t + 6), eb = point_triangle(b, t, t + 3, t + 6);
                    end_a = fmin(end_a, ea);
                    end_b = fmin(end_b, eb);
                    for (int e = 0; e < 3; e++) {
                        double c1p[3], c2p[3];
                        double de = segment_segment(a, b, t + 3 * e, t + 3 * ((e + 1) % 3), c1p, c2p);
                        if (!(de < mid)) continue;
                        mid = de;
                        memcpy(p, c1p, sizeof c1p);
                        memcpy(q, c2p, sizeof c2p);
                    }
                }
            }
    /* the tie: a link level with an end at the thickness over a face runs
     * past the face's edge at the thickness too, and the step may take it in */
    double near = fmin(end_a, end_b), far = fmax(end_a, end_b);
    int nearer = mid < (1.0 - EDGE_TIE) * near;
    if (tie && mid <= (1.0 + EDGE_TIE) * near && mid < (1.0 - EDGE_TIE) * far) nearer = 1;
    if (!nearer || !(mid < r * r) || !(mid > 0.0)) return 0;
    *d2 = mid;
    return 1;
}

static void seg_support(const void *obj, const ccd_vec3_t *dir, ccd_vec3_t *out)
{
    const dcloth_seg_shape *s = obj;
    const double *d = dir->v, *e = dcloth_dot3(s->a, d) >= dcloth_dot3(s->b, d) ? s->a : s->b;
    double l = sqrt(dcloth_dot3(d, d)), f = l > 0.0 ? s->r / l : 0.0;
    for (int k = 0; k < 3; k++) out->v[k] = e[k] + f * d[k];
}

static void seg_center(const void *obj, ccd_vec3_t *out)
{
    const dcloth_seg_shape *s = obj;
    for (int k = 0; k < 3; k++) out->v[k] = 0.5 * (s->a[k] + s->b[k]);
}

void dcloth_link_ccd(double t, ccd_t *ccd)
{
    CCD_INIT(ccd);
    ccd->support1 = dcloth_geom_support, ccd->support2 = seg_support;
    ccd->center1 = dcloth_geom_center, ccd->center2 = seg_center;
    ccd->max_iterations = 40;
    ccd->epa_tolerance = EDGE_EPA * t;
}

double dcloth_link_distance(const dcloth_geom_shape *cv, const double *a, const double *b, double r, ccd_t *ccd,
                            double n[3])
{
    dcloth_seg_shape sg = {a, b, r};
    ccd_real_t depth;
    ccd_vec3_t dir, pos;
    if (ccdGJKPenetration(cv, &sg, ccd, &depth, &dir, &pos) != 0 ||
        dcloth_epa_near_side(dcloth_geom_support, cv, seg_support, &sg, ccd->epa_tolerance, &depth, &dir) != 0 ||
        !(depth > 0.0) || !isfinite(depth))
        return INFINITY;
    double l = sqrt(dcloth_dot3(dir.v, dir.v));
    if (!(l > 0.0)) return INFINITY;
    for (int k = 0; k < 3; k++) n[k] = dir.v[k] / l;
    return r - depth;
}

/* Link [a, b] against convex cv within reach r, as link_query: 1 if its
 * middle is nearer than its ends by more than EPA's tolerance (tol), then
 * its distance *dist, n and q, a point of the convex's supporting plane along n. */
static int convex_query(const dcloth_geom_shape *cv, const double *a, const double *b, double r, double tol, ccd_t *ccd,
                        double *dist, double n[3], double q[3])
{
    double na[3], nb[3];
    double mid = *dist = dcloth_link_distance(cv, a, b, r, ccd, n);
    if (!(mid > 0.0) || !(mid < r)) return 0;
    double ends = fmin(dcloth_link_distance(cv, a, a, r, ccd, na), dcloth_link_distance(cv, b, b, r, ccd, nb));
    if (!(mid < ends - tol)) return 0;
    ccd_vec3_t d = {{n[0], n[1], n[2]}}, sp;
    dcloth_geom_support(cv, &d, &sp);
    for (int k = 0; k < 3; k++) q[k] = sp.v[k];
    return 1;
}

/* Vertex i's contact with geom (surface sf, body) on the plane through q
 * with normal n, where it has none or a shallower one with this geom; 1 if
 * set. */
static int offer(dClothID c, int i, const struct dcloth_surf *sf, dBodyID body, const double n[3], const double q[3])
{
    const double *x = cloth_positions(c->core) + 3 * i;
    vcontact *vc = &c->vc_new[i];
    double d[3];
    sub3(x, q, d);
    double height = dcloth_dot3(n, d), gap = height - sf->thickness;
    /* a vertex keeps another geom's contact (the other's may hold it out of
     * that body: a cloth between a bar and a plate) or a deeper one, with
     * this one as its second surface */
    double p[3];
    for (int r = 0; r < 3; r++) p[r] = x[r] - height * n[r];
    if (vc->geom && (vc->geom != sf->g || vc->gap <= gap)) {
        dcloth_offer_second(vc, sf->g, sf->thickness, body, n, p, gap);
        return 0;
    }
    vcontact was = *vc;
    dcloth_set_contact(vc, sf, body, n, p, gap);
    vc->from_triangle = 1; /* a shared contact: the triangles' release rules */
    vc->tri = -1;          /* a link's, not one triangle's: judged per vertex */
    if (was.geom)          /* the plane replaced, the second */
        dcloth_offer_second(vc, was.geom, was.thickness, was.body, was.normal, was.point, was.gap);
    return 1;
}

/* Link [i, j]'s nearest point `depth` m inside the shell, where the step moves the link: the stats' figure */
static void note_depth(dClothID c, int i, int j, double depth)
{
    if (!(c->pin[i].active && c->pin[j].active) && depth > c->step.deepest) c->step.deepest = depth;
}

/* Whether vertex i sits inside the geom by its own contact with it, or is
 * pinned to its body b in a linearised step: that step keeps one plane a
 * vertex, and the pin's neighbour squeezed by another geom loses the edge's. */
static int left_alone(dClothID c, int i, dGeomID g, dBodyID b, int newton)
{
    const vcontact *vc = &c->vc_new[i];
    return (!newton && c->pin[i].active && b && c->pin[i].body == b) || (vc->geom == g && vc->gap < -vc->thickness);
}

int dcloth_edge_contacts(dClothID c, const struct dcloth_surf *sf, double h, double extra)
{
    dGeomID g = sf->g;
    dcloth_geom_shape cv;
    int cls = dGeomGetClass(g);
    if (!dcloth_geom_shape_of(c, g, &cv) && cls == dConvexClass) return 0; /* no points handed over */
    if ((cls != dBoxClass && cls != dTriMeshClass && cls != dConvexClass) || dClothGetTriangleTests(c, g) ||
        !dClothGetEdgeTests(c, g))
        return 0;
    int nt = cls == dConvexClass ? 0 : fetch_triangles(c, g, cls);
    tri_grid gr;
    if (nt < 0 || (cls != dConvexClass && grid_build(c, nt, &gr) < 0)) return -1;
    ccd_t ccd;
    dcloth_link_ccd(sf->thickness, &ccd);
    dReal aabb[6];
    dGeomGetAABB(g, aabb);
    dBodyID body = dGeomGetBody(g);
    const double *x = cloth_positions(c->core), *v = cloth_velocities(c->core);
    double shell = sf->thickness * (1.0 + DCLOTH_CONTACT_MARGIN);
    /* ties and pinned links only where the step decides its contacts in its
     * loop: the linearised step holds a plane, a tie's too, the whole step */
    int newton = cloth_get_desc(c->core).solver.nonlinear == CLOTH_NEWTON;
    int hits = 0, nl = cloth_link_count(c->core, CLOTH_SEQUENTIAL);
    for (int e = 0; e < nl; e++) {
        cloth_link L;
        cloth_get_link(c->core, CLOTH_SEQUENTIAL, e, &L);
        const double *a = x + 3 * L.i, *b = x + 3 * L.j;
        double sp = fmax(dcloth_relative_speed(body, a, v + 3 * L.i), dcloth_relative_speed(body, b, v + 3 * L.j));
        double r = shell + fmax(h * sp, extra);
        if (!(r < INFINITY)) continue;
        if (fmax(a[0], b[0]) + r < aabb[0] || fmin(a[0], b[0]) - r > aabb[1] || fmax(a[1], b[1]) + r < aabb[2] ||
            fmin(a[1], b[1]) - r > aabb[3] || fmax(a[2], b[2]) + r < aabb[4] || fmin(a[2], b[2]) - r > aabb[5])
            continue;
        if (left_alone(c, L.i, g, body, newton) || left_alone(c, L.j, g, body, newton)) continue;
        double d2, dist, p[3], q[3], n[3];
        if (cls == dConvexClass) {
            int hit = convex_query(&cv, a, b, r, 10.0 * ccd.epa_tolerance, &ccd, &dist, n, q);
            note_depth(c, L.i, L.j, sf->thickness - dist);
            if (!hit) continue;
        } else {
            int met = link_query(c, &gr, e + 1, newton, a, b, r, &d2, p, q);
            if (met < 0) note_depth(c, L.i, L.j, sf->thickness); /* through a face: a point on the surface */
            if (met <= 0) continue;
            dist = sqrt(d2);
            note_depth(c, L.i, L.j, sf->thickness - dist);
            for (int m = 0; m < 3; m++) n[m] = (p[m] - q[m]) / dist;
        }
        if (!c->pin[L.i].active) hits += offer(c, L.i, sf, body, n, q);
        if (!c->pin[L.j].active) hits += offer(c, L.j, sf, body, n, q);
    }
    return hits;
}
