/* Unit: the state file format (cloth_state_write / _read and the FILE
 * versions).
 *
 * 1. Layout, checked against the documented offsets by hand-decoding here:
 *    magic, version 4, n, m, has_prev, h_prev, x[0], v of the last vertex,
 *    the last plastic flag, the last tension set; the size is
 *    32 + 8 (15 n + 2 m + 2 q) + 2 m + 8 (q sequential links: the
 *    elongation limit's multipliers and tension sets; per interlaced link its
 *    permanent set and bent flag); the checksum is FNV-1a 64 of the rest
 *    (computed here independently).
 * 2. Round trip: a 9 x 7 cloth hung for 40 steps (BDF2, so the history and
 *    warm start are non-trivial, and creased so some links are plastic):
 *    save, write, read into a fresh state: cloth_state_diff 0; written again,
 *    the bytes are identical. Through a tmpfile() too. Restoring the read
 *    state into a second cloth and stepping both 20 steps gives bitwise the
 *    same positions (the file keeps everything the step depends on). The
 *    scene has tension plasticity on, so some sequential links carry a set.
 * 3. Every damaged field is refused with a message naming it and the
 *    destination unchanged: short, long, magic, version, sizes, checksum,
 *    has_prev, h_prev (NaN, negative, 0 with history), a NaN / inf in each
 *    array, l1 <= 0, a plastic flag 2, a multiplier negative or NaN, a
 *    permanent set outside [0, 1), a bent flag 2, a tension set negative,
 *    NaN or inf (each
 *    with the checksum made right, so the field check itself is what
 *    refuses), NULL arguments, a small buffer.
 * 4. Version 1 (no multipliers), 2 (no permanent sets, bent flags) and 3
 *    (no tension sets) records still read, as the same state with those 0,
 *    into a state that held nonzero permanent sets, bent flags and tension
 *    sets.
 * 5. Newton's multipliers travel: a Newton-stepped cloth pulled past its
 *    limit (multipliers not all zero in the record) restored from a record
 *    into a new cloth steps on bitwise as the uninterrupted run.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "odecloth/cloth.h"
#include "check.h"

static uint64_t le64(const unsigned char *p)
{
    uint64_t v = 0;
    for (int k = 7; k >= 0; k--) v = v << 8 | p[k];
    return v;
}

static uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static double f64(const unsigned char *p)
{
    uint64_t v = le64(p);
    double d;
    memcpy(&d, &v, sizeof d);
    return d;
}

static void set_f64(unsigned char *p, double d)
{
    uint64_t v;
    memcpy(&v, &d, sizeof v);
    for (int k = 0; k < 8; k++) p[k] = (unsigned char)(v >> (8 * k));
}

static uint64_t fnv(const unsigned char *p, size_t n)
{
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t k = 0; k < n; k++) {
        h ^= p[k];
        h *= 0x100000001b3ull;
    }
    return h;
}

static void reseal(unsigned char *p, size_t len)
{
    uint64_t h = fnv(p, len - 8);
    for (int k = 0; k < 8; k++) p[len - 8 + k] = (unsigned char)(h >> (8 * k));
}

static cloth *scene(void)
{
    cloth_desc d = cloth_default_desc();
    d.rows = 9;
    d.cols = 7;
    d.solver.method = CLOTH_BDF2;
    d.material.alpha = 0.99;         /* creases early */
    d.material.tension_yield = 1e-4; /* the links at the pins stretch past it */
    d.material.tension_set = 0.5;
    cloth *c = NULL;
    cloth_error err;
    if (!CHECK(cloth_create(&d, &c, &err) == CLOTH_OK, "create: %s", err.message)) return NULL;
    const double *x = cloth_positions(c);
    cloth_pin(c, 0, x);
    cloth_pin(c, 3, x + 9);
    for (int s = 0; s < 40; s++) CHECK(cloth_step(c, 1.0 / 60, NULL) == CLOTH_OK, "step: %s", cloth_last_error(c));
    return c;
}

/* a copy of buf (len bytes, m interlaced, q sequential links) with every permanent set made perm, every
 * bent flag bent and every tension set perm, resealed (NULL on no memory) */
static unsigned char *with_perm(const unsigned char *buf, size_t len, size_t m, size_t q, double perm,
                                unsigned char bent)
{
    unsigned char *rec = malloc(len);
    if (!CHECK(rec != NULL, "no memory")) return NULL;
    memcpy(rec, buf, len);
    size_t end = len - 8 - 8 * q; /* where the tension sets start */
    for (size_t e = 0; e < m; e++) {
        set_f64(rec + end - 9 * m + 8 * e, perm);
        rec[end - m + e] = bent;
    }
    for (size_t e = 0; e < q; e++) set_f64(rec + end + 8 * e, perm);
    reseal(rec, len);
    return rec;
}

/* with_perm's record read into s */
static void read_with_perm(cloth_state *s, const unsigned char *buf, size_t len, size_t m, size_t q, double perm,
                           unsigned char bent)
{
    unsigned char *rec = with_perm(buf, len, m, q, perm, bent);
    cloth_error err;
    CHECK(rec && cloth_state_read(s, rec, len, &err) == CLOTH_OK, "a record with perm %g, bent %u: %s", perm, bent,
          err.message);
    free(rec);
}

/* 4: buf (len bytes, q multipliers, m interlaced links) made a version 1,
 * 2 or 3 record reads into sr, which held nonzero permanent sets, bent
 * flags and tension sets, as the same state with those zero (s0) */
static void older_version(cloth_state *s0, cloth_state *sr, const unsigned char *buf, size_t len, size_t q, size_t m)
{
    read_with_perm(s0, buf, len, m, q, 0.0, 0);
    unsigned char *zero = with_perm(buf, len, m, q, 0.0, 0); /* a version 3 record keeps perm and bent */
    for (unsigned char v = 1; zero && v <= 3; v++) {
        read_with_perm(sr, buf, len, m, q, 0.25, 1);
        CHECK(cloth_state_diff(s0, sr) != 0.0, "the permanent sets, bent flags and tension sets did not load");
        size_t len1 = len - 8 * q - (v < 3 ? 9 * m : 0) - (v == 1 ? 8 * q : 0);
        unsigned char *old = malloc(len1);
        memcpy(old, zero, len1 - 8);
        old[8] = v;
        reseal(old, len1);
        cloth_error err;
        CHECK(cloth_state_read(sr, old, len1, &err) == CLOTH_OK, "a version %u record refused: %s", v, err.message);
        CHECK(cloth_state_diff(s0, sr) == 0.0, "a version %u record reads as another state (sets, bent not 0)", v);
        free(old);
    }
    free(zero);
}

/* 5: a Newton cloth whose links are held at the limit by its multipliers */
static cloth *newton_scene(void)
{
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 7;
    d.solver.nonlinear = CLOTH_NEWTON;
    d.gravity[2] = -300.0; /* pulls the links at the pins past the limit */
    cloth *c = NULL;
    if (!CHECK(cloth_create(&d, &c, NULL) == CLOTH_OK, "create the Newton scene")) return NULL;
    cloth_pin(c, 0, cloth_positions(c));
    cloth_pin(c, 6, cloth_positions(c) + 18);
    return c;
}

static void newton_multipliers(void)
{
    cloth *a = newton_scene(), *b = newton_scene();
    if (!a || !b) return;
    for (int s = 0; s < 30; s++) CHECK(cloth_step(a, 1.0 / 60, NULL) == CLOTH_OK, "Newton step %d", s);
    cloth_state *st = cloth_state_create(a), *rd = cloth_state_create(b);
    cloth_save(a, st);
    size_t len = cloth_state_size_bytes(st), q = (size_t)cloth_link_count(a, CLOTH_SEQUENTIAL);
    unsigned char *rec = malloc(len);
    cloth_state_write(st, rec, len, NULL, NULL);
    int nonzero = 0;
    size_t tail = 9 * (size_t)cloth_link_count(a, CLOTH_INTERLACED) + 8 * q; /* permanent, tension sets, bent */
    for (size_t k = len - 8 - tail - 8 * q; k < len - 8 - tail; k++) nonzero += rec[k] != 0;
    CHECK(nonzero > 0, "the Newton scene's record has no multiplier: it does not test them");
    CHECK(cloth_state_read(rd, rec, len, NULL) == CLOTH_OK && cloth_restore(b, rd) == CLOTH_OK, "restore into b");
    int n3 = 3 * cloth_vertex_count(a), same = 1;
    for (int s = 0; s < 10; s++) {
        CHECK(cloth_step(a, 1.0 / 60, NULL) == CLOTH_OK && cloth_step(b, 1.0 / 60, NULL) == CLOTH_OK, "step");
        same = same && !memcmp(cloth_positions(a), cloth_positions(b), (size_t)n3 * sizeof(double));
    }
    CHECK(same, "a Newton run continued from a record differs from the uninterrupted one");
    free(rec);
    cloth_state_destroy(st);
    cloth_state_destroy(rd);
    cloth_destroy(a);
    cloth_destroy(b);
}

/* 3: each damaged field of buf (a record of len bytes: n vertices, m
 * interlaced, q sequential links) refused, with sr (reading as sa) unchanged;
 * bad has len bytes of room */
static void damaged(const cloth_state *sa, cloth_state *sr, const unsigned char *buf, unsigned char *bad, size_t len,
                    size_t n, size_t m, size_t q)
{
    const size_t tail = 9 * m;       /* the permanent sets and bent flags, before the tension sets */
    const size_t lend = len - 8 * q; /* the record's length without the tension sets */
    cloth_error err;
    struct {
        const char *what, *word;
        size_t off;
        int kind; /* 0 f64, 1 byte, 2 u32 */
        double val;
    } dmg[] = {
        {"magic", "magic", 0, 1, 'X'},
        {"version 5", "version", 8, 2, 5},
        {"version 0", "version", 8, 2, 0},
        {"n + 1", "vertices", 12, 2, (double)n + 1},
        {"m - 1", "interlaced", 16, 2, (double)m - 1},
        {"has_prev 2", "has_prev", 20, 2, 2},
        {"h_prev NaN", "h_prev", 24, 0, NAN},
        {"h_prev -1", "h_prev", 24, 0, -1},
        {"h_prev 0 with history", "h_prev", 24, 0, 0},
        {"x[0] NaN", "x[0]", 32, 0, NAN},
        {"v[5] inf", "v[5]", 32 + 8 * (3 * n + 5), 0, INFINITY},
        {"x_prev[1] -inf", "x_prev[1]", 32 + 8 * (6 * n + 1), 0, -INFINITY},
        {"v_prev last NaN", "v_prev", 32 + 8 * (12 * n - 1), 0, NAN},
        {"dv_prev[0] huge NaN", "dv_prev[0]", 32 + 8 * (12 * n), 0, -NAN},
        {"l1[0] = 0", "l1[0]", 32 + 8 * (15 * n), 0, 0},
        {"l1[last] = -1", "l1[", 32 + 8 * (15 * n + m - 1), 0, -1},
        {"l1[1] NaN", "l1[1]", 32 + 8 * (15 * n + 1), 0, NAN},
        {"plastic[0] = 2", "plastic[0]", 32 + 8 * (15 * n + m), 1, 2},
        {"plastic[last] = 255", "plastic[", lend - 9 - 8 * q - tail, 1, 255},
        {"lim_shift[0] = -1e-9", "lim_shift[0]", lend - 8 - 8 * q - tail, 0, -1e-9},
        {"lim_shift[last] NaN", "lim_shift[", lend - 16 - tail, 0, NAN},
        {"perm[0] = 1", "perm[0]", lend - 8 - tail, 0, 1.0},
        {"perm[last] = -1e-300", "perm[", lend - 16 - m, 0, -1e-300},
        {"perm[1] NaN", "perm[1]", lend - tail, 0, NAN},
        {"bent[0] = 2", "bent[0]", lend - 8 - m, 1, 2},
        {"bent[last] = 255", "bent[", lend - 9, 1, 255},
        {"seq_set[0] = -1e-9", "seq_set[0]", lend - 8, 0, -1e-9},
        {"seq_set[1] inf", "seq_set[1]", lend, 0, INFINITY},
        {"seq_set[last] NaN", "seq_set[", len - 16, 0, NAN},
    };
    for (size_t k = 0; k < sizeof dmg / sizeof dmg[0]; k++)
        for (int sealed = 0; sealed < 2; sealed++) {
            memcpy(bad, buf, len);
            if (dmg[k].kind == 0) set_f64(bad + dmg[k].off, dmg[k].val);
            else if (dmg[k].kind == 1) bad[dmg[k].off] = (unsigned char)dmg[k].val;
            else {
                uint32_t u = (uint32_t)dmg[k].val;
                for (int b = 0; b < 4; b++) bad[dmg[k].off + b] = (unsigned char)(u >> (8 * b));
            }
            if (sealed) reseal(bad, len);
            memset(&err, 0, sizeof err);
            cloth_status r = cloth_state_read(sr, bad, len, &err);
            CHECK(r == CLOTH_EINVAL, "%s (sealed %d) accepted", dmg[k].what, sealed);
            CHECK(cloth_state_diff(sa, sr) == 0.0, "%s: the refused record changed the state", dmg[k].what);
            /* sealed: the field check names it (the magic, version and sizes
             * come before the checksum; unsealed others hit the checksum) */
            const char *want = sealed || k < 5 ? dmg[k].word : "checksum";
            CHECK(strstr(err.message, want) != NULL, "%s (sealed %d): message '%s' does not name '%s'", dmg[k].what,
                  sealed, err.message, want);
        }
}

int main(void)
{
    cloth *a = scene(), *b = scene();
    if (!a || !b) return check_summary();
    int n = cloth_vertex_count(a), m = cloth_link_count(a, CLOTH_INTERLACED), q = cloth_link_count(a, CLOTH_SEQUENTIAL);
    cloth_state *sa = cloth_state_create(a), *sr = cloth_state_create(a);
    cloth_save(a, sa);
    size_t len = cloth_state_size_bytes(sa);
    CHECK(len == 32 + 8 * (15 * (size_t)n + 2 * (size_t)m + 2 * (size_t)q) + 2 * (size_t)m + 8, "size %zu", len);
    const size_t tail = 9 * (size_t)m + 8 * (size_t)q; /* permanent sets, bent flags, tension sets */
    CHECK(cloth_state_size_bytes(NULL) == 0, "size of NULL");
    unsigned char *buf = malloc(len + 1), *buf2 = malloc(len + 1), *bad = malloc(len + 1);
    size_t wr = 0;
    cloth_error err;
    CHECK(cloth_state_write(sa, buf, len, &wr, &err) == CLOTH_OK && wr == len, "write: %s", err.message);

    /* 1. layout */
    const double *x = cloth_positions(a), *v = cloth_velocities(a);
    cloth_link lk;
    cloth_get_link(a, CLOTH_INTERLACED, m - 1, &lk);
    int nplastic = 0;
    for (int e = 0; e < m; e++) {
        cloth_link l;
        cloth_get_link(a, CLOTH_INTERLACED, e, &l);
        nplastic += l.plastic;
    }
    CHECK(memcmp(buf, "ODCLSTAT", 8) == 0, "magic");
    CHECK(le32(buf + 8) == 4 && le32(buf + 12) == (uint32_t)n && le32(buf + 16) == (uint32_t)m, "version %u n %u m %u",
          le32(buf + 8), le32(buf + 12), le32(buf + 16));
    CHECK(le32(buf + 20) == 1 && f64(buf + 24) == 1.0 / 60, "has_prev %u h_prev %g", le32(buf + 20), f64(buf + 24));
    CHECK(f64(buf + 32) == x[0], "x[0] %g vs %g", f64(buf + 32), x[0]);
    CHECK(f64(buf + 32 + 8 * (6 * (size_t)n - 1)) == v[3 * n - 1], "v[3n-1]");
    CHECK(buf[len - 9 - 8 * (size_t)q - tail] == lk.plastic, "last plastic flag");
    cloth_link ls;
    cloth_get_link(a, CLOTH_SEQUENTIAL, q - 1, &ls);
    CHECK(ls.rest + f64(buf + len - 16) * ls.rest == ls.l1, "last tension set: %g", f64(buf + len - 16));
    int nset = 0;
    for (int e = 0; e < q; e++) {
        cloth_link l;
        cloth_get_link(a, CLOTH_SEQUENTIAL, e, &l);
        nset += l.plastic;
    }
    CHECK(le64(buf + len - 8) == fnv(buf, len - 8), "checksum");
    printf("%d vertices, %d interlaced links (%d plastic), %d sequential (%d set): a record of %zu bytes\n", n, m,
           nplastic, q, nset, len);
    CHECK(nplastic > 0, "no plastic link: the scene does not test the flags");
    CHECK(nset > 0, "no tension set: the scene does not test them");

    /* 2. round trips */
    CHECK(cloth_state_read(sr, buf, len, &err) == CLOTH_OK, "read: %s", err.message);
    CHECK(cloth_state_diff(sa, sr) == 0.0, "read back differs: %g", cloth_state_diff(sa, sr));
    CHECK(cloth_state_write(sr, buf2, len + 1, &wr, &err) == CLOTH_OK && wr == len, "write 2: %s", err.message);
    CHECK(memcmp(buf, buf2, len) == 0, "written twice, the bytes differ");
    FILE *f = tmpfile();
    if (CHECK(f != NULL, "tmpfile")) {
        CHECK(cloth_state_write_file(sa, f, &err) == CLOTH_OK, "write_file: %s", err.message);
        CHECK(cloth_state_write_file(sa, f, &err) == CLOTH_OK, "write_file 2: %s", err.message);
        rewind(f);
        cloth_state *sf = cloth_state_create(a);
        CHECK(cloth_state_read_file(sf, f, &err) == CLOTH_OK, "read_file: %s", err.message);
        CHECK(cloth_state_diff(sa, sf) == 0.0, "file round trip differs");
        CHECK(cloth_state_read_file(sf, f, &err) == CLOTH_OK, "read_file (second record): %s", err.message);
        CHECK(cloth_state_read_file(sf, f, &err) == CLOTH_EINVAL, "read_file past the end accepted");
        printf("reading past the end: %s\n", err.message);
        cloth_state_destroy(sf);
        fclose(f);
    }
    CHECK(cloth_restore(b, sr) == CLOTH_OK, "restore into b");
    for (int s = 0; s < 20; s++) {
        cloth_step(a, 1.0 / 60, NULL);
        cloth_step(b, 1.0 / 60, NULL);
    }
    CHECK(memcmp(cloth_positions(a), cloth_positions(b), 3 * (size_t)n * sizeof(double)) == 0,
          "20 steps after a file round trip, positions differ from the uninterrupted run");
    CHECK(memcmp(cloth_velocities(a), cloth_velocities(b), 3 * (size_t)n * sizeof(double)) == 0,
          "20 steps after a file round trip, velocities differ");

    damaged(sa, sr, buf, bad, len, (size_t)n, (size_t)m, (size_t)q);
    memcpy(bad, buf, len);
    bad[len] = 0;
    CHECK(cloth_state_read(sr, bad, len + 1, &err) == CLOTH_EINVAL, "one byte too many accepted");
    CHECK(cloth_state_read(sr, bad, len - 1, &err) == CLOTH_EINVAL, "one byte short accepted");
    CHECK(cloth_state_read(sr, bad, 0, &err) == CLOTH_EINVAL, "0 bytes accepted");
    CHECK(cloth_state_read(sr, bad, 31, &err) == CLOTH_EINVAL, "31 bytes accepted");
    bad[40] ^= 1;
    CHECK(cloth_state_read(sr, bad, len, &err) == CLOTH_EINVAL && strstr(err.message, "checksum"),
          "a flipped bit accepted: %s", err.message);
    CHECK(cloth_state_diff(sa, sr) == 0.0, "the refused records changed the state");
    CHECK(cloth_state_read(NULL, buf, len, &err) == CLOTH_EINVAL, "NULL state");
    CHECK(cloth_state_read(sr, NULL, len, &err) == CLOTH_EINVAL, "NULL buffer");
    CHECK(cloth_state_read(sr, buf, len, NULL) == CLOTH_OK, "NULL err must be fine");
    CHECK(cloth_state_write(NULL, buf2, len, &wr, &err) == CLOTH_EINVAL && wr == 0, "write NULL state");
    CHECK(cloth_state_write(sa, NULL, len, &wr, &err) == CLOTH_EINVAL, "write NULL buffer");
    CHECK(cloth_state_write(sa, buf2, len - 1, &wr, &err) == CLOTH_EINVAL && wr == 0, "write into a short buffer");
    CHECK(cloth_state_write_file(sa, NULL, &err) == CLOTH_EINVAL, "write_file NULL file");
    CHECK(cloth_state_read_file(sr, NULL, &err) == CLOTH_EINVAL, "read_file NULL file");
    CHECK(cloth_state_read_file(NULL, stdin, &err) == CLOTH_EINVAL, "read_file NULL state");
    /* a record for another size */
    cloth_desc d = cloth_default_desc();
    d.rows = d.cols = 3;
    cloth *small = NULL;
    cloth_create(&d, &small, &err);
    cloth_state *ss = cloth_state_create(small);
    CHECK(cloth_state_read(ss, buf, len, &err) == CLOTH_EINVAL && strstr(err.message, "vertices"),
          "a record for another cloth size accepted: %s", err.message);
    cloth_state_destroy(ss);
    cloth_destroy(small);

    cloth_state *s0 = cloth_state_create(a);
    older_version(s0, sr, buf, len, (size_t)q, (size_t)m);
    cloth_state_destroy(s0);
    newton_multipliers();
    free(buf);
    free(buf2);
    free(bad);
    cloth_state_destroy(sa);
    cloth_state_destroy(sr);
    cloth_destroy(a);
    cloth_destroy(b);
    return check_summary();
}
