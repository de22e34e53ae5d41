/* Fuzz: the state file reader (cloth_state_read), the one file input of the
 * core.
 *
 * One entry point, fuzz_one() (= LLVMFuzzerTestOneInput), for a 3 x 4 cloth:
 * input byte 0 is a mode (bit 0: make the record's checksum right first, so
 * mutations reach the field checks; bit 1: step the restored cloth once with
 * substep retries on), the rest is a record. Asserted for every input:
 *   - refused: CLOTH_EINVAL with a message, the destination state unchanged;
 *   - accepted: written back, the bytes are the input's (a version 1
 *     record: written as the current version, it reads back the same); restored, every
 *     position and velocity is finite; stepped, the step returns OK (state
 *     finite) or ESTEP (state exactly the restored one).
 * A violation prints what and aborts (a crash for libFuzzer, a failure for
 * CTest).
 *
 * Built two ways:
 *   - CTest (label fuzz, gcc or clang, no libFuzzer): main() replays every
 *     file of test/corpus/state/ and then FUZZ_MUTATIONS deterministic random
 *     mutations of them (bit flips, interesting bytes and doubles, inserted,
 *     deleted and truncated bytes, splices) through fuzz_one().
 *     `fuzz_state --write-corpus DIR` writes the seed records.
 *   - `make fuzz` (clang -fsanitize=fuzzer,address,undefined,
 *     -DODECLOTH_LIBFUZZER): libFuzzer's own main drives fuzz_one() from the
 *     same corpus for a bounded time.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"
#include "records.h"

#define FUZZ_MUTATIONS 30000

static void die(const char *what, const uint8_t *data, size_t size) { fuzz_die("fuzz_state", what, data, size); }

static cloth *small_cloth(void)
{
    cloth_desc d = cloth_default_desc();
    d.rows = 3;
    d.cols = 4;
    d.solver.max_substep_halvings = 2;
    d.solver.cg_max_iterations = 200;
    cloth *c = NULL;
    if (cloth_create(&d, &c, NULL) != CLOTH_OK) return NULL;
    cloth_pin(c, 0, cloth_positions(c));
    return c;
}

static int finite_all(const double *a, size_t n)
{
    for (size_t k = 0; k < n; k++)
        if (!(a[k] - a[k] == 0.0)) return 0;
    return 1;
}

/* back (the current version, wr bytes) holds the older record rec (len
 * bytes) whole: the same bytes between the version and the checksum, then
 * multipliers of zero */
static int keeps_older(const uint8_t *rec, size_t len, const uint8_t *back, size_t wr)
{
    if (wr < len || memcmp(back + 12, rec + 12, len - 20) != 0) return 0;
    for (size_t k = len - 8; k < wr - 8; k++)
        if (back[k]) return 0;
    return 1;
}

/* what the inputs did: refused, accepted, stepped OK, step failed */
static long n_refused, n_accepted, n_stepped, n_step_failed;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0) return 0;
    int mode = data[0];
    size_t len = size - 1;
    uint8_t *rec = malloc(len + 1);
    if (!rec) return 0;
    memcpy(rec, data + 1, len);
    if (mode & 1) reseal(rec, len);
    cloth *c = small_cloth();
    cloth_state *st = cloth_state_create(c), *ref = cloth_state_create(c);
    if (!c || !st || !ref) die("setup failed", data, size);
    size_t n3 = 3 * (size_t)cloth_vertex_count(c);
    cloth_save(c, st);
    cloth_save(c, ref);
    cloth_error err;
    memset(&err, 0, sizeof err);
    cloth_status r = cloth_state_read(st, rec, len, &err);
    if (r != CLOTH_OK) {
        n_refused++;
        if (r != CLOTH_EINVAL) die("refused with a status other than EINVAL", data, size);
        if (!err.message[0]) die("refused without a message", data, size);
        if (cloth_state_diff(st, ref) != 0.0) die("a refused record changed the state", data, size);
    } else {
        n_accepted++;
        size_t need = cloth_state_size_bytes(st), wr = 0;
        uint8_t *back = malloc(need + 1);
        if (!back || cloth_state_write(st, back, need, &wr, &err) != CLOTH_OK || wr != need)
            die("an accepted record cannot be written back", data, size);
        if (wr == len && memcmp(back, rec, len) != 0)
            die("an accepted record does not write back to the same bytes", data, size);
        if (wr != len && !keeps_older(rec, len, back, wr)) /* a version 1 record, written as the current one */
            die("an accepted older record does not read back as the same state", data, size);
        free(back);
        if (cloth_restore(c, st) != CLOTH_OK) die("restore of an accepted record failed", data, size);
        if (!finite_all(cloth_positions(c), n3) || !finite_all(cloth_velocities(c), n3))
            die("an accepted record put NaN or inf in the cloth", data, size);
        if (mode & 2) {
            cloth_step_stats sts;
            cloth_status s = cloth_step(c, 1.0 / 60, &sts);
            if (s == CLOTH_OK) {
                n_stepped++;
                if (!finite_all(cloth_positions(c), n3) || !finite_all(cloth_velocities(c), n3))
                    die("a step from an accepted record left NaN or inf", data, size);
            } else {
                n_step_failed++;
                if (s != CLOTH_ESTEP) die("the step returned neither OK nor ESTEP", data, size);
                cloth_save(c, ref);
                if (cloth_state_diff(st, ref) != 0.0) die("a failed step changed the state", data, size);
            }
        }
    }
    free(rec);
    cloth_state_destroy(st);
    cloth_state_destroy(ref);
    cloth_destroy(c);
    return 0;
}

#ifndef ODECLOTH_LIBFUZZER

static int write_file(const char *dir, const char *name, int mode, const cloth_state *s)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    fputc(mode, f);
    cloth_error err;
    int rc = cloth_state_write_file(s, f, &err) == CLOTH_OK ? 0 : -1;
    fclose(f);
    return rc;
}

/* Seeds: the rest state; hung 30 steps (history, warm start); creased
 * (plastic links) and moving fast; then under the time-dependent law; then
 * stretched with tension plasticity (sequential links' sets). */
static int write_corpus(const char *dir)
{
    cloth *c = small_cloth();
    cloth_state *s = cloth_state_create(c);
    int rc = write_file(dir, "rest", 0, (cloth_save(c, s), s));
    for (int k = 0; k < 30; k++) cloth_step(c, 1.0 / 60, NULL);
    cloth_save(c, s);
    rc |= write_file(dir, "hung", 2, s);
    cloth_material m = cloth_get_desc(c).material;
    m.alpha = 1.0;
    cloth_set_material(c, &m);
    double v[36];
    for (int k = 0; k < 36; k++) v[k] = (k % 3 == 2) ? 5.0 : -1.0;
    cloth_set_velocities(c, v);
    for (int k = 0; k < 5; k++) cloth_step(c, 1.0 / 60, NULL);
    cloth_save(c, s);
    rc |= write_file(dir, "creased_fast", 3, s);
    /* the time-dependent plastic law: permanent sets and bent flags */
    m.tau_set = 0.05;
    m.tau_recover = 0.1;
    m.set_hardening = 0.5;
    cloth_set_material(c, &m);
    for (int k = 0; k < 36; k++) v[k] = -v[k];
    cloth_set_velocities(c, v);
    for (int k = 0; k < 10; k++) cloth_step(c, 1.0 / 60, NULL);
    cloth_save(c, s);
    rc |= write_file(dir, "creased_timed", 3, s);
    /* tension plasticity: the sequential links' sets */
    m.tension_yield = 1e-4;
    m.tension_set = 0.5;
    cloth_set_material(c, &m);
    for (int k = 0; k < 36; k++) v[k] = (k % 3 == 0) ? 4.0 * (k / 3 % 4) - 6.0 : 0.0;
    cloth_set_velocities(c, v);
    for (int k = 0; k < 5; k++) cloth_step(c, 1.0 / 60, NULL);
    cloth_save(c, s);
    rc |= write_file(dir, "stretched", 3, s);
    cloth_state_destroy(s);
    cloth_destroy(c);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "--write-corpus")) return write_corpus(argv[2]) ? 1 : 0;
    const char *dir = argc > 1 ? argv[1] : ODECLOTH_TEST_CORPUS "/state";
    long mutations = argc > 2 ? atol(argv[2]) : FUZZ_MUTATIONS;
    blob seeds[64];
    int ns = load_seeds(dir, seeds, 64);
    if (!CHECK(ns >= 0, "no corpus directory %s", dir)) return check_summary();
    CHECK(ns >= 3, "%d corpus files in %s, expected the 3 seeds at least", ns, dir);
    for (int k = 0; k < ns; k++) LLVMFuzzerTestOneInput(seeds[k].p, seeds[k].n);
    /* the seeds themselves must be valid records */
    cloth *c = small_cloth();
    cloth_state *s = cloth_state_create(c);
    int valid = 0;
    for (int k = 0; k < ns; k++)
        valid += seeds[k].n > 0 && cloth_state_read(s, seeds[k].p + 1, seeds[k].n - 1, NULL) == 0;
    CHECK(valid >= 3, "only %d valid records among the seeds", valid);
    cloth_state_destroy(s);
    cloth_destroy(c);
    fuzz_mutations(seeds, ns, mutations, 0x5eedf00du, LLVMFuzzerTestOneInput);
    printf("%d corpus files and %ld mutations through cloth_state_read: no violation; %ld refused, %ld "
           "accepted (%ld stepped, %ld steps failed and rolled back)\n",
           ns, mutations, n_refused, n_accepted, n_stepped, n_step_failed);
    CHECK(n_refused > 0 && n_accepted > mutations / 100 && n_stepped > 0 && n_step_failed > 0,
          "the mutations do not reach every outcome");
    for (int k = 0; k < ns; k++) free(seeds[k].p);
    return check_summary();
}
#endif
