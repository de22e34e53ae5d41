/* The plugin's cloth object: creation, parameters, pins, what to draw. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "dcloth_internal.h"

static cloth_status create_fail(cloth_error *err, cloth_status code, const char *msg)
{
    if (err) {
        err->code = code;
        snprintf(err->message, sizeof err->message, "dClothCreate: %s", msg);
    }
    return code;
}

dClothDesc dClothDefaultDesc(void)
{
    dClothDesc d;
    memset(&d, 0, sizeof d);
    d.cloth = cloth_default_desc();
    d.thickness = 0.005;
    d.mu = 0.3;
    d.category_bits = ~0ul;
    d.collide_bits = ~0ul;
    return d;
}

static int valid_thickness(double t) { return t >= DCLOTH_THICKNESS_MIN && t <= DCLOTH_THICKNESS_MAX; }
static int valid_mu(double mu) { return mu >= 0.0 && isfinite(mu); }

cloth_status dClothCreate(dWorldID world, dSpaceID space, const dClothDesc *d, dClothID *out, cloth_error *err)
{
    if (err) {
        err->code = CLOTH_OK;
        err->message[0] = '\0';
    }
    if (!out) return create_fail(err, CLOTH_EINVAL, "out is NULL");
    *out = NULL;
    if (!world) return create_fail(err, CLOTH_EINVAL, "world is 0");
    if (!d) return create_fail(err, CLOTH_EINVAL, "desc is NULL");
    if (!valid_thickness(d->thickness)) return create_fail(err, CLOTH_EINVAL, "thickness must be in [1e-6, 10] m");
    if (!valid_mu(d->mu)) return create_fail(err, CLOTH_EINVAL, "mu must be finite and >= 0");
    if (space && !dGeomIsSpace((dGeomID)space))
        return create_fail(err, CLOTH_EINVAL, "space is a geom that is not a space");
    dClothID c = calloc(1, sizeof *c);
    if (!c) return create_fail(err, CLOTH_ENOMEM, "out of memory");
    cloth_status s = cloth_create(&d->cloth, &c->core, err);
    if (s != CLOTH_OK) {
        free(c);
        return s;
    }
    c->world = world;
    c->space = space;
    c->thickness = d->thickness;
    c->mu = d->mu;
    c->category = d->category_bits;
    c->collide = d->collide_bits;
    c->implicit = 1;
    c->n = cloth_vertex_count(c->core);
    int R = d->cloth.rows, C = d->cloth.cols;
    c->ntri = 2 * (R - 1) * (C - 1);
    c->tri = malloc(3 * (size_t)c->ntri * sizeof *c->tri);
    c->vc = calloc((size_t)c->n, sizeof *c->vc);
    c->vc_new = calloc((size_t)c->n, sizeof *c->vc_new);
    c->pin = calloc((size_t)c->n, sizeof *c->pin);
    c->step.fext = calloc(3 * (size_t)c->n, sizeof *c->step.fext);
    c->step.fuser = calloc(3 * (size_t)c->n, sizeof *c->step.fuser);
    c->fadd = calloc(3 * (size_t)c->n, sizeof *c->fadd);
    c->step.x0 = calloc(3 * (size_t)c->n, sizeof *c->step.x0);
    c->step.v0 = calloc(3 * (size_t)c->n, sizeof *c->step.v0);
    c->step.dv = calloc(3 * (size_t)c->n, sizeof *c->step.dv);
    c->reactions.vfix = calloc(3 * (size_t)c->n, sizeof *c->reactions.vfix);
    c->active_set.share_sum = calloc((size_t)c->n, sizeof *c->active_set.share_sum);
    c->reactions.holder = calloc((size_t)c->n, sizeof *c->reactions.holder);
    c->turn.bodies = calloc((size_t)c->n, sizeof *c->turn.bodies);
    c->turn.dv = calloc(3 * (size_t)c->n, sizeof *c->turn.dv);
    c->step.save = cloth_state_create(c->core);
    c->broad.box = dCreateBox(0, 1, 1, 1);
    c->vertex.sphere = dCreateSphere(0, c->thickness);
    c->vertex.ray = dCreateRay(0, 1.0);
    if (!c->tri || !c->vc || !c->vc_new || !c->pin || !c->step.fext || !c->step.fuser || !c->fadd || !c->step.x0 ||
        !c->step.v0 || !c->step.dv || !c->reactions.vfix || !c->active_set.share_sum || !c->reactions.holder ||
        !c->turn.bodies || !c->turn.dv || !c->step.save || !c->broad.box || !c->vertex.sphere || !c->vertex.ray) {
        dClothDestroy(c);
        return create_fail(err, CLOTH_ENOMEM, "out of memory");
    }
    /* split each cell along the same diagonal, counter-clockwise seen from
     * axis_u x axis_v (u along columns, v along rows) */
    int t = 0;
    for (int r = 0; r + 1 < R; r++)
        for (int k = 0; k + 1 < C; k++) {
            int a = r * C + k, b = a + 1, cc = a + C, dd = cc + 1;
            int *p = c->tri + 3 * t;
            p[0] = a, p[1] = b, p[2] = dd;
            p[3] = a, p[4] = dd, p[5] = cc;
            t += 2;
        }
    *out = c;
    return CLOTH_OK;
}

void dClothDestroy(dClothID c)
{
    if (!c) return;
    if (c->broad.box) dGeomDestroy(c->broad.box);
    if (c->vertex.sphere) dGeomDestroy(c->vertex.sphere);
    if (c->vertex.ray) dGeomDestroy(c->vertex.ray);
    cloth_destroy(c->core);
    free(c->tri);
    free(c->vc);
    free(c->vc_new);
    free(c->pin);
    free(c->step.fext);
    free(c->step.fuser);
    free(c->fadd);
    free(c->step.x0);
    free(c->step.v0);
    free(c->step.dv);
    free(c->reactions.vfix);
    free(c->active_set.share_sum);
    free(c->reactions.holder);
    free(c->turn.bodies);
    free(c->turn.dv);
    cloth_state_destroy(c->step.save);
    free(c->broad.cand);
    free(c->broad.surf);
    free(c->broad.surf_old);
    free(c->coupled.bodies);
    free(c->coupled.bdesc);
    free(c->journal.rec);
    dClothStateDestroy(c->undo);
    free(c->sleep.geoms);
    free(c->sleep.ids);
    for (int k = 0; k < c->ncvx; k++) free(c->cvx[k].p);
    free(c->cvx);
    free(c->tri_off.g);
    free(c->tri_epa.g);
    free(c->mesh.v);
    free(c->mesh.convex);
    free(c->mesh.edges);
    free(c->mesh.grid_box);
    free(c->mesh.grid_stamp);
    free(c->mesh.grid_head);
    free(c->mesh.grid_next);
    free(c->mesh.grid_tri);
    free(c->mesh.grid_key);
    free(c->edge.tri);
    free(c->edge.start);
    free(c->edge.ent);
    free(c->edge.stamp);
    free(c->edge_off.g);
    free(c);
}

cloth *dClothGetCore(dClothID c) { return c ? c->core : NULL; }
const char *dClothGetLastError(dClothID c) { return c ? c->err : "dClothID is NULL"; }
const dClothStepStats *dClothGetStats(dClothID c) { return c ? &c->stats : NULL; }

/* ---------------------------------------------------------------- drawing */

int dClothGetVertexCount(dClothID c) { return c ? c->n : 0; }
const dReal *dClothGetPositions(dClothID c) { return c ? cloth_positions(c->core) : NULL; }
int dClothGetTriangleCount(dClothID c) { return c ? c->ntri : 0; }
const int *dClothGetTriangles(dClothID c) { return c ? c->tri : NULL; }

cloth_status dClothGetNormals(dClothID c, dReal *nrm)
{
    if (!c) return CLOTH_EINVAL;
    if (!nrm) return dcloth_fail(c, CLOTH_EINVAL, "dClothGetNormals: normals is NULL");
    const double *x = cloth_positions(c->core);
    memset(nrm, 0, 3 * (size_t)c->n * sizeof *nrm);
    for (int t = 0; t < c->ntri; t++) {
        const int *p = c->tri + 3 * t;
        const double *a = x + 3 * p[0], *b = x + 3 * p[1], *d = x + 3 * p[2];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        /* the cross product's length is twice the area: area weighting */
        double w[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; k++)
            for (int q = 0; q < 3; q++) nrm[3 * p[k] + q] += w[q];
    }
    for (int i = 0; i < c->n; i++) {
        double *m = nrm + 3 * i, l = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        if (l > 0.0)
            for (int q = 0; q < 3; q++) m[q] /= l;
    }
    return CLOTH_OK;
}

/* ------------------------------------------------------------------- pins */

static cloth_status check_vertex(dClothID c, const char *fn, int vertex)
{
    if (vertex < 0 || vertex >= c->n)
        return dcloth_fail(c, CLOTH_EINVAL, "%s: vertex %d out of range [0, %d)", fn, vertex, c->n);
    return CLOTH_OK;
}

static int finite3(const dReal *p) { return p && isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]); }

cloth_status dClothPinToWorld(dClothID c, int vertex, const dReal point[3])
{
    if (!c) return CLOTH_EINVAL;
    if (check_vertex(c, "dClothPinToWorld", vertex) != CLOTH_OK) return CLOTH_EINVAL;
    if (!finite3(point)) return dcloth_fail(c, CLOTH_EINVAL, "dClothPinToWorld: point must be 3 finite numbers");
    vpin *p = &c->pin[vertex];
    memset(p, 0, sizeof *p);
    p->active = 1;
    memcpy(p->local, point, sizeof p->local);
    memcpy(p->world, point, sizeof p->world);
    dClothWake(c);
    return CLOTH_OK;
}

cloth_status dClothPinToBody(dClothID c, int vertex, dBodyID b, const dReal local[3])
{
    if (!c) return CLOTH_EINVAL;
    if (check_vertex(c, "dClothPinToBody", vertex) != CLOTH_OK) return CLOTH_EINVAL;
    if (!b) return dcloth_fail(c, CLOTH_EINVAL, "dClothPinToBody: body is 0");
    if (dBodyGetWorld(b) != c->world)
        return dcloth_fail(c, CLOTH_EINVAL, "dClothPinToBody: the body is not in the cloth's world");
    if (!finite3(local)) return dcloth_fail(c, CLOTH_EINVAL, "dClothPinToBody: point must be 3 finite numbers");
    vpin *p = &c->pin[vertex];
    memset(p, 0, sizeof *p);
    p->active = 1;
    p->body = b;
    memcpy(p->local, local, sizeof p->local);
    dVector3 w;
    dBodyGetRelPointPos(b, local[0], local[1], local[2], w);
    memcpy(p->world, w, sizeof p->world);
    dClothWake(c);
    return CLOTH_OK;
}

cloth_status dClothReleasePin(dClothID c, int vertex)
{
    if (!c) return CLOTH_EINVAL;
    if (check_vertex(c, "dClothReleasePin", vertex) != CLOTH_OK) return CLOTH_EINVAL;
    memset(&c->pin[vertex], 0, sizeof c->pin[vertex]);
    dClothWake(c);
    return CLOTH_OK;
}

cloth_status dClothReleaseBody(dClothID c, dBodyID b)
{
    if (!c) return CLOTH_EINVAL;
    if (!b) return dcloth_fail(c, CLOTH_EINVAL, "dClothReleaseBody: body is 0");
    for (int i = 0; i < c->n; i++)
        if (c->pin[i].active && c->pin[i].body == b) memset(&c->pin[i], 0, sizeof c->pin[i]);
    for (int i = 0; i < c->n; i++)
        if (c->vc[i].body == b) memset(&c->vc[i], 0, sizeof c->vc[i]);
    dClothWake(c);
    return CLOTH_OK;
}

cloth_status dClothGetPinForce(dClothID c, int vertex, dReal f[3])
{
    if (!c) return CLOTH_EINVAL;
    if (check_vertex(c, "dClothGetPinForce", vertex) != CLOTH_OK) return CLOTH_EINVAL;
    if (!f) return dcloth_fail(c, CLOTH_EINVAL, "dClothGetPinForce: force is NULL");
    for (int k = 0; k < 3; k++) f[k] = c->pin[vertex].active ? c->pin[vertex].force[k] : 0.0;
    return CLOTH_OK;
}

cloth_status dClothGetContactForce(dClothID c, int vertex, dReal f[3])
{
    if (!c) return CLOTH_EINVAL;
    if (check_vertex(c, "dClothGetContactForce", vertex) != CLOTH_OK) return CLOTH_EINVAL;
    if (!f) return dcloth_fail(c, CLOTH_EINVAL, "dClothGetContactForce: force is NULL");
    for (int k = 0; k < 3; k++) f[k] = c->vc[vertex].geom ? c->vc[vertex].force[k] : 0.0;
    return CLOTH_OK;
}

cloth_status dClothGetVertexContact(dClothID c, int vertex, dGeomID *geom, dReal point[3], dReal normal[3])
{
    if (!c) return CLOTH_EINVAL;
    if (check_vertex(c, "dClothGetVertexContact", vertex) != CLOTH_OK) return CLOTH_EINVAL;
    if (!geom) return dcloth_fail(c, CLOTH_EINVAL, "dClothGetVertexContact: geom is NULL");
    const vcontact *v = &c->vc[vertex];
    *geom = v->geom;
    for (int k = 0; k < 3; k++) {
        if (point) point[k] = v->geom ? v->point[k] : 0.0;
        if (normal) normal[k] = v->geom ? v->normal[k] : 0.0;
    }
    return CLOTH_OK;
}

/* ------------------------------------------------------------- parameters */

/* One per-geom callback at a time: the other cleared, and the reach it
 * gave the broadphase forgotten */
static cloth_status set_callback(dClothID c, dClothSurfaceFn *sfn, dClothFrictionFn *ffn, void *data)
{
    if (!c) return CLOTH_EINVAL;
    c->surface_fn = sfn;
    c->friction_fn = ffn;
    c->surface_data = sfn ? data : NULL;
    c->friction_data = ffn ? data : NULL;
    c->surf_tmax = 0.0;
    dClothWake(c);
    return CLOTH_OK;
}

cloth_status dClothSetFrictionCallback(dClothID c, dClothFrictionFn *fn, void *data)
{
    return set_callback(c, NULL, fn, data);
}

cloth_status dClothSetSurfaceCallback(dClothID c, dClothSurfaceFn *fn, void *data)
{
    return set_callback(c, fn, NULL, data);
}

void dcloth_surface(dClothID c, dGeomID g, double *mu, double *thickness)
{
    *mu = c->mu;
    *thickness = c->thickness;
    if (c->surface_fn) {
        dClothSurface s = {c->mu, c->thickness};
        c->surface_fn(c->surface_data, c, g, &s);
        if (valid_mu(s.mu)) *mu = s.mu;
        if (valid_thickness(s.thickness)) *thickness = s.thickness;
        if (*thickness > c->surf_tmax) c->surf_tmax = *thickness;
    } else if (c->friction_fn) {
        dReal m = c->mu;
        c->friction_fn(c->friction_data, c, g, &m);
        if (valid_mu(m)) *mu = m;
    }
}

cloth_status dClothSetFailureMode(dClothID c, dClothFailureMode mode)
{
    if (!c) return CLOTH_EINVAL;
    if (mode != DCLOTH_FAILURE_HOLD && mode != DCLOTH_FAILURE_STOP)
        return dcloth_fail(c, CLOTH_EINVAL, "dClothSetFailureMode: mode %d is neither HOLD (0) nor STOP (1)",
                           (int)mode);
    c->on_failure = mode;
    return CLOTH_OK;
}

cloth_status dClothAddVertexForce(dClothID c, int vertex, dReal fx, dReal fy, dReal fz)
{
    if (!c) return CLOTH_EINVAL;
    if (vertex < 0 || vertex >= c->n)
        return dcloth_fail(c, CLOTH_EINVAL, "dClothAddVertexForce: vertex %d out of range [0, %d)", vertex, c->n);
    double f[3] = {fx, fy, fz}, *a = c->fadd + 3 * (size_t)vertex;
    for (int r = 0; r < 3; r++)
        if (!isfinite(f[r]) || !isfinite(a[r] + f[r]))
            return dcloth_fail(c, CLOTH_EINVAL, "dClothAddVertexForce: the force (%g, %g, %g) must be finite", fx, fy,
                               fz);
    for (int r = 0; r < 3; r++) a[r] += f[r];
    dClothWake(c);
    return CLOTH_OK;
}

cloth_status dClothSetFriction(dClothID c, dReal mu)
{
    if (!c) return CLOTH_EINVAL;
    if (!valid_mu(mu)) return dcloth_fail(c, CLOTH_EINVAL, "dClothSetFriction: mu = %g must be finite and >= 0", mu);
    c->mu = mu;
    dClothWake(c);
    return CLOTH_OK;
}

dReal dClothGetFriction(dClothID c) { return c ? c->mu : 0.0; }

cloth_status dClothSetThickness(dClothID c, dReal t)
{
    if (!c) return CLOTH_EINVAL;
    if (!valid_thickness(t))
        return dcloth_fail(c, CLOTH_EINVAL, "dClothSetThickness: thickness = %g must be in [%g, %g] m", t,
                           DCLOTH_THICKNESS_MIN, DCLOTH_THICKNESS_MAX);
    c->thickness = t;
    dClothWake(c);
    return CLOTH_OK;
}

dReal dClothGetThickness(dClothID c) { return c ? c->thickness : 0.0; }
void dClothSetCategoryBits(dClothID c, unsigned long bits)
{
    if (!c) return;
    c->category = bits;
    dClothWake(c);
}
void dClothSetCollideBits(dClothID c, unsigned long bits)
{
    if (!c) return;
    c->collide = bits;
    dClothWake(c);
}
unsigned long dClothGetCategoryBits(dClothID c) { return c ? c->category : 0; }
unsigned long dClothGetCollideBits(dClothID c) { return c ? c->collide : 0; }
cloth_status dClothSetSpace(dClothID c, dSpaceID space)
{
    if (!c) return CLOTH_EINVAL;
    if (space && !dGeomIsSpace((dGeomID)space))
        return dcloth_fail(c, CLOTH_EINVAL, "dClothSetSpace: the geom given is not a space");
    c->space = space;
    dClothWake(c);
    return CLOTH_OK;
}

cloth_status dClothSetConvexPoints(dClothID c, dGeomID g, const dReal *points, int count)
{
    if (!c) return CLOTH_EINVAL;
    if (!g) return dcloth_fail(c, CLOTH_EINVAL, "dClothSetConvexPoints: geom is 0");
    if (dGeomGetClass(g) != dConvexClass)
        return dcloth_fail(c, CLOTH_EINVAL, "dClothSetConvexPoints: the geom is not a convex (class %d)",
                           dGeomGetClass(g));
    if (count < 0 || (count > 0 && !points))
        return dcloth_fail(c, CLOTH_EINVAL, "dClothSetConvexPoints: %d points at %p", count, (const void *)points);
    for (int k = 0; k < 3 * count; k++)
        if (!isfinite(points[k]))
            return dcloth_fail(c, CLOTH_EINVAL, "dClothSetConvexPoints: point %d is not finite", k / 3);
    int at = 0;
    while (at < c->ncvx && c->cvx[at].g != g) at++;
    if (!points || count == 0) { /* forget */
        if (at < c->ncvx) {
            free(c->cvx[at].p);
            c->cvx[at] = c->cvx[--c->ncvx];
        }
        dClothWake(c);
        return CLOTH_OK;
    }
    double *p = malloc(3 * (size_t)count * sizeof *p);
    if (!p) return dcloth_fail(c, CLOTH_ENOMEM, "dClothSetConvexPoints: out of memory for %d points", count);
    for (int k = 0; k < 3 * count; k++) p[k] = points[k];
    if (at == c->ncvx) {
        struct cvx_points *nc = realloc(c->cvx, (size_t)(c->ncvx + 1) * sizeof *nc);
        if (!nc) {
            free(p);
            return dcloth_fail(c, CLOTH_ENOMEM, "dClothSetConvexPoints: out of memory");
        }
        c->cvx = nc;
        c->cvx[c->ncvx++] = (struct cvx_points){g, 0, NULL};
    }
    free(c->cvx[at].p);
    c->cvx[at].p = p;
    c->cvx[at].n = count;
    dClothWake(c);
    return CLOTH_OK;
}
