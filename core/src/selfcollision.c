/* Cloth against itself: see odecloth/selfcollision.h. A pass after the
 * step, on positions and velocities, through the public state setters. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"
#include "vec3.h"
#include "self_contact.h"
#include "odecloth/selfcollision.h"
#include "tuning.h"

struct cloth_self_collision {
    int rows, cols, n, ntri;
    double thickness;
    double cell;             /* m, hash cell: no larger than a triangle's box (clamped), so a
                          triangle is listed in at most 8 cells */
    int *tri;                /* 3 ntri: corners */
    int *stamp;              /* ntri: last vertex visit that tested the triangle */
    int *head;               /* nbucket: first entry of each bucket, -1 none */
    int *ent_tri, *ent_next; /* 8 ntri entries: triangle and next in its bucket */
    int nbucket;
    double *x, *v; /* 3n: working copies of the state */
    double *xprev; /* 3n: positions after the last apply (the sides) */
    double *winv;  /* n: inverse mass, 0 for a constrained vertex */
    int have_prev;
    double *now, *prev;            /* TRI_GEOM per triangle: its geometry at x (when current) and at xprev */
    long *now_at, *moved_at, tick; /* ntri, n: when a triangle's pair was last found and a vertex last moved */
    self_contact *contact;         /* the Newton step's self-contact, bound to the cloth applied to */
};

/* Unit normal of triangle (a, b, c) into nrm; 0 if degenerate. */
static int tri_normal(const double *a, const double *b, const double *c, double *nrm)
{
    double e1[3], e2[3];
    vec3_sub(b, a, e1);
    vec3_sub(c, a, e2);
    vec3_cross(e1, e2, nrm);
    double l = sqrt(vec3_dot(nrm, nrm));
    if (!(l > 1e-14)) return 0;
    for (int k = 0; k < 3; k++) nrm[k] /= l;
    return 1;
}

/* A triangle's geometry for the tests below: its unit normal, whether it has one, its sides from the
 * first corner, their dot products and the Gram determinant */
#define TRI_GEOM 14

static void tri_geom(const double *x, const int *tv, double *g)
{
    const double *a = x + 3 * tv[0];
    g[3] = tri_normal(a, x + 3 * tv[1], x + 3 * tv[2], g);
    vec3_sub(x + 3 * tv[1], a, g + 4);
    vec3_sub(x + 3 * tv[2], a, g + 7);
    g[10] = vec3_dot(g + 4, g + 4);
    g[11] = vec3_dot(g + 4, g + 7);
    g[12] = vec3_dot(g + 7, g + 7);
    g[13] = g[10] * g[12] - g[11] * g[11];
}

/* Barycentric coordinates of q (in the plane of triangle g, a its first corner). */
static void barycentric(const double *g, const double *a, const double *q, double *w)
{
    double e2[3];
    vec3_sub(q, a, e2);
    double d00 = g[10], d01 = g[11], d11 = g[12];
    double d20 = vec3_dot(e2, g + 4), d21 = vec3_dot(e2, g + 7);
    double den = g[13];
    if (!(fabs(den) > 1e-30)) {
        w[0] = w[1] = w[2] = -1.0;
        return;
    }
    w[1] = (d11 * d20 - d01 * d21) / den;
    w[2] = (d00 * d21 - d01 * d20) / den;
    w[0] = 1.0 - w[1] - w[2];
}

/* Triangle t's geometry at the working positions, found again only after a corner moved */
static const double *geom_now(cloth_self_collision *s, int t)
{
    const int *tv = s->tri + 3 * t;
    double *g = s->now + TRI_GEOM * (size_t)t;
    long at = s->now_at[t];
    if (at < 0 || s->moved_at[tv[0]] > at || s->moved_at[tv[1]] > at || s->moved_at[tv[2]] > at) {
        tri_geom(s->x, tv, g);
        s->now_at[t] = s->tick;
    }
    return g;
}

static void cell_of(const cloth_self_collision *s, const double *p, long *ijk)
{
    for (int k = 0; k < 3; k++) ijk[k] = (long)floor(p[k] / s->cell);
}

static int bucket(const cloth_self_collision *s, long i, long j, long k)
{
    uint64_t h = (uint64_t)i * 73856093u ^ (uint64_t)j * 19349663u ^ (uint64_t)k * 83492791u;
    return (int)(h % (uint64_t)s->nbucket);
}

cloth_status cloth_self_collision_create(const cloth *c, double thickness, cloth_self_collision **out, cloth_error *err)
{
    if (!out) return oc_error_set(err, CLOTH_EINVAL, "cloth_self_collision_create: out is NULL");
    *out = NULL;
    if (!c) return oc_error_set(err, CLOTH_EINVAL, "cloth_self_collision_create: cloth is NULL");
    if (!(thickness > 0.0 && thickness <= 1.0))
        return oc_error_set(err, CLOTH_EINVAL, "cloth_self_collision_create: thickness = %g must be in (0, 1] m",
                            thickness);
    cloth_desc d = cloth_get_desc(c);
    double du = d.width / (d.cols - 1), dv = d.height / (d.rows - 1);
    /* the flat grid's nearest primitives sharing no vertex: parallel cell diagonals */
    double gap = du * dv / sqrt(du * du + dv * dv);
    if (!(thickness < gap))
        return oc_error_set(err, CLOTH_EINVAL,
                            "cloth_self_collision_create: thickness = %g m must be under %g m, the distance between "
                            "the flat grid's cell diagonals (cells %g x %g m): the barrier would push the sheet apart "
                            "at rest",
                            thickness, gap, du, dv);
    cloth_self_collision *s = calloc(1, sizeof *s);
    if (!s) return oc_error_set(err, CLOTH_ENOMEM, "cloth_self_collision_create: out of memory");
    s->rows = d.rows;
    s->cols = d.cols;
    s->n = d.rows * d.cols;
    s->ntri = 2 * (d.rows - 1) * (d.cols - 1);
    s->thickness = thickness;
    /* a triangle within `thickness` of a point has a corner within its
     * longest edge (the cell diagonal, stretched by the elongation limit)
     * plus the thickness; one cell each side covers that */
    s->cell = sqrt(du * du + dv * dv) * (1.0 + d.material.delta) * 1.25 + 2.0 * thickness;
    s->nbucket = 4 * s->ntri + 1;
    size_t n = (size_t)s->n;
    s->tri = malloc(3 * (size_t)s->ntri * sizeof *s->tri);
    s->stamp = malloc((size_t)s->ntri * sizeof *s->stamp);
    s->head = malloc((size_t)s->nbucket * sizeof *s->head);
    s->ent_tri = malloc(8 * (size_t)s->ntri * sizeof *s->ent_tri);
    s->ent_next = malloc(8 * (size_t)s->ntri * sizeof *s->ent_next);
    s->x = malloc(3 * n * sizeof *s->x);
    s->v = malloc(3 * n * sizeof *s->v);
    s->xprev = malloc(3 * n * sizeof *s->xprev);
    s->winv = malloc(n * sizeof *s->winv);
    s->now = malloc(TRI_GEOM * (size_t)s->ntri * sizeof *s->now);
    s->prev = malloc(TRI_GEOM * (size_t)s->ntri * sizeof *s->prev);
    s->now_at = malloc((size_t)s->ntri * sizeof *s->now_at);
    s->moved_at = malloc(n * sizeof *s->moved_at);
    if (!s->tri || !s->stamp || !s->head || !s->ent_tri || !s->ent_next || !s->x || !s->v || !s->xprev || !s->winv ||
        !s->now || !s->prev || !s->now_at || !s->moved_at) {
        cloth_self_collision_destroy(s);
        return oc_error_set(err, CLOTH_ENOMEM, "cloth_self_collision_create: out of memory");
    }
    int t = 0;
    for (int r = 0; r + 1 < d.rows; r++)
        for (int q = 0; q + 1 < d.cols; q++) {
            int a = r * d.cols + q, b = a + 1, cc = a + d.cols, dd = cc + 1;
            const int corners[2][3] = {{a, b, dd}, {a, dd, cc}};
            for (int h = 0; h < 2; h++, t++)
                for (int k = 0; k < 3; k++) s->tri[3 * t + k] = corners[h][k];
        }
    s->contact = oc_self_contact_create(s->n, s->ntri, s->tri, thickness); /* after the triangles: their edges */
    if (!s->contact) {
        cloth_self_collision_destroy(s);
        return oc_error_set(err, CLOTH_ENOMEM, "cloth_self_collision_create: out of memory");
    }
    *out = s;
    return CLOTH_OK;
}

void cloth_self_collision_destroy(cloth_self_collision *s)
{
    if (!s) return;
    oc_self_contact_destroy(s->contact);
    free(s->tri);
    free(s->stamp);
    free(s->head);
    free(s->ent_tri);
    free(s->ent_next);
    free(s->x);
    free(s->v);
    free(s->xprev);
    free(s->winv);
    free(s->now);
    free(s->prev);
    free(s->now_at);
    free(s->moved_at);
    free(s);
}

/* Vertex p against triangle t: separate them if p is closer than the
 * thickness to t's plane over t, or on the other side of it than at the
 * last apply. Returns 1 if they were moved. */
static int separate(cloth_self_collision *s, int p, int t, cloth_self_collision_stats *st)
{
    const int *tv = s->tri + 3 * t;
    double *x = s->x, *v = s->v;
    const double *xp = s->xprev;
    const double *gn = geom_now(s, t), *gp = s->prev + TRI_GEOM * (size_t)t, *nrm = gn, *nprev = gp;
    if (!gn[3]) return 0;
    double rel[3];
    vec3_sub(x + 3 * p, x + 3 * tv[0], rel);
    double s_now = vec3_dot(rel, nrm);
    /* only a point over the triangle: its edges belong to the neighbours */
    double q[3], w[3];
    for (int k = 0; k < 3; k++) q[k] = x[3 * p + k] - s_now * nrm[k];
    barycentric(gn, x + 3 * tv[0], q, w);
    if (w[0] < -SC_EDGE_SLACK || w[1] < -SC_EDGE_SLACK || w[2] < -SC_EDGE_SLACK) return 0;
    /* the side it is on at the last apply's positions */
    double side = s_now >= 0.0 ? 1.0 : -1.0;
    int over_before = 0;
    if (gp[3]) {
        vec3_sub(xp + 3 * p, xp + 3 * tv[0], rel);
        double s_prev = vec3_dot(rel, nprev), qp[3], wp[3];
        if (fabs(s_prev) > 1e-12) side = s_prev > 0.0 ? 1.0 : -1.0;
        for (int k = 0; k < 3; k++) qp[k] = xp[3 * p + k] - s_prev * nprev[k];
        barycentric(gp, xp + 3 * tv[0], qp, wp);
        over_before = wp[0] > -SC_OVER_MARGIN && wp[1] > -SC_OVER_MARGIN && wp[2] > -SC_OVER_MARGIN;
    }
    double gap = side * s_now; /* negative: crossed */
    /* a crossing only if it was over the triangle (nearly) at the last apply too: a vertex that went
     * round the triangle's edge did not pass through it */
    if (gap < 0.0 && !over_before) return 0;
    if (gap < st->closest) st->closest = gap;
    double depth = s->thickness - gap;
    if (!(depth > 0.0)) return 0;
    /* a held vertex is left to the pairs where its neighbours are the
     * vertex: moving only a triangle's corners to clear a point near
     * another corner would throw them by depth / w */
    if (!(s->winv[p] > 0.0)) return 0;
    double denom = s->winv[p];
    for (int k = 0; k < 3; k++) denom += w[k] * w[k] * s->winv[tv[k]];
    double dir[3] = {side * nrm[0], side * nrm[1], side * nrm[2]};
    double lam = depth / denom;
    s->tick++;
    s->moved_at[p] = s->moved_at[tv[0]] = s->moved_at[tv[1]] = s->moved_at[tv[2]] = s->tick;
    for (int a = 0; a < 3; a++) {
        x[3 * p + a] += lam * s->winv[p] * dir[a];
        for (int k = 0; k < 3; k++) x[3 * tv[k] + a] -= lam * w[k] * s->winv[tv[k]] * dir[a];
    }
    /* inelastic: cancel the approaching normal velocity */
    double vrel = 0.0;
    for (int a = 0; a < 3; a++) {
        double vt = w[0] * v[3 * tv[0] + a] + w[1] * v[3 * tv[1] + a] + w[2] * v[3 * tv[2] + a];
        vrel += (v[3 * p + a] - vt) * dir[a];
    }
    if (vrel < 0.0) {
        double mu = -vrel / denom;
        for (int a = 0; a < 3; a++) {
            v[3 * p + a] += mu * s->winv[p] * dir[a];
            for (int k = 0; k < 3; k++) v[3 * tv[k] + a] -= mu * w[k] * s->winv[tv[k]] * dir[a];
        }
    }
    st->pairs++;
    if (gap < 0.0) st->crossings++;
    return 1;
}

cloth_status cloth_self_collision_apply(cloth_self_collision *s, cloth *c, cloth_self_collision_stats *stats)
{
    cloth_self_collision_stats st = {0, 0, HUGE_VAL};
    if (stats) *stats = st;
    if (!s || !c) return CLOTH_EINVAL;
    if (cloth_rows(c) != s->rows || cloth_cols(c) != s->cols)
        return oc_cloth_fail(c, CLOTH_EINVAL,
                             "cloth_self_collision_apply: the cloth is %d x %d, the pass was made "
                             "for %d x %d",
                             cloth_rows(c), cloth_cols(c), s->rows, s->cols);
    size_t n = (size_t)s->n;
    oc_self_contact_bind(s->contact, c);
    memcpy(s->x, cloth_positions(c), 3 * n * sizeof *s->x);
    if (!s->have_prev) {
        memcpy(s->xprev, s->x, 3 * n * sizeof *s->x);
        s->have_prev = 1;
        return CLOTH_OK;
    }
    memcpy(s->v, cloth_velocities(c), 3 * n * sizeof *s->v);
    const double *m = cloth_masses(c);
    for (int i = 0; i < s->n; i++) {
        cloth_constraint k;
        int held = cloth_get_constraint(c, i, &k) == CLOTH_OK && k.ndof > 0;
        s->winv[i] = held || !(m[i] > 0.0) ? 0.0 : 1.0 / m[i];
    }
    /* the hash, once per apply (the passes move vertices by millimetres): each triangle in the cells of
     * its box over its corners now and at the last apply, widened by the thickness and clamped to one
     * cell's size so that it meets at most 8 cells */
    for (int b = 0; b < s->nbucket; b++) s->head[b] = -1;
    int nent = 0;
    for (int t = 0; t < s->ntri; t++) {
        double lo[3], hi[3];
        for (int a = 0; a < 3; a++) lo[a] = hi[a] = s->x[3 * s->tri[3 * t] + a];
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++) {
                double u = s->x[3 * s->tri[3 * t + k] + a], w = s->xprev[3 * s->tri[3 * t + k] + a];
                lo[a] = fmin(lo[a], fmin(u, w));
                hi[a] = fmax(hi[a], fmax(u, w));
            }
        long c0[3], c1[3];
        for (int a = 0; a < 3; a++) {
            lo[a] -= s->thickness;
            hi[a] += s->thickness;
            if (hi[a] - lo[a] > s->cell) {
                double mid = 0.5 * (lo[a] + hi[a]);
                lo[a] = mid - 0.5 * s->cell;
                hi[a] = mid + 0.5 * s->cell;
            }
            c0[a] = (long)floor(lo[a] / s->cell);
            c1[a] = (long)floor(hi[a] / s->cell);
        }
        for (long i = c0[0]; i <= c1[0]; i++)
            for (long j = c0[1]; j <= c1[1]; j++)
                for (long k = c0[2]; k <= c1[2]; k++) {
                    int b = bucket(s, i, j, k);
                    s->ent_tri[nent] = t;
                    s->ent_next[nent] = s->head[b];
                    s->head[b] = nent++;
                }
    }
    int moved = 0, visit = 0;
    for (int t = 0; t < s->ntri; t++) {
        s->stamp[t] = -1;
        s->now_at[t] = -1;
        tri_geom(s->xprev, s->tri + 3 * t, s->prev + TRI_GEOM * (size_t)t);
    }
    for (int i = 0; i < s->n; i++) s->moved_at[i] = -1;
    s->tick = 0;
    for (int pass = 0; pass < SC_PASSES; pass++) {
        int moved_pass = 0;
        for (int p = 0; p < s->n; p++, visit++) {
            long ijk[3];
            cell_of(s, s->x + 3 * p, ijk);
            for (int e = s->head[bucket(s, ijk[0], ijk[1], ijk[2])]; e >= 0; e = s->ent_next[e]) {
                int t = s->ent_tri[e];
                if (s->stamp[t] == visit) continue;
                s->stamp[t] = visit;
                const int *tv = s->tri + 3 * t;
                if (tv[0] == p || tv[1] == p || tv[2] == p) continue;
                moved_pass += separate(s, p, t, &st);
            }
        }
        moved += moved_pass;
        if (!moved_pass) break;
    }
    if (moved) {
        cloth_status r = cloth_set_positions(c, s->x);
        if (r == CLOTH_OK) r = cloth_set_velocities(c, s->v);
        if (r != CLOTH_OK) return r;
    }
    memcpy(s->xprev, s->x, 3 * n * sizeof *s->x);
    if (stats) *stats = st;
    return CLOTH_OK;
}
