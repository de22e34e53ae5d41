/* Fuzz: the plugin's state file reader (dClothReadState, through
 * dcloth_read_state on the file's bytes).
 *
 * One entry point, fuzz_one() (= LLVMFuzzerTestOneInput), for a 3 x 3
 * cloth over a box table with its corner pinned to a free body, the arrays
 * {table} and {body}: input byte 0 is a mode (bit 0: make the file's
 * checksum right first, so mutations reach the field checks; bit 1: step the
 * read cloth once), the rest is a file. Asserted for every input:
 *   - refused: CLOTH_EINVAL with a message, the cloth unchanged;
 *   - accepted: every position and velocity finite; stepped, the step
 *     returns OK (finite) or ESTEP.
 * A violation prints what and aborts. The cloth is put back after each input.
 *
 * CTest (label fuzz): main() replays test/corpus/plugin_state/ and
 * FUZZ_MUTATIONS deterministic mutations of it (records.h).
 * `fuzz_plugin_state --write-corpus DIR` writes the seeds. `make fuzz` builds
 * it with libFuzzer, the plugin and ODE.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dcloth_internal.h"
#include "check.h"
#include "records.h"

#define FUZZ_MUTATIONS 20000

static void die(const char *what, const uint8_t *data, size_t size) { fuzz_die("fuzz_plugin_state", what, data, size); }

typedef struct scene {
    dWorldID world;
    dSpaceID space;
    dGeomID table;
    dBodyID body;
    dClothID cloth;
} scene;

/* the scene, hanging (corner pinned to the body) or not */
static int make(scene *r, int hang)
{
    r->world = dWorldCreate();
    dWorldSetGravity(r->world, 0, 0, -9.81);
    r->space = dHashSpaceCreate(0);
    r->table = dCreateBox(r->space, 0.4, 0.4, 0.4);
    dGeomSetPosition(r->table, 0, 0, 0.2);
    r->body = dBodyCreate(r->world);
    dMass m;
    dMassSetSphereTotal(&m, 0.05, 0.03);
    dBodySetMass(r->body, &m);
    dBodySetPosition(r->body, -0.3, -0.3, 0.45);
    dClothDesc d = dClothDefaultDesc();
    d.cloth.rows = d.cloth.cols = 3;
    d.cloth.width = d.cloth.height = 0.6;
    d.cloth.origin[0] = d.cloth.origin[1] = -0.3;
    d.cloth.origin[2] = 0.45;
    d.cloth.solver.max_substep_halvings = 2;
    d.mu = 0.5;
    if (dClothCreate(r->world, r->space, &d, &r->cloth, NULL) != CLOTH_OK) return -1;
    dClothSetFailureMode(r->cloth, DCLOTH_FAILURE_STOP);
    const dReal local[3] = {0, 0, 0};
    return hang ? (int)dClothPinToBody(r->cloth, 0, r->body, local) : 0;
}

static void destroy(scene *r)
{
    dClothDestroy(r->cloth);
    dGeomDestroy(r->table);
    dBodyDestroy(r->body);
    dSpaceDestroy(r->space);
    dWorldDestroy(r->world);
}

static int same(const dClothState *a, const dClothState *b)
{
    size_t n = (size_t)a->n;
    return cloth_state_diff(a->core, b->core) == 0.0 && memcmp(a->vc, b->vc, n * sizeof *a->vc) == 0 &&
           memcmp(a->pin, b->pin, n * sizeof *a->pin) == 0 && memcmp(a->fadd, b->fadd, 3 * n * sizeof *a->fadd) == 0 &&
           a->held_run == b->held_run && a->sleep.on == b->sleep.on && a->sleep.asleep == b->sleep.asleep &&
           a->sleep.n == b->sleep.n && a->sleep.still == b->sleep.still;
}

static int finite_all(const double *a, size_t n)
{
    for (size_t k = 0; k < n; k++)
        if (!(a[k] - a[k] == 0.0)) return 0;
    return 1;
}

static scene S;
static dClothState *base, *now;
/* what the inputs did: refused, accepted, stepped OK, step failed */
static long n_refused, n_accepted, n_stepped, n_step_failed;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0) return 0;
    if (!base) {
        dInitODE2(0);
        if (make(&S, 1) || !(base = dClothStateCreate(S.cloth)) || !(now = dClothStateCreate(S.cloth)))
            die("setup failed", data, size);
        dClothSave(S.cloth, base);
    }
    int mode = data[0];
    size_t len = size - 1;
    uint8_t *rec = malloc(len + 1);
    if (!rec) return 0;
    memcpy(rec, data + 1, len);
    if (mode & 1) reseal(rec, len);
    size_t n3 = 3 * (size_t)S.cloth->n;
    cloth_status r = dcloth_read_state(S.cloth, "input", rec, len, &S.table, 1, &S.body, 1);
    if (r != CLOTH_OK) {
        n_refused++;
        if (r != CLOTH_EINVAL) die("refused with a status other than EINVAL", data, size);
        if (!dClothGetLastError(S.cloth)[0]) die("refused without a message", data, size);
        dClothSave(S.cloth, now);
        if (!same(now, base)) die("a refused file changed the cloth", data, size);
    } else {
        n_accepted++;
        if (!finite_all(dClothGetPositions(S.cloth), n3) || !finite_all(cloth_velocities(S.cloth->core), n3))
            die("an accepted file put NaN or inf in the cloth", data, size);
        if (mode & 2) {
            cloth_status s = dClothStep(S.cloth, 1.0 / 60);
            if (s == CLOTH_OK) {
                n_stepped++;
                if (!finite_all(dClothGetPositions(S.cloth), n3)) die("a step left NaN or inf", data, size);
            } else if (s == CLOTH_ESTEP) {
                n_step_failed++;
            } else {
                die("the step returned neither OK nor ESTEP", data, size);
            }
            dBodySetForce(S.body, 0, 0, 0);
            dBodySetTorque(S.body, 0, 0, 0);
        }
        dClothRestore(S.cloth, base);
    }
    free(rec);
    return 0;
}

#ifndef ODECLOTH_LIBFUZZER

static int write_seed(const char *dir, const char *name, int mode, scene *r)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (dClothWriteState(r->cloth, path, &r->table, 1, &r->body, 1) != CLOTH_OK) return -1;
    blob b = read_all(path);
    FILE *f = fopen(path, "wb");
    int rc = b.p && f && fputc(mode, f) == mode && fwrite(b.p, 1, b.n, f) == b.n ? 0 : -1;
    if (f) fclose(f);
    free(b.p);
    return rc;
}

/* Seeds: the rest state; hung 30 steps (contacts, the pin's force) with a
 * force pending for the next step; without the body, asleep on the table
 * (the sleep snapshot). */
static int write_corpus(const char *dir)
{
    dInitODE2(0);
    scene a, b;
    if (make(&a, 1) || make(&b, 0)) return 1;
    int rc = write_seed(dir, "rest", 0, &a);
    for (int k = 0; k < 30; k++) dClothWorldStep(a.world, &a.cloth, 1, 1.0 / 60, 0);
    rc |= dClothAddVertexForce(a.cloth, 4, 0.01, -0.02, 0.03) != CLOTH_OK;
    rc |= write_seed(dir, "hung", 2, &a);
    dClothSetAutoSleep(b.cloth, 1, 0.05, 10);
    for (int k = 0; k < 300 && !dClothIsSleeping(b.cloth); k++) dClothWorldStep(b.world, &b.cloth, 1, 1.0 / 60, 0);
    rc |= !dClothIsSleeping(b.cloth);
    rc |= write_seed(dir, "asleep", 3, &b);
    destroy(&a);
    destroy(&b);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "--write-corpus")) return write_corpus(argv[2]) ? 1 : 0;
    const char *dir = argc > 1 ? argv[1] : ODECLOTH_TEST_CORPUS "/plugin_state";
    long mutations = argc > 2 ? atol(argv[2]) : FUZZ_MUTATIONS;
    blob seeds[64];
    int ns = load_seeds(dir, seeds, 64);
    if (!CHECK(ns >= 6, "%d corpus files in %s, expected the 6 seeds", ns, dir)) return check_summary();
    long before = n_accepted;
    for (int k = 0; k < ns; k++) LLVMFuzzerTestOneInput(seeds[k].p, seeds[k].n);
    CHECK(n_accepted - before == ns, "only %ld of the %d seeds are valid files", n_accepted - before, ns);
    fuzz_mutations(seeds, ns, mutations, 0x5eedf11eu, LLVMFuzzerTestOneInput);
    printf("%d corpus files and %ld mutations through dClothReadState: no violation; %ld refused, %ld accepted "
           "(%ld stepped, %ld steps failed)\n",
           ns, mutations, n_refused, n_accepted, n_stepped, n_step_failed);
    CHECK(n_refused > 0 && n_accepted > mutations / 100 && n_stepped > 0, "the mutations do not reach every outcome");
    for (int k = 0; k < ns; k++) free(seeds[k].p);
    dClothStateDestroy(base);
    dClothStateDestroy(now);
    destroy(&S);
    dCloseODE();
    return check_summary();
}
#endif
