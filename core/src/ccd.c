/* Continuous point-triangle and edge-edge tests: see ccd.h. */
#include <math.h>
#include "ccd.h"
#include "vec3.h"
#include "tuning.h"

enum { CCD_PT, CCD_EE };

static double cubic_at(const double *c, double t) { return ((c[3] * t + c[2]) * t + c[1]) * t + c[0]; }

static double cubic_slope(const double *c, double t) { return (3.0 * c[3] * t + 2.0 * c[2]) * t + c[1]; }

/* The root in (lo, hi) of a cubic monotone there, f(lo) and f(hi) of
 * opposite signs: Newton, bisecting when a step would leave the bracket or
 * shrink the last step by less than half (rtsafe, Numerical Recipes 9.4). */
static double refine(const double *c, double lo, double hi, double flo)
{
    double neg = flo < 0.0 ? lo : hi, pos = flo < 0.0 ? hi : lo; /* f < 0 at neg, > 0 at pos */
    double t = 0.5 * (lo + hi), dx_old = hi - lo, dx = dx_old;
    double f = cubic_at(c, t), df = cubic_slope(c, t);
    for (int it = 0; it < 100 && f != 0.0; it++) {
        if (((t - pos) * df - f) * ((t - neg) * df - f) > 0.0 || fabs(2.0 * f) > fabs(dx_old * df)) {
            dx_old = dx;
            dx = 0.5 * (pos - neg);
            t = neg + dx;
        } else {
            dx_old = dx;
            dx = f / df;
            t -= dx;
        }
        if (fabs(dx) <= CCD_TTOL) break;
        f = cubic_at(c, t);
        df = cubic_slope(c, t);
        if (f < 0.0) neg = t;
        else pos = t;
    }
    return t;
}

/* Roots in (0, 1) of a t^2 + b t + c, ascending. */
static int turning_points(double a, double b, double c, double *r)
{
    double q[2];
    int n = 0;
    if (a == 0.0) {
        if (b != 0.0) q[n++] = -c / b;
    } else {
        double disc = b * b - 4.0 * a * c;
        if (disc >= 0.0) {
            double s = -0.5 * (b + copysign(sqrt(disc), b));
            q[n++] = s / a;
            if (s != 0.0) q[n++] = c / s;
        }
    }
    int m = 0;
    for (int k = 0; k < n; k++)
        if (q[k] > 0.0 && q[k] < 1.0) r[m++] = q[k];
    if (m == 2 && r[1] < r[0]) {
        double tmp = r[0];
        r[0] = r[1];
        r[1] = tmp;
    }
    return m;
}

int oc_ccd_cubic_roots(const double *c, double ftol, double *t)
{
    if (fabs(c[0]) <= ftol && fabs(c[1]) <= ftol && fabs(c[2]) <= ftol && fabs(c[3]) <= ftol) return -1;
    /* Bernstein coefficients on [0, 1] all of one sign: no root (the curve
     * lies in their convex hull) */
    double b1 = c[0] + c[1] / 3.0, b2 = b1 + (c[1] + c[2]) / 3.0, b3 = c[0] + c[1] + c[2] + c[3];
    if ((c[0] > ftol && b1 > ftol && b2 > ftol && b3 > ftol) ||
        (c[0] < -ftol && b1 < -ftol && b2 < -ftol && b3 < -ftol))
        return 0;
    double b[4] = {0.0};
    int nb = 1 + turning_points(3.0 * c[3], 2.0 * c[2], c[1], b + 1);
    b[nb++] = 1.0;
    int n = 0;
    for (int k = 0; k + 1 < nb; k++) {
        double lo = b[k], hi = b[k + 1], flo = cubic_at(c, lo), fhi = cubic_at(c, hi);
        if (fabs(flo) <= ftol) {
            if (n == 0 || t[n - 1] < lo) t[n++] = lo;
        } else if (fabs(fhi) > ftol && (flo < 0.0) != (fhi < 0.0)) {
            t[n++] = refine(c, lo, hi, flo);
        }
    }
    if (fabs(cubic_at(c, 1.0)) <= ftol && (n == 0 || t[n - 1] < 1.0)) t[n++] = 1.0;
    return n;
}

/* The coplanarity cubic of the four points: det(y1, y2, y3), y_k = x_k - x_0
 * at time t; its length scale (at least the largest |y_k| over the step)
 * in *len. */
static void coplanarity(const double *x0, const double *x1, double *c, double *len)
{
    double A[3][3], B[3][3], L2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double y1[3];
        vec3_sub(x0 + 3 * (k + 1), x0, A[k]);
        vec3_sub(x1 + 3 * (k + 1), x1, y1);
        vec3_sub(y1, A[k], B[k]);
        double l2 = vec3_dot(A[k], A[k]) + vec3_dot(B[k], B[k]);
        if (l2 > L2) L2 = l2;
    }
    c[0] = vec3_triple(A[0], A[1], A[2]);
    c[1] = vec3_triple(B[0], A[1], A[2]) + vec3_triple(A[0], B[1], A[2]) + vec3_triple(A[0], A[1], B[2]);
    c[2] = vec3_triple(B[0], B[1], A[2]) + vec3_triple(B[0], A[1], B[2]) + vec3_triple(A[0], B[1], B[2]);
    c[3] = vec3_triple(B[0], B[1], B[2]);
    *len = sqrt(2.0 * L2); /* >= max_k |A_k| + |B_k| */
}

static double clamp01(double s) { return s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s); }

/* Closest points of segments p1 q1 and p2 q2: p1 + s (q1 - p1) and
 * p2 + u (q2 - p2) (Ericson, Real-Time Collision Detection, 5.1.9). */
static void closest_segments(const double *p1, const double *q1, const double *p2, const double *q2, double *s,
                             double *u)
{
    double d1[3], d2[3], r[3];
    vec3_sub(q1, p1, d1);
    vec3_sub(q2, p2, d2);
    vec3_sub(p1, p2, r);
    double a = vec3_dot(d1, d1), e = vec3_dot(d2, d2), f = vec3_dot(d2, r);
    *s = *u = 0.0;
    if (!(a > 0.0) && !(e > 0.0)) return;
    if (!(a > 0.0)) {
        *u = clamp01(f / e);
        return;
    }
    double c = vec3_dot(d1, r);
    if (!(e > 0.0)) {
        *s = clamp01(-c / a);
        return;
    }
    double b = vec3_dot(d1, d2), den = a * e - b * b;
    *s = den > 0.0 ? clamp01((b * f - c * e) / den) : 0.0;
    *u = (b * *s + f) / e;
    if (*u < 0.0) {
        *u = 0.0;
        *s = clamp01(-c / a);
    } else if (*u > 1.0) {
        *u = 1.0;
        *s = clamp01((b - c) / a);
    }
}

/* Barycentric weights of the point of triangle (a, b, c) nearest p
 * (Ericson 5.1.5; a degenerate triangle: the nearest of its edges). */
static void closest_on_triangle(const double *p, const double *a, const double *b, const double *c, double *w)
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    vec3_sub(b, a, ab);
    vec3_sub(c, a, ac);
    vec3_sub(p, a, ap);
    vec3_sub(p, b, bp);
    vec3_sub(p, c, cp);
    double d1 = vec3_dot(ab, ap), d2 = vec3_dot(ac, ap), d3 = vec3_dot(ab, bp), d4 = vec3_dot(ac, bp);
    double d5 = vec3_dot(ab, cp), d6 = vec3_dot(ac, cp);
    double va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
    w[0] = w[1] = w[2] = 0.0;
    if (d1 <= 0.0 && d2 <= 0.0) {
        w[0] = 1.0;
    } else if (d3 >= 0.0 && d4 <= d3) {
        w[1] = 1.0;
    } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        w[1] = d1 / (d1 - d3);
        w[0] = 1.0 - w[1];
    } else if (d6 >= 0.0 && d5 <= d6) {
        w[2] = 1.0;
    } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        w[2] = d2 / (d2 - d6);
        w[0] = 1.0 - w[2];
    } else if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        w[2] = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        w[1] = 1.0 - w[2];
    } else if (va + vb + vc > 0.0) {
        w[1] = vb / (va + vb + vc);
        w[2] = vc / (va + vb + vc);
        w[0] = 1.0 - w[1] - w[2];
    } else {
        const double *q[3] = {a, b, c};
        double best = HUGE_VAL;
        for (int k = 0; k < 3; k++) {
            double s, u, e[3];
            closest_segments(p, p, q[k], q[(k + 1) % 3], &s, &u);
            for (int i = 0; i < 3; i++) e[i] = p[i] - q[k][i] - u * (q[(k + 1) % 3][i] - q[k][i]);
            if (vec3_dot(e, e) < best) {
                best = vec3_dot(e, e);
                w[k] = 1.0 - u;
                w[(k + 1) % 3] = u;
                w[(k + 2) % 3] = 0.0;
            }
        }
    }
}

/* The pair's weights (see ccd_hit) at positions x, and the normal of its
 * plane (the triangle's, or the edges' cross product) into g. */
static void pair_geometry(int kind, const double *x, double *w, double *g)
{
    double e1[3], e2[3];
    if (kind == CCD_PT) {
        double b[3];
        closest_on_triangle(x, x + 3, x + 6, x + 9, b);
        w[0] = 1.0;
        for (int k = 0; k < 3; k++) w[k + 1] = -b[k];
        vec3_sub(x + 6, x + 3, e1);
        vec3_sub(x + 9, x + 3, e2);
    } else {
        double s, u;
        closest_segments(x, x + 3, x + 6, x + 9, &s, &u);
        w[0] = 1.0 - s;
        w[1] = s;
        w[2] = -(1.0 - u);
        w[3] = -u;
        vec3_sub(x + 3, x, e1);
        vec3_sub(x + 9, x + 6, e2);
    }
    vec3_cross(e1, e2, g);
    if (!(vec3_norm(g) > 1e-12 * vec3_norm(e1) * vec3_norm(e2))) g[0] = g[1] = g[2] = 0.0;
}

void oc_ccd_pair_weights(int edge_edge, const double *x, double *w)
{
    double g[3];
    pair_geometry(edge_edge ? CCD_EE : CCD_PT, x, w, g);
}

/* Whether the pair at time t is a hit: within eta and closing. near: a
 * distance with no direction of its own (the plane's normal is used,
 * turned to the side the first primitive started on). */
static int hit_at(int kind, const double *x0, const double *x1, double t, double eta, double near, ccd_hit *h)
{
    double x[12], d[12], w[4], g[3], r[3] = {0.0}, r0[3] = {0.0}, v[3] = {0.0}, n[3];
    for (int k = 0; k < 12; k++) {
        d[k] = x1[k] - x0[k];
        x[k] = x0[k] + t * d[k];
    }
    pair_geometry(kind, x, w, g);
    for (int j = 0; j < 4; j++) {
        vec3_axpy(r, w[j], x + 3 * j);
        vec3_axpy(r0, w[j], x0 + 3 * j);
        vec3_axpy(v, w[j], d + 3 * j);
    }
    double dist = vec3_norm(r);
    if (!(dist <= eta)) return 0;
    if (dist > near) {
        for (int k = 0; k < 3; k++) n[k] = r[k] / dist;
    } else {
        const double *dir = vec3_norm(g) > 0.0 ? g : r0;
        double l = vec3_norm(dir);
        if (!(l > 0.0)) return 0;
        for (int k = 0; k < 3; k++) n[k] = dir[k] / l;
        double side = vec3_dot(n, r0);
        if (!(fabs(side) > near)) return 0; /* touching at the start: no side to keep */
        if (side < 0.0)
            for (int k = 0; k < 3; k++) n[k] = -n[k];
    }
    if (!(vec3_dot(n, v) < -CCD_CLOSING * vec3_norm(v))) return 0;
    h->t = t;
    h->dist = dist;
    for (int k = 0; k < 4; k++) h->w[k] = w[k];
    for (int k = 0; k < 3; k++) h->n[k] = n[k];
    return 1;
}

static int first_hit(int kind, const double *x0, const double *x1, double eta, ccd_hit *hit)
{
    double c[4], L, t[3];
    coplanarity(x0, x1, c, &L);
    int nr = oc_ccd_cubic_roots(c, CCD_FTOL * L * L * L, t);
    if (nr < 0) { /* coplanar throughout: the ends of the step only */
        t[0] = 0.0;
        t[1] = 1.0;
        nr = 2;
    }
    double near = fmax(CCD_NEAR * eta, 1e-13 * L);
    for (int k = 0; k < nr; k++)
        if (hit_at(kind, x0, x1, t[k], eta, near, hit)) return 1;
    return 0;
}

int oc_ccd_point_triangle(const double *x0, const double *x1, double eta, ccd_hit *hit)
{
    return first_hit(CCD_PT, x0, x1, eta, hit);
}

int oc_ccd_edge_edge(const double *x0, const double *x1, double eta, ccd_hit *hit)
{
    return first_hit(CCD_EE, x0, x1, eta, hit);
}
