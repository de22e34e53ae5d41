/* One cloth triangle against one convex shape (the geom, or a mesh triangle's prism), by libccd's
 * GJK + EPA or, on an exact box, separating axes (polytope.c): where they overlap, the triangle's
 * vertices are offered the contact, shared by barycentric weight. */
#include <ccd/ccd.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "dcloth_internal.h"
#include "body_motion.h"
#include "contact_offers.h"
#include "epa_side.h"
#include "geom_support.h"
#include "polytope.h"
#include "triangle_query.h"

typedef struct tri_shape {
    const double *v[3];
    double radius;
} tri_shape;

void dcloth_tri_support(const void *obj, const ccd_vec3_t *dir, ccd_vec3_t *out)
{
    const tri_shape *t = obj;
    const double *d = dir->v;
    int best = 0;
    double bd = -INFINITY;
    for (int k = 0; k < 3; k++) {
        double s = t->v[k][0] * d[0] + t->v[k][1] * d[1] + t->v[k][2] * d[2];
        if (s > bd) bd = s, best = k;
    }
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), s = l > 0.0 ? t->radius / l : 0.0;
    for (int k = 0; k < 3; k++) out->v[k] = t->v[best][k] + s * d[k];
}

void dcloth_tri_center(const void *obj, ccd_vec3_t *out)
{
    const tri_shape *t = obj;
    for (int k = 0; k < 3; k++) out->v[k] = (t->v[0][k] + t->v[1][k] + t->v[2][k]) / 3.0;
}

/* Barycentric coordinates of p's projection on triangle v, clamped to the
 * triangle (negative ones zeroed, the rest renormalised). */
static void barycentric(const double *const v[3], const double *p, double w[3])
{
    double e1[3], e2[3], d[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = v[1][k] - v[0][k];
        e2[k] = v[2][k] - v[0][k];
        d[k] = p[k] - v[0][k];
    }
    double a = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2], b = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    double cc = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    double d1 = e1[0] * d[0] + e1[1] * d[1] + e1[2] * d[2], d2 = e2[0] * d[0] + e2[1] * d[1] + e2[2] * d[2];
    double det = a * cc - b * b;
    double s = det > 0.0 ? (cc * d1 - b * d2) / det : 1.0 / 3.0, t = det > 0.0 ? (a * d2 - b * d1) / det : 1.0 / 3.0;
    w[0] = 1.0 - s - t;
    w[1] = s;
    w[2] = t;
    double sum = 0.0;
    for (int k = 0; k < 3; k++) {
        if (!(w[k] > 0.0)) w[k] = 0.0;
        sum += w[k];
    }
    for (int k = 0; k < 3; k++) w[k] = sum > 0.0 ? w[k] / sum : 1.0 / 3.0;
}

void dcloth_triangle_ccd(double t, ccd_t *loose, ccd_t *fine)
{
    CCD_INIT(loose);
    loose->support1 = dcloth_geom_support;
    loose->support2 = dcloth_tri_support;
    loose->center1 = dcloth_geom_center;
    loose->center2 = dcloth_tri_center;
    loose->max_iterations = 40;
    loose->epa_tolerance = 1e-3 * t;
    *fine = *loose;
    fine->epa_tolerance = EPA_FINE * t;
}

/* Triangle ts into q's shape, as ccdGJKPenetration answers (0: they overlap): by separating axes on a
 * polytope where a face decides it (polytope.c), else by libccd with ccd's tolerance, its direction
 * taken toward the nearer side of the shape */
static int penetration(const convex_query *q, const tri_shape *ts, const ccd_t *ccd, ccd_real_t *depth, ccd_vec3_t *dir,
                       ccd_vec3_t *pos)
{
    int r = q->poly ? dcloth_polytope_query(q->poly, ts->v, ts->radius, depth, dir->v, pos->v) : 0;
    if (r) return r > 0 ? 0 : -1;
    if (ccdGJKPenetration(q->shape, ts, ccd, depth, dir, pos) != 0) return -1;
    return dcloth_epa_near_side(q->support, q->shape, dcloth_tri_support, ts, ccd->epa_tolerance, depth, dir);
}

int dcloth_triangle_penetration(const convex_query *q, const double *const v[3], double radius, const ccd_t *ccd,
                                double *depth, double dir[3], double pos[3])
{
    tri_shape ts = {{v[0], v[1], v[2]}, radius};
    ccd_real_t d;
    ccd_vec3_t n, p;
    int r = penetration(q, &ts, ccd, &d, &n, &p);
    *depth = d;
    memcpy(dir, n.v, sizeof n.v);
    memcpy(pos, p.v, sizeof p.v);
    return r;
}

/* Whether direction n, found against a mesh triangle's prism, is one the
 * mesh's surface has there (MESH_FACE_COS). */
static int mesh_direction(const convex_query *q, const double n[3])
{
    double nf = dcloth_dot3(n, q->face);
    if (nf >= MESH_FACE_COS) return 1;
    if (nf < 0.0) return 0; /* into the mesh */
    int best = 0;
    for (int e = 1; e < 3; e++)
        if (dcloth_dot3(n, q->out[e]) > dcloth_dot3(n, q->out[best])) best = e;
    return q->convex[best];
}

/* The face a triangle ahead of a geom faces, where its normal is within acos(AHEAD_PARALLEL) of
 * the contact direction and the geom is flat there (a box's face, a cylinder's cap, a mesh
 * triangle, a convex's face): its own normal into face. Returns 0 where there is no such face. */
static int flat_face(const convex_query *q, const double n[3], double face[3])
{
    const dReal *R = dGeomGetRotation(q->g);
    int axis = -1;
    if (q->cls == dTriMeshClass) {
        if (dcloth_dot3(q->face, n) < AHEAD_PARALLEL) return 0;
        for (int r = 0; r < 3; r++) face[r] = q->face[r];
        return 1;
    } else if (q->cls == dConvexClass) {
        for (int r = 0; r < 3; r++) face[r] = n[r];
        return 1;
    } else if (q->cls == dCylinderClass) {
        axis = 2; /* its caps: local z */
    } else if (q->cls == dBoxClass) {
        double best = -1.0;
        for (int k = 0; k < 3; k++) {
            double e = fabs(R[k] * n[0] + R[4 + k] * n[1] + R[8 + k] * n[2]);
            if (e > best) best = e, axis = k;
        }
    } else {
        return 0; /* capsule */
    }
    double c[3] = {R[axis], R[4 + axis], R[8 + axis]}, e = dcloth_dot3(c, n);
    if (fabs(e) < AHEAD_PARALLEL) return 0;
    for (int r = 0; r < 3; r++) face[r] = e > 0.0 ? c[r] : -c[r];
    return 1;
}

/* Whether cloth triangle ts lies within acos(AHEAD_PARALLEL) of parallel
 * to a flat face of the shape that direction n finds (flat_face's, in face). */
static int facing(const convex_query *q, const tri_shape *ts, const double n[3], double face[3])
{
    double e1[3], e2[3], nt[3];
    for (int r = 0; r < 3; r++) e1[r] = ts->v[1][r] - ts->v[0][r], e2[r] = ts->v[2][r] - ts->v[0][r];
    nt[0] = e1[1] * e2[2] - e1[2] * e2[1];
    nt[1] = e1[2] * e2[0] - e1[0] * e2[2];
    nt[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double ntl = sqrt(dcloth_dot3(nt, nt));
    return ntl > 0.0 && fabs(dcloth_dot3(nt, n)) >= AHEAD_PARALLEL * ntl && flat_face(q, n, face);
}

/* EPA's direction n (with lift, depth) for mesh prism vs triangle ts, replaced by the prism's face or
 * allowed edge normal of least overlap: each overlap bounds the penetration, EPA's can be far above it
 * over a prism's corner. r: the radius the triangle was grown by; clear_ok: whether clear may hold. */
static void mesh_least(const convex_query *q, const tri_shape *ts, double r, double t, double n[3], double *lift,
                       int *clear, int clear_ok, ccd_real_t *depth)
{
    const double *cand[4] = {q->face, q->out[0], q->out[1], q->out[2]};
    double d0 = *lift + (r - t), d = d0;
    for (int k = 0; k < 4; k++) {
        const double *u = cand[k];
        if (!mesh_direction(q, u)) continue;
        ccd_vec3_t ud = {{u[0], u[1], u[2]}}, sp;
        q->support(q->shape, &ud, &sp);
        double low = INFINITY;
        for (int a = 0; a < 3; a++) low = fmin(low, dcloth_dot3(u, ts->v[a]));
        double o = dcloth_dot3(u, sp.v) - low + r;
        if (!(o < d)) continue;
        d = o;
        for (int e = 0; e < 3; e++) n[e] = u[e];
    }
    if (!(d < d0)) return;
    *lift = d - (r - t);
    *clear = clear_ok && d < r;
    if (depth) *depth = d;
}

/* Whether point x lies over the face of a box or a cylinder's cap whose
 * outward normal is face (flat_face's): its projection on that face's plane
 * is within the face, where the face's plane is the geom's nearest */
static int over_face(const convex_query *q, const double face[3], const double x[3])
{
    const dcloth_geom_shape *gs = q->shape;
    const dReal *R = dGeomGetRotation(q->g), *o = dGeomGetPosition(q->g);
    double l[3], d[3] = {x[0] - o[0], x[1] - o[1], x[2] - o[2]};
    int axis = 0;
    for (int k = 0; k < 3; k++) {
        l[k] = R[k] * d[0] + R[4 + k] * d[1] + R[8 + k] * d[2];
        if (fabs(R[k] * face[0] + R[4 + k] * face[1] + R[8 + k] * face[2]) > 0.5) axis = k;
    }
    if (gs->cls == dCylinderClass) return l[0] * l[0] + l[1] * l[1] <= gs->half[0] * gs->half[0];
    for (int k = 0; k < 3; k++)
        if (k != axis && fabs(l[k]) > gs->half[k]) return 0;
    return 1;
}

/* The flat face (a box's, a cylinder's cap) direction n finds, and its
 * supporting plane face . x = *fsup: a clear triangle's vertices over it
 * are held by it too, exact there where EPA's direction is not */
static int face_plane(const convex_query *q, const double n[3], double face[3], double *fsup)
{
    if ((q->cls != dBoxClass && q->cls != dCylinderClass) || !flat_face(q, n, face)) return 0;
    ccd_vec3_t fd = {{face[0], face[1], face[2]}}, sp;
    q->support(q->shape, &fd, &sp);
    *fsup = dcloth_dot3(face, sp.v);
    return 1;
}

/* A contact tying to rounding with another triangle's on the same geom (mirror images at a vertex on the
 * cloth's line of symmetry) is merged with it, not chosen by the tests' order: each tie weighs alike, held
 * along their normals' mean by their mean gap, by the triangle whose point weighs the vertex most. */
int dcloth_merge_tie(dClothID c, const convex_query *q, vcontact *vc, int k, const double n[3], double gap,
                     const double pt[3], const double vb[3], double w)
{
    if (!q->poly || !vc->geom || vc->geom != q->g || !vc->from_triangle || vc->tri < 0) return 0;
    if (!(fabs(vc->gap - gap) <= MERGE_TIE * q->surf->thickness)) return 0;
    double ties = vc->ties > 1 ? vc->ties : 1.0, *sum = vc->tie_sum;
    if (vc->ties < 1) memcpy(sum, vc->normal, sizeof vc->tie_sum);
    double m[3] = {sum[0] + n[0], sum[1] + n[1], sum[2] + n[2]}, ml = sqrt(dcloth_dot3(m, m));
    double cs = ml > 0.0 ? dcloth_dot3(m, n) / ml : 0.0;
    if (!(cs > 0.5)) return 0; /* normals apart by more than 120 degrees: no corner to hold at */
    for (int r = 0; r < 3; r++) {
        sum[r] = m[r];
        vc->normal[r] = m[r] / ml;
        vc->point[r] = (ties * vc->point[r] + pt[r]) / (ties + 1.0);
        vc->vbody[r] = (ties * vc->vbody[r] + vb[r]) / (ties + 1.0);
    }
    vc->gap = (ties * vc->gap + gap) / (ties + 1.0);
    vc->ties = (int)ties + 1;
    if (w > vc->weight + TRI_TIE) { /* the triangle whose point weighs the vertex most carries it */
        vc->weight = w;
        vc->tri = k;
        vc->query = c->triangles.query;
    }
    return 1;
}

/* Offers vertex i of cloth triangle k, in this query (c->triangles.query), the
 * contact along n with gap, on the plane n . x = plane, kept where deeper than
 * what it has. pos: the contact point; w: its barycentric weight on i. */
static void tri_vertex_contact(dClothID c, const convex_query *q, int k, int i, const double n[3], double gap,
                               double plane, const ccd_vec3_t *pos, double w, int exact)
{
    vcontact *vc = &c->vc_new[i];
    const double *xv = (q->x ? q->x : cloth_positions(c->core)) + 3 * (size_t)i;
    /* only deeper than the vertex's own contact, with no rounding margin */
    dcloth_offer_opposite(vc, q->g, q->body, n, gap, pos->v);
    double height = dcloth_dot3(n, xv) - plane, pt[3], vb[3];
    for (int r = 0; r < 3; r++) pt[r] = xv[r] - height * n[r];
    dcloth_point_velocity(q->body, pos->v, vb);
    if (dcloth_merge_tie(c, q, vc, k, n, gap, pt, vb, w)) return;
    /* another geom's deeper contact is kept, this one its second surface, as the vertex tests do */
    int other = vc->geom && vc->geom != q->g;
    /* and so is a plane of the same geom the vertex touches: at an edge it needs both faces' planes */
    int touch = gap < DCLOTH_CONTACT_SLOP * q->surf->thickness;
    if ((other || touch) && vc->gap <= gap) dcloth_offer_second(vc, q->g, q->surf->thickness, q->body, n, pt, gap);
    if (vc->geom && vc->gap <= gap) return;
    /* on a face's own plane, a vertex's own contact with the geom is the
     * same plane: kept where they tie to rounding */
    if (exact && vc->geom == q->g && vc->gap <= gap + TRI_TIE * q->surf->thickness) return;
    vcontact was;
    if (other) was = *vc; /* the one this replaces, offered as the second below */
    /* the point reported (and pushed at while asleep): under the vertex on the geom's face (support)
     * where known, else on the plane through EPA's point, which may be any point of the overlap */
    dcloth_set_contact(vc, q->surf, q->body, n, pt, gap);
    memcpy(vc->vbody, vb, sizeof vc->vbody); /* the body's point under the contact, not under the vertex */
    vc->from_triangle = 1;
    vc->tri = k;
    vc->query = c->triangles.query;
    vc->weight = w;
    vc->ties = 1;
    memcpy(vc->tie_sum, n, sizeof vc->tie_sum);
    if (other) dcloth_offer_second(vc, was.geom, was.thickness, was.body, was.normal, was.point, was.gap);
}

/* A moving triangle's contact (from its swept shape ts and the loose EPA) taken from its shell (ts grown
 * by shell_r alone), converged tightly, where the triangle is already within it (shell_hit); else, still
 * apart from a static geom, converged tightly on the swept shape */
static void refine_swept(const convex_query *q, const tri_shape *ts, double shell_r, double t, ccd_t *fine,
                         ccd_real_t *depth, ccd_vec3_t *dir, ccd_vec3_t *pos, double *lift, int *clear, int *shell_hit)
{
    tri_shape shell = *ts;
    shell.radius = shell_r;
    ccd_real_t d2;
    ccd_vec3_t dir2, pos2;
    if (penetration(q, &shell, fine, &d2, &dir2, &pos2) == 0 && d2 > 0.0 && isfinite(d2)) {
        *lift = d2 - (shell_r - t);
        *dir = dir2;
        *pos = pos2;
        *clear = d2 < shell_r;
        *shell_hit = 1;
    } else if (!q->moving) {
        /* still apart from a static geom: the geometry converged tightly, since the loose EPA's direction
         * can lean enough to drop the support plane by millimetres (docs/contacts.md, "Design notes") */
        ccd_real_t d2;
        ccd_vec3_t dir2, pos2;
        if (penetration(q, ts, fine, &d2, &dir2, &pos2) == 0 && d2 > 0.0 && isfinite(d2)) {
            *lift = d2 - (ts->radius - t);
            *dir = dir2;
            *pos = pos2;
            *depth = d2;
        }
    }
}

/* The plane along n through q's support (returned: n . x there): each vertex's height above it less the
 * thickness t (above), whether it reaches the plane within the step of h seconds (reaches, v the cloth's
 * velocities, p the triangle's vertices); ahead kept only while each vertex w weighs reaches it */
static double heights(const convex_query *q, const tri_shape *ts, const double *v, const int *p, const double n[3],
                      double t, double h, const double w[3], double above[3], int reaches[3], int *ahead)
{
    ccd_vec3_t nd = {{n[0], n[1], n[2]}}, sp;
    q->support(q->shape, &nd, &sp);
    double support = n[0] * sp.v[0] + n[1] * sp.v[1] + n[2] * sp.v[2];
    for (int a = 0; a < 3; a++) {
        const double *xa = ts->v[a];
        double rv[3];
        above[a] = n[0] * xa[0] + n[1] * xa[1] + n[2] * xa[2] - support - t;
        dcloth_relative_velocity(q->body, xa, v + 3 * p[a], rv);
        reaches[a] = above[a] + h * dcloth_dot3(rv, n) <= DCLOTH_CONTACT_SLOP * t;
        if (*ahead && w[a] > 0.0 && !reaches[a]) *ahead = 0;
    }
    return support;
}

/* Cloth triangle k against the shape: sets its vertices' contacts where
 * deeper than what they have; returns how many it set. */
int dcloth_triangle_query(dClothID c, const convex_query *q, int k, double h, ccd_t *ccd, ccd_t *fine)
{
    const double *x = q->x ? q->x : cloth_positions(c->core), *v = q->v ? q->v : cloth_velocities(c->core);
    double t = q->surf->thickness;
    double shell_r = t * (1.0 + DCLOTH_CONTACT_MARGIN); /* the triangle grown by thickness and margin */
    const int *p = c->tri + 3 * k;
    /* grown by the thickness, the margin and the step's approach, so the contact starts before the geom
     * is inside the triangle; pushing a deep corner out in one step overstretches links (docs/contacts.md) */
    double sweep = 0.0; /* the fastest vertex relative to the body */
    for (int a = 0; a < 3; a++) {
        double s2 = dcloth_relative_speed(q->body, x + 3 * p[a], v + 3 * p[a]);
        if (s2 > sweep) sweep = s2;
    }
    /* a sweep beyond the geom's own size sees nothing more (and an
     * overflowing one, |v| = inf, crashed libccd: found by
     * plugin_fuzz_api) */
    double reach = fmax(h * sweep, q->reach_min);
    if (!(reach <= q->span)) reach = q->span;
    tri_shape ts = {{x + 3 * p[0], x + 3 * p[1], x + 3 * p[2]}, shell_r + reach};
    for (int a = 0; a < 3; a++) {
        double lo = fmin(ts.v[0][a], fmin(ts.v[1][a], ts.v[2][a])) - ts.radius;
        double hi = fmax(ts.v[0][a], fmax(ts.v[1][a], ts.v[2][a])) + ts.radius;
        if (hi < q->aabb[2 * a] || lo > q->aabb[2 * a + 1]) return 0;
    }
    /* At rest (sweep under SWEEP_NEGLIGIBLE thicknesses) one tight query on the shell gives the contact;
     * a moving triangle is found by its swept shape and loose EPA, its geometry re-taken tightly from the
     * shell once inside, since the loose direction wanders and a swept shape's can lie along the triangle. */
    int swept = reach > SWEEP_NEGLIGIBLE * t;
    ccd_real_t depth;
    ccd_vec3_t dir, pos;
    if (penetration(q, &ts, swept ? ccd : fine, &depth, &dir, &pos) != 0) return 0;
    if (!(depth > 0.0) || !isfinite(depth)) return 0;
    /* the triangle's distance beyond the thickness, as a vertex gap */
    double lift = depth - (ts.radius - t);
    /* clear: the thin triangle itself is outside the geom, so the support plane separates them and each
     * vertex is at least its height above it away; also for a moving geom (far vertices not dragged
     * along), not for a static one (a far vertex let go could fall through) (docs/contacts.md) */
    int clear = (!swept || q->moving) && depth < ts.radius, shell_hit = 0;
    if (swept) refine_swept(q, &ts, shell_r, t, fine, &depth, &dir, &pos, &lift, &clear, &shell_hit);
    double nl = sqrt(dir.v[0] * dir.v[0] + dir.v[1] * dir.v[1] + dir.v[2] * dir.v[2]);
    if (!(nl > 0.0)) return 0;
    double n[3] = {dir.v[0] / nl, dir.v[1] / nl, dir.v[2] / nl}, support = 0.0;
    if (q->face && !mesh_direction(q, n)) return 0;
    if (q->face)
        mesh_least(q, &ts, shell_hit ? shell_r : ts.radius, t, n, &lift, &clear, !swept || q->moving || shell_hit,
                   shell_hit ? NULL : &depth);
    /* barycentric weights of the contact point, projected on the
     * triangle and clamped into it */
    double w[3];
    barycentric(ts.v, pos.v, w);
    /* the lift is shared over the vertices the step moves, a pinned one taking none, so that their shares
     * (w_a lift / sum w_b^2 over them) move the contact point by the lift */
    double w2 = 0.0, moved = 0.0;
    for (int a = 0; a < 3; a++) {
        w2 += c->pin[p[a]].active ? 0.0 : w[a] * w[a];
        moved += c->pin[p[a]].active ? 0.0 : w[a];
    }
    if (!(w2 > 0.0)) w2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]; /* only pinned ones: theirs, ignored */
    /* the triangle's deepest point in the shell, where it weighs a vertex the step moves */
    if (moved > 0.0 && lift > c->step.deepest) c->step.deepest = lift;
    /* ahead: a triangle approaching a static geom, still apart. If every weighted vertex reaches the
     * separating plane within the step, each gets its own height as gap, so the triangle lands as it lies;
     * else the shares hold it, lest it fall through (docs/contacts.md, "Design notes from the code"). */
    double face[3];
    int ahead = swept && !shell_hit && !q->moving && depth < ts.radius && facing(q, &ts, n, face);
    if (ahead) memcpy(n, face, sizeof face);
    double above[3] = {0.0, 0.0, 0.0};
    int reaches[3] = {0, 0, 0};
    if (clear || ahead) support = heights(q, &ts, v, p, n, t, h, w, above, reaches, &ahead);
    double fsup = 0.0;
    int fl = clear && face_plane(q, n, face, &fsup);
    int hits = 0;
    c->triangles.query++;
    for (int a = 0; a < 3; a++) {
        double gap;
        if (w[a] > 0.0) {
            gap = -lift * w[a] / w2;
        } else if (ahead && reaches[a]) {
            gap = above[a];
        } else {
            continue;
        }
        /* A vertex never gets a smaller gap than its height above the separating plane allows: on a face the
         * tight EPA returns any point, and a lift shared from there would hold a vertex above its place */
        if (clear && above[a] > gap) gap = above[a];
        if (ahead) gap = above[a];
        /* of two supporting planes (both bound the distance from below),
         * the higher holds the vertex */
        double fh = fl && over_face(q, face, ts.v[a]) ? dcloth_dot3(face, ts.v[a]) - fsup - t : -INFINITY;
        double plane = (clear || ahead) ? support : dcloth_dot3(n, pos.v);
        if (fh >= above[a]) tri_vertex_contact(c, q, k, p[a], face, fmax(gap, fh), fsup, &pos, w[a], 1);
        else tri_vertex_contact(c, q, k, p[a], n, gap, plane, &pos, w[a], 0);
        hits += c->vc_new[p[a]].query == c->triangles.query;
    }
    return hits;
}

double dcloth_diagonal(const double aabb[6])
{
    double s = 0.0;
    for (int a = 0; a < 3; a++) s += (aabb[2 * a + 1] - aabb[2 * a]) * (aabb[2 * a + 1] - aabb[2 * a]);
    return sqrt(s);
}
