/* A cloth triangle grown by a radius against a convex polytope by separating axes (face normals, the
 * triangle's normal, edge cross products): the depth, and the contact's plane and point where the features
 * along the least axis meet, not EPA's path-dependent answer (docs/contacts.md, exact triangle tests). */
#include <math.h>
#include <string.h>
#include "polytope.h"
#include "tuning.h"

/* points of a clipped feature: a quadrilateral clipped by three sides has at most seven */
#define MAXP 12

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static int unit(double *a)
{
    double l = sqrt(dot(a, a));
    if (!(l > 0.0) || !isfinite(l)) return 0;
    for (int k = 0; k < 3; k++) a[k] /= l;
    return 1;
}

void dcloth_polytope_box(dcloth_polytope *P, const double o[3], const double *R, const double half[3])
{
    memset(P, 0, sizeof *P);
    P->nv = 8;
    for (int i = 0; i < 8; i++) {
        double q[3];
        for (int k = 0; k < 3; k++) q[k] = (i >> k & 1) ? half[k] : -half[k];
        for (int k = 0; k < 3; k++) P->v[i][k] = o[k] + R[4 * k] * q[0] + R[4 * k + 1] * q[1] + R[4 * k + 2] * q[2];
    }
    P->nf = 6;
    P->ne = 3;
    for (int f = 0; f < 6; f++) {
        int k = f / 2, s = f & 1, a = (k + 1) % 3, b = (k + 2) % 3;
        for (int r = 0; r < 3; r++) P->n[f][r] = s ? R[4 * r + k] : -R[4 * r + k];
        /* around the face: (a-, b-), (a+, b-), (a+, b+), (a-, b+) */
        static const int sa[4] = {0, 1, 1, 0}, sb[4] = {0, 0, 1, 1};
        for (int m = 0; m < 4; m++) P->face[f][m] = (s << k) | (sa[m] << a) | (sb[m] << b);
        P->fv[f] = 4;
    }
    for (int k = 0; k < 3; k++)
        for (int r = 0; r < 3; r++) P->e[k][r] = R[4 * r + k];
}

static double support(const dcloth_polytope *P, const double u[3])
{
    double h = -INFINITY;
    for (int i = 0; i < P->nv; i++) h = fmax(h, dot(P->v[i], u));
    return h;
}

static double tri_min(const double *const t[3], const double u[3])
{
    return fmin(dot(t[0], u), fmin(dot(t[1], u), dot(t[2], u)));
}

/* The overlap of t grown by r and P along u, and along -u; the lesser kept in *best with its direction */
static void axis(const dcloth_polytope *P, const double *const t[3], double r, const double u[3], int both,
                 double *best, double bn[3])
{
    for (int s = 0; s <= both; s++) {
        double d[3] = {s ? -u[0] : u[0], s ? -u[1] : u[1], s ? -u[2] : u[2]};
        double ov = support(P, d) - tri_min(t, d) + r;
        if (ov < *best) {
            *best = ov;
            memcpy(bn, d, sizeof d);
        }
    }
}

typedef struct poly {
    int n;
    double p[MAXP][3];
} poly;

/* a keeps its part where s . x <= d (a point, a segment or a convex polygon) */
static void clip(poly *a, const double s[3], double d)
{
    double f[MAXP];
    for (int i = 0; i < a->n; i++) f[i] = dot(s, a->p[i]) - d;
    if (a->n <= 2) {
        int out = 0;
        for (int i = 0; i < a->n; i++) out += f[i] > 0.0;
        if (out == a->n) {
            a->n = 0;
            return;
        }
        if (out != 1) return;
        int i = f[0] > 0.0 ? 0 : 1, j = 1 - i;
        for (int k = 0; k < 3; k++) a->p[i][k] += (a->p[j][k] - a->p[i][k]) * f[i] / (f[i] - f[j]);
        return;
    }
    poly b = {0};
    for (int i = 0; i < a->n && b.n + 2 <= MAXP; i++) {
        int j = (i + 1) % a->n;
        if (f[i] <= 0.0) memcpy(b.p[b.n++], a->p[i], sizeof b.p[0]);
        if ((f[i] <= 0.0) != (f[j] <= 0.0))
            for (int k = 0; k < 3; k++) b.p[b.n][k] = a->p[i][k] + (a->p[j][k] - a->p[i][k]) * f[i] / (f[i] - f[j]);
        b.n += (f[i] <= 0.0) != (f[j] <= 0.0);
    }
    *a = b;
}

/* a clipped by the sides of the polygon q[0..m) of normal nrm (planes through its edges along nrm) */
static void clip_sides(poly *a, const double (*q)[3], int m, const double nrm[3])
{
    double g[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < m; i++)
        for (int k = 0; k < 3; k++) g[k] += q[i][k] / m;
    for (int i = 0; i < m && a->n > 0; i++) {
        const double *p0 = q[i], *p1 = q[(i + 1) % m];
        double e[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]}, s[3];
        double gp[3] = {g[0] - p0[0], g[1] - p0[1], g[2] - p0[2]};
        cross(nrm, e, s);
        if (dot(s, gp) > 0.0)
            for (int k = 0; k < 3; k++) s[k] = -s[k];
        clip(a, s, dot(s, p0));
    }
}

/* the centroid of a's area, or of its points where it has none; 0 if a is empty */
static int centroid(const poly *a, double c[3])
{
    if (a->n == 0) return 0;
    double w = 0.0, m[3] = {0.0, 0.0, 0.0}, avg[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < a->n; i++)
        for (int k = 0; k < 3; k++) avg[k] += a->p[i][k] / a->n;
    for (int i = 1; i + 1 < a->n; i++) {
        double e1[3], e2[3], x[3];
        for (int k = 0; k < 3; k++) e1[k] = a->p[i][k] - a->p[0][k], e2[k] = a->p[i + 1][k] - a->p[0][k];
        cross(e1, e2, x);
        double wi = sqrt(dot(x, x));
        w += wi;
        for (int k = 0; k < 3; k++) m[k] += wi * (a->p[0][k] + a->p[i][k] + a->p[i + 1][k]) / 3.0;
    }
    for (int k = 0; k < 3; k++) c[k] = w > 0.0 ? m[k] / w : avg[k];
    return 1;
}

/* point x onto the plane u . x = h, into a */
static void add_projected(poly *a, const double x[3], const double u[3], double h)
{
    double s = dot(u, x) - h;
    for (int k = 0; k < 3; k++) a->p[a->n][k] = x[k] - s * u[k];
    a->n++;
}

/* The feature pair where triangle t and P meet along bn (from P toward t), P's supporting plane there
 * bn . x = h: its point on that plane into c. kind: P's face f >= 0, the triangle's plane -1, or edges -2.
 * 0 where the features do not meet (the axis is not where they are nearest). */
static int meet(const dcloth_polytope *P, const double *const t[3], const double nt[3], const double bn[3], int kind,
                double tol, double c[3])
{
    double h = support(P, bn), lo = tri_min(t, bn);
    poly a = {0}, b = {0};
    for (int k = 0; k < 3; k++) /* the triangle's lowest feature */
        if (dot(t[k], bn) <= lo + tol) add_projected(&b, t[k], bn, h);
    for (int i = 0; i < P->nv; i++) /* P's highest */
        if (dot(P->v[i], bn) >= h - tol) add_projected(&a, P->v[i], bn, h);
    if (kind >= 0) { /* the triangle's feature clipped to face `kind` */
        double q[4][3];
        for (int m = 0; m < P->fv[kind]; m++) memcpy(q[m], P->v[P->face[kind][m]], sizeof q[0]);
        clip_sides(&b, (const double(*)[3])q, P->fv[kind], P->n[kind]);
        return centroid(&b, c);
    }
    if (kind == -1) { /* P's feature (a face: the one facing most along bn) clipped to the triangle */
        int top = 0;
        for (int k = 1; k < P->nf; k++)
            if (dot(P->n[k], bn) > dot(P->n[top], bn)) top = k;
        if (a.n >= 3)
            for (int m = a.n = 0; m < P->fv[top]; m++) add_projected(&a, P->v[P->face[top][m]], bn, h);
        double q[3][3];
        for (int k = 0; k < 3; k++) memcpy(q[k], t[k], sizeof q[0]);
        clip_sides(&a, (const double(*)[3])q, 3, nt);
        return centroid(&a, c);
    }
    if (a.n != 2 || b.n != 2) return 0; /* edges: the nearest points of the two, within both */
    double d1[3], d2[3], r0[3];
    for (int k = 0; k < 3; k++) {
        d1[k] = a.p[1][k] - a.p[0][k];
        d2[k] = b.p[1][k] - b.p[0][k];
        r0[k] = a.p[0][k] - b.p[0][k];
    }
    double aa = dot(d1, d1), ab = dot(d1, d2), bb = dot(d2, d2), ar = dot(d1, r0), br = dot(d2, r0);
    double den = aa * bb - ab * ab;
    if (!(den > EDGE_PARALLEL * EDGE_PARALLEL * aa * bb)) return 0;
    double s = (ab * br - bb * ar) / den, u = (aa * br - ab * ar) / den;
    if (!(s >= 0.0 && s <= 1.0 && u >= 0.0 && u <= 1.0)) return 0;
    for (int k = 0; k < 3; k++) c[k] = a.p[0][k] + s * d1[k];
    return 1;
}

static double clamp01(double x) { return x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x; }

/* The nearest points cp, cq of segments [p0, p1] and [q0, q1] (parallel ones: the middle of where they
 * overlap, seen along them); their distance */
static double seg_seg(const double *p0, const double *p1, const double *q0, const double *q1, double cp[3],
                      double cq[3])
{
    double d1[3], d2[3], r[3];
    for (int k = 0; k < 3; k++) d1[k] = p1[k] - p0[k], d2[k] = q1[k] - q0[k], r[k] = p0[k] - q0[k];
    double a = dot(d1, d1), e = dot(d2, d2), b = dot(d1, d2), c = dot(d1, r), f = dot(d2, r), s, u;
    double den = a * e - b * b;
    if (!(a > 0.0) || !(e > 0.0)) return INFINITY;
    if (den <= EDGE_PARALLEL * EDGE_PARALLEL * a * e) {
        double t0 = -c / a, t1 = (b - c) / a, lo = fmax(0.0, fmin(t0, t1)), hi = fmin(1.0, fmax(t0, t1));
        s = lo <= hi ? 0.5 * (lo + hi) : (hi < 0.0 ? 0.0 : 1.0);
        u = clamp01((b * s + f) / e);
    } else {
        s = clamp01((b * f - c * e) / den);
        u = (b * s + f) / e;
        if (u < 0.0 || u > 1.0) {
            u = clamp01(u);
            s = clamp01((b * u - c) / a);
        }
    }
    for (int k = 0; k < 3; k++) cp[k] = p0[k] + s * d1[k], cq[k] = q0[k] + u * d2[k];
    double d[3] = {cp[0] - cq[0], cp[1] - cq[1], cp[2] - cq[2]};
    return sqrt(dot(d, d));
}

/* whether x lies over polygon q[0..m) of normal nrm (within the planes through its edges along nrm) */
static int over(const double (*q)[3], int m, const double nrm[3], const double x[3])
{
    poly a = {1, {{x[0], x[1], x[2]}}};
    clip_sides(&a, q, m, nrm);
    return a.n == 1;
}

/* Triangle t apart from P: their nearest points p (on P) and q (on t), from the pairs a nearest pair can be
 * (a vertex of either over a face of the other, two edges), face pairs first; their distance */
static double nearest(const dcloth_polytope *P, const double *const t[3], const double nt[3], double tol, double p[3],
                      double q[3])
{
    double best = INFINITY, tq[3][3], fq[4][3];
    for (int k = 0; k < 3; k++) memcpy(tq[k], t[k], sizeof tq[0]);
    for (int f = 0; f < P->nf; f++) { /* the triangle's vertices over P's faces */
        for (int m = 0; m < P->fv[f]; m++) memcpy(fq[m], P->v[P->face[f][m]], sizeof fq[0]);
        for (int k = 0; k < 3; k++) {
            double h = dot(P->n[f], t[k]) - dot(P->n[f], fq[0]);
            if (!(h >= 0.0 && h < best) || !over((const double(*)[3])fq, P->fv[f], P->n[f], t[k])) continue;
            best = h;
            for (int r = 0; r < 3; r++) q[r] = t[k][r], p[r] = t[k][r] - h * P->n[f][r];
        }
    }
    for (int i = 0; i < P->nv; i++) { /* P's vertices over the triangle */
        double h = dot(nt, P->v[i]) - dot(nt, t[0]);
        if (!(fabs(h) < best) || !over((const double(*)[3])tq, 3, nt, P->v[i])) continue;
        best = fabs(h);
        for (int r = 0; r < 3; r++) p[r] = P->v[i][r], q[r] = P->v[i][r] - h * nt[r];
    }
    for (int f = 0; f < P->nf; f++) /* edges: each of P's twice, once from each face */
        for (int m = 0; m < P->fv[f]; m++)
            for (int k = 0; k < 3; k++) {
                double cp[3], cq[3];
                const double *a = P->v[P->face[f][m]], *b = P->v[P->face[f][(m + 1) % P->fv[f]]];
                double d = seg_seg(a, b, t[k], t[(k + 1) % 3], cp, cq);
                if (!(d < best - tol)) continue;
                best = d;
                memcpy(p, cp, sizeof cp);
                memcpy(q, cq, sizeof cq);
            }
    return best;
}

int dcloth_polytope_query(const dcloth_polytope *P, const double *const t[3], double r, double *depth, double n[3],
                          double pos[3])
{
    double e[3][3], nt[3];
    for (int k = 0; k < 3; k++)
        for (int a = 0; a < 3; a++) e[k][a] = t[(k + 1) % 3][a] - t[k][a];
    cross(e[0], e[1], nt);
    if (!unit(nt) || !unit(e[0]) || !unit(e[1]) || !unit(e[2])) return 0;
    /* faces of P first, then the triangle's plane: a tie goes to P's face */
    double best = INFINITY, bn[3] = {0.0, 0.0, 1.0}, edge = INFINITY, en[3] = {0.0, 0.0, 1.0};
    int kind = -1;
    for (int k = 0; k < P->nf; k++) {
        double was = best;
        axis(P, t, r, P->n[k], 0, &best, bn);
        if (best < was) kind = k;
    }
    double was = best;
    axis(P, t, r, nt, 1, &best, bn);
    if (best < was) kind = -1;
    for (int a = 0; a < P->ne; a++)
        for (int k = 0; k < 3; k++) {
            double c[3];
            cross(P->e[a], e[k], c);
            if (!(sqrt(dot(c, c)) > EDGE_PARALLEL) || !unit(c)) continue;
            axis(P, t, r, c, 1, &edge, en);
        }
    if (!isfinite(best)) return 0;
    if (best <= 0.0 || edge <= 0.0) return -1;
    /* an edge pair decides only where less by more than rounding */
    double tol = FEATURE_TIE * r, c[3];
    if (edge < best - tol) {
        best = edge;
        memcpy(bn, en, sizeof bn);
        kind = -2;
    }
    if (!meet(P, t, nt, bn, kind, tol, c)) {
        /* the triangle itself inside P: EPA's; apart: the nearest points decide */
        double p[3], q[3], d = best < r ? nearest(P, t, nt, tol, p, q) : INFINITY;
        if (!(d > 0.0) || !isfinite(d)) return 0;
        best = r - d;
        for (int k = 0; k < 3; k++) bn[k] = (q[k] - p[k]) / d, c[k] = p[k];
        if (!(best > 0.0)) return -1;
    }
    *depth = best;
    for (int k = 0; k < 3; k++) {
        n[k] = bn[k];
        pos[k] = c[k] - 0.5 * best * bn[k];
    }
    return 1;
}
