/* Plugin state files (dClothWriteState / dClothReadState): a dClothState in
 * a versioned binary file, geoms and bodies stored as indices into arrays
 * the caller names, so that a run continues bitwise in a new process.
 *
 * Format version 2, every number little-endian (u32, i32, u64, f64 as
 * IEEE 754 bits); geom and body fields are i32 indices, -1 for none:
 *   0   8   magic "ODCLPLUG"
 *   8   4   u32 format version (2; 1 is read too: no held run, no forces)
 *   12  4   u32 vertex count n
 *   16  8   u64 length L of the core's record
 *   24  L   the core's state record (cloth_state_write, its own format; an
 *           older, shorter core version is read too)
 *       sleep: i32 on, steps, still, asleep; f64 speed, gravity[3];
 *           i32 count k; k times: i32 geom, f64 position[3]
 *       f64 the surface callback's largest thickness so far (0: none)
 *       n contact records (308 bytes each, fields in xfer_contact's order)
 *       n pin records (80 bytes each: i32 active, i32 body, f64 local[3],
 *           world[3], force[3])
 *       i32 steps held in a row, 0 to DCLOTH_HOLD_MAX_HALVINGS (version 2 only)
 *       n f64[3] forces dClothAddVertexForce added for the next step
 *           (version 2 only)
 *   end-8 8 u64 FNV-1a 64 of every byte before it
 * The last step's stats are not kept: they describe a step, not the state. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "dcloth_internal.h"

#define PSTATE_MAGIC "ODCLPLUG"
#define PSTATE_VERSION 2u
#define PSTATE_HEADER 24u

/* One pass over a state's fields, writing them to buf or reading them from
 * it: the field order is written once (the xfer_* functions). */
typedef struct io {
    int reading;
    unsigned char *buf; /* writing: grown as needed; reading: the file   */
    size_t len, at, cap;
    const dGeomID *geoms;
    int ngeoms;
    const dBodyID *bodies;
    int nbodies;
    char where[48]; /* the record being transferred, for messages    */
    char err[320];  /* the first error; empty while all is well      */
} io;

/* Note the first error: "<record>: <field><what>". */
static void io_fail(io *s, const char *field, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void io_fail(io *s, const char *field, const char *fmt, ...)
{
    if (s->err[0]) return;
    char what[120];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    snprintf(s->err, sizeof s->err, "%s%s%s%s", s->where, s->where[0] ? ": " : "", field, what);
}

/* Room for k more bytes: the next k bytes of buf, or NULL after an error. */
static unsigned char *io_room(io *s, size_t k, const char *field)
{
    if (s->err[0]) return NULL;
    if (s->reading) {
        if (s->len - s->at < k) {
            io_fail(s, field, " runs past the end of the file (at byte %zu)", s->at);
            return NULL;
        }
    } else if (s->cap - s->at < k) {
        size_t cap = 2 * s->cap + k + 4096;
        unsigned char *b = realloc(s->buf, cap);
        if (!b) {
            snprintf(s->err, sizeof s->err, "out of memory");
            return NULL;
        }
        s->buf = b;
        s->cap = cap;
    }
    unsigned char *p = s->buf + s->at;
    s->at += k;
    return p;
}

static void io_u64(io *s, uint64_t *v, const char *field)
{
    unsigned char *p = io_room(s, 8, field);
    if (!p) return;
    if (s->reading) {
        *v = 0;
        for (int k = 7; k >= 0; k--) *v = *v << 8 | p[k];
    } else {
        for (int k = 0; k < 8; k++) p[k] = (unsigned char)(*v >> (8 * k));
    }
}

static uint32_t io_raw32(io *s, uint32_t v, const char *field)
{
    unsigned char *p = io_room(s, 4, field);
    if (!p) return 0;
    if (!s->reading) {
        for (int k = 0; k < 4; k++) p[k] = (unsigned char)(v >> (8 * k));
        return v;
    }
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* An int field, refused on reading outside [lo, hi]. */
static void io_int(io *s, int *v, int lo, int hi, const char *field)
{
    uint32_t u = io_raw32(s, (uint32_t)*v, field);
    if (!s->reading || s->err[0]) return;
    long long x = (long long)u - (u >> 31 ? 4294967296LL : 0);
    if (x < lo || x > hi) {
        io_fail(s, field, " = %lld is outside [%d, %d]", x, lo, hi);
        return;
    }
    *v = (int)x;
}

static void io_flag(io *s, int *v, const char *field) { io_int(s, v, 0, 1, field); }

/* k doubles, refused on reading unless finite. */
static void io_f64(io *s, double *v, int k, const char *field)
{
    for (int j = 0; j < k; j++) {
        uint64_t u = 0;
        if (!s->reading) memcpy(&u, &v[j], sizeof u);
        io_u64(s, &u, field);
        if (!s->reading || s->err[0]) continue;
        double d;
        memcpy(&d, &u, sizeof d);
        if (!isfinite(d)) {
            io_fail(s, field, "[%d] = %g is not finite", j, d);
            return;
        }
        v[j] = d;
    }
}

/* A pointer among n named ones (ptrs), as its index (-1 for NULL). */
static void io_ref(io *s, void **v, void *const *ptrs, int n, const char *field, const char *array)
{
    int idx = -1;
    if (!s->reading && *v) {
        for (idx = 0; idx < n && ptrs[idx] != *v; idx++) {
        }
        if (idx == n) {
            io_fail(s, field, " is %p, not in %s[]", *v, array);
            return;
        }
    }
    io_int(s, &idx, -1, n - 1, field);
    if (s->reading && !s->err[0]) *v = idx < 0 ? NULL : ptrs[idx];
}

static void io_geom(io *s, dGeomID *g, const char *field)
{
    void *p = *g;
    io_ref(s, &p, (void *const *)s->geoms, s->ngeoms, field, "geoms");
    *g = p;
}

static void io_body(io *s, dBodyID *b, const char *field)
{
    void *p = *b;
    io_ref(s, &p, (void *const *)s->bodies, s->nbodies, field, "bodies");
    *b = p;
}

static void xfer_contact(io *s, vcontact *c)
{
    io_geom(s, &c->geom, "geom");
    io_body(s, &c->body, "body");
    io_f64(s, c->normal, 3, "normal");
    io_f64(s, c->point, 3, "point");
    io_f64(s, &c->gap, 1, "gap");
    io_f64(s, c->vbody, 3, "vbody");
    io_flag(s, &c->sticking, "sticking");
    io_flag(s, &c->anchored, "anchored");
    io_f64(s, c->anchor, 3, "anchor");
    io_flag(s, &c->from_triangle, "from_triangle");
    io_f64(s, &c->weight, 1, "weight");
    io_flag(s, &c->active, "active");
    io_flag(s, &c->forced, "forced");
    io_flag(s, &c->candidate, "candidate");
    io_flag(s, &c->let_go, "let_go");
    io_flag(s, &c->slides, "slides");
    io_f64(s, c->friction, 3, "friction");
    io_f64(s, c->slip, 3, "slip");
    io_f64(s, c->force, 3, "force");
    io_geom(s, &c->opp_geom, "opp_geom");
    io_body(s, &c->opp_body, "opp_body");
    io_f64(s, c->opp_normal, 3, "opp_normal");
    io_f64(s, &c->opp_gap, 1, "opp_gap");
    io_f64(s, c->opp_vbody, 3, "opp_vbody");
    io_flag(s, &c->pinched, "pinched");
    io_f64(s, &c->thickness, 1, "thickness");
    io_f64(s, &c->mu, 1, "mu");
}

static void xfer_pin(io *s, vpin *p)
{
    io_flag(s, &p->active, "active");
    io_body(s, &p->body, "body");
    io_f64(s, p->local, 3, "local");
    io_f64(s, p->world, 3, "world");
    io_f64(s, p->force, 3, "force");
}

/* The sleep state and snapshot; on reading the snapshot arrays of st are
 * (re)allocated for the count the file gives. */
static void xfer_sleep(io *s, dClothState *st)
{
    struct sleep_state *z = &st->sleep;
    snprintf(s->where, sizeof s->where, "sleep");
    io_flag(s, &z->on, "on");
    io_int(s, &z->steps, 0, INT32_MAX, "steps");
    io_int(s, &z->still, 0, INT32_MAX, "still");
    io_flag(s, &z->asleep, "asleep");
    io_f64(s, &z->speed, 1, "speed");
    io_f64(s, z->gravity, 3, "gravity");
    /* each snapshot entry takes 28 bytes: the count cannot exceed the rest */
    size_t left = s->reading && s->at <= s->len ? (s->len - s->at) / 28 : 0;
    int hi = !s->reading || left > INT32_MAX ? INT32_MAX : (int)left;
    io_int(s, &z->n, 0, hi, "count");
    if (s->err[0]) return;
    if (s->reading && z->n > 0) {
        free(st->sleep_ids);
        free(st->sleep_geoms);
        st->sleep_ids = malloc((size_t)z->n * sizeof *st->sleep_ids);
        st->sleep_geoms = malloc(3 * (size_t)z->n * sizeof *st->sleep_geoms);
        if (!st->sleep_ids || !st->sleep_geoms) {
            snprintf(s->err, sizeof s->err, "out of memory");
            return;
        }
    }
    for (int k = 0; k < z->n && !s->err[0]; k++) {
        snprintf(s->where, sizeof s->where, "sleep geom %d", k);
        io_geom(s, &st->sleep_ids[k], "geom");
        io_f64(s, &st->sleep_geoms[3 * k], 3, "position");
    }
    if (!s->err[0] && z->on && (z->steps < 1 || !(z->speed > 0.0)))
        snprintf(s->err, sizeof s->err, "sleep: on with steps = %d, speed = %g (need >= 1 and > 0)", z->steps,
                 z->speed);
}

static uint64_t fnv1a(const unsigned char *p, size_t n)
{
    uint64_t h = 14695981039346656037ull;
    for (size_t k = 0; k < n; k++) h = (h ^ p[k]) * 1099511628211ull;
    return h;
}

/* Everything after the header's fixed part: the core record (length L known), sleep, contacts, pins,
 * then from version 2 the held run and pending forces (version 1: left zero as dClothStateCreate
 * made them). */
static void xfer_body(io *s, dClothState *st, size_t core_len, uint32_t version)
{
    unsigned char *core = io_room(s, core_len, "core state");
    if (!core) return;
    cloth_error e;
    memset(&e, 0, sizeof e);
    cloth_status r = s->reading ? cloth_state_read(st->core, core, core_len, &e)
                                : cloth_state_write(st->core, core, core_len, NULL, &e);
    if (r != CLOTH_OK) {
        snprintf(s->err, sizeof s->err, "core state: %s", e.message);
        return;
    }
    xfer_sleep(s, st);
    snprintf(s->where, sizeof s->where, "surface");
    io_f64(s, &st->surf_tmax, 1, "largest thickness");
    if (s->reading && !s->err[0] && !(st->surf_tmax >= 0.0 && st->surf_tmax <= DCLOTH_THICKNESS_MAX))
        io_fail(s, "largest thickness", " = %g is outside [0, %g]", st->surf_tmax, DCLOTH_THICKNESS_MAX);
    for (int i = 0; i < st->n && !s->err[0]; i++) {
        snprintf(s->where, sizeof s->where, "contact of vertex %d", i);
        xfer_contact(s, &st->vc[i]);
    }
    for (int i = 0; i < st->n && !s->err[0]; i++) {
        snprintf(s->where, sizeof s->where, "pin of vertex %d", i);
        xfer_pin(s, &st->pin[i]);
    }
    if (version >= 2u) {
        s->where[0] = 0;
        io_int(s, &st->held_run, 0, DCLOTH_HOLD_MAX_HALVINGS, "held run");
        for (int i = 0; i < st->n && !s->err[0]; i++) {
            snprintf(s->where, sizeof s->where, "pending force of vertex %d", i);
            io_f64(s, &st->fadd[3 * i], 3, "force");
        }
    }
    s->where[0] = 0;
}

static void io_names(io *s, const dGeomID *geoms, int ngeoms, const dBodyID *bodies, int nbodies)
{
    memset(s, 0, sizeof *s);
    s->geoms = geoms;
    s->ngeoms = geoms ? ngeoms : 0;
    s->bodies = bodies;
    s->nbodies = bodies ? nbodies : 0;
}

static cloth_status check_args(dClothID c, const char *fn, const char *path, int ngeoms, int nbodies)
{
    if (!c) return CLOTH_EINVAL;
    if (!path) return dcloth_fail(c, CLOTH_EINVAL, "%s: path is NULL", fn);
    if (!path[0]) return dcloth_fail(c, CLOTH_EINVAL, "%s: path is empty", fn);
    if (ngeoms < 0 || nbodies < 0)
        return dcloth_fail(c, CLOTH_EINVAL, "%s: ngeoms = %d and nbodies = %d must be >= 0", fn, ngeoms, nbodies);
    return CLOTH_OK;
}

cloth_status dClothWriteState(dClothID c, const char *path, const dGeomID *geoms, int ngeoms, const dBodyID *bodies,
                              int nbodies)
{
    cloth_status r = check_args(c, "dClothWriteState", path, ngeoms, nbodies);
    if (r != CLOTH_OK) return r;
    dClothState *st = dClothStateCreate(c);
    if (!st) return dcloth_fail(c, CLOTH_ENOMEM, "dClothWriteState: out of memory");
    r = dClothSave(c, st);
    io s;
    io_names(&s, geoms, ngeoms, bodies, nbodies);
    if (r == CLOTH_OK) {
        uint64_t core_len = cloth_state_size_bytes(st->core);
        unsigned char *h = io_room(&s, 8, "magic");
        if (h) memcpy(h, PSTATE_MAGIC, 8);
        io_raw32(&s, PSTATE_VERSION, "version");
        io_raw32(&s, (uint32_t)c->n, "vertex count");
        io_u64(&s, &core_len, "core length");
        xfer_body(&s, st, (size_t)core_len, PSTATE_VERSION);
        uint64_t sum = s.err[0] ? 0 : fnv1a(s.buf, s.at);
        io_u64(&s, &sum, "checksum");
        if (s.err[0]) {
            r = dcloth_fail(c, strcmp(s.err, "out of memory") ? CLOTH_EINVAL : CLOTH_ENOMEM, "dClothWriteState: %s",
                            s.err);
        } else {
            FILE *f = fopen(path, "wb");
            if (!f)
                r = dcloth_fail(c, CLOTH_EINVAL, "dClothWriteState: path %s cannot be opened: %s", path,
                                strerror(errno));
            else if ((fwrite(s.buf, 1, s.at, f) != s.at) | (fclose(f) != 0))
                r = dcloth_fail(c, CLOTH_EINVAL, "dClothWriteState: writing path %s failed", path);
        }
    }
    free(s.buf);
    dClothStateDestroy(st);
    return r;
}

/* The whole file into *buf (malloc'd); an error message or NULL. */
static const char *read_all(const char *path, unsigned char **buf, size_t *len)
{
    *buf = NULL;
    *len = 0;
    FILE *f = fopen(path, "rb");
    if (!f) return strerror(errno);
    size_t cap = 0, got;
    do {
        if (*len == cap) {
            unsigned char *b = realloc(*buf, cap = 2 * cap + 65536);
            if (!b) {
                fclose(f);
                return "out of memory";
            }
            *buf = b;
        }
        got = fread(*buf + *len, 1, cap - *len, f);
        *len += got;
    } while (got > 0);
    int bad = ferror(f), why = errno; /* a directory opens, then fails to read */
    fclose(f);
    return bad ? strerror(why) : NULL;
}

/* Check and decode the file s into st (made for c); s->err says why not. */
static void decode(io *s, dClothID c, dClothState *st)
{
    if (s->len < PSTATE_HEADER + 8 || memcmp(s->buf, PSTATE_MAGIC, 8) != 0) {
        snprintf(s->err, sizeof s->err, "not an odecloth plugin state (bad magic or %zu bytes)", s->len);
        return;
    }
    s->at = 8;
    uint32_t ver = io_raw32(s, 0, "version"), n = io_raw32(s, 0, "vertex count");
    uint64_t core_len = 0;
    io_u64(s, &core_len, "core length");
    if (ver != 1u && ver != PSTATE_VERSION) {
        snprintf(s->err, sizeof s->err, "format version %u, this library reads 1 and %u", (unsigned)ver,
                 PSTATE_VERSION);
        return;
    }
    if (n != (uint32_t)c->n) {
        snprintf(s->err, sizeof s->err, "the file is for %u vertices, the cloth has %d", (unsigned)n, c->n);
        return;
    }
    /* an older core record is shorter; the core's reader checks its length */
    if (core_len > cloth_state_size_bytes(st->core) || core_len > s->len) {
        snprintf(s->err, sizeof s->err, "core length %llu, this cloth's core record has %zu",
                 (unsigned long long)core_len, cloth_state_size_bytes(st->core));
        return;
    }
    uint64_t sum = 0;
    s->at = s->len - 8;
    io_u64(s, &sum, "checksum");
    if (sum != fnv1a(s->buf, s->len - 8)) {
        snprintf(s->err, sizeof s->err, "checksum mismatch (the file is damaged)");
        return;
    }
    s->at = PSTATE_HEADER;
    s->len -= 8;
    xfer_body(s, st, (size_t)core_len, ver);
    if (!s->err[0] && s->at != s->len)
        snprintf(s->err, sizeof s->err, "%zu bytes after the last %s record", s->len - s->at,
                 ver == 1u ? "pin" : "pending force");
}

cloth_status dcloth_read_state(dClothID c, const char *name, const unsigned char *buf, size_t len, const dGeomID *geoms,
                               int ngeoms, const dBodyID *bodies, int nbodies)
{
    io s;
    io_names(&s, geoms, ngeoms, bodies, nbodies);
    s.reading = 1;
    s.buf = (unsigned char *)buf; /* only read */
    s.len = len;
    dClothState *st = dClothStateCreate(c);
    if (!st) return dcloth_fail(c, CLOTH_ENOMEM, "dClothReadState: out of memory");
    memset(st->vc, 0, (size_t)c->n * sizeof *st->vc);
    memset(st->pin, 0, (size_t)c->n * sizeof *st->pin);
    decode(&s, c, st);
    cloth_status r;
    if (s.err[0]) {
        r = dcloth_fail(c, strcmp(s.err, "out of memory") ? CLOTH_EINVAL : CLOTH_ENOMEM, "dClothReadState: %s: %s",
                        name, s.err);
    } else {
        st->stats = c->stats;
        r = dClothRestore(c, st);
    }
    dClothStateDestroy(st);
    return r;
}

cloth_status dClothReadState(dClothID c, const char *path, const dGeomID *geoms, int ngeoms, const dBodyID *bodies,
                             int nbodies)
{
    cloth_status r = check_args(c, "dClothReadState", path, ngeoms, nbodies);
    if (r != CLOTH_OK) return r;
    unsigned char *buf;
    size_t len;
    const char *why = read_all(path, &buf, &len);
    r = why ? dcloth_fail(c, CLOTH_EINVAL, "dClothReadState: path %s cannot be read: %s", path, why)
            : dcloth_read_state(c, path, buf, len, geoms, ngeoms, bodies, nbodies);
    free(buf);
    return r;
}
