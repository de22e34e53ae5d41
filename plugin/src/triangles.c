/* Cloth triangles against convex geoms, with libccd (dcloth.h, step 2).
 *
 * Why: vertex contacts alone let a box's edge or corner pass between the
 * vertices of a coarse cloth (the paper's own flaw at the table corners:
 * the corner pokes through a triangle whose three vertices all rest beside
 * it). So each cloth triangle near a box, capsule, cylinder or convex, grown by the
 * thickness (the Minkowski sum with a sphere), is tested against the geom
 * with libccd's GJK + EPA penetration query (MPR's direction, taken along
 * the line of centres, was wrong at box corners). The triangle is grown by the
 * thickness plus a margin, as vertices are (contacts.c), so a triangle held
 * exactly at the thickness is still seen and stays held instead of falling
 * free every other step. A triangle the geom enters gives its three vertices
 * a contact along the separating direction. The lift the contact point needs
 * is shared by barycentric weight w_k (Bridson, Fedkiw, Anderson 2002): vertex
 * k moves by lift w_k / sum w^2, which moves the contact point by exactly the
 * lift, and leaves a far vertex (w = 0) alone (applying the whole lift to all
 * three held up vertices far from the contact, measured: a cloth hovering
 * over a box top, never settling). Kept only where deeper than the vertex's
 * own contact; the step's contact rule then treats it like any vertex
 * contact.
 *
 * ODE's convex class: ODE 0.16 does not hand back its points (no getter),
 * so the user hands them over (dClothSetConvexPoints); a convex without them
 * keeps vertex contacts, as do trimesh and heightfield (not convex). */
#include <ccd/ccd.h>
#include <math.h>
#include <string.h>
#include "dcloth_internal.h"

/* EPA's tolerance, of the thickness, for a triangle within its shell (the
 * loose one, 1e-3, serves to detect moving triangles). Measured with the
 * refinement on every class, plugin_coupling_light's 0.5 kg box on a pinned
 * cloth (worst pin-force imbalance, worst box speed over the last 2 s, bound
 * 2% and 1 mm/s): 1e-5: 0.08%, 0.16 mm/s; 3e-6: 0.10%, 0.36; 1e-6: 0.24%,
 * 0.60; 3e-7: 0.16%, 0.29; 1e-7: 0.24%, 0.42; with the loose tolerance
 * alone: 15%, 36 mm/s. A cloth at rest on a capsule: kinetic energy 1-7e-5
 * J loose, 1.1e-7 J refined (plugin_colliders). */
#define EPA_FINE 1e-6
/* a triangle moving less than this, of the thickness, per step is at rest */
#define SWEEP_NEGLIGIBLE 1e-3

typedef struct tri_shape {
    const double *v[3];
    double radius;
} tri_shape;

typedef struct geom_shape {
    dGeomID g;
    int cls;
    double half[3];   /* box half lengths; capsule / cylinder: r, half length */
    const double *pts; /* convex: points in the geom's frame, and how many */
    int npts;
} geom_shape;

static void tri_support(const void *obj, const ccd_vec3_t *dir, ccd_vec3_t *out)
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

static void tri_center(const void *obj, ccd_vec3_t *out)
{
    const tri_shape *t = obj;
    for (int k = 0; k < 3; k++) out->v[k] = (t->v[0][k] + t->v[1][k] + t->v[2][k]) / 3.0;
}

static void geom_support(const void *obj, const ccd_vec3_t *dir, ccd_vec3_t *out)
{
    const geom_shape *s = obj;
    const dReal *o = dGeomGetPosition(s->g), *R = dGeomGetRotation(s->g);
    const double *d = dir->v;
    double p[3], q[3];
    for (int k = 0; k < 3; k++) p[k] = R[k] * d[0] + R[4 + k] * d[1] + R[8 + k] * d[2]; /* R^T d */
    if (s->cls == dBoxClass) {
        for (int k = 0; k < 3; k++) q[k] = p[k] >= 0.0 ? s->half[k] : -s->half[k];
    } else if (s->cls == dCapsuleClass) { /* an end point, grown by r */
        double r = s->half[0], l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), f = l > 0.0 ? r / l : 0.0;
        q[0] = f * p[0];
        q[1] = f * p[1];
        q[2] = (p[2] >= 0.0 ? s->half[1] : -s->half[1]) + f * p[2];
    } else if (s->cls == dConvexClass) { /* the farthest point along d */
        int best = 0;
        double bd = -INFINITY;
        for (int k = 0; k < s->npts; k++) {
            const double *a = s->pts + 3 * k;
            double e = a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
            if (e > bd) bd = e, best = k;
        }
        for (int k = 0; k < 3; k++) q[k] = s->pts[3 * best + k];
    } else { /* cylinder: the rim point of the cap toward d */
        double r = s->half[0], rho = sqrt(p[0] * p[0] + p[1] * p[1]), f = rho > 0.0 ? r / rho : 0.0;
        q[0] = f * p[0];
        q[1] = f * p[1];
        q[2] = p[2] >= 0.0 ? s->half[1] : -s->half[1];
    }
    for (int k = 0; k < 3; k++) out->v[k] = o[k] + R[4 * k] * q[0] + R[4 * k + 1] * q[1] + R[4 * k + 2] * q[2];
}

static void geom_center(const void *obj, ccd_vec3_t *out)
{
    const geom_shape *s = obj;
    const dReal *o = dGeomGetPosition(s->g);
    for (int k = 0; k < 3; k++) out->v[k] = o[k];
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

int dcloth_triangle_contacts(dClothID c, dGeomID g, double h)
{
    geom_shape gs = {0};
    gs.g = g;
    gs.cls = dGeomGetClass(g);
    if (gs.cls == dBoxClass) {
        dVector3 L;
        dGeomBoxGetLengths(g, L);
        for (int k = 0; k < 3; k++) gs.half[k] = 0.5 * L[k];
    } else if (gs.cls == dCapsuleClass || gs.cls == dCylinderClass) {
        dReal r, len;
        if (gs.cls == dCapsuleClass) dGeomCapsuleGetParams(g, &r, &len);
        else dGeomCylinderGetParams(g, &r, &len);
        gs.half[0] = r;
        gs.half[1] = 0.5 * len;
        gs.half[2] = 0.0;
    } else if (gs.cls == dConvexClass) {
        int k = 0;
        while (k < c->ncvx && c->cvx[k].g != g) k++;
        if (k == c->ncvx) return 0; /* no points handed over: vertex contacts only */
        gs.pts = c->cvx[k].p;
        gs.npts = c->cvx[k].n;
    } else {
        return 0;
    }
    dReal aabb[6];
    dGeomGetAABB(g, aabb);
    double span = 0.0;
    for (int a = 0; a < 3; a++) span += (aabb[2 * a + 1] - aabb[2 * a]) * (aabb[2 * a + 1] - aabb[2 * a]);
    span = sqrt(span);
    const double *x = cloth_positions(c->core), *v = cloth_velocities(c->core);
    double t = c->thickness;
    ccd_t ccd;
    CCD_INIT(&ccd);
    ccd.support1 = geom_support;
    ccd.support2 = tri_support;
    ccd.center1 = geom_center;
    ccd.center2 = tri_center;
    ccd.max_iterations = 40;
    ccd.epa_tolerance = 1e-3 * t;
    ccd_t fine = ccd;
    fine.epa_tolerance = EPA_FINE * t;
    double shell_r = t * (1.0 + DCLOTH_CONTACT_MARGIN); /* the triangle grown by thickness and margin */
    dBodyID body = dGeomGetBody(g);
    int moving = dcloth_geom_speed(g) * h > SWEEP_NEGLIGIBLE * t; /* not ODE's jitter of a body at rest */
    int hits = 0;
    for (int k = 0; k < c->ntri; k++) {
        const int *p = c->tri + 3 * k;
        /* grown by the thickness, the margin and the step's approach: the
         * contact starts before the geom is inside the triangle (at 81x81 a
         * box corner otherwise entered a triangle ~1 cm in one step, and
         * pushing it out in one step stretched links 70%) */
        double sweep = 0.0; /* the fastest vertex relative to the body */
        for (int a = 0; a < 3; a++) {
            double s2 = dcloth_relative_speed(body, x + 3 * p[a], v + 3 * p[a]);
            if (s2 > sweep) sweep = s2;
        }
        /* a sweep beyond the geom's own size sees nothing more (and an
         * overflowing one, |v| = inf, crashed libccd: found by
         * plugin_fuzz_api) */
        double reach = h * sweep;
        if (!(reach <= span)) reach = span;
        tri_shape ts = {{x + 3 * p[0], x + 3 * p[1], x + 3 * p[2]}, shell_r + reach};
        int out = 0;
        for (int a = 0; a < 3 && !out; a++) {
            double lo = fmin(ts.v[0][a], fmin(ts.v[1][a], ts.v[2][a])) - ts.radius;
            double hi = fmax(ts.v[0][a], fmax(ts.v[1][a], ts.v[2][a])) + ts.radius;
            out = hi < aabb[2 * a] || lo > aabb[2 * a + 1];
        }
        if (out) continue;
        /* At rest (a sweep under SWEEP_NEGLIGIBLE of the thickness) the
         * swept shape is the shell (the triangle grown by the thickness and
         * margin) and one query, converged tightly, gives the contact. A
         * moving triangle is detected with its swept shape and a loose EPA;
         * if it is already within its shell, the geometry is taken from the
         * shell, converged tightly, and otherwise the swept query's
         * (predictive) geometry is kept. Why: the loose EPA's direction and
         * point wandered from step to step on a capsule's round side, and
         * the swept shape, several times thicker than the cloth at speed,
         * can have its least separating direction along the triangle. */
        int swept = reach > SWEEP_NEGLIGIBLE * t;
        ccd_real_t depth;
        ccd_vec3_t dir, pos;
        if (ccdGJKPenetration(&gs, &ts, swept ? &ccd : &fine, &depth, &dir, &pos) != 0) continue;
        if (!(depth > 0.0) || !isfinite(depth)) continue;
        /* the triangle's distance beyond the thickness, as a vertex gap */
        double lift = depth - (ts.radius - t);
        /* clear: the thin triangle itself is outside the geom (its depth
         * into the grown shape is less than the growth), so the plane
         * through the geom's support along the contact direction separates
         * them, and every vertex is at least as far from the geom as its
         * height above that plane. Also for a moving triangle when the geom
         * moves: a vertex held by a triangle's contact moves with the body,
         * and a far vertex given the triangle's small share of the gap was
         * dragged along (a box falling at 2.4 m/s into a hammock pulled a
         * vertex 2.7 cm below it down 3.7 cm in one step, 22% past its
         * neighbour; trampoline). Not for a static geom: there a far vertex
         * so let go (it stays apart) could fall through the plane with its
         * triangle in the same step (plugin_colliders: a box's and a
         * cylinder's edge through a triangle at impact, measured). */
        int clear = (!swept || moving) && depth < ts.radius;
        if (swept) {
            tri_shape shell = ts;
            shell.radius = shell_r;
            ccd_real_t d2;
            ccd_vec3_t dir2, pos2;
            if (ccdGJKPenetration(&gs, &shell, &fine, &d2, &dir2, &pos2) == 0 && d2 > 0.0 && isfinite(d2)) {
                lift = d2 - (shell_r - t);
                dir = dir2;
                pos = pos2;
                clear = d2 < shell_r;
            }
        }
        double nl = sqrt(dir.v[0] * dir.v[0] + dir.v[1] * dir.v[1] + dir.v[2] * dir.v[2]);
        if (!(nl > 0.0)) continue;
        double n[3] = {dir.v[0] / nl, dir.v[1] / nl, dir.v[2] / nl}, support = 0.0;
        if (clear) {
            ccd_vec3_t nd = {{n[0], n[1], n[2]}}, sp;
            geom_support(&gs, &nd, &sp);
            support = n[0] * sp.v[0] + n[1] * sp.v[1] + n[2] * sp.v[2];
        }
        /* barycentric weights of the contact point, projected on the
         * triangle and clamped into it */
        double w[3];
        barycentric(ts.v, pos.v, w);
        double w2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        for (int a = 0; a < 3; a++) {
            vcontact *vc = &c->vc_new[p[a]];
            if (!(w[a] > 0.0)) continue;
            double gap = -lift * w[a] / w2;
            /* A vertex never gets a smaller gap than its height above the
             * separating plane allows. A triangle lying flat on a face
             * touches it everywhere, the tight EPA returns any point of the
             * face, and the lift shared from there held a vertex 1.5 mm
             * above its place (plugin_api, measured) */
            if (clear) {
                const double *xa = ts.v[a];
                double above = n[0] * xa[0] + n[1] * xa[1] + n[2] * xa[2] - support - t;
                if (above > gap) gap = above;
            }
            /* only deeper than the vertex's own contact. (Requiring "deeper
             * beyond rounding" instead, so that ties at 1e-17 keep the
             * vertex's own, made an 81x81 cloth on a box fail at step 425 of
             * bench_contact: measured, and reverted.) */
            if (vc->geom && vc->gap <= gap) continue;
            vc->geom = g;
            vc->body = body;
            for (int q = 0; q < 3; q++) {
                vc->normal[q] = n[q];
                vc->point[q] = pos.v[q];
                vc->vbody[q] = 0.0;
            }
            vc->gap = gap;
            if (body) {
                dVector3 pv;
                dBodyGetPointVel(body, pos.v[0], pos.v[1], pos.v[2], pv);
                for (int q = 0; q < 3; q++) vc->vbody[q] = pv[q];
            }
            vc->from_triangle = 1;
            vc->weight = w[a];
            hits++;
        }
    }
    return hits;
}
