/* Vertex contacts (dcloth.h, step 2): each candidate's vertices within their reach get signed distance
 * and normal: closed form for sphere, box, capsule, cylinder and plane; a ray for heightfields; a sphere
 * proxy through dCollide for convex, trimesh and others. The deepest is kept (docs/contacts.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "dcloth_internal.h"
#include "body_motion.h"
#include "contact_offers.h"
#include "vertex_contacts.h"

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
        } else { /* inside: out through the nearest face */
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
    default: return 0;
    }
}

/* Heightfield: a ray down the field's up axis (its local y) from above the
 * vertex; the distance is to the plane of the triangle hit. 0 if it misses
 * (off the field, or the vertex is more than `reach` above it). */
static int heightfield_query(dClothID c, dGeomID g, const double *x, double reach, double *dist, double n[3])
{
    const dReal *R = dGeomGetRotation(g);
    double up[3] = {R[1], R[5], R[9]}; /* world image of local y */
    double L = 2.0 * reach + 1.0;      /* start well above any bump the vertex sits in */
    dGeomRaySet(c->vertex.ray, x[0] + L * up[0], x[1] + L * up[1], x[2] + L * up[2], -up[0], -up[1], -up[2]);
    dGeomRaySetLength(c->vertex.ray, L + reach);
    dContactGeom cg;
    if (dCollide(c->vertex.ray, g, 1, &cg, sizeof cg) < 1) return 0;
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
    int closest = dGeomRayGetClosestHit(c->vertex.ray);
    dGeomRaySetClosestHit(c->vertex.ray, 1);
    dGeomRaySetLength(c->vertex.ray, L);
    for (int a = 0; a < 6; a++) {
        double s = a & 1 ? -1.0 : 1.0, d[3] = {s * R[a / 2], s * R[4 + a / 2], s * R[8 + a / 2]};
        dGeomRaySet(c->vertex.ray, x[0] + L * d[0], x[1] + L * d[1], x[2] + L * d[2], -d[0], -d[1], -d[2]);
        dContactGeom cg;
        if (dCollide(c->vertex.ray, g, 1, &cg, sizeof cg) < 1 || !(cg.depth < L)) {
            best = INFINITY;
            break;
        }
        if (L - cg.depth < best) {
            best = L - cg.depth;
            for (int k = 0; k < 3; k++) nrm[k] = d[k];
        }
    }
    dGeomRaySetClosestHit(c->vertex.ray, closest);
    if (!isfinite(best)) return 0;
    *dist = -best;
    return 1;
}

int dcloth_vertex_distance(dClothID c, dGeomID g, const double *x, double reach, double *dist, double nrm[3])
{
    if (dGeomGetClass(g) == dHeightfieldClass) {
        if (!heightfield_query(c, g, x, reach, dist, nrm)) return 0;
    } else if (!closed_form(g, x, dist, nrm)) {
        dContactGeom cg[8];
        dGeomSphereSetRadius(c->vertex.sphere, reach);
        dGeomSetPosition(c->vertex.sphere, x[0], x[1], x[2]);
        int m = dCollide(c->vertex.sphere, g, 8, cg, sizeof cg[0]);
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
    for (int a = 0; a < c->broad.ncand; a++) {
        dGeomID g = c->broad.cand[a];
        dBodyID body = dGeomGetBody(g);
        double t = c->broad.surf[a].thickness;
        for (int i = 0; i < c->n; i++) {
            vcontact *vc = &c->vc_new[i];
            double dist, nrm[3];
            if (vc->geom || c->pin[i].active || !dcloth_vertex_distance(c, g, x1 + 3 * i, t, &dist, nrm)) continue;
            if (!(dist < (1.0 - depth) * t)) continue;
            /* the shell's plane at the end position, as seen from the start */
            double point[3];
            for (int k = 0; k < 3; k++) point[k] = x1[3 * i + k] - nrm[k] * dist;
            double gap = nrm[0] * (x0[3 * i] - point[0]) + nrm[1] * (x0[3 * i + 1] - point[1]) +
                         nrm[2] * (x0[3 * i + 2] - point[2]) - t;
            dcloth_set_contact(vc, &c->broad.surf[a], body, nrm, point, gap);
            found++;
        }
    }
    return found;
}

void dcloth_vertex_contacts(dClothID c, double h, double extra)
{
    const double *x = cloth_positions(c->core), *v = cloth_velocities(c->core);
    int n = c->n;
    for (int a = 0; a < c->broad.ncand; a++) {
        dGeomID g = c->broad.cand[a];
        dReal aabb[6];
        dGeomGetAABB(g, aabb);
        dBodyID body = dGeomGetBody(g);
        double t = c->broad.surf[a].thickness;
        /* a vertex's reach: the thickness with its margin plus what vertex and geom can close in the step at
         * their relative speed, neither the vertex's speed alone nor it plus the geom's fastest point
         * (docs/contacts.md, "Design notes from the code") */
        for (int i = 0; i < n; i++) {
            const double *xi = x + 3 * i, *vi = v + 3 * i;
            double reach = t * (1.0 + DCLOTH_CONTACT_MARGIN) + fmax(h * dcloth_relative_speed(body, xi, vi), extra);
            if (xi[0] + reach < aabb[0] || xi[0] - reach > aabb[1] || xi[1] + reach < aabb[2] ||
                xi[1] - reach > aabb[3] || xi[2] + reach < aabb[4] || xi[2] - reach > aabb[5])
                continue;
            double dist, nrm[3];
            if (!dcloth_vertex_distance(c, g, xi, reach, &dist, nrm)) continue;
            double gap = dist - t, point[3];
            vcontact *vc = &c->vc_new[i];
            if (!c->pin[i].active && -gap > c->step.deepest) c->step.deepest = -gap;
            for (int k = 0; k < 3; k++) point[k] = xi[k] - nrm[k] * dist;
            dcloth_offer_opposite(vc, g, body, nrm, gap, point);
            if (vc->geom && vc->gap <= gap) { /* a deeper one is kept, this one its second */
                dcloth_offer_second(vc, g, t, body, nrm, point, gap);
                continue;
            }
            vcontact was = *vc;
            dcloth_set_contact(vc, &c->broad.surf[a], body, nrm, point, gap);
            if (was.geom && was.geom != g) /* the one replaced, the second */
                dcloth_offer_second(vc, was.geom, was.thickness, was.body, was.normal, was.point, was.gap);
        }
    }
}
