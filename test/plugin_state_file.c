/* Plugin: state files (dClothWriteState / dClothReadState).
 *
 * Scene: a cotton cloth dropped on a static box table (0.4 m a side, mu
 * 0.5: contacts, sticking, triangle contacts at the edges), its corner
 * vertex pinned to a free 50 g body that hangs off the table.
 *
 * 1. A 9 x 9 cloth run 60 steps, forces added to a few vertices for the
 *    next step (dClothAddVertexForce), its state written (the body's pose
 *    and velocities kept by hand, bit for bit), then run 40 more. A second
 *    scene built from scratch reads the file (with its own table and body in
 *    the arrays) and runs 40 steps: positions and velocities bitwise the
 *    first run's. Both with the linearised step and with Newton's (under
 *    which the body turns: its orientation must go back bit for bit).
 *    Held steps: a cloth thrown onto a box with Newton's budget cut
 *    (DCLOTH_FAILURE_HOLD, as plugin_failure_hold) written after the second
 *    of a run of held steps: read into a new scene, it continues bitwise
 *    (the run decides the next step's substep halvings).
 * 2. Sleep: a 3 x 3 cloth without the body falls asleep on the table; the
 *    file carries the sleep snapshot (the table by index): read into a
 *    fresh scene, it sleeps, and wakes as the first does when the table moves.
 * 3. Refused, with a message and the cloth unchanged (its state written
 *    again gives the same bytes): a missing file, every truncation of a
 *    3 x 3 cloth's file, a bad magic, version 3, a file of another vertex
 *    count, a geom and a body index out of range, NaN in a contact's normal,
 *    a held run out of range, NaN in a pending force, a damaged byte
 *    (checksum), a trailing byte, NULL path and negative counts. Writing
 *    with the body or table left out of the arrays is refused naming the pin
 *    or contact, and the existing file is untouched. A version 1 file (no
 *    held run, no pending forces) is read, both zero.
 */
#include "odecloth/dcloth.h"
#include "check.h"
#include "body_state.h"
#include "records.h"

#define H (1.0 / 60)
#define CONTACT_BYTES 308
#define PIN_BYTES 80
#define SLEEP_BYTES 52
#define SLEEP_ENTRY 28
#define HELD_BYTES 4
#define FORCE_BYTES 24

typedef struct scene {
    dWorldID world;
    dSpaceID space;
    dGeomID table;
    dBodyID body; /* 0: no hanging body */
    dClothID cloth;
} scene;

static int make(scene *r, int rows, int hang, cloth_nonlinear nl)
{
    memset(r, 0, sizeof *r);
    r->world = dWorldCreate();
    dWorldSetGravity(r->world, 0, 0, -9.81);
    r->space = dHashSpaceCreate(0);
    r->table = dCreateBox(r->space, 0.4, 0.4, 0.4);
    dGeomSetPosition(r->table, 0, 0, 0.2);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = rows;
    d.cloth.width = d.cloth.height = 0.6;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.3;
    d.cloth.origin[2] = 0.45;
    d.mu = 0.5;
    d.cloth.solver.nonlinear = nl;
    cloth_error err;
    if (!CHECK(dClothCreate(r->world, r->space, &d, &r->cloth, &err) == CLOTH_OK, "dClothCreate: %s", err.message))
        return -1;
    dClothSetFailureMode(r->cloth, DCLOTH_FAILURE_STOP);
    if (hang) {
        r->body = dBodyCreate(r->world);
        dMass m;
        dMassSetSphereTotal(&m, 0.05, 0.03);
        dBodySetMass(r->body, &m);
        dBodySetPosition(r->body, -0.3, -0.3, 0.45);
        const dReal local[3] = {0, 0, 0};
        CHECK(dClothPinToBody(r->cloth, 0, r->body, local) == CLOTH_OK, "pin: %s", dClothGetLastError(r->cloth));
    }
    return 0;
}

static void destroy(scene *r)
{
    dClothDestroy(r->cloth);
    dGeomDestroy(r->table);
    if (r->body) dBodyDestroy(r->body);
    dSpaceDestroy(r->space);
    dWorldDestroy(r->world);
}

static int run(scene *r, int steps)
{
    for (int s = 0; s < steps; s++)
        if (!CHECK(dClothWorldStep(r->world, &r->cloth, 1, H, 0) == CLOTH_OK, "step %d: %s", s,
                   dClothGetLastError(r->cloth)))
            return -1;
    return 0;
}

static cloth_status write_state(scene *r, const char *path)
{
    return dClothWriteState(r->cloth, path, &r->table, 1, &r->body, r->body ? 1 : 0);
}

static cloth_status read_state(scene *r, const char *path)
{
    return dClothReadState(r->cloth, path, &r->table, 1, &r->body, r->body ? 1 : 0);
}

static void store(const char *path, const unsigned char *p, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f) return;
    fwrite(p, 1, n, f);
    fclose(f);
}

static uint64_t le(const unsigned char *p, int bytes)
{
    uint64_t v = 0;
    for (int k = bytes - 1; k >= 0; k--) v = v << 8 | p[k];
    return v;
}

static void put_le(unsigned char *p, uint64_t v, int bytes)
{
    for (int k = 0; k < bytes; k++) p[k] = (unsigned char)(v >> (8 * k));
}

/* offset of the first contact record */
static size_t contacts_at(const blob *b)
{
    size_t sleep = 24 + (size_t)le(b->p + 16, 8);
    return sleep + SLEEP_BYTES + SLEEP_ENTRY * (size_t)le(b->p + sleep + 48, 4) + 8; /* + the surface's reach */
}

/* the cloth's state as bytes, for "unchanged" */
static blob snapshot(scene *r)
{
    CHECK(write_state(r, "plugin_state_file.ref") == CLOTH_OK, "write ref: %s", dClothGetLastError(r->cloth));
    return read_all("plugin_state_file.ref");
}

/* Calls refused whole: NULL paths, a negative count, a NULL cloth; writes naming no body or geom
 * for what the scene holds, the file (ref's record) untouched */
static void refused_calls(scene *r, const blob *ref)
{
    CHECK(dClothReadState(r->cloth, NULL, NULL, 0, NULL, 0) == CLOTH_EINVAL &&
              dClothWriteState(r->cloth, NULL, NULL, 0, NULL, 0) == CLOTH_EINVAL &&
              dClothReadState(r->cloth, "plugin_state_file.ref", &r->table, -1, NULL, 0) == CLOTH_EINVAL &&
              dClothWriteState(NULL, "x", NULL, 0, NULL, 0) == CLOTH_EINVAL,
          "NULL path, negative count, NULL cloth refused");

    /* writing what the arrays do not name: refused, the file untouched */
    CHECK(dClothWriteState(r->cloth, "plugin_state_file.ref", &r->table, 1, NULL, 0) == CLOTH_EINVAL &&
              strstr(dClothGetLastError(r->cloth), "pin of vertex 0: body is") &&
              strstr(dClothGetLastError(r->cloth), "not in bodies[]"),
          "a pin to an unnamed body: %s", dClothGetLastError(r->cloth));
    CHECK(dClothWriteState(r->cloth, "plugin_state_file.ref", NULL, 0, &r->body, 1) == CLOTH_EINVAL &&
              strstr(dClothGetLastError(r->cloth), "geom is") && strstr(dClothGetLastError(r->cloth), "not in geoms[]"),
          "a contact with an unnamed geom: %s", dClothGetLastError(r->cloth));
    blob now = read_all("plugin_state_file.ref");
    CHECK(now.n == ref->n && memcmp(now.p, ref->p, now.n) == 0, "a refused write changed the file");
    free(now.p);
}

/* b written to a file and read into r: refused, with `want` in the message
 * and the cloth unchanged (ref) */
static void refused(scene *r, const blob *ref, const unsigned char *p, size_t n, const char *want, const char *what)
{
    store("plugin_state_file.bad", p, n);
    cloth_status s = read_state(r, "plugin_state_file.bad");
    const char *msg = dClothGetLastError(r->cloth);
    CHECK(s == CLOTH_EINVAL && strstr(msg, want), "%s: status %d, message \"%s\" (want \"%s\")", what, s, msg, want);
    blob now = snapshot(r);
    CHECK(now.n == ref->n && memcmp(now.p, ref->p, now.n) == 0, "%s: the cloth changed", what);
    free(now.p);
}

static void bad_input(void)
{
    scene r, big;
    if (make(&r, 3, 1, CLOTH_LINEARIZED) || make(&big, 9, 1, CLOTH_LINEARIZED)) return;
    if (run(&r, 30)) return;
    blob ref = snapshot(&r), b = snapshot(&r);
    CHECK(dClothGetStats(r.cloth)->contacts > 0, "the small scene has no contacts");
    int n = dClothGetVertexCount(r.cloth);
    size_t c0 = contacts_at(&b), held = c0 + (size_t)n * (CONTACT_BYTES + PIN_BYTES);
    CHECK(b.n == held + HELD_BYTES + (size_t)n * FORCE_BYTES + 8, "file of %zu bytes, the layout says %zu", b.n,
          held + HELD_BYTES + (size_t)n * FORCE_BYTES + 8);

    CHECK(dClothReadState(r.cloth, "no_such_dir/none.state", NULL, 0, NULL, 0) == CLOTH_EINVAL &&
              strstr(dClothGetLastError(r.cloth), "no_such_dir/none.state"),
          "missing file: %s", dClothGetLastError(r.cloth));
    int truncs = 0;
    for (size_t len = 0; len < b.n; len++) {
        store("plugin_state_file.bad", b.p, len);
        truncs += read_state(&r, "plugin_state_file.bad") == CLOTH_EINVAL && dClothGetLastError(r.cloth)[0];
    }
    CHECK(truncs == (int)b.n, "%d of %zu truncations refused", truncs, b.n);
    blob now = snapshot(&r);
    CHECK(now.n == ref.n && memcmp(now.p, ref.p, now.n) == 0, "truncations: the cloth changed");
    free(now.p);

    blob m = snapshot(&r);
    m.p[0] ^= 1;
    refused(&r, &ref, m.p, m.n, "magic", "bad magic");
    m.p[0] ^= 1;
    put_le(m.p + 8, 3, 4);
    reseal(m.p, m.n);
    refused(&r, &ref, m.p, m.n, "format version 3, this library reads 1 and 2", "version 3");
    put_le(m.p + 8, 2, 4);
    put_le(m.p + 12, 10, 4);
    reseal(m.p, m.n);
    refused(&r, &ref, m.p, m.n, "for 10 vertices", "vertex count 10");
    put_le(m.p + 12, (uint64_t)n, 4);
    reseal(m.p, m.n);
    blob other = snapshot(&big);
    refused(&r, &ref, other.p, other.n, "for 81 vertices", "a 9 x 9 cloth's file");
    free(other.p);

    /* a vertex with a contact: its geom index out of range */
    int v = -1;
    for (int i = 0; i < n && v < 0; i++)
        if ((int32_t)le(m.p + c0 + (size_t)i * CONTACT_BYTES, 4) == 0) v = i;
    CHECK(v >= 0, "no vertex of the small file has a contact with the table");
    if (v >= 0) {
        unsigned char *rec = m.p + c0 + (size_t)v * CONTACT_BYTES;
        put_le(rec, 1, 4);
        reseal(m.p, m.n);
        char want[64];
        snprintf(want, sizeof want, "contact of vertex %d: geom = 1 is outside [-1, 0]", v);
        refused(&r, &ref, m.p, m.n, want, "geom index 1");
        put_le(rec, 0, 4);
        double nan = NAN;
        uint64_t u;
        memcpy(&u, &nan, 8);
        put_le(rec + 8 + 8, u, 8); /* normal[1] */
        reseal(m.p, m.n);
        snprintf(want, sizeof want, "contact of vertex %d: normal[1] = nan is not finite", v);
        refused(&r, &ref, m.p, m.n, want, "NaN normal");
    }
    memcpy(m.p, ref.p, ref.n);
    {
        double neg = -1.0; /* the surface callback's largest thickness, just before the contacts */
        uint64_t u;
        memcpy(&u, &neg, 8);
        put_le(m.p + c0 - 8, u, 8);
        reseal(m.p, m.n);
        refused(&r, &ref, m.p, m.n, "surface: largest thickness = -1 is outside [0, 10]", "negative reach");
        memcpy(m.p, ref.p, ref.n);
    }
    unsigned char *pin0 = m.p + c0 + (size_t)n * CONTACT_BYTES;
    put_le(pin0 + 4, 1, 4);
    reseal(m.p, m.n);
    refused(&r, &ref, m.p, m.n, "pin of vertex 0: body = 1 is outside [-1, 0]", "body index 1");
    put_le(pin0 + 4, (uint64_t)-2, 4);
    reseal(m.p, m.n);
    refused(&r, &ref, m.p, m.n, "pin of vertex 0: body = -2 is outside [-1, 0]", "body index -2");
    memcpy(m.p, ref.p, ref.n);
    put_le(m.p + held, 17, 4);
    reseal(m.p, m.n);
    refused(&r, &ref, m.p, m.n, "held run = 17 is outside [0, 16]", "held run 17");
    put_le(m.p + held, (uint64_t)-1, 4);
    reseal(m.p, m.n);
    refused(&r, &ref, m.p, m.n, "held run = -1 is outside [0, 16]", "held run -1");
    memcpy(m.p, ref.p, ref.n);
    {
        double nan = NAN;
        uint64_t u;
        memcpy(&u, &nan, 8);
        put_le(m.p + held + HELD_BYTES + 2 * FORCE_BYTES + 8, u, 8);
        reseal(m.p, m.n);
        refused(&r, &ref, m.p, m.n, "pending force of vertex 2: force[1] = nan is not finite", "NaN pending force");
        memcpy(m.p, ref.p, ref.n);
    }
    m.p[c0 + 20] ^= 0x10;
    refused(&r, &ref, m.p, m.n, "checksum", "damaged byte");
    memcpy(m.p, ref.p, ref.n);
    unsigned char *longer = malloc(m.n + 1);
    memcpy(longer, m.p, m.n - 8);
    longer[m.n - 8] = 0;
    blob lb = {longer, m.n + 1};
    reseal(lb.p, lb.n);
    refused(&r, &ref, lb.p, lb.n, "1 bytes after the last pending force record", "a trailing byte");
    free(longer);

    /* version 1: no held run, no pending forces; read, both zero (a force
     * added before reading is gone) */
    memcpy(m.p + held, m.p + m.n - 8, 8);
    blob v1 = {m.p, held + 8};
    put_le(v1.p + 8, 1, 4);
    reseal(v1.p, v1.n);
    dClothAddVertexForce(r.cloth, 1, 0.5, 0, 0);
    store("plugin_state_file.bad", v1.p, v1.n);
    CHECK(read_state(&r, "plugin_state_file.bad") == CLOTH_OK, "a version 1 file: %s", dClothGetLastError(r.cloth));
    now = snapshot(&r);
    CHECK(now.n == ref.n && memcmp(now.p, ref.p, now.n) == 0, "a version 1 file read is not the state it holds");
    free(now.p);
    v1.p[v1.n - 9] ^= 1;
    refused(&r, &ref, v1.p, v1.n, "checksum", "a damaged version 1 file");
    v1.p[v1.n - 9] ^= 1;
    v1.n += 4;
    reseal(v1.p, v1.n);
    refused(&r, &ref, v1.p, v1.n, "4 bytes after the last pin record", "a version 1 file with a held run");
    memcpy(m.p, ref.p, ref.n);

    refused_calls(&r, &ref);
    printf("refused: a missing file, %d truncations, magic, version, vertex count, indices, NaN, held run, "
           "checksum, a trailing byte; writes naming no body or geom; a version 1 file read\n",
           truncs);
    free(m.p);
    free(b.p);
    free(ref.p);
    destroy(&r);
    destroy(&big);
}

/* Written at step n, read into a new scene, m steps on: bitwise the same */
static void round_trip(int n, int m, cloth_nonlinear nl)
{
    const char *name = nl == CLOTH_NEWTON ? "Newton" : "linearized";
    scene a, b;
    if (make(&a, 9, 1, nl) || make(&b, 9, 1, nl)) return;
    size_t n3 = 3 * (size_t)dClothGetVertexCount(a.cloth);
    run(&a, n);
    /* forces for the next step, pending when the file is written */
    for (int i = 40; i < 44; i++)
        CHECK(dClothAddVertexForce(a.cloth, i, 0.02, -0.01 * (i - 41), 0.05) == CLOTH_OK, "add force: %s",
              dClothGetLastError(a.cloth));
    CHECK(write_state(&a, "plugin_state_file.state") == CLOTH_OK, "write: %s", dClothGetLastError(a.cloth));
    body_state bs;
    body_save(a.body, &bs);
    run(&a, m);
    CHECK(dClothGetStats(a.cloth)->contacts > 20 && dClothGetStats(a.cloth)->sticking > 0,
          "%s: the scene has too few contacts (%d, sticking %d)", name, dClothGetStats(a.cloth)->contacts,
          dClothGetStats(a.cloth)->sticking);
    run(&b, 5); /* somewhere else, to be overwritten */
    CHECK(read_state(&b, "plugin_state_file.state") == CLOTH_OK, "read: %s", dClothGetLastError(b.cloth));
    body_restore(b.body, &bs);
    CHECK(body_same(b.body, &bs), "%s: the hanging body is not restored bit for bit", name);
    run(&b, m);
    int same = memcmp(dClothGetPositions(a.cloth), dClothGetPositions(b.cloth), n3 * sizeof(double)) == 0 &&
               memcmp(cloth_velocities(dClothGetCore(a.cloth)), cloth_velocities(dClothGetCore(b.cloth)),
                      n3 * sizeof(double)) == 0;
    CHECK(same, "%s: read into a new scene and run %d steps: differs from the uninterrupted run", name, m);
    printf("%s: written at step %d with forces pending, read into a new scene, %d steps on: %s\n", name, n, m,
           same ? "bitwise the uninterrupted run" : "DIFFERS");
    destroy(&a);
    destroy(&b);
}

/* A cloth thrown onto a box, Newton's budget cut so that steps are held
 * (plugin_failure_hold's scene); geoms[0] the box, geoms[1] the ground. */
typedef struct held_scene {
    dWorldID world;
    dSpaceID space;
    dGeomID geoms[2];
    dClothID cloth;
} held_scene;

static int held_make(held_scene *r)
{
    r->world = dWorldCreate();
    dWorldSetGravity(r->world, 0, 0, -9.81);
    r->space = dHashSpaceCreate(0);
    r->geoms[0] = dCreateBox(r->space, 0.5, 0.5, 0.2);
    dGeomSetPosition(r->geoms[0], 0, 0, 0.1);
    r->geoms[1] = dCreatePlane(r->space, 0, 0, 1, 0);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = 21;
    d.cloth.material.density = 0.2;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.5;
    d.cloth.origin[2] = 0.2 + d.thickness + 0.01;
    d.cloth.solver.nonlinear = CLOTH_NEWTON;
    d.cloth.solver.newton_iterations = 1;
    d.cloth.solver.max_substep_halvings = 0;
    cloth_error err;
    if (!CHECK(dClothCreate(r->world, r->space, &d, &r->cloth, &err) == CLOTH_OK, "held scene: %s", err.message))
        return -1;
    cloth *core = dClothGetCore(r->cloth);
    size_t n3 = 3 * (size_t)dClothGetVertexCount(r->cloth);
    double *v = calloc(n3, sizeof *v);
    for (size_t q = 2; q < n3; q += 3) v[q] = -5.0;
    cloth_set_velocities(core, v);
    free(v);
    return 0;
}

static void held_destroy(held_scene *r)
{
    dClothDestroy(r->cloth);
    dGeomDestroy(r->geoms[0]);
    dGeomDestroy(r->geoms[1]);
    dSpaceDestroy(r->space);
    dWorldDestroy(r->world);
}

/* Written after the second step held in a row, read into a new scene, m
 * steps on: bitwise the same, held steps included */
static void held_round_trip(int m)
{
    held_scene a, b;
    if (held_make(&a) || held_make(&b)) return;
    size_t n3 = 3 * (size_t)dClothGetVertexCount(a.cloth);
    int s = 0, in_row = 0, held_a = 0, held_b = 0;
    for (; s < 120 && in_row < 2; s++) {
        dClothWorldStep(a.world, &a.cloth, 1, H, 0);
        in_row = dClothGetStats(a.cloth)->held ? in_row + 1 : 0;
    }
    if (!CHECK(in_row == 2, "no two steps of the thrown cloth held in a row in %d", s)) return;
    CHECK(dClothWriteState(a.cloth, "plugin_state_file.state", a.geoms, 2, NULL, 0) == CLOTH_OK, "write held: %s",
          dClothGetLastError(a.cloth));
    dClothWorldStep(b.world, &b.cloth, 1, H, 0); /* somewhere else, to be overwritten */
    CHECK(dClothReadState(b.cloth, "plugin_state_file.state", b.geoms, 2, NULL, 0) == CLOTH_OK, "read held: %s",
          dClothGetLastError(b.cloth));
    for (int k = 0; k < m; k++) {
        CHECK(dClothWorldStep(a.world, &a.cloth, 1, H, 0) == CLOTH_OK, "held, step %d: %s", k,
              dClothGetLastError(a.cloth));
        CHECK(dClothWorldStep(b.world, &b.cloth, 1, H, 0) == CLOTH_OK, "held, read, step %d: %s", k,
              dClothGetLastError(b.cloth));
        held_a += dClothGetStats(a.cloth)->held;
        held_b += dClothGetStats(b.cloth)->held;
    }
    int same = memcmp(dClothGetPositions(a.cloth), dClothGetPositions(b.cloth), n3 * sizeof(double)) == 0 &&
               memcmp(cloth_velocities(dClothGetCore(a.cloth)), cloth_velocities(dClothGetCore(b.cloth)),
                      n3 * sizeof(double)) == 0;
    CHECK(same && held_a == held_b,
          "held: read after two held steps and run %d steps: differs from the "
          "uninterrupted run (%d and %d steps held)",
          m, held_a, held_b);
    CHECK(held_a > 0, "held: no step held after the file was written: the run's count is not tested");
    printf("held: written after step %d, the second held in a row, read into a new scene, %d steps on (%d held): "
           "%s\n",
           s, m, held_a, same ? "bitwise the uninterrupted run" : "DIFFERS");
    held_destroy(&a);
    held_destroy(&b);
}

int main(void)
{
    dInitODE2(0);
    const int N = 60, M = 40;

    /* 1. written at step N, read into a new scene: bitwise the same */
    round_trip(N, M, CLOTH_LINEARIZED);
    round_trip(N, M, CLOTH_NEWTON);
    held_round_trip(12);
    scene a, b;
    size_t n3;

    /* 2. a sleeping cloth: the snapshot goes by index */
    if (!make(&a, 3, 0, CLOTH_LINEARIZED) && !make(&b, 3, 0, CLOTH_LINEARIZED)) {
        dClothSetAutoSleep(a.cloth, 1, 0.05, 10);
        for (int s = 0; s < 300 && !dClothIsSleeping(a.cloth); s++) run(&a, 1);
        CHECK(dClothIsSleeping(a.cloth), "the small cloth never fell asleep");
        CHECK(write_state(&a, "plugin_state_file.state") == CLOTH_OK, "write asleep: %s", dClothGetLastError(a.cloth));
        CHECK(read_state(&b, "plugin_state_file.state") == CLOTH_OK && dClothIsSleeping(b.cloth), "read asleep: %s",
              dClothGetLastError(b.cloth));
        run(&a, 3);
        run(&b, 3);
        CHECK(dClothIsSleeping(b.cloth), "the read cloth woke with nothing moving");
        dGeomSetPosition(a.table, 0.01, 0, 0.2);
        dGeomSetPosition(b.table, 0.01, 0, 0.2);
        run(&a, 3);
        run(&b, 3);
        n3 = 3 * (size_t)dClothGetVertexCount(a.cloth);
        CHECK(!dClothIsSleeping(b.cloth) &&
                  memcmp(dClothGetPositions(a.cloth), dClothGetPositions(b.cloth), n3 * sizeof(double)) == 0,
              "the table moved: the read cloth wakes as the written one did");
        destroy(&a);
        destroy(&b);
    }

    bad_input();
    remove("plugin_state_file.state");
    remove("plugin_state_file.ref");
    remove("plugin_state_file.bad");
    dCloseODE();
    return check_summary();
}
