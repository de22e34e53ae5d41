/* Cloth triangles a geom ends a solve through, carried there from beyond the start's swept test: the
 * implicit step can drag a slow triangle farther than its own velocity says. Each is tested again over
 * the motion the solve found, from the step's start, and its vertices take the contact it gives. */
#include <math.h>
#include "dcloth_internal.h"
#include "body_motion.h"
#include "convex_query.h"
#include "late_triangles.h"
#include "mesh_contacts.h"
#include "triangle_query.h"
#include "vertex_contacts.h"

/* Triangle p's vertices at the step's end (x1) relative to the body, moved back by h times the body's
 * velocity under their start (x0), into e; returns the farthest any of them moved from its start */
static double moved(dBodyID body, const int *p, const double *x0, const double *x1, double h, double e[9])
{
    double far = 0.0;
    for (int a = 0; a < 3; a++) {
        const double *s = x0 + 3 * p[a], *x = x1 + 3 * p[a];
        double vb[3], *d = e + 3 * a;
        dcloth_point_velocity(body, s, vb);
        for (int r = 0; r < 3; r++) d[r] = x[r] - h * vb[r];
        double m[3] = {d[0] - s[0], d[1] - s[1], d[2] - s[2]};
        far = fmax(far, sqrt(dcloth_dot3(m, m)));
    }
    return far;
}

/* How deep triangle v, grown by r, reaches into q's shape (0 where apart) */
static double overlap(const convex_query *q, const double *const v[3], double r, const ccd_t *ccd)
{
    for (int a = 0; a < 3; a++) {
        double lo = fmin(v[0][a], fmin(v[1][a], v[2][a])) - r, hi = fmax(v[0][a], fmax(v[1][a], v[2][a])) + r;
        if (hi < q->aabb[2 * a] || lo > q->aabb[2 * a + 1]) return 0.0;
    }
    double depth, dir[3], pos[3];
    if (dcloth_triangle_penetration(q, v, r, ccd, &depth, dir, pos) != 0 || !(depth > 0.0) || !isfinite(depth))
        return 0.0;
    return depth;
}

/* Whether the geom ends through triangle v (deeper than the thickness t in its shell), and deeper than
 * its deepest vertex by more than the RESOLVE_DEPTH a vertex may end inside: between its vertices */
static int deeper_than_vertices(dClothID c, const convex_query *q, const double *const v[3], double t,
                                const ccd_t *fine)
{
    double tri = overlap(q, v, t, fine), vert = 0.0;
    if (!(tri > t)) return 0;
    for (int a = 0; a < 3; a++) {
        double dist, nrm[3];
        if (dcloth_vertex_distance(c, q->g, v[a], t, &dist, nrm)) vert = fmax(vert, t - dist);
    }
    return tri > vert + RESOLVE_DEPTH * t;
}

/* Whether triangle k, ending near box, moved relative to q's body beyond its start test's swept shape
 * (reach plus margin and RESOLVE_DEPTH: within it, ending in the shell means that test overlapped);
 * its reach, how far it moved, and its end relative to the body (e) */
static int moved_beyond(dClothID c, const convex_query *q, const double box[6], int k, double h, double *reach,
                        double *far, double e[9])
{
    const int *p = c->tri + 3 * k;
    if (c->pin[p[0]].active && c->pin[p[1]].active && c->pin[p[2]].active) return 0;
    const double *x0 = c->step.x0, *v0 = c->step.v0, *x1 = cloth_positions(c->core);
    double t = q->surf->thickness, sweep = 0.0, r = t + q->travel;
    for (int a = 0; a < 3; a++) { /* its end, within the geom's travel, must reach into the shell */
        double lo = fmin(x1[3 * p[0] + a], fmin(x1[3 * p[1] + a], x1[3 * p[2] + a])) - r;
        double hi = fmax(x1[3 * p[0] + a], fmax(x1[3 * p[1] + a], x1[3 * p[2] + a])) + r;
        if (hi < box[2 * a] || lo > box[2 * a + 1]) return 0;
    }
    for (int a = 0; a < 3; a++) sweep = fmax(sweep, dcloth_relative_speed(q->body, x0 + 3 * p[a], v0 + 3 * p[a]));
    *reach = fmin(h * sweep, q->span);
    *far = moved(q->body, p, x0, x1, h, e);
    return *far > *reach + (DCLOTH_CONTACT_MARGIN + RESOLVE_DEPTH) * t;
}

/* Triangle k against q after a solve: tested again from the start (x0, v0) over the motion the solve
 * found where it moved beyond its start test's shape, ends with the geom between its vertices, and its
 * start test missed */
static int late_triangle(dClothID c, convex_query *q, int k, double h, ccd_t *ccd, ccd_t *fine)
{
    double reach, far, e[9], t = q->surf->thickness;
    if (!moved_beyond(c, q, q->aabb, k, h, &reach, &far, e)) return 0;
    const double *end[3] = {e, e + 3, e + 6};
    if (!deeper_than_vertices(c, q, end, t, fine)) return 0;
    const int *p = c->tri + 3 * k;
    const double *x0 = c->step.x0, *start[3] = {x0 + 3 * p[0], x0 + 3 * p[1], x0 + 3 * p[2]};
    int swept = reach > SWEEP_NEGLIGIBLE * t;
    if (overlap(q, start, t * (1.0 + DCLOTH_CONTACT_MARGIN) + reach, swept ? ccd : fine) > 0.0) return 0;
    q->x = x0;
    q->v = c->step.v0;
    q->reach_min = fmin(far, q->span);
    int hits = dcloth_triangle_query(c, q, k, h, ccd, fine);
    q->x = q->v = NULL;
    q->reach_min = 0.0;
    return hits;
}

/* A mesh's pairs: cloth triangle k's box over where the late test looks (its start grown by the shell and
 * how far it moved), where it moved beyond its start test's shape */
static int late_bounds(dClothID c, const convex_query *q, int k, double h, double span, double b[6])
{
    double reach, far, e[9], box[6];
    (void)span;
    dReal gb[6];
    dGeomGetAABB(q->g, gb);
    for (int a = 0; a < 6; a++) box[a] = gb[a];
    if (!moved_beyond(c, q, box, k, h, &reach, &far, e)) return 0;
    const double *x0 = c->step.x0;
    const int *p = c->tri + 3 * k;
    double r = q->surf->thickness * (1.0 + DCLOTH_CONTACT_MARGIN) + far;
    for (int a = 0; a < 3; a++) {
        b[2 * a] = fmin(x0[3 * p[0] + a], fmin(x0[3 * p[1] + a], x0[3 * p[2] + a])) - r;
        b[2 * a + 1] = fmax(x0[3 * p[0] + a], fmax(x0[3 * p[1] + a], x0[3 * p[2] + a])) + r;
    }
    return 1;
}

int dcloth_late_triangles(dClothID c, double h)
{
    int found = 0;
    for (int a = 0; a < c->broad.ncand; a++) {
        dcloth_geom_shape gs;
        dcloth_polytope box;
        convex_query q;
        ccd_t ccd, fine;
        if (!dcloth_convex_query_of(c, &c->broad.surf[a], h, &q, &gs, &box, &ccd, &fine)) continue;
        if (gs.cls == dTriMeshClass) {
            found += dcloth_mesh_pairs(c, &q, h, &ccd, &fine, late_bounds, late_triangle);
            continue;
        }
        for (int k = 0; k < c->ntri; k++) found += late_triangle(c, &q, k, h, &ccd, &fine);
    }
    return found;
}
