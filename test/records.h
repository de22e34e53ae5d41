/* Binary records for the state-file tests and fuzzers (fuzz_state,
 * fuzz_plugin_state, plugin_state_file): whole files in memory, the
 * checksum made right after an edit, seeds from a corpus directory and
 * deterministic mutations of them (byte 0 of a seed is the fuzzer's mode). */
#ifndef ODECLOTH_TEST_RECORDS_H
#define ODECLOTH_TEST_RECORDS_H

#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"

#ifndef ODECLOTH_TEST_CORPUS
#define ODECLOTH_TEST_CORPUS "test/corpus"
#endif

/* a fuzzer's violation: say what, and abort (a crash for libFuzzer) */
static inline void fuzz_die(const char *fuzzer, const char *what, const uint8_t *data, size_t size)
{
    fprintf(stderr, "%s: %s (input of %zu bytes, mode %d)\n", fuzzer, what, size, size ? data[0] : -1);
    abort();
}

/* FNV-1a 64 of all but the last 8 bytes, written into them (the state
 * files' checksum, computed here on its own) */
static inline void reseal(uint8_t *p, size_t len)
{
    if (len < 8) return;
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t k = 0; k + 8 < len; k++) h = (h ^ p[k]) * 0x100000001b3ull;
    for (int k = 0; k < 8; k++) p[len - 8 + k] = (uint8_t)(h >> (8 * k));
}

typedef struct blob {
    uint8_t *p;
    size_t n;
} blob;

/* the whole file (p NULL if it cannot be opened) */
static inline blob read_all(const char *path)
{
    blob b = {NULL, 0};
    FILE *f = fopen(path, "rb");
    if (!f) return b;
    size_t cap = 1 << 16;
    b.p = malloc(cap);
    size_t got;
    while (b.p && (got = fread(b.p + b.n, 1, cap - b.n, f)) > 0) {
        b.n += got;
        if (b.n == cap) b.p = realloc(b.p, cap *= 2);
    }
    fclose(f);
    return b;
}

/* every file of dir (at most max) into seeds; their count, -1 without dir */
static inline int load_seeds(const char *dir, blob *seeds, int max)
{
    DIR *dp = opendir(dir);
    if (!dp) return -1;
    int ns = 0;
    struct dirent *de;
    while ((de = readdir(dp)) && ns < max) {
        if (de->d_name[0] == '.') continue;
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", dir, de->d_name);
        blob b = read_all(path);
        if (b.p) seeds[ns++] = b;
    }
    closedir(dp);
    return ns;
}

/* a copy of a random seed with 1-4 edits: bit flips, bytes, interesting
 * doubles and header u32s, truncation, insertion, deletion, splices */
static inline void mutate(rng *g, const blob *seeds, int ns, blob *out)
{
    static const double special[] = {0.0, -0.0, 1.0, -1.0, 1e-310, 1e308, -1e308, 1e300, 5e-324, 1.0 / 60, 0.05};
    const blob *s = &seeds[rng_u64(g) % (uint64_t)ns];
    size_t cap = s->n + 64;
    out->p = malloc(cap);
    memcpy(out->p, s->p, s->n);
    out->n = s->n;
    int edits = 1 + (int)(rng_u64(g) % 4);
    for (int e = 0; e < edits && out->n > 0; e++) {
        size_t at = (size_t)(rng_u64(g) % out->n);
        switch (rng_u64(g) % 9) {
        case 0: out->p[at] ^= (uint8_t)(1u << (rng_u64(g) % 8)); break; /* bit flip */
        case 1: out->p[at] = (uint8_t)rng_u64(g); break;                /* random byte */
        case 2: { /* an interesting double at an 8-aligned offset of the record */
            double d = rng_u64(g) % 2 ? special[rng_u64(g) % (sizeof special / sizeof special[0])]
                                      : (rng_u64(g) % 2 ? NAN : (rng_u64(g) % 2 ? INFINITY : -INFINITY));
            size_t off = 1 + ((at / 8) * 8);
            if (off + 8 <= out->n) memcpy(out->p + off, &d, 8);
            break;
        }
        case 3: { /* an interesting u32 in the header */
            static const uint32_t u[] = {0, 1, 2, 11, 12, 13, 0x7fffffff, 0xffffffff, 0x80000000};
            size_t off = 1 + 4 * (size_t)(2 + rng_u64(g) % 4);
            uint32_t val = u[rng_u64(g) % (sizeof u / sizeof u[0])];
            if (off + 4 <= out->n) memcpy(out->p + off, &val, 4);
            break;
        }
        case 4: out->n = at; break; /* truncate */
        case 5:                     /* insert bytes */
            if (out->n + 8 <= cap) {
                size_t k = 1 + (size_t)(rng_u64(g) % 8);
                memmove(out->p + at + k, out->p + at, out->n - at);
                for (size_t q = 0; q < k; q++) out->p[at + q] = (uint8_t)rng_u64(g);
                out->n += k;
            }
            break;
        case 6: { /* delete bytes */
            size_t k = 1 + (size_t)(rng_u64(g) % 8);
            if (at + k > out->n) k = out->n - at;
            memmove(out->p + at, out->p + at + k, out->n - at - k);
            out->n -= k;
            break;
        }
        case 7: { /* splice: the tail of another seed */
            const blob *o = &seeds[rng_u64(g) % (uint64_t)ns];
            size_t k = o->n > at ? o->n - at : 0;
            if (at + k > cap) k = cap - at;
            memcpy(out->p + at, o->p + at, k);
            out->n = at + k;
            break;
        }
        default: out->p[0] = (uint8_t)(rng_u64(g) % 4); break; /* mode */
        }
    }
}

/* count mutations of the seeds (a generator seeded with seed) through one */
static inline void fuzz_mutations(const blob *seeds, int ns, long count, uint64_t seed,
                                  int (*one)(const uint8_t *, size_t))
{
    rng g = rng_seed(seed);
    for (long k = 0; k < count && ns > 0; k++) {
        blob m;
        mutate(&g, seeds, ns, &m);
        one(m.p, m.n);
        free(m.p);
    }
}

#endif
