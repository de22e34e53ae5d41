/* Plugin: random and extreme input to every public dCloth function (seeded).
 * The rule checked: an error or a valid result, never a crash, never NaN or
 * inf left in the cloth, and the cloth (core state) and the bodies as they
 * were when a call fails.
 *
 * 1. NULL cloth for every function: an error or a neutral value.
 * 2. dClothCreate with 500 descriptors, each the default with 1-3 fields
 *    set to extremes (NaN, +-inf, 0, -1, 1e-300, 1e300, DBL_MAX; grid sizes
 *    as the core's fuzz test; thickness, mu, bits), a NULL world, desc or
 *    out: refused ones give EINVAL, *out NULL and a message; accepted ones
 *    take 2 steps over the scene's geoms (OK or ESTEP, finite).
 * 3. A random walk of 1000 calls on two cloths in a world with a static
 *    plane, box and trimesh, a dynamic sphere and a kinematic capsule:
 *    pins to the world and to bodies (NULL body, a body of another world),
 *    releases, forces, normals, friction, thickness, bits, space changes
 *    (a geom as the space included), vertex forces for the next step,
 *    failure modes (valid and not), vertex contact queries, per-geom
 *    friction and surface callbacks answering any value, triangle test
 *    queries, sleeping queries and wake-ups, state files written and read
 *    (NULL, empty, in a directory that does not exist, a directory, good;
 *    geom and body arrays full, none or of negative count),
 *    dClothStep and dClothWorldStep with good and bad h and bad cloth
 *    arrays. After each call: a status of the enum; positions finite; after
 *    a failure the core state, the bodies' poses, velocities and forces
 *    unchanged (both cloths' for dClothWorldStep, which is all or nothing)
 *    and a message set; a bad path refused with a message naming the path,
 *    the good path's file untouched by a failed write.
 */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "body_state.h"
#include "records.h"

static const double XD[] = {NAN, INFINITY, -INFINITY, 0.0, -0.0, -1.0, 1e-300, 1e300, DBL_MAX, -1e300, 1e-12, 1e6, 0.5};
#define NXD (sizeof XD / sizeof XD[0])
static const int XI[] = {INT_MIN, -1, 0, 1, 2, 3, 4, 7, 64, 100000, INT_MAX};
#define NXI (sizeof XI / sizeof XI[0])

static double xd(rng *g) { return XD[rng_u64(g) % NXD]; }
static int xi(rng *g) { return XI[rng_u64(g) % NXI]; }
static double dval(rng *g, double lo, double hi) { return rng_u64(g) % 3 ? rng_range(g, lo, hi) : xd(g); }

/* the friction callback's answer (NaN, negative and huge included) */
static double fuzz_mu;
static void fuzz_friction(void *data, dClothID c, dGeomID g, dReal *mu)
{
    (void)c, (void)g;
    *mu = *(const double *)data;
}
/* the surface callback's answer: any mu and thickness, the thickness for
 * one geom only (0: all) */
static struct fuzz_surf {
    double mu, thickness;
    dGeomID only;
} fuzz_surf;
static void fuzz_surface(void *data, dClothID c, dGeomID g, dClothSurface *sf)
{
    const struct fuzz_surf *f = data;
    (void)c;
    sf->mu = f->mu;
    if (!f->only || f->only == g) sf->thickness = f->thickness;
}
static int index_of(rng *g, int n) { return rng_u64(g) % 2 ? (int)(rng_u64(g) % (uint64_t)n) : xi(g); }

/* A thickness: any extreme (unbounded, 1e300 would crash libccd and 1e-300
 * spin its GJK: the plugin bounds the thickness). */
static double thick(rng *g) { return xd(g); }

static int status_ok(cloth_status s)
{
    return s == CLOTH_OK || s == CLOTH_EINVAL || s == CLOTH_ENOMEM || s == CLOTH_ESTEP;
}

static int finite_all(const double *a, size_t n)
{
    for (size_t k = 0; k < n; k++)
        if (!isfinite(a[k])) return 0;
    return 1;
}

typedef struct scene {
    dWorldID world, other;
    dSpaceID space, space2;
    dGeomID plane, box, mesh, sph, cap;
    dBodyID ball, kin, stranger;
    dTriMeshDataID td;
} scene;

static const float mesh_v[] = {-1, -1, 0.1f, 1, -1, 0.1f, 1, 1, 0.1f, -1, 1, 0.1f, 0, 0, 0.3f};
static const dTriIndex mesh_i[] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};

static void scene_make(scene *s)
{
    s->world = dWorldCreate();
    s->other = dWorldCreate();
    dWorldSetGravity(s->world, 0, 0, -9.81);
    s->space = dHashSpaceCreate(0);
    s->space2 = dSimpleSpaceCreate(0);
    s->plane = dCreatePlane(s->space, 0, 0, 1, 0);
    s->box = dCreateBox(s->space, 0.3, 0.3, 0.3);
    dGeomSetPosition(s->box, 0.2, 0, 0.4);
    s->td = dGeomTriMeshDataCreate();
    dGeomTriMeshDataBuildSingle(s->td, mesh_v, 3 * sizeof(float), 5, mesh_i, 12, 3 * sizeof(dTriIndex));
    s->mesh = dCreateTriMesh(s->space2, s->td, NULL, NULL, NULL);
    s->ball = dBodyCreate(s->world);
    dMass m;
    dMassSetSphereTotal(&m, 1.0, 0.1);
    dBodySetMass(s->ball, &m);
    dBodySetPosition(s->ball, -0.2, 0.1, 0.6);
    s->sph = dCreateSphere(s->space, 0.1);
    dGeomSetBody(s->sph, s->ball);
    s->kin = dBodyCreate(s->world);
    dBodySetKinematic(s->kin);
    dBodySetPosition(s->kin, 0, -0.3, 0.5);
    dBodySetAngularVel(s->kin, 0, 0, 0.5);
    s->cap = dCreateCapsule(s->space, 0.05, 0.3);
    dGeomSetBody(s->cap, s->kin);
    s->stranger = dBodyCreate(s->other);
}

static void scene_free(scene *s)
{
    dGeomDestroy(s->plane);
    dGeomDestroy(s->box);
    dGeomDestroy(s->mesh);
    dGeomDestroy(s->sph);
    dGeomDestroy(s->cap);
    dGeomTriMeshDataDestroy(s->td);
    dSpaceDestroy(s->space);
    dSpaceDestroy(s->space2);
    dWorldDestroy(s->world);
    dWorldDestroy(s->other);
}

static void null_cloth(void)
{
    dReal p[3] = {0, 0, 0}, nrm[3];
    CHECK(dClothGetVersion()[0] != '\0', "version");
    CHECK(dClothGetCore(NULL) == NULL, "GetCore(NULL)");
    CHECK(dClothGetLastError(NULL) != NULL, "GetLastError(NULL)");
    CHECK(dClothStep(NULL, 0.01) == CLOTH_EINVAL, "Step(NULL)");
    CHECK(dClothGetStats(NULL) == NULL, "GetStats(NULL)");
    CHECK(dClothGetVertexCount(NULL) == 0 && dClothGetPositions(NULL) == NULL, "counts/positions of NULL");
    CHECK(dClothGetNormals(NULL, nrm) == CLOTH_EINVAL, "GetNormals(NULL)");
    CHECK(dClothGetTriangleCount(NULL) == 0 && dClothGetTriangles(NULL) == NULL, "triangles of NULL");
    CHECK(dClothPinToWorld(NULL, 0, p) == CLOTH_EINVAL && dClothPinToBody(NULL, 0, NULL, p) == CLOTH_EINVAL &&
              dClothReleasePin(NULL, 0) == CLOTH_EINVAL && dClothReleaseBody(NULL, NULL) == CLOTH_EINVAL,
          "pins of NULL");
    CHECK(dClothGetPinForce(NULL, 0, nrm) == CLOTH_EINVAL && dClothGetContactForce(NULL, 0, nrm) == CLOTH_EINVAL,
          "forces of NULL");
    CHECK(dClothSetFriction(NULL, 0.3) == CLOTH_EINVAL && dClothSetThickness(NULL, 0.01) == CLOTH_EINVAL,
          "setters of NULL");
    CHECK(dClothGetFriction(NULL) == 0 && dClothGetThickness(NULL) == 0, "getters of NULL: %g %g",
          dClothGetFriction(NULL), dClothGetThickness(NULL));
    dClothSetCategoryBits(NULL, 1);
    dClothSetCollideBits(NULL, 1);
    CHECK(dClothGetCategoryBits(NULL) == 0 && dClothGetCollideBits(NULL) == 0, "bits of NULL");
    CHECK(dClothSetSpace(NULL, 0) == CLOTH_EINVAL, "dClothSetSpace(NULL) accepted");
    CHECK(dClothAddVertexForce(NULL, 0, 1, 0, 0) == CLOTH_EINVAL, "dClothAddVertexForce(NULL) accepted");
    CHECK(dClothSetFailureMode(NULL, DCLOTH_FAILURE_STOP) == CLOTH_EINVAL, "dClothSetFailureMode(NULL) accepted");
    CHECK(dClothGetVertexContact(NULL, 0, NULL, NULL, NULL) == CLOTH_EINVAL, "dClothGetVertexContact(NULL) accepted");
    CHECK(dClothSetFrictionCallback(NULL, NULL, NULL) == CLOTH_EINVAL, "dClothSetFrictionCallback(NULL) accepted");
    CHECK(dClothSetSurfaceCallback(NULL, NULL, NULL) == CLOTH_EINVAL, "dClothSetSurfaceCallback(NULL) accepted");
    CHECK(dClothWriteState(NULL, "plugin_fuzz_api.state", NULL, 0, NULL, 0) == CLOTH_EINVAL &&
              dClothReadState(NULL, "plugin_fuzz_api.state", NULL, 0, NULL, 0) == CLOTH_EINVAL &&
              dClothWriteState(NULL, NULL, NULL, -1, NULL, -1) == CLOTH_EINVAL &&
              dClothReadState(NULL, NULL, NULL, -1, NULL, -1) == CLOTH_EINVAL,
          "state files of NULL accepted");
    CHECK(dClothGetTriangleTests(NULL, 0) == 0, "dClothGetTriangleTests(NULL) is not 0");
    CHECK(dClothSetExactTriangleTests(NULL, 0, 1) == CLOTH_EINVAL && dClothGetExactTriangleTests(NULL, 0) == 0,
          "dClothSetExactTriangleTests(NULL) accepted or dClothGetExactTriangleTests(NULL) not 0");
    CHECK(dClothSetEdgeTests(NULL, 0, 1) == CLOTH_EINVAL && dClothGetEdgeTests(NULL, 0) == 0,
          "dClothSetEdgeTests(NULL) accepted or dClothGetEdgeTests(NULL) not 0");
    CHECK(dClothIsSleeping(NULL) == 0, "dClothIsSleeping(NULL) is not 0");
    dClothWake(NULL);
    dClothDestroy(NULL);
}

static long created, refused;

static void descriptors(scene *s)
{
    rng g = rng_seed(0xd0c10u);
    for (int k = 0; k < 500; k++) {
        dClothDesc d = dClothDefaultDesc();
        d.cloth.rows = d.cloth.cols = 5;
        d.cloth.width = d.cloth.height = 0.5;
        d.cloth.origin[0] = d.cloth.origin[1] = -0.25;
        d.cloth.origin[2] = 0.8;
        int nf = 1 + (int)(rng_u64(&g) % 3);
        for (int q = 0; q < nf; q++) {
            switch (rng_u64(&g) % 14) {
            case 0: d.thickness = thick(&g); break;
            case 1: d.mu = xd(&g); break;
            case 2: d.category_bits = (unsigned long)rng_u64(&g); break;
            case 3: d.collide_bits = rng_u64(&g) % 2 ? 0 : ~0ul; break;
            case 4: {
                int v = xi(&g);
                d.cloth.rows = v > 16 && v < INT_MAX ? 16 : v;
                break;
            }
            case 5: {
                int v = xi(&g);
                d.cloth.cols = v > 16 && v < INT_MAX ? 16 : v;
                break;
            }
            case 6: d.cloth.width = xd(&g); break;
            case 7: d.cloth.origin[rng_u64(&g) % 3] = xd(&g); break;
            case 8: d.cloth.material.k_t = xd(&g); break;
            case 9: d.cloth.material.density = xd(&g); break;
            case 10: d.cloth.gravity[2] = xd(&g); break;
            case 11: d.cloth.material.tension_yield = xd(&g); break;
            case 12: d.cloth.material.tension_set = xd(&g); break;
            default: d.cloth.solver.cg_tolerance = xd(&g); break;
            }
        }
        int which = (int)(rng_u64(&g) % 20);
        dWorldID w = which == 0 ? NULL : s->world;
        const dClothDesc *dp = which == 1 ? NULL : &d;
        dClothID c = (dClothID)&g, *out = which == 2 ? NULL : &c;
        cloth_error err;
        memset(&err, 0, sizeof err);
        cloth_status r = dClothCreate(w, which == 3 ? 0 : s->space, dp, out, &err);
        CHECK(status_ok(r), "descriptor %d: status %d", k, (int)r);
        if (r != CLOTH_OK) {
            refused++;
            CHECK(out == NULL || c == NULL, "descriptor %d: refused, *out not NULL", k);
            CHECK(err.message[0] != '\0', "descriptor %d: refused without a message", k);
            continue;
        }
        CHECK(w && dp && out, "descriptor %d: NULL world/desc/out accepted", k);
        created++;
        int n = dClothGetVertexCount(c);
        for (int q = 0; q < 2; q++) {
            cloth_status t = dClothStep(c, 1.0 / 60);
            CHECK(t == CLOTH_OK || t == CLOTH_ESTEP, "descriptor %d: step returned %d", k, (int)t);
            CHECK(finite_all(dClothGetPositions(c), 3 * (size_t)n), "descriptor %d: NaN after a step (%s)", k,
                  cloth_status_string(t));
        }
        dClothDestroy(c);
    }
    printf("dClothCreate: %ld created, %ld refused\n", created, refused);
}

static long ncalls, nfail, steps_ok, steps_fail;
static long files_written, files_read, files_refused; /* the state file calls' outcomes */
static long file_calls;                               /* picks the next path in turn        */
static int bad_paths[4][2];                           /* each bad path refused, read, written */
static const char *const STATE_FILE[2] = {"plugin_fuzz_api0.state", "plugin_fuzz_api1.state"};

/* The walk's two cloths and the geoms' tests as the walk's calls left them. */
typedef struct walker {
    scene *s;
    dClothID cl[2];
    /* each cloth's tests of each geom: none, box, mesh, sphere, capsule */
    int tri_on[2][5], edge_on[2][5], exact_on[2][5];
} walker;

/* One call of the walk: its cloth, vertex and point, and what the checks after it compare with. */
typedef struct call {
    rng *g;
    walker *w;
    int it, ci, n;
    dClothID c;
    cloth *core;
    cloth_state *before, *after, *other_before; /* this cloth's state and the other's, before the call */
    body_state b0[2];                           /* the ball and the kinematic body before the call */
    int vi;                                     /* a vertex, sometimes out of range */
    dReal p[3];                                 /* near vertex vi, sometimes extreme */
    int is_step;                                /* 1: dClothStep, 2: dClothWorldStep */
} call;

/* Pins to the world and to bodies, releases, and the forces they hold. */
static cloth_status call_pin(call *k, int op)
{
    rng *g = k->g;
    scene *s = k->w->s;
    dClothID c = k->c;
    int vi = k->vi;
    dReal out3[3];
    cloth_status st = CLOTH_OK;
    switch (op) {
    case 0: st = dClothPinToWorld(c, vi, rng_u64(g) % 10 ? k->p : NULL); break;
    case 1: {
        dBodyID b = rng_u64(g) % 5 == 0 ? NULL : rng_u64(g) % 5 == 0 ? s->stranger : rng_u64(g) % 2 ? s->ball : s->kin;
        dReal loc[3] = {dval(g, -0.1, 0.1), dval(g, -0.1, 0.1), dval(g, -0.1, 0.1)};
        st = dClothPinToBody(c, vi, b, rng_u64(g) % 10 ? loc : NULL);
        break;
    }
    case 2: st = dClothReleasePin(c, vi); break;
    case 3: st = dClothReleaseBody(c, rng_u64(g) % 4 ? (rng_u64(g) % 2 ? s->ball : s->kin) : NULL); break;
    case 4: st = dClothGetPinForce(c, vi, rng_u64(g) % 8 ? out3 : NULL); break;
    default: st = dClothGetContactForce(c, vi, rng_u64(g) % 8 ? out3 : NULL); break;
    }
    return st;
}

/* Friction, thickness, bits, space, sleeping, failure mode and the per-geom callbacks. */
static cloth_status call_setting(call *k, int op)
{
    rng *g = k->g;
    scene *s = k->w->s;
    dClothID c = k->c;
    cloth_status st = CLOTH_OK;
    switch (op) {
    case 6: st = dClothSetFriction(c, dval(g, 0, 1)); break;
    case 7: st = dClothSetThickness(c, rng_u64(g) % 3 ? rng_range(g, 0.001, 0.02) : thick(g)); break;
    case 8: dClothSetCategoryBits(c, rng_u64(g) % 2 ? ~0ul : (unsigned long)rng_u64(g)); break;
    case 9: dClothSetCollideBits(c, rng_u64(g) % 2 ? ~0ul : (unsigned long)rng_u64(g)); break;
    case 10: { /* a space, none, or a geom that is not a space (refused) */
        unsigned q = (unsigned)(rng_u64(g) % 6);
        st = dClothSetSpace(c, q == 0 ? 0 : q == 1 ? (dSpaceID)s->box : q % 2 ? s->space : s->space2);
        break;
    }
    case 14: /* sleeping: on or off, extreme speeds and step counts */
        st = dClothSetAutoSleep(c, (int)(rng_u64(g) % 3), rng_u64(g) % 3 ? dval(g, 1e-3, 0.1) : xd(g),
                                rng_u64(g) % 3 ? (int)(rng_u64(g) % 20) : xi(g));
        break;
    case 19: /* hold or stop on a failed step, or a mode that does not exist */
        st = dClothSetFailureMode(c, (dClothFailureMode)(rng_u64(g) % 4 ? (int)(rng_u64(g) % 2) : xi(g)));
        break;
    case 21: /* a per-geom friction callback answering any value, or none */
        fuzz_mu = dval(g, 0, 1.5);
        st = dClothSetFrictionCallback(c, rng_u64(g) % 4 ? fuzz_friction : NULL, &fuzz_mu);
        break;
    default: /* a per-geom surface callback answering any value, or none */
        fuzz_surf.mu = dval(g, 0, 1.5);
        fuzz_surf.thickness = rng_u64(g) % 2 ? dval(g, 1e-3, 0.05) : thick(g);
        fuzz_surf.only = rng_u64(g) % 2 ? s->box : 0;
        st = dClothSetSurfaceCallback(c, rng_u64(g) % 4 ? fuzz_surface : NULL, &fuzz_surf);
        break;
    }
    return st;
}

/* Normals, triangles, convex points, vertex forces for the next step and vertex contacts. */
static cloth_status call_geometry(call *k, int op)
{
    rng *g = k->g;
    scene *s = k->w->s;
    dClothID c = k->c;
    int n = k->n, vi = k->vi;
    size_t n3 = 3 * (size_t)n;
    cloth_status st = CLOTH_OK;
    switch (op) {
    case 11: {
        double *nrm = malloc(n3 * sizeof *nrm);
        st = dClothGetNormals(c, rng_u64(g) % 8 ? nrm : NULL);
        if (st == CLOTH_OK) CHECK(finite_all(nrm, n3), "normals not finite");
        free(nrm);
        break;
    }
    case 12: {
        const int *t = dClothGetTriangles(c);
        int nt = dClothGetTriangleCount(c), bad = 0;
        for (int q = 0; q < 3 * nt; q++) bad += t[q] < 0 || t[q] >= n;
        CHECK(bad == 0, "triangle indices out of range");
        break;
    }
    case 15: { /* convex points for geoms that are not convex, NULL, bad counts and values */
        dReal pts[12];
        for (int q = 0; q < 12; q++) pts[q] = rng_u64(g) % 6 ? rng_range(g, -1, 1) : xd(g);
        dGeomID gg = rng_u64(g) % 3 == 0 ? 0 : rng_u64(g) % 2 ? s->box : s->sph;
        st = dClothSetConvexPoints(c, gg, rng_u64(g) % 6 ? pts : NULL, rng_u64(g) % 3 ? 4 : xi(g));
        break;
    }
    case 18: /* forces for the next step: any vertex, extreme components */
        st = dClothAddVertexForce(c, rng_u64(g) % 6 ? vi : xi(g), dval(g, -0.05, 0.05), dval(g, -0.05, 0.05),
                                  dval(g, -0.05, 0.05));
        break;
    default: { /* which geom a vertex touches, any vertex, NULL outputs */
        dGeomID gg;
        dReal pt[3], nr[3];
        st = dClothGetVertexContact(c, rng_u64(g) % 6 ? vi : xi(g), rng_u64(g) % 8 ? &gg : NULL,
                                    rng_u64(g) % 2 ? pt : NULL, rng_u64(g) % 2 ? nr : NULL);
        break;
    }
    }
    return st;
}

/* Triangle tests off and on, for a box, a mesh, a sphere or none. */
static cloth_status call_set_triangle_tests(call *k)
{
    rng *g = k->g;
    scene *s = k->w->s;
    dClothID c = k->c;
    int ci = k->ci, it = k->it;
    unsigned q = (unsigned)(rng_u64(g) % 4);
    dGeomID gg = q == 0 ? 0 : q == 1 ? s->box : q == 2 ? s->mesh : s->sph;
    int enable = (int)(rng_u64(g) % 3);
    cloth_status st = dClothSetTriangleTests(c, gg, enable);
    if (st == CLOTH_OK) k->w->tri_on[ci][q] = enable != 0;
    /* the links' edge tests where triangle tests are off (as by default): the walk unchanged */
    cloth_status se = dClothSetEdgeTests(c, gg, enable == 0);
    CHECK(se == (gg ? CLOTH_OK : CLOTH_EINVAL), "call %d: dClothSetEdgeTests gave %d", it, (int)se);
    if (se == CLOTH_OK) k->w->edge_on[ci][q] = enable == 0;
    /* decided by the geometry for enable 2: a box only, the rest refused and unchanged */
    cloth_status sx = dClothSetExactTriangleTests(c, gg, enable == 2);
    CHECK(sx == (gg == s->box ? CLOTH_OK : CLOTH_EINVAL), "call %d: dClothSetExactTriangleTests gave %d", it, (int)sx);
    if (sx == CLOTH_OK) k->w->exact_on[ci][q] = enable == 2;
    return st;
}

/* Triangle tests as call_set_triangle_tests left them, for none, a geom it sets, or one it never does. */
static void call_get_triangle_tests(call *k)
{
    scene *s = k->w->s;
    dClothID c = k->c;
    int ci = k->ci, it = k->it;
    unsigned q = (unsigned)(rng_u64(k->g) % 5);
    dGeomID gg = q == 0 ? 0 : q == 1 ? s->box : q == 2 ? s->mesh : q == 3 ? s->sph : s->cap;
    int on = dClothGetTriangleTests(c, gg), edges = dClothGetEdgeTests(c, gg);
    CHECK(on == (gg ? k->w->tri_on[ci][q] : 0), "call %d: dClothGetTriangleTests of geom %u gave %d", it, q, on);
    CHECK(edges == (gg ? k->w->edge_on[ci][q] : 0), "call %d: dClothGetEdgeTests of geom %u gave %d", it, q, edges);
    CHECK(dClothGetExactTriangleTests(c, gg) == (gg ? k->w->exact_on[ci][q] : 0),
          "call %d: dClothGetExactTriangleTests of geom %u gave %d", it, q, dClothGetExactTriangleTests(c, gg));
}

/* Save, then restore into itself (nothing changes) or the other cloth (another size). */
static cloth_status call_save_restore(call *k)
{
    dClothID c = k->c;
    int it = k->it;
    dClothState *ds = dClothStateCreate(c);
    if (!CHECK(ds != NULL, "dClothStateCreate")) return CLOTH_OK;
    cloth_status st = dClothSave(c, ds);
    if (st == CLOTH_OK) {
        dClothID into = rng_u64(k->g) % 3 ? c : k->w->cl[1 - k->ci];
        st = dClothRestore(into, ds);
        if (into == c) {
            cloth_state *mid = cloth_state_create(k->core);
            cloth_save(k->core, mid);
            CHECK(st == CLOTH_OK && cloth_state_diff(k->before, mid) == 0.0,
                  "call %d: saving and restoring a cloth changed it", it);
            cloth_state_destroy(mid);
        } else {
            CHECK(st == CLOTH_EINVAL, "call %d: a state restored into a cloth of another size", it);
            cloth *oc = dClothGetCore(into);
            cloth_state *oa = cloth_state_create(oc);
            cloth_save(oc, oa);
            CHECK(cloth_state_diff(k->other_before, oa) == 0.0, "call %d: a refused restore changed the cloth", it);
            cloth_state_destroy(oa);
            st = CLOTH_OK; /* refused on the other cloth; this one was only saved */
        }
    }
    dClothStateDestroy(ds);
    return st;
}

/* A state file written or read: bad paths, this cloth's file or the other's (another
 * size: refused), arrays full, none or of negative count. */
static cloth_status call_state_file(call *k)
{
    rng *g = k->g;
    scene *s = k->w->s;
    dClothID c = k->c;
    int ci = k->ci, it = k->it;
    const char *paths[] = {NULL, "", "plugin_fuzz_api_no_dir/x.state", ".", STATE_FILE[ci], STATE_FILE[1 - ci]};
    /* the paths in turn, each written then read (every bad one reached) */
    unsigned q = (unsigned)(file_calls % 8);
    int writing = (int)(file_calls++ / 8 % 2);
    const char *path = paths[q < 4 ? q : q < 7 ? 4 : 5];
    dGeomID geoms[] = {s->plane, s->box, s->mesh, s->sph, s->cap};
    dBodyID bodies[] = {s->ball, s->kin};
    /* a missing directory and a directory as the path get whole arrays: only
     * the path can then be at fault, whatever the cloth touches */
    unsigned a = (unsigned)(rng_u64(g) % 6);
    if (q == 2 || q == 3) a = 2 + a % 4;
    int ng = a == 0 ? 0 : a == 1 ? xi(g) : 5, nb = a == 0 ? 0 : a == 1 ? xi(g) : 2;
    if (ng > 5) ng = 5;
    if (nb > 2) nb = 2;
    blob file = read_all(path && path[0] ? path : STATE_FILE[ci]);
    cloth_status st = writing ? dClothWriteState(c, path, a ? geoms : NULL, ng, a ? bodies : NULL, nb)
                              : dClothReadState(c, path, a ? geoms : NULL, ng, a ? bodies : NULL, nb);
    /* NULL and empty paths are named before negative counts, the rest after */
    const char *field = q < 2 || (q < 4 && ng >= 0 && nb >= 0) ? "path" : ng < 0 || nb < 0 ? "ngeoms" : NULL;
    if (q < 4 && !strcmp(field, "path")) bad_paths[q][writing]++;
    if (field)
        CHECK(st == CLOTH_EINVAL && strstr(dClothGetLastError(c), field),
              "call %d: %s with path %s%s%s: status %d, \"%s\"", it, writing ? "write" : "read", path ? "\"" : "",
              path ? path : "NULL", path ? "\"" : "", (int)st, dClothGetLastError(c));
    files_written += st == CLOTH_OK && writing;
    files_read += st == CLOTH_OK && !writing;
    files_refused += st != CLOTH_OK;
    if (st != CLOTH_OK && writing) {
        blob now = read_all(path && path[0] ? path : STATE_FILE[ci]);
        CHECK(now.n == file.n && (!now.n || memcmp(now.p, file.p, now.n) == 0),
              "call %d: a refused write changed the state file", it);
        free(now.p);
    }
    free(file.p);
    return st;
}

/* Asleep or not, and woken: the core untouched. */
static void call_sleep(call *k)
{
    dClothID c = k->c;
    int it = k->it;
    int was = dClothIsSleeping(c);
    CHECK(was == 0 || was == 1, "call %d: dClothIsSleeping gave %d", it, was);
    if (rng_u64(k->g) % 2) {
        dClothWake(c);
        cloth_save(k->core, k->after);
        CHECK(!dClothIsSleeping(c) && cloth_state_diff(k->before, k->after) == 0.0,
              "call %d: dClothWake left it asleep or changed the cloth", it);
    }
}

/* dClothWorldStep over both cloths, or a bad array, count, world or h. */
static cloth_status call_world_step(call *k)
{
    rng *g = k->g;
    dClothID arr[3] = {k->w->cl[0], k->w->cl[1], NULL};
    int nn = rng_u64(g) % 4 ? 1 + (int)(rng_u64(g) % 2) : xi(g);
    if (nn > 3) nn = 3;
    double h = rng_u64(g) % 5 ? rng_range(g, 1e-3, 0.03) : xd(g);
    if (h > 0.1 && isfinite(h)) h = 0.1;
    cloth_status st = dClothWorldStep(rng_u64(g) % 10 ? k->w->s->world : NULL, rng_u64(g) % 10 ? arr : NULL, nn, h,
                                      (int)(rng_u64(g) % 2));
    k->is_step = 2;
    return st;
}

/* dClothStep with a good or bad h. */
static cloth_status call_step(call *k)
{
    rng *g = k->g;
    double h = rng_u64(g) % 5 ? rng_range(g, 1e-3, 0.03) : xd(g);
    if (h > 0.1 && isfinite(h)) h = 0.1;
    cloth_status st = dClothStep(k->c, h);
    k->is_step = 1;
    if (st == CLOTH_OK) steps_ok++;
    else steps_fail++;
    if (getenv("FUZZ_DEBUG") && st != CLOTH_OK) printf("step h=%g: %s\n", h, dClothGetLastError(k->c));
    return st;
}

/* Operation op (0..30) of the walk: 0-25 the calls, the rest steps. */
static cloth_status call_op(call *k, int op)
{
    if (op <= 5) return call_pin(k, op);
    if ((op >= 6 && op <= 10) || op == 14 || op == 19 || op == 21 || op == 22) return call_setting(k, op);
    if (op == 11 || op == 12 || op == 15 || op == 18 || op == 20) return call_geometry(k, op);
    switch (op) {
    case 13: return call_world_step(k);
    case 16: return call_save_restore(k);
    case 17: return call_set_triangle_tests(k);
    case 23: return call_state_file(k);
    case 24: call_sleep(k); return CLOTH_OK;
    case 25: call_get_triangle_tests(k); return CLOTH_OK;
    default: return call_step(k);
    }
}

/* The checks after a call (op, status st): a known status, finite cloths and
 * ball, and after a failure a message and nothing changed. */
static void check_call(call *k, int op, cloth_status st)
{
    dClothID *cl = k->w->cl;
    scene *s = k->w->s;
    int it = k->it;
    body_state b1[2];
    CHECK(status_ok(st), "call %d (op %d): status %d", it, op, (int)st);
    for (int q = 0; q < 2; q++)
        CHECK(finite_all(dClothGetPositions(cl[q]), 3 * (size_t)dClothGetVertexCount(cl[q])),
              "call %d (op %d, %s): NaN/inf in cloth %d", it, op, cloth_status_string(st), q);
    body_save(s->ball, &b1[0]);
    body_save(s->kin, &b1[1]);
    CHECK(finite_all(b1[0].pos, 3) && finite_all(b1[0].lv, 3), "call %d (op %d): the ball is not finite", it, op);
    if (st != CLOTH_OK) {
        nfail++;
        CHECK(dClothGetLastError(k->c)[0] != '\0' || k->is_step == 2, "call %d (op %d): failure without a message", it,
              op);
        cloth_save(k->core, k->after);
        CHECK(cloth_state_diff(k->before, k->after) == 0.0, "call %d (op %d, %s): the cloth changed", it, op,
              cloth_status_string(st));
        if (k->is_step == 2) { /* dClothWorldStep is all or nothing: the other cloth too */
            cloth *oc = dClothGetCore(cl[1 - k->ci]);
            cloth_state *oa = cloth_state_create(oc);
            cloth_save(oc, oa);
            CHECK(cloth_state_diff(k->other_before, oa) == 0.0,
                  "call %d: a failed dClothWorldStep moved the other cloth", it);
            cloth_state_destroy(oa);
        }
        CHECK(memcmp(k->b0, b1, sizeof k->b0) == 0, "call %d (op %d, %s): a body changed", it, op,
              cloth_status_string(st));
    }
}

/* Keep the scene sane: the ball back, settings back. */
static void reset_scene(walker *w)
{
    scene *s = w->s;
    dBodySetPosition(s->ball, -0.2, 0.1, 0.6);
    dBodySetLinearVel(s->ball, 0, 0, 0);
    dBodySetAngularVel(s->ball, 0, 0, 0);
    for (int k = 0; k < 2; k++) {
        for (int i = 0; i < dClothGetVertexCount(w->cl[k]); i++) dClothReleasePin(w->cl[k], i);
        dClothSetFriction(w->cl[k], 0.3);
        dClothSetThickness(w->cl[k], 0.005);
        dClothSetSpace(w->cl[k], s->space);
    }
}

/* Call it of the walk: a random operation on a random cloth, checked. */
static void walk_call(rng *g, walker *w, int it)
{
    call k = {.g = g, .w = w, .it = it};
    int ci = k.ci = (int)(rng_u64(g) % 2);
    dClothID c = k.c = w->cl[ci];
    cloth *core = k.core = dClothGetCore(c);
    int n = k.n = dClothGetVertexCount(c);
    k.before = cloth_state_create(core);
    k.after = cloth_state_create(core);
    k.other_before = cloth_state_create(dClothGetCore(w->cl[1 - ci]));
    cloth_save(core, k.before);
    cloth_save(dClothGetCore(w->cl[1 - ci]), k.other_before);
    body_save(w->s->ball, &k.b0[0]);
    body_save(w->s->kin, &k.b0[1]);
    const double *x = dClothGetPositions(c);
    int vi = k.vi = index_of(g, n), vv = vi >= 0 && vi < n ? vi : 0;
    for (int r = 0; r < 3; r++) k.p[r] = rng_u64(g) % 12 ? x[3 * vv + r] : xd(g);
    int op = (int)(rng_u64(g) % 31); /* 0-25 the calls, the rest steps */
    cloth_status st = call_op(&k, op);
    ncalls++;
    check_call(&k, op, st);
    cloth_state_destroy(k.before);
    cloth_state_destroy(k.after);
    cloth_state_destroy(k.other_before);
    if (it % 25 == 24) reset_scene(w);
}

/* The walk's counts; every state file outcome and bad path reached, enough steps succeeded. */
static void walk_summary(void)
{
    printf("random walk: %ld calls, %ld refused or failed; dClothStep %ld ok, %ld failed\n", ncalls, nfail, steps_ok,
           steps_fail);
    printf("state files: %ld written, %ld read, %ld refused\n", files_written, files_read, files_refused);
    CHECK(files_written > 0 && files_read > 0 && files_refused > 0, "the state file calls do not reach every outcome");
    for (int k = 0; k < 8; k++)
        CHECK(bad_paths[k / 2][k % 2] > 0, "bad path %d never %s", k / 2, k % 2 ? "written" : "read");
}

static void walk(scene *s)
{
    walker w = {.s = s};
    for (int k = 0; k < 2; k++) {
        dClothDesc d = dClothDefaultDesc();
        d.cloth.rows = 7 + 2 * k;
        d.cloth.cols = 6;
        d.cloth.width = d.cloth.height = 0.6;
        d.cloth.origin[0] = d.cloth.origin[1] = -0.3;
        d.cloth.origin[2] = 0.7 + 0.2 * k;
        d.cloth.solver.cg_max_iterations = 400;
        if (!CHECK(dClothCreate(s->world, s->space, &d, &w.cl[k], NULL) == CLOTH_OK, "walk cloth")) return;
    }
    for (int k = 0; k < 10; k++) {
        w.tri_on[k / 5][k % 5] = w.edge_on[k / 5][k % 5] = 1;
        w.exact_on[k / 5][k % 5] = k % 5 == 1; /* the box's exact tests, on by default */
    }
    rng g = rng_seed(0x9a1cu);
    for (int it = 0; it < 1000; it++) walk_call(&g, &w, it);
    walk_summary();
    remove(STATE_FILE[0]);
    remove(STATE_FILE[1]);
    CHECK(steps_ok > 50, "too few successful steps (%ld) for the walk to mean much", steps_ok);
    dClothDestroy(w.cl[0]);
    dClothDestroy(w.cl[1]);
}

int main(void)
{
    dInitODE2(0);
    null_cloth();
    scene s;
    scene_make(&s);
    descriptors(&s);
    walk(&s);
    scene_free(&s);
    dCloseODE();
    return check_summary();
}
