/* Which vertices touch which geoms (step 1-2 of dcloth.h).
 *
 * Broadphase: one box geom around the cloth, swept by the vertices' motion
 * over the step and grown by the thickness, against the user's space with
 * ODE's own dSpaceCollide2 (which applies the category / collide bits);
 * nested spaces are entered the same way. The box is in no space, so the
 * user's dSpaceCollide never meets it. A geom whose AABB misses the box costs
 * nothing per vertex.
 * Narrowphase: for each candidate, the vertices inside its AABB (grown by
 * each vertex's reach, reach = thickness (1 + DCLOTH_CONTACT_MARGIN) + |v| h) get
 * their signed distance and normal to the geom. Sphere, box, capsule,
 * cylinder and plane in closed form (exact, and cheaper than a collider);
 * heightfields with a ray along the field's up axis through the vertex (the
 * hit triangle's plane gives distance and normal: ODE's sphere-heightfield
 * collider reports nothing for a small sphere over a peak or a grid edge,
 * measured: vertices fell 2 cm into a bump); convex and trimesh (and any user
 * class) with a sphere proxy of radius reach through dCollide, which every
 * geom class supports against a sphere. The deepest contact over
 * all candidates is kept. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "dcloth_internal.h"
#include "edges.h"

static int bits_meet(dClothID c, dGeomID g)
{
    return (c->collide & dGeomGetCategoryBits(g)) || (dGeomGetCollideBits(g) & c->category);
}

static void near_cb(void *data, dGeomID o1, dGeomID o2)
{
    dClothID c = data;
    dGeomID g = o1 == c->box ? o2 : o1;
    if (g == c->box || g == c->sphere) return;
    if (dGeomIsSpace(g)) {
        dSpaceCollide2(c->box, g, c, near_cb);
        return;
    }
    if (!dGeomIsEnabled(g) || !bits_meet(c, g)) return;
    if (c->ncand == c->cand_cap) {
        int cap = c->cand_cap ? 2 * c->cand_cap : 16;
        dGeomID *p = realloc(c->cand, (size_t)cap * sizeof *p);
        if (!p) {
            c->cand_cap = -1; /* out of memory: reported by the caller */
            return;
        }
        c->cand = p;
        c->cand_cap = cap;
    }
    if (c->cand_cap > 0) c->cand[c->ncand++] = g;
}

/* x in the geom's frame: p = R^T (x - centre) */
static void to_local(dGeomID g, const double *x, double p[3])
{
    const dReal *o = dGeomGetPosition(g), *R = dGeomGetRotation(g); /* 3x4 row-major */
    double d[3] = {x[0] - o[0], x[1] - o[1], x[2] - o[2]};
    for (int k = 0; k < 3; k++) p[k] = R[k] * d[0] + R[4 + k] * d[1] + R[8 + k] * d[2];
}

static void to_world_dir(dGeomID g, const double q[3], double n[3])
{
    const dReal *R = dGeomGetRotation(g);
    for (int k = 0; k < 3; k++) n[k] = R[4 * k] * q[0] + R[4 * k + 1] * q[1] + R[4 * k + 2] * q[2];
}

/* Signed distance (negative inside) and outward unit normal of a point from
 * a geom whose class has a closed form. 0 if the class has none. */
static int closed_form(dGeomID g, const double *x, double *dist, double n[3])
{
    double p[3], q[3];
    switch (dGeomGetClass(g)) {
    case dSphereClass: {
        const dReal *o = dGeomGetPosition(g);
        double d[3] = {x[0] - o[0], x[1] - o[1], x[2] - o[2]}, l = sqrt(dcloth_dot3(d, d));
        if (l > 0.0) {
            for (int k = 0; k < 3; k++) n[k] = d[k] / l;
        } else {
            n[0] = 0.0, n[1] = 0.0, n[2] = 1.0;
        }
        *dist = l - dGeomSphereGetRadius(g);
        return 1;
    }
    case dPlaneClass: {
        dVector4 pl;
        dGeomPlaneGetParams(g, pl);
        double l = sqrt(pl[0] * pl[0] + pl[1] * pl[1] + pl[2] * pl[2]);
        for (int k = 0; k < 3; k++) n[k] = pl[k] / l;
        *dist = dcloth_dot3(n, x) - pl[3] / l;
        return 1;
    }
    case dBoxClass: {
        dVector3 L;
        dGeomBoxGetLengths(g, L);
        to_local(g, x, p);
        double out = 0.0, qmax = -INFINITY;
        int amax = 0;
        for (int k = 0; k < 3; k++) {
            double e = fabs(p[k]) - 0.5 * L[k];
            q[k] = e > 0.0 ? (p[k] > 0.0 ? e : -e) : 0.0;
            out += q[k] * q[k];
            if (e > qmax) qmax = e, amax = k;
        }
        if (out > 0.0) { /* outside: to the nearest point of the surface */
            out = sqrt(out);
            for (int k = 0; k < 3; k++) q[k] /= out;
            *dist = out;
        } else {         /* inside: out through the nearest face */
            q[0] = q[1] = q[2] = 0.0;
            q[amax] = p[amax] >= 0.0 ? 1.0 : -1.0;
            *dist = qmax;
        }
        to_world_dir(g, q, n);
        return 1;
    }
    case dCapsuleClass:
    case dCylinderClass: {
        dReal r, len;
        int capsule = dGeomGetClass(g) == dCapsuleClass;
        if (capsule) dGeomCapsuleGetParams(g, &r, &len);
        else dGeomCylinderGetParams(g, &r, &len);
        to_local(g, x, p);
        double rho = sqrt(p[0] * p[0] + p[1] * p[1]), half = 0.5 * len;
        double ux = rho > 0.0 ? p[0] / rho : 1.0, uy = rho > 0.0 ? p[1] / rho : 0.0;
        double sz = p[2] >= 0.0 ? 1.0 : -1.0;
        if (capsule) { /* distance to the axis segment, minus r */
            double a = fabs(p[2]) > half ? p[2] - sz * half : 0.0, l = sqrt(rho * rho + a * a);
            if (l > 0.0) q[0] = rho * ux / l, q[1] = rho * uy / l, q[2] = a / l;
            else q[0] = ux, q[1] = uy, q[2] = 0.0;
            *dist = l - r;
        } else {
            double dr = rho - r, da = fabs(p[2]) - half;
            if (dr <= 0.0 && da <= 0.0) { /* inside: through the nearer of side and cap */
                if (dr > da) q[0] = ux, q[1] = uy, q[2] = 0.0, *dist = dr;
                else q[0] = 0.0, q[1] = 0.0, q[2] = sz, *dist = da;
            } else if (da <= 0.0) {
                q[0] = ux, q[1] = uy, q[2] = 0.0, *dist = dr;
            } else if (dr <= 0.0) {
                q[0] = 0.0, q[1] = 0.0, q[2] = sz, *dist = da;
            } else { /* beyond the rim */
                double l = sqrt(dr * dr + da * da);
                q[0] = dr * ux / l, q[1] = dr * uy / l, q[2] = sz * da / l, *dist = l;
            }
        }
        to_world_dir(g, q, n);
        return 1;
    }
    default:
        return 0;
    }
}

/* Heightfield: a ray down the field's up axis (its local y) from above the
 * vertex; the distance is to the plane of the triangle hit. 0 if it misses
 * (off the field, or the vertex is more than `reach` above it). */
static int heightfield_query(dClothID c, dGeomID g, const double *x, double reach, double *dist, double n[3])
{
    const dReal *R = dGeomGetRotation(g);
    double up[3] = {R[1], R[5], R[9]}; /* world image of local y */
    double L = 2.0 * reach + 1.0;       /* start well above any bump the vertex sits in */
    dGeomRaySet(c->ray, x[0] + L * up[0], x[1] + L * up[1], x[2] + L * up[2], -up[0], -up[1], -up[2]);
    dGeomRaySetLength(c->ray, L + reach);
    dContactGeom cg;
    if (dCollide(c->ray, g, 1, &cg, sizeof cg) < 1) return 0;
    double nn = dcloth_dot3(cg.normal, cg.normal);
    if (!(nn > 0.0)) return 0;
    nn = 1.0 / sqrt(nn);
    for (int k = 0; k < 3; k++) n[k] = cg.normal[k] * nn;
    if (dcloth_dot3(n, up) < 0.0)
        for (int k = 0; k < 3; k++) n[k] = -n[k];
    double d[3] = {x[0] - cg.pos[0], x[1] - cg.pos[1], x[2] - cg.pos[2]};
    *dist = dcloth_dot3(d, n);
    return 1;
}

/* A body's velocity, or 0 if it has none or it is not finite (a body whose
 * velocity is NaN or inf is treated as static here: every vertex's reach
 * infinite gave every vertex a contact and a NaN target; found in review) */
static int body_velocity(dBodyID b, const dReal **v, const dReal **w)
{
    if (!b) return 0;
    *v = dBodyGetLinearVel(b);
    *w = dBodyGetAngularVel(b);
    for (int k = 0; k < 3; k++)
        if (!isfinite((*v)[k]) || !isfinite((*w)[k])) return 0;
    return 1;
}

/* An upper bound of the speed of any point of geom g (0 if it has no
 * body): |v| + |w| (distance from the body's centre to the AABB's centre +
 * the AABB's half diagonal); |v| alone where that distance is not finite. */
double dcloth_geom_speed(dGeomID g)
{
    dBodyID b = dGeomGetBody(g);
    const dReal *v, *w;
    if (!body_velocity(b, &v, &w)) return 0.0;
    const dReal *o = dBodyGetPosition(b);
    dReal aabb[6];
    dGeomGetAABB(g, aabb);
    double cen[3], half = 0.0, arm = 0.0;
    for (int k = 0; k < 3; k++) {
        double e = 0.5 * (aabb[2 * k + 1] - aabb[2 * k]);
        cen[k] = 0.5 * (aabb[2 * k + 1] + aabb[2 * k]) - o[k];
        half += e * e;
        arm += cen[k] * cen[k];
    }
    double lin = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), wn = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    double ang = wn > 0.0 ? wn * (sqrt(arm) + sqrt(half)) : 0.0;
    return isfinite(ang) ? lin + ang : lin;
}

/* r = v - the velocity of the body's point at x: how a vertex at x with
 * velocity v moves against a geom of body b (0: static) */
void dcloth_relative_velocity(dBodyID b, const double *x, const double *v, double r[3])
{
    for (int k = 0; k < 3; k++) r[k] = v[k];
    const dReal *l, *w;
    if (body_velocity(b, &l, &w)) {
        const dReal *o = dBodyGetPosition(b);
        double d[3] = {x[0] - o[0], x[1] - o[1], x[2] - o[2]};
        r[0] -= l[0] + w[1] * d[2] - w[2] * d[1];
        r[1] -= l[1] + w[2] * d[0] - w[0] * d[2];
        r[2] -= l[2] + w[0] * d[1] - w[1] * d[0];
    }
}

/* |dcloth_relative_velocity|, inf if not finite */
double dcloth_relative_speed(dBodyID b, const double *x, const double *v)
{
    double r[3];
    dcloth_relative_velocity(b, x, v, r);
    double s = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    return isfinite(s) ? s : INFINITY;
}

/* the fastest geom of a space (nested spaces entered), by dcloth_geom_speed.
 * ODE's quadtree space cannot hand out its geoms (dSpaceGetGeom is not
 * implemented there: it aborts), so a quadtree counts nothing: bodies in it
 * are found as they arrive, not before */
static double space_speed(dSpaceID s)
{
    if (dSpaceGetClass(s) == dQuadTreeSpaceClass) return 0.0;
    double m = 0.0;
    for (int k = 0, n = dSpaceGetNumGeoms(s); k < n; k++) {
        dGeomID g = dSpaceGetGeom(s, k);
        if (!g) continue;
        double v = dGeomIsSpace(g) ? space_speed((dSpaceID)g) : dcloth_geom_speed(g);
        if (v > m) m = v;
    }
    return m;
}

int dcloth_find_candidates(dClothID c, double h, double reach)
{
    const double *x = cloth_positions(c->core), *v = cloth_velocities(c->core);
    int n = c->n;
    memset(c->vc_new, 0, (size_t)n * sizeof *c->vc_new);
    c->ncand = 0;
    if (!c->space) return 0;

    /* the cloth's swept bounds */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            double a = x[3 * i + k], b = a + h * v[3 * i + k];
            lo[k] = fmin(lo[k], fmin(a, b));
            hi[k] = fmax(hi[k], fmax(a, b));
        }
    /* grown by the thickness (the largest a geom has had, dcloth_surface)
     * and what the fastest body covers in the step: a body approaching the
     * cloth is a candidate before it arrives */
    double t = fmax(c->thickness, c->surf_tmax);
    double grow = t * (1.0 + DCLOTH_CONTACT_MARGIN) + reach + h * space_speed(c->space);
    for (int k = 0; k < 3; k++) {
        lo[k] -= grow;
        hi[k] += grow;
    }
    dGeomBoxSetLengths(c->box, hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    dGeomSetPosition(c->box, 0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]));
    dGeomSetCategoryBits(c->box, c->category);
    dGeomSetCollideBits(c->box, c->collide);
    dSpaceCollide2(c->box, (dGeomID)c->space, c, near_cb);
    if (c->cand_cap < 0) {
        c->cand_cap = 0;
        free(c->cand);
        c->cand = NULL;
        c->ncand = 0;
        return -1;
    }
    return c->ncand;
}

/* the velocity of body's point p (zero without a body) */
static void point_velocity(dBodyID body, const double p[3], double v[3])
{
    dVector3 pv = {0, 0, 0};
    if (body) dBodyGetPointVel(body, p[0], p[1], p[2], pv);
    for (int k = 0; k < 3; k++) v[k] = pv[k];
}

static int plane_finite(const double *n, const double *p, double gap)
{
    return isfinite(n[0] + n[1] + n[2] + p[0] + p[1] + p[2] + gap);
}

void dcloth_offer_opposite(vcontact *vc, dGeomID g, dBodyID body, const double n[3], double gap,
                           const double point[3])
{
    if (!vc->geom || vc->geom == g || dcloth_dot3(vc->normal, n) > -DCLOTH_PINCH_COS) return;
    if (gap < vc->gap) { /* the candidate replaces vc's contact, which becomes the opposite */
        if (vc->opp_geom && vc->opp_gap <= vc->gap && vc->opp_geom != g) return;
        vc->opp_geom = vc->geom;
        vc->opp_body = vc->body;
        vc->opp_gap = vc->gap;
        memcpy(vc->opp_normal, vc->normal, sizeof vc->opp_normal);
        memcpy(vc->opp_vbody, vc->vbody, sizeof vc->opp_vbody);
        return;
    }
    if (vc->opp_geom && vc->opp_gap <= gap) return;
    vc->opp_geom = g;
    vc->opp_body = body;
    vc->opp_gap = gap;
    memcpy(vc->opp_normal, n, sizeof vc->opp_normal);
    point_velocity(body, point, vc->opp_vbody);
}

/* whether a surface of a static or kinematic body with normal n may be vc's second */
static int second_fits(const vcontact *vc, dBodyID body, const double n[3])
{
    double nn = dcloth_dot3(vc->normal, n);
    return vc->geom && (!body || dBodyIsKinematic(body)) && nn > -DCLOTH_PINCH_COS &&
           nn < DCLOTH_SECOND_COS;
}

void dcloth_offer_second(vcontact *vc, dGeomID g, double t, dBodyID body, const double n[3], const double point[3],
                         double gap)
{
    if (!second_fits(vc, body, n) || (vc->sec_geom && vc->sec_gap <= gap) || !plane_finite(n, point, gap)) return;
    vc->sec_geom = g;
    vc->sec_body = body;
    vc->sec_thickness = t;
    vc->sec_gap = gap;
    memcpy(vc->sec_normal, n, sizeof vc->sec_normal);
    memcpy(vc->sec_point, point, sizeof vc->sec_point);
    point_velocity(body, point, vc->sec_vbody);
}

/* vc becomes a contact with geom g (surface sf, of body, 0 if static): the
 * surface's outward normal and nearest point, and the gap from the shell */
static void set_contact(vcontact *vc, const struct dcloth_surf *sf, dBodyID body, const double nrm[3],
                        const double point[3], double gap)
{
    vc->geom = sf->g;
    vc->thickness = sf->thickness;
    vc->mu = sf->mu;
    vc->body = body;
    memcpy(vc->normal, nrm, sizeof vc->normal);
    memcpy(vc->point, point, sizeof vc->point);
    vc->gap = gap;
    vc->weight = 1.0;
    point_velocity(body, point, vc->vbody); /* zero for a static geom (it replaced a moving one's: stale) */
}

/* Whether x is inside trimesh g: behind its surface seen from outside along
 * each of the geom's six axis directions (ODE's sphere test misses a centre on
 * or behind a face); then how deep, to the nearest way out, and that way. */
static int mesh_inside(dClothID c, dGeomID g, const double *x, double *dist, double nrm[3])
{
    dReal aabb[6];
    dGeomGetAABB(g, aabb);
    const dReal *R = dGeomGetRotation(g);
    double L = 1.0, best = INFINITY;
    for (int k = 0; k < 3; k++) L += aabb[2 * k + 1] - aabb[2 * k];
    int closest = dGeomRayGetClosestHit(c->ray);
    dGeomRaySetClosestHit(c->ray, 1);
    dGeomRaySetLength(c->ray, L);
    for (int a = 0; a < 6; a++) {
        double s = a & 1 ? -1.0 : 1.0, d[3] = {s * R[a / 2], s * R[4 + a / 2], s * R[8 + a / 2]};
        dGeomRaySet(c->ray, x[0] + L * d[0], x[1] + L * d[1], x[2] + L * d[2], -d[0], -d[1], -d[2]);
        dContactGeom cg;
        if (dCollide(c->ray, g, 1, &cg, sizeof cg) < 1 || !(cg.depth < L)) {
            best = INFINITY;
            break;
        }
        if (L - cg.depth < best) {
            best = L - cg.depth;
            for (int k = 0; k < 3; k++) nrm[k] = d[k];
        }
    }
    dGeomRaySetClosestHit(c->ray, closest);
    if (!isfinite(best)) return 0;
    *dist = -best;
    return 1;
}

/* The distance from x to geom g's surface and the outward normal there, if
 * within reach: 1, else 0 */
static int vertex_query(dClothID c, dGeomID g, const double *x, double reach, double *dist, double nrm[3])
{
    if (dGeomGetClass(g) == dHeightfieldClass) {
        if (!heightfield_query(c, g, x, reach, dist, nrm)) return 0;
    } else if (!closed_form(g, x, dist, nrm)) {
        dContactGeom cg[8];
        dGeomSphereSetRadius(c->sphere, reach);
        dGeomSetPosition(c->sphere, x[0], x[1], x[2]);
        int m = dCollide(c->sphere, g, 8, cg, sizeof cg[0]);
        int best = -1;
        for (int k = 0; k < m; k++)
            if (best < 0 || cg[k].depth > cg[best].depth) best = k;
        if (best < 0) return dGeomGetClass(g) == dTriMeshClass && mesh_inside(c, g, x, dist, nrm);
        double nn = dcloth_dot3(cg[best].normal, cg[best].normal);
        if (!(nn > 0.0)) return 0;
        nn = 1.0 / sqrt(nn);
        for (int k = 0; k < 3; k++) nrm[k] = cg[best].normal[k] * nn;
        *dist = reach - cg[best].depth;
    }
    return *dist < reach;
}

int dcloth_find_late_contacts(dClothID c, const double *x0, const double *x1, double depth)
{
    int found = 0;
    for (int a = 0; a < c->ncand; a++) {
        dGeomID g = c->cand[a];
        dBodyID body = dGeomGetBody(g);
        double t = c->surf[a].thickness;
        for (int i = 0; i < c->n; i++) {
            vcontact *vc = &c->vc_new[i];
            double dist, nrm[3];
            if (vc->geom || c->pin[i].active || !vertex_query(c, g, x1 + 3 * i, t, &dist, nrm)) continue;
            if (!(dist < (1.0 - depth) * t)) continue;
            /* the shell's plane at the end position, as seen from the start */
            double point[3];
            for (int k = 0; k < 3; k++) point[k] = x1[3 * i + k] - nrm[k] * dist;
            double gap = nrm[0] * (x0[3 * i] - point[0]) + nrm[1] * (x0[3 * i + 1] - point[1]) +
                         nrm[2] * (x0[3 * i + 2] - point[2]) - t;
            set_contact(vc, &c->surf[a], body, nrm, point, gap);
            found++;
        }
    }
    return found;
}

/* What any vertex may cover in a Newton step beyond its own start
 * velocity: h times the cloth's fastest vertex (the implicit step pulls a
 * vertex toward its neighbours' velocities); 0 for the linearised step. */
static double newton_reach(dClothID c, double h)
{
    if (cloth_get_desc(c->core).solver.nonlinear != CLOTH_NEWTON) return 0.0;
    const double *v = cloth_velocities(c->core);
    double vmax = 0.0;
    for (int i = 0; i < c->n; i++) vmax = fmax(vmax, dcloth_dot3(v + 3 * i, v + 3 * i));
    return h * sqrt(vmax);
}

/* Each candidate's surface (dcloth_surface) into c->surf, asking for each
 * geom once a step. When a geom is thicker than the broadphase reached, it
 * is run again that much wider, the geoms already asked keeping their answers. */
static int find_surfaces(dClothID c, double h, double extra)
{
    int nold = 0;
    for (;;) {
        double reached = fmax(c->thickness, c->surf_tmax);
        if (dcloth_find_candidates(c, h, extra) < 0) return -1;
        if (c->ncand > c->surf_cap) {
            int cap = c->cand_cap;
            struct dcloth_surf *p = realloc(c->surf, (size_t)cap * sizeof *p);
            if (p) c->surf = p;
            struct dcloth_surf *q = p ? realloc(c->surf_old, (size_t)cap * sizeof *q) : NULL;
            if (q) c->surf_old = q;
            if (!q) return -1;
            c->surf_cap = cap;
        }
        for (int a = 0; a < c->ncand; a++) {
            struct dcloth_surf *sf = &c->surf[a];
            int k = 0;
            while (k < nold && c->surf_old[k].g != c->cand[a]) k++;
            if (k < nold) {
                *sf = c->surf_old[k];
                continue;
            }
            sf->g = c->cand[a];
            dcloth_surface(c, sf->g, &sf->mu, &sf->thickness);
        }
        if (!(c->surf_tmax > reached)) return c->ncand;
        nold = c->ncand;
        memcpy(c->surf_old, c->surf, (size_t)nold * sizeof *c->surf_old);
    }
}

int dcloth_find_contacts(dClothID c, double h)
{
    double extra = newton_reach(c, h);
    if (find_surfaces(c, h, extra) < 0) return -1;
    const double *x = cloth_positions(c->core), *v = cloth_velocities(c->core);
    int n = c->n;
    for (int a = 0; a < c->ncand; a++) {
        dGeomID g = c->cand[a];
        dReal aabb[6];
        dGeomGetAABB(g, aabb);
        dBodyID body = dGeomGetBody(g);
        double t = c->surf[a].thickness;
        /* a vertex's reach: the thickness with its margin, and what the
         * vertex and the geom can close in the step, at their relative
         * speed (with the vertex's speed alone, a box falling at 2.4 m/s
         * onto a resting cloth found vertices 1 cm inside it, nearer a side
         * face than the bottom: pushed out sideways, the cloth stretched 29%
         * in one step; trampoline. With |v| + the geom's fastest point, a
         * cloth turning with a table counted as moving and lost its resting
         * contacts' fine geometry; soak_turntable) */
        for (int i = 0; i < n; i++) {
            const double *xi = x + 3 * i, *vi = v + 3 * i;
            double reach = t * (1.0 + DCLOTH_CONTACT_MARGIN) + fmax(h * dcloth_relative_speed(body, xi, vi), extra);
            if (xi[0] + reach < aabb[0] || xi[0] - reach > aabb[1] || xi[1] + reach < aabb[2] ||
                xi[1] - reach > aabb[3] || xi[2] + reach < aabb[4] || xi[2] - reach > aabb[5])
                continue;
            double dist, nrm[3];
            if (!vertex_query(c, g, xi, reach, &dist, nrm)) continue;
            double gap = dist - t, point[3];
            vcontact *vc = &c->vc_new[i];
            for (int k = 0; k < 3; k++) point[k] = xi[k] - nrm[k] * dist;
            dcloth_offer_opposite(vc, g, body, nrm, gap, point);
            if (vc->geom && vc->gap <= gap) { /* a deeper one is kept, this one its second */
                dcloth_offer_second(vc, g, t, body, nrm, point, gap);
                continue;
            }
            vcontact was = *vc;
            set_contact(vc, &c->surf[a], body, nrm, point, gap);
            if (was.geom && was.geom != g) /* the one replaced, the second */
                dcloth_offer_second(vc, was.geom, was.thickness, was.body, was.normal, was.point, was.gap);
        }
    }
    c->tri_hits = 0;
    for (int a = 0; a < c->ncand; a++) c->tri_hits += dcloth_triangle_contacts(c, &c->surf[a], h);
    c->edge_hits = 0;
    for (int a = 0; a < c->ncand; a++) {
        int e = dcloth_edge_contacts(c, &c->surf[a], h, extra);
        if (e < 0) return -1;
        c->edge_hits += e;
    }
    /* a second that no longer fits the contact the tests left */
    for (int i = 0; i < n; i++) {
        vcontact *vc = &c->vc_new[i];
        if (vc->sec_geom && !second_fits(vc, vc->sec_body, vc->sec_normal)) vc->sec_geom = 0;
    }
    return c->ncand;
}
