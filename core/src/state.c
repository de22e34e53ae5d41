/* The evolving state (positions, velocities, plastic state, step history)
 * apart from the model: save, restore, compare. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

int oc_state_alloc(struct cloth_state *s, int n, int n_int, int n_seq)
{
    memset(s, 0, sizeof *s);
    size_t n3 = 3 * (size_t)n;
    s->n = n;
    s->n_int = n_int;
    s->x = calloc(n3, sizeof *s->x);
    s->v = calloc(n3, sizeof *s->v);
    s->x_prev = calloc(n3, sizeof *s->x_prev);
    s->v_prev = calloc(n3, sizeof *s->v_prev);
    s->dv_prev = calloc(n3, sizeof *s->dv_prev);
    s->plastic = calloc((size_t)n_int + 1, sizeof *s->plastic);
    s->l1 = calloc((size_t)n_int + 1, sizeof *s->l1);
    s->perm = calloc((size_t)n_int + 1, sizeof *s->perm);
    s->bent = calloc((size_t)n_int + 1, sizeof *s->bent);
    s->n_seq = n_seq;
    s->lim_shift = calloc((size_t)n_seq + 1, sizeof *s->lim_shift);
    s->seq_set = calloc((size_t)n_seq + 1, sizeof *s->seq_set);
    if (!s->x || !s->v || !s->x_prev || !s->v_prev || !s->dv_prev || !s->plastic || !s->l1 || !s->perm || !s->bent ||
        !s->lim_shift || !s->seq_set) {
        oc_state_free(s);
        return -1;
    }
    return 0;
}

void oc_state_free(struct cloth_state *s)
{
    free(s->x);
    free(s->v);
    free(s->x_prev);
    free(s->v_prev);
    free(s->dv_prev);
    free(s->plastic);
    free(s->l1);
    free(s->perm);
    free(s->bent);
    free(s->lim_shift);
    free(s->seq_set);
    memset(s, 0, sizeof *s);
}

void oc_state_copy(struct cloth_state *dst, const struct cloth_state *src)
{
    size_t n3 = 3 * (size_t)src->n * sizeof(double);
    memcpy(dst->x, src->x, n3);
    memcpy(dst->v, src->v, n3);
    memcpy(dst->x_prev, src->x_prev, n3);
    memcpy(dst->v_prev, src->v_prev, n3);
    memcpy(dst->dv_prev, src->dv_prev, n3);
    memcpy(dst->plastic, src->plastic, (size_t)src->n_int * sizeof *src->plastic);
    memcpy(dst->l1, src->l1, (size_t)src->n_int * sizeof *src->l1);
    memcpy(dst->perm, src->perm, (size_t)src->n_int * sizeof *src->perm);
    memcpy(dst->bent, src->bent, (size_t)src->n_int * sizeof *src->bent);
    memcpy(dst->lim_shift, src->lim_shift, (size_t)src->n_seq * sizeof *src->lim_shift);
    memcpy(dst->seq_set, src->seq_set, (size_t)src->n_seq * sizeof *src->seq_set);
    dst->h_prev = src->h_prev;
    dst->has_prev = src->has_prev;
}

cloth_state *cloth_state_create(const cloth *c)
{
    if (!c) return NULL;
    cloth_state *s = malloc(sizeof *s);
    if (!s) return NULL;
    if (oc_state_alloc(s, c->n, c->n_int, c->n_seq) != 0) {
        free(s);
        return NULL;
    }
    return s;
}

void cloth_state_destroy(cloth_state *s)
{
    if (!s) return;
    oc_state_free(s);
    free(s);
}

cloth_status cloth_save(const cloth *c, cloth_state *s)
{
    if (!c) return CLOTH_EINVAL;
    if (!s) return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_save: state is NULL");
    if (s->n != c->n || s->n_int != c->n_int)
        return oc_cloth_fail((cloth *)c, CLOTH_EINVAL, "cloth_save: state was made for another cloth size");
    oc_state_copy(s, &c->st);
    return CLOTH_OK;
}

cloth_status cloth_restore(cloth *c, const cloth_state *s)
{
    if (!c) return CLOTH_EINVAL;
    if (!s) return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_restore: state is NULL");
    if (s->n != c->n || s->n_int != c->n_int)
        return oc_cloth_fail(c, CLOTH_EINVAL, "cloth_restore: state was made for another cloth size");
    oc_state_copy(&c->st, s);
    return CLOTH_OK;
}

static double maxdiff(const double *a, const double *b, size_t n, double m)
{
    for (size_t k = 0; k < n; k++) {
        double d = fabs(a[k] - b[k]);
        if (d > m || d != d) m = d != d ? INFINITY : d;
    }
    return m;
}

double cloth_state_diff(const cloth_state *a, const cloth_state *b)
{
    if (!a || !b || a->n != b->n || a->n_int != b->n_int) return -1.0;
    size_t n3 = 3 * (size_t)a->n;
    double m = maxdiff(a->x, b->x, n3, 0.0);
    m = maxdiff(a->v, b->v, n3, m);
    m = maxdiff(a->l1, b->l1, (size_t)a->n_int, m);
    m = maxdiff(a->perm, b->perm, (size_t)a->n_int, m);
    m = maxdiff(a->seq_set, b->seq_set, (size_t)a->n_seq, m);
    for (int e = 0; e < a->n_int; e++)
        if (a->plastic[e] != b->plastic[e] || a->bent[e] != b->bent[e]) return m + 1.0;
    return m;
}

/* ------------------------------------------------------------ state files
 *
 * Format version 4, every number little-endian, doubles as IEEE 754 bits:
 *   offset  size
 *   0       8     magic "ODCLSTAT"
 *   8       4     u32 format version (4; 3 is read too: no tension sets, read
 *                     as 0; 2 nor perm and bent, read as 0; 1 neither, nor the
 *                     multipliers)
 *   12      4     u32 vertex count n
 *   16      4     u32 interlaced link count m
 *   20      4     u32 has_prev (0 or 1)
 *   24      8     f64 h_prev (s; finite, >= 0, > 0 when has_prev)
 *   32      8*3n  f64 x      positions (m)
 *           8*3n  f64 v      velocities (m/s)
 *           8*3n  f64 x_prev previous positions (BDF2)
 *           8*3n  f64 v_prev previous velocities (BDF2)
 *           8*3n  f64 dv_prev last velocity change (warm start)
 *           8*m   f64 l1     plastic rest lengths (m, finite, > 0)
 *           m     u8  plastic flags (0 or 1)
 *           8*q   f64 lim_shift the elongation limit's multipliers (m, finite,
 *                     >= 0; q the state's sequential links; from version 2)
 *           8*m   f64 perm   permanent set of each interlaced link, a share of
 *                     its l0 (finite, in [0, 1); version 3)
 *           m     u8  bent flags (0 or 1; version 3)
 *           8*q   f64 seq_set tension set of each sequential link, a share of
 *                     its l0 (finite, >= 0; version 4)
 *   end-8   8     u64 FNV-1a 64 of every byte before it
 * Every value is checked on reading; nothing is changed unless all pass. */

#define STATE_MAGIC "ODCLSTAT"
#define STATE_VERSION 4u
#define STATE_HEADER 32u

/* A record's bytes: q multipliers, p = 1 with each link's perm and bent
 * (version 3), t = 1 with the tension sets (version 4), 0 without. */
static size_t state_bytes(size_t n, size_t m, size_t q, size_t p, size_t t)
{
    return STATE_HEADER + 8 * (15 * n + m + q + p * m + t * q) + m + p * m + 8;
}

size_t cloth_state_size_bytes(const cloth_state *s)
{
    return s ? state_bytes((size_t)s->n, (size_t)s->n_int, (size_t)s->n_seq, 1, 1) : 0;
}

static size_t state_record_bytes(const cloth_state *s, uint32_t version)
{
    size_t n = (size_t)s->n, m = (size_t)s->n_int, q = version > 1u ? (size_t)s->n_seq : 0;
    return version >= STATE_VERSION ? cloth_state_size_bytes(s) : state_bytes(n, m, q, version > 2u, 0);
}

static void put_u32(unsigned char *p, uint32_t v)
{
    for (int k = 0; k < 4; k++) p[k] = (unsigned char)(v >> (8 * k));
}

static void put_u64(unsigned char *p, uint64_t v)
{
    for (int k = 0; k < 8; k++) p[k] = (unsigned char)(v >> (8 * k));
}

static uint32_t get_u32(const unsigned char *p)
{
    uint32_t v = 0;
    for (int k = 0; k < 4; k++) v |= (uint32_t)p[k] << (8 * k);
    return v;
}

static uint64_t get_u64(const unsigned char *p)
{
    uint64_t v = 0;
    for (int k = 0; k < 8; k++) v |= (uint64_t)p[k] << (8 * k);
    return v;
}

static void put_f64(unsigned char *p, double d)
{
    uint64_t v;
    memcpy(&v, &d, sizeof v);
    put_u64(p, v);
}

static double get_f64(const unsigned char *p)
{
    uint64_t v = get_u64(p);
    double d;
    memcpy(&d, &v, sizeof d);
    return d;
}

static uint64_t fnv1a(const unsigned char *p, size_t n)
{
    uint64_t h = 14695981039346656037ull;
    for (size_t k = 0; k < n; k++) h = (h ^ p[k]) * 1099511628211ull;
    return h;
}

/* The five 3n arrays of a state, in file order. */
static void state_arrays(const struct cloth_state *s, double *a[5])
{
    a[0] = s->x;
    a[1] = s->v;
    a[2] = s->x_prev;
    a[3] = s->v_prev;
    a[4] = s->dv_prev;
}

cloth_status cloth_state_write(const cloth_state *s, void *buf, size_t cap, size_t *written, cloth_error *err)
{
    if (written) *written = 0;
    if (!s) return oc_error_set(err, CLOTH_EINVAL, "cloth_state_write: state is NULL");
    if (!buf) return oc_error_set(err, CLOTH_EINVAL, "cloth_state_write: buffer is NULL");
    size_t n = (size_t)s->n, m = (size_t)s->n_int, need = cloth_state_size_bytes(s);
    if (cap < need)
        return oc_error_set(err, CLOTH_EINVAL, "cloth_state_write: buffer of %zu bytes, the state needs %zu", cap,
                            need);
    unsigned char *p = buf, *q = p;
    memcpy(q, STATE_MAGIC, 8);
    put_u32(q + 8, STATE_VERSION);
    put_u32(q + 12, (uint32_t)n);
    put_u32(q + 16, (uint32_t)m);
    put_u32(q + 20, (uint32_t)(s->has_prev != 0));
    put_f64(q + 24, s->h_prev);
    q += STATE_HEADER;
    double *a[5];
    state_arrays(s, a);
    for (int k = 0; k < 5; k++)
        for (size_t i = 0; i < 3 * n; i++, q += 8) put_f64(q, a[k][i]);
    for (size_t e = 0; e < m; e++, q += 8) put_f64(q, s->l1[e]);
    for (size_t e = 0; e < m; e++) *q++ = s->plastic[e];
    for (int e = 0; e < s->n_seq; e++, q += 8) put_f64(q, s->lim_shift[e]);
    for (size_t e = 0; e < m; e++, q += 8) put_f64(q, s->perm[e]);
    for (size_t e = 0; e < m; e++) *q++ = s->bent[e];
    for (int e = 0; e < s->n_seq; e++, q += 8) put_f64(q, s->seq_set[e]);
    put_u64(q, fnv1a(p, (size_t)(q - p)));
    if (written) *written = need;
    return CLOTH_OK;
}

/* The version 3 fields at q: m permanent sets, then m bent flags; from version 4 (qs > 0), qs tension sets. */
static cloth_status check_perm(const unsigned char *q, size_t m, size_t qs, cloth_error *err)
{
    for (size_t e = 0; e < m; e++, q += 8) {
        double v = get_f64(q);
        if (!(v >= 0.0 && v < 1.0))
            return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: perm[%zu] = %g must be in [0, 1)", e, v);
    }
    for (size_t e = 0; e < m; e++, q++)
        if (*q > 1) return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: bent[%zu] = %u must be 0 or 1", e, *q);
    for (size_t e = 0; e < qs; e++, q += 8) {
        double v = get_f64(q);
        if (!(v >= 0.0 && isfinite(v)))
            return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: seq_set[%zu] = %g must be finite and >= 0", e, v);
    }
    return CLOTH_OK;
}

static const char *const array_name[5] = {"x", "v", "x_prev", "v_prev", "dv_prev"};

/* Check every field of a record for state s; CLOTH_OK or a message. */
static cloth_status check_record(const cloth_state *s, const unsigned char *p, size_t len, cloth_error *err)
{
    if (len < STATE_HEADER)
        return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: %zu bytes, shorter than the %u-byte header", len,
                            STATE_HEADER);
    if (memcmp(p, STATE_MAGIC, 8) != 0)
        return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: not an odecloth state (bad magic)");
    uint32_t ver = get_u32(p + 8), n = get_u32(p + 12), m = get_u32(p + 16), hp = get_u32(p + 20);
    if (ver < 1u || ver > STATE_VERSION)
        return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: format version %u, this library reads 1 to %u",
                            (unsigned)ver, STATE_VERSION);
    if (n != (uint32_t)s->n || m != (uint32_t)s->n_int)
        return oc_error_set(err, CLOTH_EINVAL,
                            "cloth_state_read: the record is for %u vertices and %u interlaced links, the state "
                            "for %d and %d",
                            (unsigned)n, (unsigned)m, s->n, s->n_int);
    size_t need = state_record_bytes(s, ver);
    if (len != need)
        return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: %zu bytes, a record of this size has %zu", len, need);
    uint64_t sum = get_u64(p + need - 8);
    if (sum != fnv1a(p, need - 8))
        return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: checksum mismatch (the record is damaged)");
    if (hp > 1) return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: has_prev = %u must be 0 or 1", (unsigned)hp);
    double hprev = get_f64(p + 24);
    if (!isfinite(hprev) || hprev < 0.0 || (hp && !(hprev > 0.0)))
        return oc_error_set(err, CLOTH_EINVAL,
                            "cloth_state_read: h_prev = %g must be finite and >= 0 (> 0 with "
                            "history)",
                            hprev);
    const unsigned char *q = p + STATE_HEADER;
    for (int k = 0; k < 5; k++)
        for (size_t i = 0; i < 3 * (size_t)n; i++, q += 8)
            if (!isfinite(get_f64(q)))
                return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: %s[%zu] is not finite", array_name[k], i);
    for (size_t e = 0; e < m; e++, q += 8) {
        double l1 = get_f64(q);
        if (!isfinite(l1) || !(l1 > 0.0))
            return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: l1[%zu] = %g must be finite and > 0", e, l1);
    }
    for (size_t e = 0; e < m; e++, q++)
        if (*q > 1) return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: plastic[%zu] = %u must be 0 or 1", e, *q);
    for (int e = 0; ver > 1u && e < s->n_seq; e++, q += 8) {
        double sh = get_f64(q);
        if (!isfinite(sh) || sh < 0.0)
            return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: lim_shift[%d] = %g must be finite and >= 0", e,
                                sh);
    }
    size_t qs = ver > 3u ? (size_t)s->n_seq : 0;
    return ver > 2u ? check_perm(p + need - 8 - 8 * qs - 9 * (size_t)m, m, qs, err) : CLOTH_OK;
}

cloth_status cloth_state_read(cloth_state *s, const void *buf, size_t len, cloth_error *err)
{
    if (!s) return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: state is NULL");
    if (!buf) return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read: buffer is NULL");
    const unsigned char *p = buf;
    cloth_status r = check_record(s, p, len, err);
    if (r != CLOTH_OK) return r;
    size_t n = (size_t)s->n, m = (size_t)s->n_int;
    s->has_prev = (int)get_u32(p + 20);
    s->h_prev = get_f64(p + 24);
    const unsigned char *q = p + STATE_HEADER;
    double *a[5];
    state_arrays(s, a);
    for (int k = 0; k < 5; k++)
        for (size_t i = 0; i < 3 * n; i++, q += 8) a[k][i] = get_f64(q);
    for (size_t e = 0; e < m; e++, q += 8) s->l1[e] = get_f64(q);
    for (size_t e = 0; e < m; e++) s->plastic[e] = *q++;
    /* the limit's multipliers: a version 1 record has none */
    memset(s->lim_shift, 0, (size_t)s->n_seq * sizeof *s->lim_shift);
    for (int e = 0; get_u32(p + 8) > 1u && e < s->n_seq; e++, q += 8) s->lim_shift[e] = get_f64(q);
    /* the permanent sets and bent flags: older records have none */
    memset(s->perm, 0, m * sizeof *s->perm);
    memset(s->bent, 0, m * sizeof *s->bent);
    for (size_t e = 0; get_u32(p + 8) > 2u && e < m; e++, q += 8) s->perm[e] = get_f64(q);
    for (size_t e = 0; get_u32(p + 8) > 2u && e < m; e++) s->bent[e] = *q++;
    /* the tension sets: older records have none */
    memset(s->seq_set, 0, (size_t)s->n_seq * sizeof *s->seq_set);
    for (int e = 0; get_u32(p + 8) > 3u && e < s->n_seq; e++, q += 8) s->seq_set[e] = get_f64(q);
    return CLOTH_OK;
}

cloth_status cloth_state_write_file(const cloth_state *s, FILE *f, cloth_error *err)
{
    if (!s) return oc_error_set(err, CLOTH_EINVAL, "cloth_state_write_file: state is NULL");
    if (!f) return oc_error_set(err, CLOTH_EINVAL, "cloth_state_write_file: file is NULL");
    size_t need = cloth_state_size_bytes(s);
    unsigned char *buf = malloc(need);
    if (!buf) return oc_error_set(err, CLOTH_ENOMEM, "cloth_state_write_file: no memory for %zu bytes", need);
    cloth_status r = cloth_state_write(s, buf, need, NULL, err);
    if (r == CLOTH_OK && fwrite(buf, 1, need, f) != need)
        r = oc_error_set(err, CLOTH_EINVAL, "cloth_state_write_file: writing %zu bytes failed", need);
    free(buf);
    return r;
}

cloth_status cloth_state_read_file(cloth_state *s, FILE *f, cloth_error *err)
{
    if (!s) return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read_file: state is NULL");
    if (!f) return oc_error_set(err, CLOTH_EINVAL, "cloth_state_read_file: file is NULL");
    /* exactly one record: the size of s's, read to its end and no further */
    size_t need = cloth_state_size_bytes(s);
    unsigned char *buf = malloc(need);
    if (!buf) return oc_error_set(err, CLOTH_ENOMEM, "cloth_state_read_file: no memory for %zu bytes", need);
    size_t got = fread(buf, 1, STATE_HEADER, f);
    cloth_status r;
    if (got == STATE_HEADER && memcmp(buf, STATE_MAGIC, 8) == 0 && get_u32(buf + 12) == (uint32_t)s->n &&
        get_u32(buf + 16) == (uint32_t)s->n_int && state_record_bytes(s, get_u32(buf + 8)) <= need)
        got += fread(buf + got, 1, state_record_bytes(s, get_u32(buf + 8)) - got, f);
    /* a short or foreign record: check_record names what is wrong */
    r = cloth_state_read(s, buf, got, err);
    if (r != CLOTH_OK && got < need && ferror(f))
        r = oc_error_set(err, CLOTH_EINVAL, "cloth_state_read_file: reading failed after %zu bytes", got);
    free(buf);
    return r;
}
