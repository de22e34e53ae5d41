/* Fuzz: the demos' command-line parser (demo_parse, examples/common/
 * options.c), the project's one text input.
 *
 * One entry point (= LLVMFuzzerTestOneInput): the input, split at NUL bytes,
 * is the argument list (at most 32 arguments after the program name).
 * Asserted for every input: demo_parse returns 0 (parsed), 1 (--help) or 2
 * (refused, with a message); when it returns 0 every field is within what
 * its usage text promises: grid 3..161, steps per second 10..10000, 0..8
 * alphas each in [0, 1], frames 0..1000, smooth 0..3, picture 32..4096
 * pixels a side, a known material, a known fabric and not with --material,
 * a removal 0..2, a crease grip and a crease law in [0, 100], a non-empty output directory, flags 0 or
 * 1. A violation prints the arguments and aborts.
 *
 * CTest (label fuzz): main() replays test/corpus/options/ and 30,000
 * deterministic mutations (bytes, NULs, numbers, option names swapped in
 * and out). The parser's messages go to /dev/null while it runs.
 * `fuzz_options --write-corpus DIR` writes the seeds. `make fuzz` builds it
 * with libFuzzer, with examples/common/options.c and ODE.
 *
 * Note: on success demo_parse also initialises ODE and registers
 * dCloseODE with atexit (a parser with side effects), so
 * every accepted input adds an atexit entry; harmless at this count. */
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "demo.h"
#include "check.h"

#ifndef ODECLOTH_TEST_CORPUS
#define ODECLOTH_TEST_CORPUS "test/corpus"
#endif

#define MAX_ARGS 32

static long n_parsed, n_help, n_refused;

static void violation(const char *what, int argc, char **argv)
{
    fprintf(stderr, "fuzz_options: %s; arguments:", what);
    for (int a = 1; a < argc; a++) fprintf(stderr, " '%s'", argv[a]);
    fputc('\n', stderr);
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *buf = malloc(size + 1);
    if (!buf) return 0;
    memcpy(buf, data, size);
    buf[size] = '\0';
    char *argv[MAX_ARGS + 2];
    int argc = 0;
    argv[argc++] = "fuzz_options";
    for (size_t k = 0; k < size && argc <= MAX_ARGS;) {
        argv[argc++] = buf + k;
        k += strlen(buf + k) + 1;
    }
    argv[argc] = NULL;
    /* the parser's messages (help on stdout, refusals on stderr) go to
     * /dev/null; ours and the sanitizers' keep the real ones */
    static int saved_out = -1, saved_err = -1, devnull = -1;
    if (devnull < 0) {
        devnull = open("/dev/null", O_WRONLY);
        saved_out = dup(1);
        saved_err = dup(2);
    }
    fflush(stdout);
    fflush(stderr);
    if (devnull >= 0) {
        dup2(devnull, 1);
        dup2(devnull, 2);
    }
    demo_opts o;
    int r = demo_parse(&o, "fuzz_options", "usage: fuzz_options [options]\n", argc, argv);
    fflush(stdout);
    fflush(stderr);
    if (devnull >= 0) {
        dup2(saved_out, 1);
        dup2(saved_err, 2);
    }
    if (r == 1) n_help++;
    else if (r == 2) n_refused++;
    else if (r != 0) violation("demo_parse returned neither 0, 1 nor 2", argc, argv);
    else {
        n_parsed++;
        if (o.grid < 3 || o.grid > 161) violation("grid out of 3..161", argc, argv);
        if (!(o.hz >= 10.0 && o.hz <= 10000.0)) violation("steps per second out of 10..10000", argc, argv);
        if (o.nalpha < 0 || o.nalpha > DEMO_MAX_ALPHAS) violation("alpha count out of range", argc, argv);
        for (int k = 0; k < o.nalpha; k++)
            if (!(o.alphas[k] >= 0.0 && o.alphas[k] <= 1.0)) violation("an alpha out of [0, 1]", argc, argv);
        if (o.frames < 0 || o.frames > 1000) violation("frames out of 0..1000", argc, argv);
        if (o.smooth < 0 || o.smooth > 3) violation("smooth out of 0..3", argc, argv);
        if (o.width < 32 || o.width > 4096 || o.height < 32 || o.height > 4096)
            violation("picture size out of 32..4096", argc, argv);
        if (o.material != CLOTH_COTTON && o.material != CLOTH_WOOL && o.material != CLOTH_ELASTIC)
            violation("unknown material", argc, argv);
        if (o.fabric < 0 || o.fabric > 5 || (o.fabric && !*demo_fabric_name(o.fabric)))
            violation("unknown fabric", argc, argv);
        if (o.fabric && o.material_set) violation("both --fabric and --material", argc, argv);
        if (o.removal < 0 || o.removal > 2) violation("removal out of 0..2", argc, argv);
        if (!(o.crease_grip >= 0.0 && o.crease_grip <= 100.0)) violation("crease grip out of [0, 100]", argc, argv);
        if (!(o.crease_law >= 0.0 && o.crease_law <= 100.0)) violation("crease law out of [0, 100]", argc, argv);
        if (!o.out || !o.out[0]) violation("empty output directory", argc, argv);
        if (o.csv && !o.csv[0]) violation("empty csv name", argc, argv);
        int flags[] = {o.obj, o.check, o.short_run, o.images, o.trace, o.phases, o.box_table, o.material_set, o.video};
        for (size_t k = 0; k < sizeof flags / sizeof flags[0]; k++)
            if (flags[k] != 0 && flags[k] != 1) violation("a flag neither 0 nor 1", argc, argv);
    }
    free(buf);
    return 0;
}

#ifndef ODECLOTH_LIBFUZZER

typedef struct blob {
    char *p;
    size_t n;
} blob;

/* the seeds: argument lists, NUL-separated */
typedef struct seed {
    const char *p;
    size_t n;
} seed;
/* clang-format would put each string of a seed on a line of its own */
/* clang-format off */
#define SEED(lit) {lit, sizeof lit - 1}
static const seed seeds[] = {
    SEED("--grid\0" "21\0" "--alpha\0" "0,0.5,0.8,1\0" "--material\0" "wool\0"),
    SEED("--steps-per-second\0" "240\0" "--out\0" "out/x\0" "--obj\0" "--frames\0" "5\0" "--smooth\0" "2\0"),
    SEED("--size\0" "640x480\0" "--no-images\0" "--csv\0" "runs.csv\0" "--phases\0" "--trace\0"),
    SEED("--box-table\0" "--short\0" "--check\0" "--hz\0" "60\0" "--material\0" "elastic\0"),
    SEED("--help\0"),
    SEED("--grid\0" "3\0" "--alpha\0" "1\0" "--smooth\0" "0\0" "--size\0" "32x4096\0"),
    SEED("--fabric\0" "denim\0" "--removal\0" "two\0" "--crease-grip\0" "0.04\0" "--memory\0" "1\0"),
    SEED("--fabric\0" "cotton\0" "--crease-law\0" "0.02\0" "--grid\0" "41\0"),
};
/* clang-format on */
#define NSEEDS (sizeof seeds / sizeof seeds[0])

static const char *const words[] = {
    "--grid",
    "--alpha",
    "--material",
    "--steps-per-second",
    "--hz",
    "--out",
    "--obj",
    "--frames",
    "--smooth",
    "--size",
    "--no-images",
    "--video",
    "--csv",
    "--phases",
    "--trace",
    "--box-table",
    "--short",
    "--check",
    "--help",
    "-h",
    "--fabric",
    "--removal",
    "--crease-grip",
    "--crease-law",
    "--memory",
    "two",
    "four",
    "denim",
    "polyester",
    "100",
    "100.0001",
    "",
    "-",
    "--",
    "nan",
    "inf",
    "-inf",
    "1e999",
    "-0",
    "0x10",
    "161",
    "162",
    "2",
    "10000",
    "10000.0001",
    "9.99",
    "4096x4096",
    "31x32",
    "1x",
    "x1",
    "32x32x",
    "0,0,0,0,0,0,0,0",
    "0,0,0,0,0,0,0,0,0",
    ",",
    "1,",
    ",1",
    "0.5,,1",
    "2147483648",
    "-2147483649",
    "99999999999999999999",
    " 21",
    "21 ",
    "cotton",
    "wool",
    "elastic",
    "silk",
};
#define NWORDS (sizeof words / sizeof words[0])

static blob mutate(rng *g)
{
    size_t s = (size_t)(rng_u64(g) % NSEEDS);
    blob b;
    size_t cap = seeds[s].n + 512;
    b.p = malloc(cap);
    memcpy(b.p, seeds[s].p, seeds[s].n);
    b.n = seeds[s].n;
    int edits = 1 + (int)(rng_u64(g) % 2);
    for (int e = 0; e < edits; e++) {
        size_t at = b.n ? (size_t)(rng_u64(g) % b.n) : 0;
        switch (rng_u64(g) % 6) {
        case 0:
            if (b.n) b.p[at] = (char)rng_u64(g);
            break;
        case 1:
            if (b.n) b.p[at] = '\0';
            break;
        case 2:
            if (b.n) b.p[at] = "0123456789.,-+xeE"[rng_u64(g) % 17];
            break;
        case 3: b.n = at; break;
        default: { /* insert a word (and its NUL), mostly at an argument boundary */
            const char *w = words[rng_u64(g) % NWORDS];
            size_t k = strlen(w) + 1;
            if (rng_u64(g) % 4) {
                while (at < b.n && b.p[at]) at++;
                if (at < b.n) at++;
            }
            if (b.n + k > cap) break;
            memmove(b.p + at + k, b.p + at, b.n - at);
            memcpy(b.p + at, w, k);
            b.n += k;
            break;
        }
        }
    }
    return b;
}

static blob read_all(const char *path)
{
    blob b = {NULL, 0};
    FILE *f = fopen(path, "rb");
    if (!f) return b;
    b.p = malloc(1 << 16);
    if (b.p) b.n = fread(b.p, 1, 1 << 16, f);
    fclose(f);
    return b;
}

int main(int argc, char **argv)
{
    char path[1024];
    if (argc == 3 && !strcmp(argv[1], "--write-corpus")) {
        for (size_t k = 0; k < NSEEDS; k++) {
            snprintf(path, sizeof path, "%s/seed%zu", argv[2], k);
            FILE *f = fopen(path, "wb");
            if (!f || fwrite(seeds[k].p, 1, seeds[k].n, f) != seeds[k].n) return 1;
            fclose(f);
        }
        return 0;
    }
    long mutations = argc > 1 ? atol(argv[1]) : 30000;
    int files = 0;
    for (size_t k = 0; k < 64; k++) {
        snprintf(path, sizeof path, "%s/options/seed%zu", ODECLOTH_TEST_CORPUS, k);
        blob b = read_all(path);
        if (!b.p) break;
        LLVMFuzzerTestOneInput((const uint8_t *)b.p, b.n);
        free(b.p);
        files++;
    }
    long parsed_seeds = n_parsed;
    rng g = rng_seed(0x0b71u);
    for (long k = 0; k < mutations; k++) {
        blob b = mutate(&g);
        LLVMFuzzerTestOneInput((const uint8_t *)b.p, b.n);
        free(b.p);
    }
    CHECK(files >= (int)NSEEDS, "%d corpus files in %s/options, expected %zu", files, ODECLOTH_TEST_CORPUS, NSEEDS);
    CHECK(parsed_seeds >= (long)NSEEDS - 1, "only %ld of the seeds parse", parsed_seeds);
    CHECK(n_parsed > mutations / 20 && n_refused > mutations / 20 && n_help > 0,
          "the mutations do not reach every outcome: %ld parsed, %ld help, %ld refused", n_parsed, n_help, n_refused);
    printf("%d corpus files and %ld mutations through demo_parse: no violation; %ld parsed, %ld --help, %ld "
           "refused\n",
           files, mutations, n_parsed, n_help, n_refused);
    return check_summary();
}
#endif
