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

static void walk(scene *s)
{
    dClothID cl[2];
    for (int k = 0; k < 2; k++) {
        dClothDesc d = dClothDefaultDesc();
        d.cloth.rows = 7 + 2 * k;
        d.cloth.cols = 6;
        d.cloth.width = d.cloth.height = 0.6;
        d.cloth.origin[0] = d.cloth.origin[1] = -0.3;
        d.cloth.origin[2] = 0.7 + 0.2 * k;
        d.cloth.solver.cg_max_iterations = 400;
        if (!CHECK(dClothCreate(s->world, s->space, &d, &cl[k], NULL) == CLOTH_OK, "walk cloth")) return;
    }
    /* what case 17 made each geom's tests (17's and 25's order) */
    int tri_on[2][5], edge_on[2][5], exact_on[2][5] = {{0}};
    for (int k = 0; k < 10; k++) tri_on[k / 5][k % 5] = edge_on[k / 5][k % 5] = 1;
    rng g = rng_seed(0x9a1cu);
    for (int it = 0; it < 1000; it++) {
        int ci = (int)(rng_u64(&g) % 2);
        dClothID c = cl[ci];
        cloth *core = dClothGetCore(c);
        int n = dClothGetVertexCount(c);
        size_t n3 = 3 * (size_t)n;
        cloth_state *before = cloth_state_create(core), *after = cloth_state_create(core);
        cloth_state *other_before = cloth_state_create(dClothGetCore(cl[1 - ci]));
        cloth_save(core, before);
        cloth_save(dClothGetCore(cl[1 - ci]), other_before);
        body_state b0[2], b1[2];
        body_save(s->ball, &b0[0]);
        body_save(s->kin, &b0[1]);
        dReal p[3], out3[3];
        const double *x = dClothGetPositions(c);
        int vi = index_of(&g, n), vv = vi >= 0 && vi < n ? vi : 0;
        for (int r = 0; r < 3; r++) p[r] = rng_u64(&g) % 12 ? x[3 * vv + r] : xd(&g);
        int op = (int)(rng_u64(&g) % 31); /* 0-25 the calls, the rest steps */
        cloth_status st = CLOTH_OK;
        int is_step = 0;
        switch (op) {
        case 0: st = dClothPinToWorld(c, vi, rng_u64(&g) % 10 ? p : NULL); break;
        case 1: {
            dBodyID b = rng_u64(&g) % 5 == 0   ? NULL
                        : rng_u64(&g) % 5 == 0 ? s->stranger
                        : rng_u64(&g) % 2      ? s->ball
                                               : s->kin;
            dReal loc[3] = {dval(&g, -0.1, 0.1), dval(&g, -0.1, 0.1), dval(&g, -0.1, 0.1)};
            st = dClothPinToBody(c, vi, b, rng_u64(&g) % 10 ? loc : NULL);
            break;
        }
        case 2: st = dClothReleasePin(c, vi); break;
        case 3: st = dClothReleaseBody(c, rng_u64(&g) % 4 ? (rng_u64(&g) % 2 ? s->ball : s->kin) : NULL); break;
        case 4: st = dClothGetPinForce(c, vi, rng_u64(&g) % 8 ? out3 : NULL); break;
        case 5: st = dClothGetContactForce(c, vi, rng_u64(&g) % 8 ? out3 : NULL); break;
        case 6: st = dClothSetFriction(c, dval(&g, 0, 1)); break;
        case 7: st = dClothSetThickness(c, rng_u64(&g) % 3 ? rng_range(&g, 0.001, 0.02) : thick(&g)); break;
        case 8: dClothSetCategoryBits(c, rng_u64(&g) % 2 ? ~0ul : (unsigned long)rng_u64(&g)); break;
        case 9: dClothSetCollideBits(c, rng_u64(&g) % 2 ? ~0ul : (unsigned long)rng_u64(&g)); break;
        case 10: { /* a space, none, or a geom that is not a space (refused) */
            unsigned k = (unsigned)(rng_u64(&g) % 6);
            st = dClothSetSpace(c, k == 0 ? 0 : k == 1 ? (dSpaceID)s->box : k % 2 ? s->space : s->space2);
            break;
        }
        case 11: {
            double *nrm = malloc(n3 * sizeof *nrm);
            st = dClothGetNormals(c, rng_u64(&g) % 8 ? nrm : NULL);
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
        case 13: {
            dClothID arr[3] = {cl[0], cl[1], NULL};
            int nn = rng_u64(&g) % 4 ? 1 + (int)(rng_u64(&g) % 2) : xi(&g);
            if (nn > 3) nn = 3;
            double h = rng_u64(&g) % 5 ? rng_range(&g, 1e-3, 0.03) : xd(&g);
            if (h > 0.1 && isfinite(h)) h = 0.1;
            st = dClothWorldStep(rng_u64(&g) % 10 ? s->world : NULL, rng_u64(&g) % 10 ? arr : NULL, nn, h,
                                 (int)(rng_u64(&g) % 2));
            is_step = 2;
            break;
        }
        case 14: /* sleeping: on or off, extreme speeds and step counts */
            st = dClothSetAutoSleep(c, (int)(rng_u64(&g) % 3), rng_u64(&g) % 3 ? dval(&g, 1e-3, 0.1) : xd(&g),
                                    rng_u64(&g) % 3 ? (int)(rng_u64(&g) % 20) : xi(&g));
            break;
        case 15: { /* convex points for geoms that are not convex, NULL, bad counts and values */
            dReal pts[12];
            for (int q = 0; q < 12; q++) pts[q] = rng_u64(&g) % 6 ? rng_range(&g, -1, 1) : xd(&g);
            dGeomID gg = rng_u64(&g) % 3 == 0 ? 0 : rng_u64(&g) % 2 ? s->box : s->sph;
            st = dClothSetConvexPoints(c, gg, rng_u64(&g) % 6 ? pts : NULL, rng_u64(&g) % 3 ? 4 : xi(&g));
            break;
        }
        case 17: { /* triangle tests off and on, for a box, a mesh, a sphere or none */
            unsigned k = (unsigned)(rng_u64(&g) % 4);
            dGeomID gg = k == 0 ? 0 : k == 1 ? s->box : k == 2 ? s->mesh : s->sph;
            int enable = (int)(rng_u64(&g) % 3);
            st = dClothSetTriangleTests(c, gg, enable);
            if (st == CLOTH_OK) tri_on[ci][k] = enable != 0;
            /* the links' edge tests where triangle tests are off (as by default): the walk unchanged */
            cloth_status se = dClothSetEdgeTests(c, gg, enable == 0);
            CHECK(se == (gg ? CLOTH_OK : CLOTH_EINVAL), "call %d: dClothSetEdgeTests gave %d", it, (int)se);
            if (se == CLOTH_OK) edge_on[ci][k] = enable == 0;
            /* decided by the geometry for enable 2: a box only, the rest refused and unchanged */
            cloth_status sx = dClothSetExactTriangleTests(c, gg, enable == 2);
            CHECK(sx == (gg == s->box ? CLOTH_OK : CLOTH_EINVAL), "call %d: dClothSetExactTriangleTests gave %d", it,
                  (int)sx);
            if (sx == CLOTH_OK) exact_on[ci][k] = enable == 2;
            break;
        }
        case 16: { /* save, then restore into itself (nothing changes) or the other cloth (another size) */
            dClothState *ds = dClothStateCreate(c);
            if (!CHECK(ds != NULL, "dClothStateCreate")) break;
            st = dClothSave(c, ds);
            if (st == CLOTH_OK) {
                dClothID into = rng_u64(&g) % 3 ? c : cl[1 - ci];
                st = dClothRestore(into, ds);
                if (into == c) {
                    cloth_state *mid = cloth_state_create(core);
                    cloth_save(core, mid);
                    CHECK(st == CLOTH_OK && cloth_state_diff(before, mid) == 0.0,
                          "call %d: saving and restoring a cloth changed it", it);
                    cloth_state_destroy(mid);
                } else {
                    CHECK(st == CLOTH_EINVAL, "call %d: a state restored into a cloth of another size", it);
                    cloth *oc = dClothGetCore(into);
                    cloth_state *oa = cloth_state_create(oc);
                    cloth_save(oc, oa);
                    CHECK(cloth_state_diff(other_before, oa) == 0.0, "call %d: a refused restore changed the cloth",
                          it);
                    cloth_state_destroy(oa);
                    st = CLOTH_OK; /* refused on the other cloth; this one was only saved */
                }
            }
            dClothStateDestroy(ds);
            break;
        }
        case 18: /* forces for the next step: any vertex, extreme components */
            st = dClothAddVertexForce(c, rng_u64(&g) % 6 ? vi : xi(&g), dval(&g, -0.05, 0.05), dval(&g, -0.05, 0.05),
                                      dval(&g, -0.05, 0.05));
            break;
        case 20: { /* which geom a vertex touches, any vertex, NULL outputs */
            dGeomID gg;
            dReal pt[3], nr[3];
            st = dClothGetVertexContact(c, rng_u64(&g) % 6 ? vi : xi(&g), rng_u64(&g) % 8 ? &gg : NULL,
                                        rng_u64(&g) % 2 ? pt : NULL, rng_u64(&g) % 2 ? nr : NULL);
            break;
        }
        case 21: /* a per-geom friction callback answering any value, or none */
            fuzz_mu = dval(&g, 0, 1.5);
            st = dClothSetFrictionCallback(c, rng_u64(&g) % 4 ? fuzz_friction : NULL, &fuzz_mu);
            break;
        case 22: /* a per-geom surface callback answering any value, or none */
            fuzz_surf.mu = dval(&g, 0, 1.5);
            fuzz_surf.thickness = rng_u64(&g) % 2 ? dval(&g, 1e-3, 0.05) : thick(&g);
            fuzz_surf.only = rng_u64(&g) % 2 ? s->box : 0;
            st = dClothSetSurfaceCallback(c, rng_u64(&g) % 4 ? fuzz_surface : NULL, &fuzz_surf);
            break;
        case 23: { /* a state file written or read: bad paths, this cloth's file or the other's (another
                    * size: refused), arrays full, none or of negative count */
            const char *paths[] = {NULL, "", "plugin_fuzz_api_no_dir/x.state", ".", STATE_FILE[ci], STATE_FILE[1 - ci]};
            /* the paths in turn, each written then read (every bad one reached) */
            unsigned k = (unsigned)(file_calls % 8);
            int writing = (int)(file_calls++ / 8 % 2);
            const char *path = paths[k < 4 ? k : k < 7 ? 4 : 5];
            dGeomID geoms[] = {s->plane, s->box, s->mesh, s->sph, s->cap};
            dBodyID bodies[] = {s->ball, s->kin};
            /* a missing directory and a directory as the path get whole arrays: only
             * the path can then be at fault, whatever the cloth touches */
            unsigned a = (unsigned)(rng_u64(&g) % 6);
            if (k == 2 || k == 3) a = 2 + a % 4;
            int ng = a == 0 ? 0 : a == 1 ? xi(&g) : 5, nb = a == 0 ? 0 : a == 1 ? xi(&g) : 2;
            if (ng > 5) ng = 5;
            if (nb > 2) nb = 2;
            blob file = read_all(path && path[0] ? path : STATE_FILE[ci]);
            st = writing ? dClothWriteState(c, path, a ? geoms : NULL, ng, a ? bodies : NULL, nb)
                         : dClothReadState(c, path, a ? geoms : NULL, ng, a ? bodies : NULL, nb);
            /* NULL and empty paths are named before negative counts, the rest after */
            const char *field = k < 2 || (k < 4 && ng >= 0 && nb >= 0) ? "path" : ng < 0 || nb < 0 ? "ngeoms" : NULL;
            if (k < 4 && !strcmp(field, "path")) bad_paths[k][writing]++;
            if (field)
                CHECK(st == CLOTH_EINVAL && strstr(dClothGetLastError(c), field),
                      "call %d: %s with path %s%s%s: status %d, \"%s\"", it, writing ? "write" : "read",
                      path ? "\"" : "", path ? path : "NULL", path ? "\"" : "", (int)st, dClothGetLastError(c));
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
            break;
        }
        case 24: { /* asleep or not, and woken: the core untouched */
            int was = dClothIsSleeping(c);
            CHECK(was == 0 || was == 1, "call %d: dClothIsSleeping gave %d", it, was);
            if (rng_u64(&g) % 2) {
                dClothWake(c);
                cloth_save(core, after);
                CHECK(!dClothIsSleeping(c) && cloth_state_diff(before, after) == 0.0,
                      "call %d: dClothWake left it asleep or changed the cloth", it);
            }
            break;
        }
        case 25: { /* triangle tests as case 17 left them, for none, a geom it sets, or one it never does */
            unsigned k = (unsigned)(rng_u64(&g) % 5);
            dGeomID gg = k == 0 ? 0 : k == 1 ? s->box : k == 2 ? s->mesh : k == 3 ? s->sph : s->cap;
            int on = dClothGetTriangleTests(c, gg), edges = dClothGetEdgeTests(c, gg);
            CHECK(on == (gg ? tri_on[ci][k] : 0), "call %d: dClothGetTriangleTests of geom %u gave %d", it, k, on);
            CHECK(edges == (gg ? edge_on[ci][k] : 0), "call %d: dClothGetEdgeTests of geom %u gave %d", it, k, edges);
            CHECK(dClothGetExactTriangleTests(c, gg) == (gg ? exact_on[ci][k] : 0),
                  "call %d: dClothGetExactTriangleTests of geom %u gave %d", it, k, dClothGetExactTriangleTests(c, gg));
            break;
        }
        case 19: /* hold or stop on a failed step, or a mode that does not exist */
            st = dClothSetFailureMode(c, (dClothFailureMode)(rng_u64(&g) % 4 ? (int)(rng_u64(&g) % 2) : xi(&g)));
            break;
        default: {
            double h = rng_u64(&g) % 5 ? rng_range(&g, 1e-3, 0.03) : xd(&g);
            if (h > 0.1 && isfinite(h)) h = 0.1;
            st = dClothStep(c, h);
            is_step = 1;
            if (st == CLOTH_OK) steps_ok++;
            else steps_fail++;
            if (getenv("FUZZ_DEBUG") && st != CLOTH_OK) printf("step h=%g: %s\n", h, dClothGetLastError(c));
            break;
        }
        }
        ncalls++;
        CHECK(status_ok(st), "call %d (op %d): status %d", it, op, (int)st);
        for (int k = 0; k < 2; k++)
            CHECK(finite_all(dClothGetPositions(cl[k]), 3 * (size_t)dClothGetVertexCount(cl[k])),
                  "call %d (op %d, %s): NaN/inf in cloth %d", it, op, cloth_status_string(st), k);
        body_save(s->ball, &b1[0]);
        body_save(s->kin, &b1[1]);
        CHECK(finite_all(b1[0].pos, 3) && finite_all(b1[0].lv, 3), "call %d (op %d): the ball is not finite", it, op);
        if (st != CLOTH_OK) {
            nfail++;
            CHECK(dClothGetLastError(c)[0] != '\0' || is_step == 2, "call %d (op %d): failure without a message", it,
                  op);
            cloth_save(core, after);
            CHECK(cloth_state_diff(before, after) == 0.0, "call %d (op %d, %s): the cloth changed", it, op,
                  cloth_status_string(st));
            if (is_step == 2) { /* dClothWorldStep is all or nothing: the other cloth too */
                cloth *oc = dClothGetCore(cl[1 - ci]);
                cloth_state *oa = cloth_state_create(oc);
                cloth_save(oc, oa);
                CHECK(cloth_state_diff(other_before, oa) == 0.0,
                      "call %d: a failed dClothWorldStep moved the other "
                      "cloth",
                      it);
                cloth_state_destroy(oa);
            }
            CHECK(memcmp(b0, b1, sizeof b0) == 0, "call %d (op %d, %s): a body changed", it, op,
                  cloth_status_string(st));
        }
        cloth_state_destroy(before);
        cloth_state_destroy(after);
        cloth_state_destroy(other_before);
        if (it % 25 == 24) { /* keep the scene sane: the ball back, settings back */
            dBodySetPosition(s->ball, -0.2, 0.1, 0.6);
            dBodySetLinearVel(s->ball, 0, 0, 0);
            dBodySetAngularVel(s->ball, 0, 0, 0);
            for (int k = 0; k < 2; k++) {
                for (int i = 0; i < dClothGetVertexCount(cl[k]); i++) dClothReleasePin(cl[k], i);
                dClothSetFriction(cl[k], 0.3);
                dClothSetThickness(cl[k], 0.005);
                dClothSetSpace(cl[k], s->space);
            }
        }
    }
    printf("random walk: %ld calls, %ld refused or failed; dClothStep %ld ok, %ld failed\n", ncalls, nfail, steps_ok,
           steps_fail);
    printf("state files: %ld written, %ld read, %ld refused\n", files_written, files_read, files_refused);
    CHECK(files_written > 0 && files_read > 0 && files_refused > 0, "the state file calls do not reach every outcome");
    for (int k = 0; k < 8; k++)
        CHECK(bad_paths[k / 2][k % 2] > 0, "bad path %d never %s", k / 2, k % 2 ? "written" : "read");
    remove(STATE_FILE[0]);
    remove(STATE_FILE[1]);
    CHECK(steps_ok > 50, "too few successful steps (%ld) for the walk to mean much", steps_ok);
    dClothDestroy(cl[0]);
    dClothDestroy(cl[1]);
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
