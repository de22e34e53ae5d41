/* The plugin's API contract (plugin/include/odecloth/dcloth.h): collision
 * filtering, the cloth's invisibility to the user's own collision callback,
 * bad input, geoms destroyed between steps, and what is handed out for
 * drawing (normals, triangles).
 *
 *  1. Collision filtering. A default 21 x 21, 1 m cloth, unpinned, falls
 *     from z = 1 onto a static 0.4 x 0.4 x 0.2 m box whose top is at
 *     z = 0.8, for 1 s at h = 1/60 (the box is reached after 0.2 s; a cloth
 *     that misses it is 3.9 m lower after 1 s). Outcomes, by where the box is
 *     and by the bits (dcloth.h: a geom meets the cloth iff
 *     (cloth.collide & geom.category) or (geom.collide & cloth.category)):
 *       - in the cloth's space, default bits: stopped (control);
 *       - cloth category = collide = 1, box category = collide = 2: neither
 *         side meets, so the box is never a candidate (stats.candidates 0 in
 *         every step) and the cloth falls through;
 *       - one side meeting (box collide 1 or box category 1) is enough:
 *         stopped;
 *       - inside a simple space nested in the cloth's hash space: stopped;
 *         nested with the non-meeting bits: falls through;
 *       - after dClothSetSpace(c, 0): falls through.
 *     "Stopped" means: after 1 s the centre vertex is above the box top by at
 *     least half the thickness (and less than 5 cm), and its contact pushes it
 *     up (dClothGetContactForce z > 0: it rests); "falls through":
 *     the centre vertex is below the box's bottom (z = 0.6).
 *  2. The cloth's collision proxies are in no space: while a cloth drapes
 *     over a static box, next to a dynamic box resting on a ground plane and
 *     a sphere in a nested space, the user's own dSpaceCollide (recursing
 *     into nested spaces the usual way, and creating contact joints for the
 *     body) sees only the user's geoms, whether called between dClothStep
 *     and dWorldStep or after dWorldStep; the space's geom count never
 *     changes.
 *  3. Bad input returns an error, sets the message and changes nothing:
 *     dClothCreate (NULL out, world, desc; thickness <= 0 / NaN / inf; mu < 0
 *     / NaN / inf; an invalid core descriptor); dClothStep with h 0, -1, NaN,
 *     +-inf (CLOTH_EINVAL, positions and velocities unchanged bit for bit, no
 *     force on any body); dClothWorldStep with a bad h, a NULL cloth, n < 0 or
 *     no world (CLOTH_EINVAL, the world not stepped); pins with vertex -1 or
 *     n, a NULL / NaN / inf point, a NULL body, a body of another world (an
 *     existing pin on that vertex stays, and no pin is added); release, pin
 *     force, contact force with bad vertices or NULL outputs; friction and
 *     thickness out of range (the value stays); dClothGetNormals(c, NULL).
 *     Each message is checked to come from the failing call: before it,
 *     another failing call (dClothSetFriction, or dClothSetThickness when
 *     dClothSetFriction is checked) sets a different message. (No dCloth
 *     function takes a geom; geoms reach the cloth only through the space,
 *     see 5.)
 *  4. A NULL dClothID is refused (or a harmless no-op, or 0 / NULL) by every
 *     function.
 *  5. A geom (static, and one on a 50 kg body held by a fixed joint)
 *     destroyed between steps while the cloth rests on it (after 1 s the
 *     centre vertex is within 1 mm of the top + thickness and its contact
 *     pushes it up): the following steps succeed (and, under ASan, touch no
 *     freed memory), the geom is no candidate any more, and 1 s later the
 *     cloth has fallen through where the geom was.
 *  6. Normals and triangles of a flat cloth: every vertex normal is the
 *     plane's normal axis_u x axis_v (to 1e-12; its negative when axis_v is
 *     reversed), for the default cloth and for a tilted 7 x 11, 2 x 1.2 m one;
 *     there are 2 (R-1)(C-1) triangles, each inside one grid cell, two per
 *     cell, all counter-clockwise seen from axis_u x axis_v, their areas
 *     summing to width x height (1e-12 relative); every interior edge is
 *     shared by exactly two triangles, in opposite directions (consistent
 *     winding), every boundary edge belongs to one.
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "odecloth/dcloth.h"
#include "check.h"
#include "body_state.h"

static const double H = 1.0 / 60;

/* ---------------------------------------------------------------- helpers */

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int centre_vertex(dClothID c)
{
    const cloth *k = dClothGetCore(c);
    return (cloth_rows(k) / 2) * cloth_cols(k) + cloth_cols(k) / 2;
}

static int has_text(const char *s, const char *part) { return s && part && strstr(s, part) != NULL; }

/* Make the cloth's last error a known message that the call checked next
 * does not write: dClothSetFriction's, or dClothSetThickness's when
 * dClothSetFriction itself is checked. */
static void prime_error_with(dClothID c, int thickness)
{
    cloth_status s = thickness ? dClothSetThickness(c, -1.0) : dClothSetFriction(c, -1.0);
    const char *fn = thickness ? "dClothSetThickness" : "dClothSetFriction";
    CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), fn), "priming the error message failed: status %d, '%s'",
          s, dClothGetLastError(c));
}

static void prime_error(dClothID c) { prime_error_with(c, 0); }

/* ------------------------------------------------------ 1. filtering */

enum outcome { STOPPED, FALLS };

typedef struct drop_case {
    const char *name;
    int nested; /* the box inside a simple space inside the cloth's space */
    unsigned long cloth_cat, cloth_col, box_cat, box_col;
    int no_space; /* dClothSetSpace(c, 0) after creation */
    enum outcome expect;
} drop_case;

static void drop_on_box(const drop_case *k)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID top = dHashSpaceCreate(0), inner = 0, where = top;
    if (k->nested) {
        inner = dSimpleSpaceCreate(top);
        where = inner;
    }
    dGeomID box = dCreateBox(where, 0.4, 0.4, 0.2);
    dGeomSetPosition(box, 0, 0, 0.7);
    dGeomSetCategoryBits(box, k->box_cat);
    dGeomSetCollideBits(box, k->box_col);

    dClothDesc d = dClothDefaultDesc();
    d.category_bits = k->cloth_cat;
    d.collide_bits = k->cloth_col;
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, top, &d, &c, &err) == CLOTH_OK, "%s: dClothCreate: %s", k->name, err.message)) {
        dSpaceDestroy(top);
        dWorldDestroy(w);
        return;
    }
    CHECK(dClothGetCategoryBits(c) == k->cloth_cat && dClothGetCollideBits(c) == k->cloth_col,
          "%s: bits read back %lx / %lx, set %lx / %lx", k->name, dClothGetCategoryBits(c), dClothGetCollideBits(c),
          k->cloth_cat, k->cloth_col);
    if (k->no_space) dClothSetSpace(c, 0);

    int steps = (int)(1.0 / H + 0.5), failed = 0, max_cand = 0, max_contacts = 0;
    for (int s = 1; s <= steps && !failed; s++) {
        if (!CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "%s: step %d: %s", k->name, s, dClothGetLastError(c)))
            failed = 1;
        const dClothStepStats *st = dClothGetStats(c);
        if (st->candidates > max_cand) max_cand = st->candidates;
        if (st->contacts > max_contacts) max_contacts = st->contacts;
    }
    int ic = centre_vertex(c);
    double zc = dClothGetPositions(c)[3 * ic + 2], top_z = 0.8, bottom_z = 0.6;
    dReal f[3];
    dClothGetContactForce(c, ic, f);
    printf("%-44s centre z %+8.4f, max candidates %d, max contacts %3d, centre contact force z %.4f N\n", k->name, zc,
           max_cand, max_contacts, f[2]);
    if (k->expect == STOPPED) {
        CHECK(zc >= top_z + 0.5 * d.thickness && zc < top_z + 0.05,
              "%s: the box did not stop the cloth: centre at z = %.4f (box top %.2f, thickness %.3f)", k->name, zc,
              top_z, d.thickness);
        CHECK(max_cand >= 1 && f[2] > 0.0,
              "%s: the centre vertex does not rest on a contact: %d candidates, its contact force z %.3g N (resting, "
              "it is pushed up by about its weight, 4.9e-3 N)",
              k->name, max_cand, f[2]);
    } else {
        CHECK(zc < bottom_z, "%s: the cloth should have fallen through the box: centre at z = %.4f", k->name, zc);
        CHECK(max_cand == 0 && max_contacts == 0, "%s: the box was a candidate (%d) or touched (%d contacts)", k->name,
              max_cand, max_contacts);
    }
    dClothDestroy(c);
    dSpaceDestroy(top); /* destroys the nested space and the box (cleanup mode) */
    dWorldDestroy(w);
}

static void test_filtering(void)
{
    const unsigned long ALL = ~0ul;
    const drop_case cases[] = {
        {"top space, default bits", 0, ALL, ALL, ALL, ALL, 0, STOPPED},
        {"top space, bits do not meet", 0, 1, 1, 2, 2, 0, FALLS},
        {"top space, only box.collide meets cloth.cat", 0, 1, 1, 2, 1, 0, STOPPED},
        {"top space, only cloth.collide meets box.cat", 0, 1, 1, 1, 0, 0, STOPPED},
        {"nested space, default bits", 1, ALL, ALL, ALL, ALL, 0, STOPPED},
        {"nested space, bits do not meet", 1, 1, 1, 2, 2, 0, FALLS},
        {"no space (dClothSetSpace(c, 0))", 0, ALL, ALL, ALL, ALL, 1, FALLS},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) drop_on_box(&cases[i]);

    /* the setters */
    dWorldID w = dWorldCreate();
    dClothDesc d = dClothDefaultDesc();
    dClothID c = NULL;
    if (CHECK(dClothCreate(w, 0, &d, &c, NULL) == CLOTH_OK, "dClothCreate with err NULL failed")) {
        CHECK(dClothGetCategoryBits(c) == ~0ul && dClothGetCollideBits(c) == ~0ul,
              "default bits %lx / %lx, expected all set", dClothGetCategoryBits(c), dClothGetCollideBits(c));
        dClothSetCategoryBits(c, 0x5ul);
        dClothSetCollideBits(c, 0xa0ul);
        CHECK(dClothGetCategoryBits(c) == 0x5ul && dClothGetCollideBits(c) == 0xa0ul,
              "bits read back %lx / %lx, set 5 / a0", dClothGetCategoryBits(c), dClothGetCollideBits(c));
        dClothDestroy(c);
    }
    dWorldDestroy(w);
}

/* ------------------------------------------ 2. the user's own callback */

typedef struct user_scene {
    dWorldID world;
    dJointGroupID contacts;
    dGeomID mine[8];
    int nmine;
    int make_joints; /* 0: only look (the call before dClothStep) */
    long pairs, foreign;
} user_scene;

static int is_mine(const user_scene *u, dGeomID g)
{
    for (int i = 0; i < u->nmine; i++)
        if (u->mine[i] == g) return 1;
    return 0;
}

static void user_near(void *data, dGeomID o1, dGeomID o2)
{
    user_scene *u = data;
    if (dGeomIsSpace(o1) || dGeomIsSpace(o2)) {
        if (!is_mine(u, o1) || !is_mine(u, o2)) u->foreign++;
        dSpaceCollide2(o1, o2, u, user_near);
        return;
    }
    u->pairs++;
    if (!is_mine(u, o1) || !is_mine(u, o2)) {
        if (u->foreign++ < 3)
            CHECK(0, "the user's callback met a geom that is not the user's: %p (class %d) / %p (class %d)", (void *)o1,
                  dGeomGetClass(o1), (void *)o2, dGeomGetClass(o2));
        return;
    }
    dContact ct[4];
    dBodyID b1 = dGeomGetBody(o1), b2 = dGeomGetBody(o2);
    if (!u->make_joints || (!b1 && !b2)) return;
    int n = dCollide(o1, o2, 4, &ct[0].geom, sizeof ct[0]);
    for (int i = 0; i < n; i++) {
        ct[i].surface.mode = 0;
        ct[i].surface.mu = 0.5;
        dJointID j = dJointCreateContact(u->world, u->contacts, &ct[i]);
        dJointAttach(j, b1, b2);
    }
}

static void test_user_callback(void)
{
    user_scene u;
    memset(&u, 0, sizeof u);
    u.world = dWorldCreate();
    dWorldSetGravity(u.world, 0, 0, -9.81);
    u.contacts = dJointGroupCreate(0);
    dSpaceID top = dHashSpaceCreate(0), inner = dSimpleSpaceCreate(top);
    dGeomID ground = dCreatePlane(top, 0, 0, 1, 0);
    dGeomID table = dCreateBox(top, 0.4, 0.4, 0.2); /* static, under the cloth */
    dGeomSetPosition(table, 0, 0, 0.7);
    dGeomID crate = dCreateBox(top, 0.3, 0.3, 0.6); /* dynamic, on the ground, under the cloth's corner */
    dBodyID crate_body = dBodyCreate(u.world);
    dMass m;
    dMassSetBoxTotal(&m, 2.0, 0.3, 0.3, 0.6);
    dBodySetMass(crate_body, &m);
    dGeomSetBody(crate, crate_body);
    dBodySetPosition(crate_body, 0.45, 0.45, 0.3);
    dGeomID ball = dCreateSphere(inner, 0.1); /* static, nested, under another corner */
    dGeomSetPosition(ball, -0.4, -0.4, 0.6);
    dGeomID mine[] = {(dGeomID)top, (dGeomID)inner, ground, table, crate, ball};
    u.nmine = (int)(sizeof mine / sizeof mine[0]);
    memcpy(u.mine, mine, sizeof mine);
    int ngeoms = dSpaceGetNumGeoms(top), ninner = dSpaceGetNumGeoms(inner);

    dClothDesc d = dClothDefaultDesc();
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(u.world, top, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) {
        dJointGroupDestroy(u.contacts);
        dSpaceDestroy(top);
        dWorldDestroy(u.world);
        return;
    }
    CHECK(dSpaceGetNumGeoms(top) == ngeoms && dSpaceGetNumGeoms(inner) == ninner,
          "dClothCreate changed the space: %d / %d geoms, was %d / %d", dSpaceGetNumGeoms(top),
          dSpaceGetNumGeoms(inner), ngeoms, ninner);
    int steps = (int)(1.5 / H + 0.5), count_bad = 0, max_cand = 0, max_contacts = 0;
    for (int s = 1; s <= steps; s++) {
        u.make_joints = 0;
        dSpaceCollide(top, &u, user_near); /* before the cloth's step: look only */
        if (!CHECK(dClothStep(c, H) == CLOTH_OK, "step %d: %s", s, dClothGetLastError(c))) break;
        if (dClothGetStats(c)->candidates > max_cand) max_cand = dClothGetStats(c)->candidates;
        if (dClothGetStats(c)->contacts > max_contacts) max_contacts = dClothGetStats(c)->contacts;
        long before = u.pairs;
        u.make_joints = 1;
        dSpaceCollide(top, &u, user_near); /* between dClothStep and dWorldStep: the contact joints */
        if (s == 1) CHECK(u.pairs > before, "the user's callback saw no pair between dClothStep and dWorldStep");
        dWorldStep(u.world, H);
        dJointGroupEmpty(u.contacts);
        if ((dSpaceGetNumGeoms(top) != ngeoms || dSpaceGetNumGeoms(inner) != ninner) && count_bad++ < 3)
            CHECK(0, "step %d: the space holds %d / %d geoms, was %d / %d", s, dSpaceGetNumGeoms(top),
                  dSpaceGetNumGeoms(inner), ngeoms, ninner);
    }
    printf("user callback: %ld pairs seen, %ld foreign; the cloth met up to %d candidates, %d contacts\n", u.pairs,
           u.foreign, max_cand, max_contacts);
    CHECK(u.foreign == 0, "the user's callback met %ld foreign geoms or spaces", u.foreign);
    CHECK(u.pairs >= steps, "the user's callback saw only %ld pairs in %d calls (the crate rests on the ground)",
          u.pairs, 2 * steps);
    /* the cloth did meet the user's geoms, and the crate stayed on the ground */
    CHECK(max_cand >= 3 && max_contacts > 0,
          "the cloth met %d candidates, %d contacts: expected the table, the "
          "crate and the ball",
          max_cand, max_contacts);
    CHECK(fabs(dBodyGetPosition(crate_body)[2] - 0.3) < 0.01, "the crate is at z = %.4f, not resting on the ground",
          dBodyGetPosition(crate_body)[2]);
    dClothDestroy(c);
    dJointGroupDestroy(u.contacts);
    dSpaceDestroy(top);
    dWorldDestroy(u.world);
}

/* ---------------------------------------------------------- 3. bad input */

static void test_create_bad_input(void)
{
    dWorldID w = dWorldCreate();
    dClothDesc good = dClothDefaultDesc();
    dClothID sentinel = (dClothID)&good, c;
    cloth_error err;

    CHECK(dClothCreate(w, 0, &good, NULL, &err) == CLOTH_EINVAL && err.code == CLOTH_EINVAL && err.message[0],
          "dClothCreate with out NULL: status %d, '%s'", err.code, err.message);

    struct {
        const char *name;
        int null_world, null_desc;
        double thickness, mu;
        int bad_rows;
    } bad[] = {
        {"world 0", 1, 0, 0.005, 0.3, 0},     {"desc NULL", 0, 1, 0.005, 0.3, 0},
        {"thickness 0", 0, 0, 0.0, 0.3, 0},   {"thickness -1 mm", 0, 0, -0.001, 0.3, 0},
        {"thickness NaN", 0, 0, NAN, 0.3, 0}, {"thickness inf", 0, 0, INFINITY, 0.3, 0},
        {"mu -0.1", 0, 0, 0.005, -0.1, 0},    {"mu NaN", 0, 0, 0.005, NAN, 0},
        {"mu inf", 0, 0, 0.005, INFINITY, 0}, {"rows 2 (core descriptor)", 0, 0, 0.005, 0.3, 1},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        dClothDesc d = good;
        d.thickness = bad[i].thickness;
        d.mu = bad[i].mu;
        if (bad[i].bad_rows) d.cloth.rows = 2;
        c = sentinel;
        memset(&err, 0, sizeof err);
        err.code = CLOTH_OK;
        cloth_status s = dClothCreate(bad[i].null_world ? 0 : w, 0, bad[i].null_desc ? NULL : &d, &c, &err);
        CHECK(s == CLOTH_EINVAL && err.code == CLOTH_EINVAL && c == NULL && err.message[0] != '\0',
              "dClothCreate with %s: status %d, err.code %d, out %p, message '%s'", bad[i].name, s, err.code, (void *)c,
              err.message);
        /* err may be NULL */
        c = sentinel;
        s = dClothCreate(bad[i].null_world ? 0 : w, 0, bad[i].null_desc ? NULL : &d, &c, NULL);
        CHECK(s == CLOTH_EINVAL && c == NULL, "dClothCreate with %s and err NULL: status %d, out %p", bad[i].name, s,
              (void *)c);
    }
    /* a geom that is not a space, where a space belongs */
    dSpaceID sp = dHashSpaceCreate(0);
    dGeomID ball = dCreateSphere(sp, 0.1);
    c = sentinel;
    cloth_status s = dClothCreate(w, (dSpaceID)ball, &good, &c, &err);
    CHECK(s == CLOTH_EINVAL && c == NULL && strstr(err.message, "space") != NULL,
          "dClothCreate with a sphere as the space: status %d, out %p, message '%s'", s, (void *)c, err.message);
    if (CHECK(dClothCreate(w, sp, &good, &c, &err) == CLOTH_OK, "create: %s", err.message)) {
        s = dClothSetSpace(c, (dSpaceID)ball);
        CHECK(s == CLOTH_EINVAL && strstr(dClothGetLastError(c), "space") != NULL,
              "dClothSetSpace with a sphere: status %d, message '%s'", s, dClothGetLastError(c));
        CHECK(dClothStep(c, H) == CLOTH_OK, "a step after the refused space: %s", dClothGetLastError(c));
        CHECK(dClothSetSpace(c, 0) == CLOTH_OK && dClothSetSpace(c, sp) == CLOTH_OK, "setting spaces");
        dClothDestroy(c);
    }
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

/* The state a failed call must leave alone. */
typedef struct snapshot {
    int n;
    double *x, *v;
    dReal body_pos[3], body_vel[3];
} snapshot;

static void snap(snapshot *s, dClothID c, dBodyID b)
{
    s->n = dClothGetVertexCount(c);
    size_t bytes = 3 * (size_t)s->n * sizeof(double);
    if (!s->x) s->x = malloc(bytes);
    if (!s->v) s->v = malloc(bytes);
    memcpy(s->x, cloth_positions(dClothGetCore(c)), bytes);
    memcpy(s->v, cloth_velocities(dClothGetCore(c)), bytes);
    memcpy(s->body_pos, dBodyGetPosition(b), sizeof s->body_pos);
    memcpy(s->body_vel, dBodyGetLinearVel(b), sizeof s->body_vel);
}

static int same_cloth(const snapshot *s, dClothID c)
{
    size_t bytes = 3 * (size_t)s->n * sizeof(double);
    return memcmp(s->x, cloth_positions(dClothGetCore(c)), bytes) == 0 &&
           memcmp(s->v, cloth_velocities(dClothGetCore(c)), bytes) == 0;
}

static int same_body(const snapshot *s, dBodyID b)
{
    return memcmp(s->body_pos, dBodyGetPosition(b), sizeof s->body_pos) == 0 &&
           memcmp(s->body_vel, dBodyGetLinearVel(b), sizeof s->body_vel) == 0;
}

static int no_force(dBodyID b)
{
    const dReal *f = dBodyGetForce(b), *t = dBodyGetTorque(b);
    return f[0] == 0 && f[1] == 0 && f[2] == 0 && t[0] == 0 && t[1] == 0 && t[2] == 0;
}

/* A warmed-up cloth with a body pinned to corner 0 and a world pin at the
 * other corner of row 0, and a snapshot of both that failed calls keep. */
typedef struct pinned_cloth {
    dWorldID w, w2;
    dSpaceID sp;
    dClothDesc d;
    dClothID c;
    dBodyID b;
    int n, C;
    dReal zero[3], wp[3]; /* the body pin's point on the body, the world pin's point */
    snapshot snp;
} pinned_cloth;

/* Returns 0 (after a failed check) when the cloth cannot be created. */
static int pinned_cloth_make(pinned_cloth *p)
{
    p->w = dWorldCreate();
    p->w2 = dWorldCreate();
    dWorldSetGravity(p->w, 0, 0, -9.81);
    p->sp = dHashSpaceCreate(0);
    p->d = dClothDefaultDesc();
    p->c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(p->w, p->sp, &p->d, &p->c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) return 0;
    dClothID c = p->c;
    int n = p->n = dClothGetVertexCount(c), C = p->C = p->d.cloth.cols;
    dBodyID b = p->b = dBodyCreate(p->w);
    dMass m;
    dMassSetSphereTotal(&m, 2.0, 0.05);
    dBodySetMass(b, &m);
    const double *x0 = dClothGetPositions(c);
    dBodySetPosition(b, x0[0], x0[1], x0[2]);
    dBodySetGravityMode(b, 0);
    for (int r = 0; r < 3; r++) {
        p->zero[r] = 0;
        p->wp[r] = x0[3 * (C - 1) + r];
    }
    CHECK(dClothPinToBody(c, 0, b, p->zero) == CLOTH_OK, "dClothPinToBody: %s", dClothGetLastError(c));
    CHECK(dClothPinToWorld(c, C - 1, p->wp) == CLOTH_OK, "dClothPinToWorld: %s", dClothGetLastError(c));
    for (int s = 0; s < 20; s++)
        CHECK(dClothWorldStep(p->w, &p->c, 1, H, 0) == CLOTH_OK, "warm-up step %d: %s", s, dClothGetLastError(c));
    CHECK(dClothGetStats(c)->pins == 2, "%d pins, expected 2", dClothGetStats(c)->pins);
    dBodySetLinearVel(b, 0.1, 0, 0);

    memset(&p->snp, 0, sizeof p->snp);
    snap(&p->snp, c, b);
    int nonzero_v = 0;
    for (int i = 0; i < 3 * n; i++) nonzero_v += p->snp.v[i] != 0.0;
    CHECK(nonzero_v > n, "the warm-up left the cloth at rest: the bit-for-bit checks would be empty");
    return 1;
}

/* dClothStep and dClothWorldStep with a bad h, and dClothWorldStep with bad
 * cloth arrays, counts or world: refused before touching the cloth or the world. */
static void check_bad_step(pinned_cloth *p)
{
    dClothID c = p->c;
    dBodyID b = p->b;
    const snapshot *snp = &p->snp;
    const double bad_h[] = {0.0, -0.0, -1.0, -H, NAN, INFINITY, -INFINITY};
    const char *bad_h_name[] = {"0", "-0", "-1", "-1/60", "NaN", "inf", "-inf"};
    dClothStepStats before = *dClothGetStats(c);
    for (size_t i = 0; i < sizeof bad_h / sizeof bad_h[0]; i++) {
        prime_error(c);
        cloth_status s = dClothStep(c, bad_h[i]);
        CHECK(s == CLOTH_EINVAL, "dClothStep(h = %s) returned %d, expected CLOTH_EINVAL", bad_h_name[i], s);
        CHECK(has_text(dClothGetLastError(c), "dClothStep"), "dClothStep(h = %s): message '%s'", bad_h_name[i],
              dClothGetLastError(c));
        CHECK(same_cloth(snp, c), "dClothStep(h = %s) changed the cloth's positions or velocities", bad_h_name[i]);
        CHECK(no_force(b), "dClothStep(h = %s) applied a force or torque to the pinned body", bad_h_name[i]);
        CHECK(memcmp(&before, dClothGetStats(c), sizeof before) == 0, "dClothStep(h = %s) changed the stats",
              bad_h_name[i]);
    }
    /* dClothWorldStep: fails before touching the cloth or the world */
    for (size_t i = 0; i < sizeof bad_h / sizeof bad_h[0]; i++) {
        cloth_status s = dClothWorldStep(p->w, &p->c, 1, bad_h[i], 0);
        CHECK(s == CLOTH_EINVAL && same_cloth(snp, c) && same_body(snp, b),
              "dClothWorldStep(h = %s): status %d (expected CLOTH_EINVAL), cloth unchanged %d, body unchanged %d",
              bad_h_name[i], s, same_cloth(snp, c), same_body(snp, b));
    }
    dClothID two[2] = {c, NULL};
    cloth_status s = dClothWorldStep(p->w, two + 1, 1, H, 0);
    CHECK(s == CLOTH_EINVAL && same_body(snp, b), "dClothWorldStep({NULL}): status %d, body unchanged %d", s,
          same_body(snp, b));
    s = dClothWorldStep(p->w, NULL, 1, H, 0);
    CHECK(s == CLOTH_EINVAL && same_body(snp, b), "dClothWorldStep(cloths NULL, n 1): status %d", s);
    s = dClothWorldStep(p->w, &p->c, -1, H, 0);
    CHECK(s == CLOTH_EINVAL && same_body(snp, b) && same_cloth(snp, c), "dClothWorldStep(n -1): status %d", s);
    s = dClothWorldStep(0, &p->c, 1, H, 0);
    CHECK(s == CLOTH_EINVAL && same_cloth(snp, c), "dClothWorldStep(world 0): status %d", s);
    CHECK(no_force(b), "a failed dClothWorldStep left a force on the body");
}

/* The pin calls and the force queries with a vertex out of range. */
static void check_bad_pin_vertex(pinned_cloth *p)
{
    dClothID c = p->c;
    int n = p->n;
    cloth_status s;
    dReal ok[3] = {0, 0, 1};
    struct {
        const char *name;
        cloth_status got;
        const char *fn;
    } pin_calls[16];
    int np = 0;
    const int bad_vertex[] = {-1, n, n + 1000000};
    for (int i = 0; i < 3; i++) {
        prime_error(c);
        pin_calls[np].got = dClothPinToWorld(c, bad_vertex[i], ok);
        pin_calls[np].fn = "dClothPinToWorld";
        pin_calls[np].name = "dClothPinToWorld, vertex out of range";
        CHECK(pin_calls[np].got == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothPinToWorld"),
              "dClothPinToWorld(vertex %d): status %d, message '%s'", bad_vertex[i], pin_calls[np].got,
              dClothGetLastError(c));
        np++;
        prime_error(c);
        s = dClothPinToBody(c, bad_vertex[i], p->b, p->zero);
        CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothPinToBody"),
              "dClothPinToBody(vertex %d): status %d, message '%s'", bad_vertex[i], s, dClothGetLastError(c));
        prime_error(c);
        s = dClothReleasePin(c, bad_vertex[i]);
        CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothReleasePin"),
              "dClothReleasePin(vertex %d): status %d, message '%s'", bad_vertex[i], s, dClothGetLastError(c));
        dReal f[3] = {7, 7, 7};
        prime_error(c);
        s = dClothGetPinForce(c, bad_vertex[i], f);
        CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothGetPinForce"),
              "dClothGetPinForce(vertex %d): status %d, message '%s'", bad_vertex[i], s, dClothGetLastError(c));
        prime_error(c);
        s = dClothGetContactForce(c, bad_vertex[i], f);
        CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothGetContactForce"),
              "dClothGetContactForce(vertex %d): status %d, message '%s'", bad_vertex[i], s, dClothGetLastError(c));
    }
}

/* Bad points and bodies, on the pinned vertices themselves (0: body pin,
 * C - 1: world pin) and on a free one (the centre); NULL outputs. */
static void check_bad_pin_args(pinned_cloth *p)
{
    dClothID c = p->c;
    dBodyID b = p->b;
    cloth_status s;
    dReal pnan[3] = {0, NAN, 0}, pinf[3] = {INFINITY, 0, 0};
    dBodyID other = dBodyCreate(p->w2);
    const int targets[] = {0, p->C - 1, centre_vertex(c)};
    for (int t = 0; t < 3; t++) {
        int v = targets[t];
        const dReal *pts[] = {NULL, pnan, pinf};
        const char *pname[] = {"NULL", "NaN", "inf"};
        for (int q = 0; q < 3; q++) {
            prime_error(c);
            s = dClothPinToWorld(c, v, pts[q]);
            CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothPinToWorld"),
                  "dClothPinToWorld(vertex %d, %s point): status %d, message '%s'", v, pname[q], s,
                  dClothGetLastError(c));
            prime_error(c);
            s = dClothPinToBody(c, v, b, pts[q]);
            CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothPinToBody"),
                  "dClothPinToBody(vertex %d, %s point): status %d, message '%s'", v, pname[q], s,
                  dClothGetLastError(c));
        }
        prime_error(c);
        s = dClothPinToBody(c, v, NULL, p->zero);
        CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothPinToBody"),
              "dClothPinToBody(vertex %d, body 0): status %d, message '%s'", v, s, dClothGetLastError(c));
        prime_error(c);
        s = dClothPinToBody(c, v, other, p->zero);
        CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothPinToBody"),
              "dClothPinToBody(vertex %d, a body of another world): status %d, message '%s'", v, s,
              dClothGetLastError(c));
    }
    prime_error(c);
    s = dClothReleaseBody(c, NULL);
    CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothReleaseBody"),
          "dClothReleaseBody(body 0): status %d, message '%s'", s, dClothGetLastError(c));
    prime_error(c);
    s = dClothGetPinForce(c, 0, NULL);
    CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothGetPinForce"),
          "dClothGetPinForce(force NULL): status %d, message '%s'", s, dClothGetLastError(c));
    prime_error(c);
    s = dClothGetContactForce(c, 0, NULL);
    CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothGetContactForce"),
          "dClothGetContactForce(force NULL): status %d, message '%s'", s, dClothGetLastError(c));
    prime_error(c);
    s = dClothGetNormals(c, NULL);
    CHECK(s == CLOTH_EINVAL && has_text(dClothGetLastError(c), "dClothGetNormals"),
          "dClothGetNormals(NULL): status %d, message '%s'", s, dClothGetLastError(c));
    CHECK(same_cloth(&p->snp, c) && same_body(&p->snp, b) && no_force(b),
          "a failed pin call changed the cloth or body");
}

/* Friction and thickness out of range keep their value. */
static void check_bad_parameters(pinned_cloth *p)
{
    dClothID c = p->c;
    const dClothDesc *d = &p->d;
    cloth_status s;
    const double bad_mu[] = {-0.1, -INFINITY, NAN, INFINITY};
    for (int i = 0; i < 4; i++) {
        prime_error_with(c, 1);
        s = dClothSetFriction(c, bad_mu[i]);
        CHECK(s == CLOTH_EINVAL && dClothGetFriction(c) == d->mu &&
                  has_text(dClothGetLastError(c), "dClothSetFriction"),
              "dClothSetFriction(%g): status %d, friction now %g, message '%s'", bad_mu[i], s, dClothGetFriction(c),
              dClothGetLastError(c));
    }
    const double bad_t[] = {0.0, -0.001, NAN, INFINITY, -INFINITY, 1e300, 1e-300};
    for (int i = 0; i < 7; i++) {
        prime_error(c);
        s = dClothSetThickness(c, bad_t[i]);
        CHECK(s == CLOTH_EINVAL && dClothGetThickness(c) == d->thickness &&
                  has_text(dClothGetLastError(c), "dClothSetThickness"),
              "dClothSetThickness(%g): status %d, thickness now %g, message '%s'", bad_t[i], s, dClothGetThickness(c),
              dClothGetLastError(c));
    }
    CHECK(dClothSetFriction(c, 0.0) == CLOTH_OK && dClothGetFriction(c) == 0.0, "dClothSetFriction(0) refused");
    CHECK(dClothSetFriction(c, d->mu) == CLOTH_OK && dClothGetFriction(c) == d->mu, "dClothSetFriction(mu) refused");
}

/* Nothing was pinned, unpinned or moved by the failed calls: the next
 * step has the same two pins, the world pin holds its point, the body
 * pin follows the body, and the centre is free. */
static void check_pins_kept(pinned_cloth *p)
{
    dClothID c = p->c;
    int C = p->C;
    const dReal *wp = p->wp;
    if (CHECK(dClothWorldStep(p->w, &p->c, 1, H, 0) == CLOTH_OK, "step after the bad calls: %s",
              dClothGetLastError(c))) {
        const double *x = dClothGetPositions(c);
        const dReal *pb = dBodyGetPosition(p->b);
        dReal f[3];
        CHECK(dClothGetStats(c)->pins == 2, "%d pins after the failed pin calls, expected 2", dClothGetStats(c)->pins);
        CHECK(x[3 * (C - 1)] == wp[0] && x[3 * (C - 1) + 1] == wp[1] && x[3 * (C - 1) + 2] == wp[2],
              "the world pin moved to (%.17g, %.17g, %.17g)", x[3 * (C - 1)], x[3 * (C - 1) + 1], x[3 * (C - 1) + 2]);
        /* the pinned vertex ends where the body's point would be after h at
         * the step's start velocity; the body moved by ODE since, by a few
         * micrometres */
        double dpin = sqrt((x[0] - pb[0]) * (x[0] - pb[0]) + (x[1] - pb[1]) * (x[1] - pb[1]) +
                           (x[2] - pb[2]) * (x[2] - pb[2]));
        CHECK(dpin < 1e-3, "the body pin let go: vertex 0 is %.3g m from the body", dpin);
        dClothGetPinForce(c, centre_vertex(c), f);
        CHECK(f[0] == 0 && f[1] == 0 && f[2] == 0, "the centre vertex got pinned");
    }
}

static void test_step_and_pin_bad_input(void)
{
    pinned_cloth p;
    if (!pinned_cloth_make(&p)) return;
    check_bad_step(&p);
    check_bad_pin_vertex(&p);
    check_bad_pin_args(&p);
    check_bad_parameters(&p);
    check_pins_kept(&p);
    free(p.snp.x);
    free(p.snp.v);
    dClothDestroy(p.c);
    dSpaceDestroy(p.sp);
    dWorldDestroy(p.w2);
    dWorldDestroy(p.w);
}

/* ------------------------------------------------------ 4. NULL dClothID */

static void test_null_cloth(void)
{
    dWorldID w = dWorldCreate();
    dBodyID b = dBodyCreate(w);
    dReal p[3] = {0, 0, 0}, f[3] = {1, 2, 3}, nrm[3];
    dClothID none = NULL;
    const char *v = dClothGetVersion();
    CHECK(v && strcmp(v, cloth_version()) == 0, "dClothGetVersion() '%s' != cloth_version() '%s'", v ? v : "(null)",
          cloth_version());
    dClothDestroy(NULL);
    CHECK(dClothGetCore(NULL) == NULL, "dClothGetCore(NULL) is not NULL");
    CHECK(dClothGetLastError(NULL) != NULL && dClothGetLastError(NULL)[0] != '\0', "dClothGetLastError(NULL) empty");
    CHECK(dClothStep(NULL, H) == CLOTH_EINVAL, "dClothStep(NULL) accepted");
    CHECK(dClothWorldStep(w, &none, 1, H, 0) == CLOTH_EINVAL, "dClothWorldStep({NULL}) accepted");
    CHECK(dClothGetStats(NULL) == NULL, "dClothGetStats(NULL) is not NULL");
    CHECK(dClothGetVertexCount(NULL) == 0, "dClothGetVertexCount(NULL) is not 0");
    CHECK(dClothGetPositions(NULL) == NULL, "dClothGetPositions(NULL) is not NULL");
    CHECK(dClothGetNormals(NULL, nrm) == CLOTH_EINVAL, "dClothGetNormals(NULL, ...) accepted");
    CHECK(dClothGetTriangleCount(NULL) == 0, "dClothGetTriangleCount(NULL) is not 0");
    CHECK(dClothGetTriangles(NULL) == NULL, "dClothGetTriangles(NULL) is not NULL");
    CHECK(dClothPinToWorld(NULL, 0, p) == CLOTH_EINVAL, "dClothPinToWorld(NULL) accepted");
    CHECK(dClothPinToBody(NULL, 0, b, p) == CLOTH_EINVAL, "dClothPinToBody(NULL) accepted");
    CHECK(dClothReleasePin(NULL, 0) == CLOTH_EINVAL, "dClothReleasePin(NULL) accepted");
    CHECK(dClothReleaseBody(NULL, b) == CLOTH_EINVAL, "dClothReleaseBody(NULL) accepted");
    CHECK(dClothGetPinForce(NULL, 0, f) == CLOTH_EINVAL, "dClothGetPinForce(NULL) accepted");
    CHECK(dClothGetContactForce(NULL, 0, f) == CLOTH_EINVAL, "dClothGetContactForce(NULL) accepted");
    CHECK(dClothSetFriction(NULL, 0.3) == CLOTH_EINVAL, "dClothSetFriction(NULL) accepted");
    CHECK(dClothGetFriction(NULL) == 0.0, "dClothGetFriction(NULL) is not 0");
    CHECK(dClothSetThickness(NULL, 0.01) == CLOTH_EINVAL, "dClothSetThickness(NULL) accepted");
    CHECK(dClothGetThickness(NULL) == 0.0, "dClothGetThickness(NULL) is not 0");
    dClothSetCategoryBits(NULL, 1);
    dClothSetCollideBits(NULL, 1);
    CHECK(dClothSetSpace(NULL, 0) == CLOTH_EINVAL, "dClothSetSpace(NULL) accepted");
    CHECK(dClothAddVertexForce(NULL, 0, 1, 0, 0) == CLOTH_EINVAL, "dClothAddVertexForce(NULL) accepted");
    CHECK(dClothGetCategoryBits(NULL) == 0 && dClothGetCollideBits(NULL) == 0, "bits of NULL are not 0");
    dWorldDestroy(w);
}

/* ------------------------------------------ 5. geoms destroyed between steps */

static void test_destroyed_geom(int dynamic)
{
    const char *what = dynamic ? "a geom on a dynamic body" : "a static geom";
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dGeomID box = dCreateBox(sp, 0.4, 0.4, 0.2);
    dBodyID body = 0;
    if (dynamic) {
        /* a heavy body held up by a fixed joint, so it stays where it is */
        body = dBodyCreate(w);
        dMass m;
        dMassSetBoxTotal(&m, 50.0, 0.4, 0.4, 0.2);
        dBodySetMass(body, &m);
        dBodySetPosition(body, 0, 0, 0.7);
        dGeomSetBody(box, body);
        dJointID j = dJointCreateFixed(w, 0);
        dJointAttach(j, body, 0);
        dJointSetFixed(j);
    } else {
        dGeomSetPosition(box, 0, 0, 0.7);
    }
    dClothDesc d = dClothDefaultDesc();
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) return;
    int ic = centre_vertex(c), ok = 1;
    for (int s = 0; s < 60 && ok; s++) {
        ok = CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "%s: step %d: %s", what, s, dClothGetLastError(c));
    }
    double z_rest = dClothGetPositions(c)[3 * ic + 2];
    int contacts = dClothGetStats(c)->contacts;
    /* the box carries the cloth: the centre vertex itself may tent a millimetre
     * off the top, as the hanging sides pull, and let go now and then */
    double fz = 0.0, mg = 0.0;
    for (int i = 0; i < dClothGetVertexCount(c); i++) {
        dReal f[3];
        dClothGetContactForce(c, i, f);
        fz += f[2];
        mg += 9.81 * cloth_masses(dClothGetCore(c))[i];
    }
    printf("%s: the box carries %.4g N of the cloth's weight %.4g N\n", what, fz, mg);
    /* at rest after a second, its sides hanging from the top, the cloth puts
     * its whole weight on the box: the contact forces must carry it, to 10% */
    CHECK(fabs(z_rest - (0.8 + d.thickness)) < 1e-3 && contacts > 0 && fabs(fz - mg) <= 0.1 * mg,
          "%s: the cloth is not resting on the box: centre at z = %.4f (top + thickness = %.4f), %d contacts, "
          "contact forces' sum z %.3g N of its weight %.3g N",
          what, z_rest, 0.8 + d.thickness, contacts, fz, mg);
    /* destroy it between steps: dGeomDestroy takes it out of the space */
    dGeomDestroy(box);
    if (body) dBodyDestroy(body); /* its joint goes with it */
    int max_cand = 0;
    for (int s = 0; s < 60 && ok; s++) {
        ok = CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "%s: step %d after the geom was destroyed: %s", what, s,
                   dClothGetLastError(c));
        if (dClothGetStats(c)->candidates > max_cand) max_cand = dClothGetStats(c)->candidates;
    }
    double z_end = dClothGetPositions(c)[3 * ic + 2];
    printf("destroyed %s: centre at z %.4f with %d contacts before, z %.4f 1 s after; %d candidates after\n", what,
           z_rest, contacts, z_end, max_cand);
    CHECK(z_end < 0.6 && max_cand == 0,
          "%s destroyed: the cloth did not fall through (centre at z = %.4f, %d "
          "candidates)",
          what, z_end, max_cand);
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

/* --------------------------------------------- 6. normals and triangles */

static void cross(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static int cmp_edge(const void *a, const void *b)
{
    const long *p = a, *q = b;
    return (p[0] > q[0]) - (p[0] < q[0]) ? (p[0] > q[0]) - (p[0] < q[0]) : (p[1] > q[1]) - (p[1] < q[1]);
}

static void check_mesh(const char *name, const dClothDesc *d, const double expect_n[3])
{
    dWorldID w = dWorldCreate();
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, 0, d, &c, &err) == CLOTH_OK, "%s: dClothCreate: %s", name, err.message)) {
        dWorldDestroy(w);
        return;
    }
    int R = d->cloth.rows, C = d->cloth.cols, n = dClothGetVertexCount(c), nt = dClothGetTriangleCount(c);
    CHECK(n == R * C, "%s: %d vertices, expected %d", name, n, R * C);
    CHECK(nt == 2 * (R - 1) * (C - 1), "%s: %d triangles, expected %d", name, nt, 2 * (R - 1) * (C - 1));
    const double *x = dClothGetPositions(c);
    const int *t = dClothGetTriangles(c);

    dReal *nrm = malloc(3 * (size_t)n * sizeof *nrm);
    CHECK(dClothGetNormals(c, nrm) == CLOTH_OK, "%s: dClothGetNormals: %s", name, dClothGetLastError(c));
    double worst = 0;
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(nrm[3 * i + k] - expect_n[k]));
    CHECK(worst <= 1e-12, "%s: a vertex normal is %.3g off (%g, %g, %g)", name, worst, expect_n[0], expect_n[1],
          expect_n[2]);

    int *per_cell = calloc((size_t)(R - 1) * (C - 1), sizeof *per_cell);
    double *cell_area = calloc((size_t)(R - 1) * (C - 1), sizeof *cell_area);
    long *edges = malloc(3 * (size_t)nt * 2 * sizeof *edges);
    int bad_index = 0, bad_cell = 0, bad_wind = 0;
    double area = 0;
    for (int q = 0; q < nt; q++) {
        const int *p = t + 3 * q;
        int rmin = R, rmax = -1, cmin = C, cmax = -1, inrange = 1;
        for (int k = 0; k < 3; k++) {
            if (p[k] < 0 || p[k] >= n) inrange = 0;
            rmin = p[k] / C < rmin ? p[k] / C : rmin;
            rmax = p[k] / C > rmax ? p[k] / C : rmax;
            cmin = p[k] % C < cmin ? p[k] % C : cmin;
            cmax = p[k] % C > cmax ? p[k] % C : cmax;
        }
        if (!inrange || p[0] == p[1] || p[1] == p[2] || p[0] == p[2]) {
            if (bad_index++ < 3) CHECK(0, "%s: triangle %d has vertices %d %d %d", name, q, p[0], p[1], p[2]);
            continue;
        }
        if (rmax - rmin != 1 || cmax - cmin != 1) {
            if (bad_cell++ < 3)
                CHECK(0, "%s: triangle %d (%d %d %d) is not inside one cell", name, q, p[0], p[1], p[2]);
            continue;
        }
        const double *a = x + 3 * p[0], *b = x + 3 * p[1], *e = x + 3 * p[2];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {e[0] - a[0], e[1] - a[1], e[2] - a[2]}, cr[3];
        cross(e1, e2, cr);
        double signed_area = 0.5 * (cr[0] * expect_n[0] + cr[1] * expect_n[1] + cr[2] * expect_n[2]);
        if (!(signed_area > 0) && bad_wind++ < 3)
            CHECK(0, "%s: triangle %d (%d %d %d) is clockwise seen from the normal (signed area %g)", name, q, p[0],
                  p[1], p[2], signed_area);
        area += signed_area;
        per_cell[rmin * (C - 1) + cmin]++;
        cell_area[rmin * (C - 1) + cmin] += signed_area;
        for (int k = 0; k < 3; k++) {
            edges[2 * (3 * q + k)] = p[k];
            edges[2 * (3 * q + k) + 1] = p[(k + 1) % 3];
        }
    }
    CHECK(bad_index == 0 && bad_cell == 0 && bad_wind == 0,
          "%s: %d triangles with bad indices, %d across cells, %d clockwise", name, bad_index, bad_cell, bad_wind);
    double W = d->cloth.width, Hh = d->cloth.height, cell = W / (C - 1) * Hh / (R - 1);
    CHECK_REL(area, W * Hh, 1e-12, 0.0);
    int bad_count = 0;
    double cell_err = 0;
    for (int k = 0; k < (R - 1) * (C - 1); k++) {
        bad_count += per_cell[k] != 2;
        cell_err = fmax(cell_err, fabs(cell_area[k] - cell) / cell);
    }
    CHECK(bad_count == 0 && cell_err <= 1e-12, "%s: %d cells not covered by exactly 2 triangles; cell area off by %.3g",
          name, bad_count, cell_err);

    /* edges: each directed edge once; an undirected edge in two triangles
     * appears once each way (consistent winding), a boundary edge once */
    int ne = 3 * nt;
    if (bad_index == 0 && bad_cell == 0) {
        qsort(edges, (size_t)ne, 2 * sizeof *edges, cmp_edge);
        int dup = 0, unpaired = 0, boundary_expected = 2 * (R - 1) + 2 * (C - 1), boundary = 0;
        for (int e = 0; e + 1 < ne; e++)
            if (edges[2 * e] == edges[2 * e + 2] && edges[2 * e + 1] == edges[2 * e + 3]) dup++;
        for (int e = 0; e < ne; e++) {
            long rev[2] = {edges[2 * e + 1], edges[2 * e]};
            if (!bsearch(rev, edges, (size_t)ne, 2 * sizeof *edges, cmp_edge)) {
                unpaired++;
                int i = (int)edges[2 * e], j = (int)edges[2 * e + 1], ri = i / C, ci = i % C, rj = j / C, cj = j % C;
                int on_boundary = (ri == rj && (ri == 0 || ri == R - 1)) || (ci == cj && (ci == 0 || ci == C - 1));
                boundary += on_boundary;
            }
        }
        CHECK(dup == 0, "%s: %d directed edges appear twice (inconsistent winding)", name, dup);
        CHECK(unpaired == boundary_expected && boundary == boundary_expected,
              "%s: %d edges without a reversed twin, %d of them on the boundary; expected exactly the %d boundary "
              "edges",
              name, unpaired, boundary, boundary_expected);
    }
    printf("%s: %d triangles, area %.15g (w h = %.15g), worst normal error %.3g\n", name, nt, area, W * Hh, worst);
    free(edges);
    free(per_cell);
    free(cell_area);
    free(nrm);
    dClothDestroy(c);
    dWorldDestroy(w);
}

static void test_mesh(void)
{
    dClothDesc d = dClothDefaultDesc();
    const double up[3] = {0, 0, 1}, down[3] = {0, 0, -1};
    check_mesh("default cloth", &d, up);

    /* axis_v reversed: the normal flips */
    dClothDesc f = d;
    f.cloth.axis_v[1] = -1.0;
    f.cloth.origin[1] = 0.5;
    check_mesh("default cloth, axis_v = -y", &f, down);

    /* tilted by 30 degrees about x, not square, rows != cols */
    dClothDesc t = d;
    double a = 30.0 * 3.14159265358979323846 / 180.0;
    t.cloth.rows = 7;
    t.cloth.cols = 11;
    t.cloth.width = 2.0;
    t.cloth.height = 1.2;
    t.cloth.axis_u[0] = 1, t.cloth.axis_u[1] = 0, t.cloth.axis_u[2] = 0;
    t.cloth.axis_v[0] = 0, t.cloth.axis_v[1] = cos(a), t.cloth.axis_v[2] = sin(a);
    double n[3];
    cross(t.cloth.axis_u, t.cloth.axis_v, n);
    check_mesh("7 x 11, 2 x 1.2 m, tilted 30 deg", &t, n);
}

/* dClothSetTriangleTests: a 21x21 cloth dropped across the edge of a box,
 * ODE's geom or the same box as 12 triangles, gets contacts from its
 * triangle tests (dClothStepStats.triangle_contacts) with them on (the
 * default), none with them off; bad input refused. */
static const dReal edge_box_v[24] = {-0.2, -0.2, -0.2, 0.2, -0.2, -0.2, -0.2, 0.2, -0.2, 0.2, 0.2, -0.2,
                                     -0.2, -0.2, 0.2,  0.2, -0.2, 0.2,  -0.2, 0.2, 0.2,  0.2, 0.2, 0.2};
/* vertex i at bit 0 x, bit 1 y, bit 2 z; faces counter-clockwise from outside */
static const dTriIndex edge_box_t[36] = {1, 3, 7, 1, 7, 5, 0, 4, 6, 0, 6, 2, 2, 6, 7, 2, 7, 3,
                                         0, 1, 5, 0, 5, 4, 4, 5, 7, 4, 7, 6, 0, 2, 3, 0, 3, 1};

static int drop_across_edge(int mesh, int tests, int *tri_contacts)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dTriMeshDataID data = 0;
    dGeomID box;
    if (mesh) {
        data = dGeomTriMeshDataCreate();
        dGeomTriMeshDataBuildDouble(data, edge_box_v, 3 * sizeof(dReal), 8, edge_box_t, 36, 3 * sizeof(dTriIndex));
        box = dCreateTriMesh(sp, data, 0, 0, 0);
    } else {
        box = dCreateBox(sp, 0.4, 0.4, 0.4);
    }
    dGeomSetPosition(box, 0.3, 0, 0.2); /* its edge x = 0.1 under the cloth */
    dClothDesc d = dClothDefaultDesc();
    d.cloth.origin[2] = 0.45;
    dClothID c = NULL;
    cloth_error err;
    int ok = CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "triangle tests: dClothCreate: %s", err.message);
    if (ok) {
        CHECK(dClothGetTriangleTests(c, box) == 1, "triangle tests: on by default");
        if (!tests)
            CHECK(dClothSetTriangleTests(c, box, 0) == CLOTH_OK, "triangle tests off: %s", dClothGetLastError(c));
        CHECK(dClothGetTriangleTests(c, box) == tests, "triangle tests: read back %d, set %d",
              dClothGetTriangleTests(c, box), tests);
        *tri_contacts = 0;
        for (int s = 0; s < 30 && ok; s++) {
            ok = CHECK(dClothWorldStep(w, &c, 1, H, 0) == CLOTH_OK, "triangle tests %d: step %d: %s", tests, s,
                       dClothGetLastError(c));
            *tri_contacts += dClothGetStats(c)->triangle_contacts;
        }
        dClothDestroy(c);
    }
    dSpaceDestroy(sp);
    if (data) dGeomTriMeshDataDestroy(data);
    dWorldDestroy(w);
    return ok;
}

static void test_triangle_tests(void)
{
    for (int mesh = 0; mesh < 2; mesh++) {
        int on = 0, off = 0;
        if (drop_across_edge(mesh, 1, &on) && drop_across_edge(mesh, 0, &off)) {
            printf("triangle tests, %s: %d triangle contacts over 30 steps on, %d off\n", mesh ? "box mesh" : "box", on,
                   off);
            CHECK(on > 0 && off == 0, "triangle tests, %s: %d triangle contacts on, %d off", mesh ? "box mesh" : "box",
                  on, off);
        }
    }
    dWorldID w = dWorldCreate();
    dSpaceID sp = dHashSpaceCreate(0);
    dGeomID box = dCreateBox(sp, 1, 1, 1);
    dClothDesc d = dClothDefaultDesc();
    dClothID c = NULL;
    cloth_error err;
    if (CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "dClothCreate: %s", err.message)) {
        CHECK(dClothSetTriangleTests(c, 0, 0) == CLOTH_EINVAL && strstr(dClothGetLastError(c), "geom is 0"),
              "triangle tests: geom 0 refused with a message (%s)", dClothGetLastError(c));
        CHECK(dClothSetTriangleTests(NULL, box, 0) == CLOTH_EINVAL, "triangle tests: NULL cloth refused");
        CHECK(dClothGetTriangleTests(NULL, box) == 0 && dClothGetTriangleTests(c, 0) == 0,
              "triangle tests: read with NULL gives 0");
        CHECK(dClothSetTriangleTests(c, box, 0) == CLOTH_OK && dClothSetTriangleTests(c, box, 0) == CLOTH_OK &&
                  dClothGetTriangleTests(c, box) == 0,
              "triangle tests: off twice");
        CHECK(dClothSetTriangleTests(c, box, 1) == CLOTH_OK && dClothGetTriangleTests(c, box) == 1,
              "triangle tests: on again (forgotten)");
        dClothDestroy(c);
    }
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

/* dClothSetConvexPoints: bad input refused with a message; a good call
 * taken, replaced and forgotten. (Its effect, triangle tests against the
 * convex, is measured in plugin_colliders.) */
static void test_convex_points(void)
{
    dWorldID w = dWorldCreate();
    dSpaceID sp = dHashSpaceCreate(0);
    static const dReal planes[24] = {1, 0, 0, 1, -1, 0, 0, 1, 0, 1, 0, 1, 0, -1, 0, 1, 0, 0, 1, 1, 0, 0, -1, 1};
    static const dReal pts[24] = {-1, -1, -1, 1, -1, -1, -1, 1, -1, 1, 1, -1, -1, -1, 1, 1, -1, 1, -1, 1, 1, 1, 1, 1};
    static const unsigned polys[30] = {4, 1, 3, 7, 5, 4, 0, 4, 6, 2, 4, 2, 6, 7, 3,
                                       4, 0, 1, 5, 4, 4, 4, 5, 7, 6, 4, 0, 2, 3, 1};
    dGeomID cvx = dCreateConvex(sp, planes, 6, pts, 8, polys), sph = dCreateSphere(sp, 0.1);
    dClothDesc d = dClothDefaultDesc();
    dClothID c = NULL;
    cloth_error err;
    if (CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "create: %s", err.message)) {
        dReal bad[24];
        memcpy(bad, pts, sizeof bad);
        bad[7] = NAN;
        CHECK(dClothSetConvexPoints(c, 0, pts, 8) == CLOTH_EINVAL, "convex points: geom 0");
        CHECK(dClothSetConvexPoints(c, sph, pts, 8) == CLOTH_EINVAL, "convex points: a sphere");
        CHECK(strstr(dClothGetLastError(c), "not a convex") != NULL, "message: %s", dClothGetLastError(c));
        CHECK(dClothSetConvexPoints(c, cvx, NULL, 8) == CLOTH_EINVAL, "convex points: NULL with 8");
        CHECK(dClothSetConvexPoints(c, cvx, pts, -1) == CLOTH_EINVAL, "convex points: count -1");
        CHECK(dClothSetConvexPoints(c, cvx, bad, 8) == CLOTH_EINVAL, "convex points: a NaN");
        CHECK(dClothSetConvexPoints(NULL, cvx, pts, 8) == CLOTH_EINVAL, "convex points: NULL cloth");
        CHECK(dClothSetConvexPoints(c, cvx, pts, 8) == CLOTH_OK, "convex points: %s", dClothGetLastError(c));
        CHECK(dClothSetConvexPoints(c, cvx, pts, 4) == CLOTH_OK, "convex points replaced");
        CHECK(dClothSetConvexPoints(c, cvx, NULL, 0) == CLOTH_OK, "convex points forgotten");
        CHECK(dClothSetConvexPoints(c, cvx, NULL, 0) == CLOTH_OK, "forgetting twice is fine");
        dClothDestroy(c);
    }
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

/* dClothWorldStep is all or nothing: cloth A, pinned to a free 1 kg body,
 * steps; cloth B then fails (its vertex 0 thrown at 1e4 m/s, its linear
 * solves cut to one block-Jacobi CG iteration and its Newton iterations to
 * one, which no solver survives);
 * A and the body are as before the call, bitwise, and the
 * world did not step. Then a bad h, a cloth twice, a cloth of another
 * world: refused before anything moves. */

/* dClothGetVertexContact: a 21x21 cloth, 1 m, settles for 1 s over a
 * static box covering x < 0 (top at z = 0.2) and the plane z = 0: a vertex
 * well inside the box's top (x < -0.125, between grid columns: the column at
 * x = -0.1 lies on the bend over the box's edge, lifting off and landing)
 * names the box, its point on the top and the normal +z; one well past the
 * box's edge (x > 0.3) the plane, or nothing where the drape lifts it off.
 * Before the first step no vertex touches anything. */
static void test_vertex_contact(void)
{
    dWorldID w = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dGeomID plane = dCreatePlane(sp, 0, 0, 1, 0), box = dCreateBox(sp, 0.8, 1.4, 0.2);
    dGeomSetPosition(box, -0.4, 0, 0.1);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.origin[0] = d.cloth.origin[1] = -0.5;
    d.cloth.origin[2] = 0.25;
    dClothID c = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, sp, &d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return;
    int n = dClothGetVertexCount(c), none = 0;
    dGeomID g = box;
    dReal p[3] = {1, 1, 1}, nrm[3];
    for (int i = 0; i < n; i++) none += dClothGetVertexContact(c, i, &g, p, NULL) == CLOTH_OK && g == 0 && p[2] == 0;
    CHECK(none == n, "before any step %d of %d vertices touch nothing", none, n);
    for (int s = 0; s < 60; s++) dClothWorldStep(w, &c, 1, H, 0);
    int on_box = 0, on_plane = 0, wrong = 0;
    const dReal *x = dClothGetPositions(c);
    double off_max = 0.0; /* the largest distance of a contact point from under its vertex */
    for (int i = 0; i < n; i++) {
        CHECK(dClothGetVertexContact(c, i, &g, p, nrm) == CLOTH_OK, "vertex %d: %s", i, dClothGetLastError(c));
        if (g) {
            double d[3] = {x[3 * i] - p[0], x[3 * i + 1] - p[1], x[3 * i + 2] - p[2]};
            double dn = d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2];
            for (int k = 0; k < 3; k++) d[k] -= dn * nrm[k];
            off_max = fmax(off_max, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        }
        if (x[3 * i] > -0.125 && x[3 * i] < 0.3) continue; /* near the box's edge: its sides and corners */
        dGeomID want = x[3 * i] < 0 ? box : plane;
        double top = want == box ? 0.2 : 0.0;
        on_box += g == box;
        on_plane += g == plane;
        /* on the box's top every vertex rests; past its edge those the
         * drape lifts off the plane touch nothing */
        int bad = want == box ? g != box : g != plane && g != 0;
        bad = bad || (g && (fabs(p[2] - top) > 1e-9 || fabs(nrm[2] - 1.0) > 1e-9));
        wrong += bad;
    }
    printf("vertex contacts after 1 s: %d on the box, %d on the plane, %d wrong; a point %.3g m from under its "
           "vertex\n",
           on_box, on_plane, wrong, off_max);
    CHECK(off_max < 1e-3, "a contact point %g m from under its vertex", off_max);
    CHECK(on_box > 50 && on_plane > 20 && wrong == 0, "contacts: %d box, %d plane, %d wrong", on_box, on_plane, wrong);
    CHECK(dClothGetVertexContact(c, n, &g, NULL, NULL) == CLOTH_EINVAL && dClothGetLastError(c)[0],
          "vertex n accepted");
    CHECK(dClothGetVertexContact(c, 0, NULL, p, NULL) == CLOTH_EINVAL, "geom NULL accepted");
    CHECK(dClothGetVertexContact(NULL, 0, &g, NULL, NULL) == CLOTH_EINVAL, "NULL cloth accepted");
    dClothDestroy(c);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
}

/* whether two files hold the same bytes */
static int same_file(const char *p, const char *q)
{
    FILE *f = fopen(p, "rb"), *g = fopen(q, "rb");
    int same = f && g;
    for (int a = 0, b = 0; same && (a != EOF || b != EOF);) {
        a = fgetc(f);
        b = fgetc(g);
        same = a == b;
    }
    if (f) fclose(f);
    if (g) fclose(g);
    return same;
}

static void test_world_step_undo(void)
{
    dWorldID w = dWorldCreate(), w2 = dWorldCreate();
    dWorldSetGravity(w, 0, 0, -9.81);
    dSpaceID sp = dHashSpaceCreate(0);
    dClothDesc d = dClothDefaultDesc();
    dClothID a = NULL, b = NULL, other = NULL;
    cloth_error err;
    if (!CHECK(dClothCreate(w, sp, &d, &a, &err) == CLOTH_OK && dClothCreate(w, sp, &d, &b, &err) == CLOTH_OK &&
                   dClothCreate(w2, 0, &d, &other, &err) == CLOTH_OK,
               "create: %s", err.message))
        goto done;
    dBodyID body = dBodyCreate(w);
    dMass m;
    dMassSetBoxTotal(&m, 1.0, 0.1, 0.1, 0.1);
    dBodySetMass(body, &m);
    const dReal *x0 = dClothGetPositions(a);
    dBodySetPosition(body, x0[0], x0[1], x0[2] + 0.05);
    dReal local[3] = {0, 0, -0.05};
    CHECK(dClothPinToBody(a, 0, body, local) == CLOTH_OK, "pin to body: %s", dClothGetLastError(a));
    dClothID both[2] = {a, b};
    for (int k = 0; k < 5; k++) CHECK(dClothWorldStep(w, both, 2, 1.0 / 60, 0) == CLOTH_OK, "warm-up step");
    double v0[3] = {1e4, 0, 0};
    CHECK(cloth_set_vertex(dClothGetCore(b), 0, dClothGetPositions(b), v0) == CLOTH_OK, "throw B's vertex");
    const cloth_solver sb0 = cloth_get_desc(dClothGetCore(b)).solver;
    cloth_solver sb = sb0;
    sb.precond = CLOTH_PRECOND_BLOCK_JACOBI;
    sb.cg_max_iterations = 1;
    sb.newton_iterations = 1; /* under Newton one iteration cannot catch the thrown vertex */
    CHECK(cloth_set_solver(dClothGetCore(b), &sb) == CLOTH_OK, "cap B's CG");
    CHECK(dClothSetFailureMode(b, DCLOTH_FAILURE_STOP) == CLOTH_OK, "B stops on failure");
    cloth_state *sa = cloth_state_create(dClothGetCore(a)), *sa2 = cloth_state_create(dClothGetCore(a));
    CHECK(dClothAddVertexForce(a, 7, 0.1, 0.0, 0.2) == CLOTH_OK, "a force pending on A");
    cloth_save(dClothGetCore(a), sa);
    CHECK(dClothWriteState(a, "undo_a0.state", NULL, 0, &body, 1) == CLOTH_OK, "A's state: %s", dClothGetLastError(a));
    body_state b0, b1;
    dBodyAddForce(body, 0.5, 0, 0); /* the user's own force, before the step */
    body_save(body, &b0);
    cloth_status s = dClothWorldStep(w, both, 2, 1.0 / 60, 0);
    cloth_save(dClothGetCore(a), sa2);
    body_save(body, &b1);
    CHECK(s == CLOTH_ESTEP, "B's step fails: status %d (%s)", s, dClothGetLastError(b));
    CHECK(cloth_state_diff(sa, sa2) == 0.0, "A is back as before the call (diff %g)", cloth_state_diff(sa, sa2));
    CHECK(dClothWriteState(a, "undo_a1.state", NULL, 0, &body, 1) == CLOTH_OK, "A's state: %s", dClothGetLastError(a));
    CHECK(same_file("undo_a0.state", "undo_a1.state"), "A's plugin state (contacts, pins, pending forces) is back");
    remove("undo_a0.state");
    remove("undo_a1.state");
    CHECK(memcmp(&b0, &b1, sizeof b0) == 0, "the body A pulls on is as before, force accumulator included");
    dReal pin[3];
    CHECK(dClothGetPinForce(a, 0, pin) == CLOTH_OK, "pin force");
    /* refused before anything moves */
    CHECK(dClothWorldStep(w, both, 2, NAN, 0) == CLOTH_EINVAL, "h NaN refused");
    CHECK(dClothWorldStep(w, NULL, 0, -1.0, 0) == CLOTH_EINVAL, "no cloth and h -1: refused (ODE never sees it)");
    dClothID twice[2] = {a, a};
    CHECK(dClothWorldStep(w, twice, 2, 1.0 / 60, 0) == CLOTH_EINVAL, "a cloth twice refused");
    dClothID mixed[2] = {a, other};
    CHECK(dClothWorldStep(w, mixed, 2, 1.0 / 60, 0) == CLOTH_EINVAL, "a cloth of another world refused");
    cloth_save(dClothGetCore(a), sa2);
    body_save(body, &b1);
    CHECK(cloth_state_diff(sa, sa2) == 0.0 && memcmp(&b0, &b1, sizeof b0) == 0, "nothing moved");
    /* the default, DCLOTH_FAILURE_HOLD: B is stopped where it was (its
     * velocities zeroed), A and the world step on; from rest B's next step
     * succeeds */
    CHECK(dClothSetFailureMode(b, DCLOTH_FAILURE_HOLD) == CLOTH_OK, "B holds on failure");
    const int nb = dClothGetVertexCount(b);
    double *xb = malloc(3 * (size_t)nb * sizeof *xb);
    memcpy(xb, cloth_positions(dClothGetCore(b)), 3 * (size_t)nb * sizeof *xb);
    s = dClothWorldStep(w, both, 2, 1.0 / 60, 0);
    CHECK(s == CLOTH_OK && dClothGetStats(b)->held == 1 && dClothGetStats(b)->core.failure != CLOTH_FAIL_NONE &&
              dClothGetLastError(b)[0] != '\0',
          "held step: status %d, held %d, failure %d, '%s'", s, dClothGetStats(b)->held,
          (int)dClothGetStats(b)->core.failure, dClothGetLastError(b));
    double vmax = 0.0;
    for (int i = 0; i < 3 * nb; i++) vmax = fmax(vmax, fabs(cloth_velocities(dClothGetCore(b))[i]));
    CHECK(memcmp(xb, cloth_positions(dClothGetCore(b)), 3 * (size_t)nb * sizeof *xb) == 0 && vmax == 0.0,
          "B not stopped where it was: speed %g", vmax);
    cloth_save(dClothGetCore(a), sa2);
    body_save(body, &b1);
    CHECK(dClothGetStats(a)->held == 0 && cloth_state_diff(sa, sa2) > 0.0 && memcmp(&b0, &b1, sizeof b0) != 0,
          "A or the world did not step on");
    CHECK(cloth_set_solver(dClothGetCore(b), &sb0) == CLOTH_OK, "B's solver back");
    s = dClothWorldStep(w, both, 2, 1.0 / 60, 0);
    CHECK(s == CLOTH_OK && dClothGetStats(b)->held == 0, "B from rest: status %d, held %d (%s)", s,
          dClothGetStats(b)->held, dClothGetLastError(b));
    free(xb);
    CHECK(dClothSetFailureMode(b, (dClothFailureMode)2) == CLOTH_EINVAL &&
              dClothSetFailureMode(NULL, 0) == CLOTH_EINVAL,
          "bad failure modes accepted");
    cloth_state_destroy(sa);
    cloth_state_destroy(sa2);
done:
    dClothDestroy(a);
    dClothDestroy(b);
    dClothDestroy(other);
    dSpaceDestroy(sp);
    dWorldDestroy(w);
    dWorldDestroy(w2);
}

int main(void)
{
    dInitODE2(0);
    test_convex_points();
    test_triangle_tests();
    test_world_step_undo();
    test_vertex_contact();
    double t0 = now();
    test_filtering();
    double t1 = now();
    test_user_callback();
    double t2 = now();
    test_create_bad_input();
    test_step_and_pin_bad_input();
    test_null_cloth();
    double t3 = now();
    test_destroyed_geom(0);
    test_destroyed_geom(1);
    double t4 = now();
    test_mesh();
    printf("wall time: filtering %.1f s, user callback %.1f s, bad input %.1f s, destroyed geoms %.1f s, mesh %.1f s\n",
           t1 - t0, t2 - t1, t3 - t2, t4 - t3, now() - t4);
    dCloseODE();
    return check_summary();
}
