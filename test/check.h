/* A tiny header-only assertion harness for the odecloth tests.
 *
 *   CHECK(cond, fmt, ...)           fails (and says why) when cond is false
 *   CHECK_NEAR(a, b, tol)           |a - b| <= tol
 *   CHECK_REL(a, b, rel, abs_floor) |a - b| <= rel * max(|a|, |b|, abs_floor)
 *   check_summary()                 prints "N checks, M failed"; returns the
 *                                   exit status for main (0 iff nothing failed)
 *
 * A NaN never passes CHECK_NEAR or CHECK_REL. Failures print file:line and the
 * message to stderr; the tests keep going, so one run shows every failure.
 *
 * rng_*: a deterministic splitmix64 generator. Every test seeds it with a fixed
 * constant, so reruns are identical (no rand()).
 *
 * Everything is static so each test executable includes this once.
 */
#ifndef ODECLOTH_TEST_CHECK_H
#define ODECLOTH_TEST_CHECK_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>

static long check_count_ = 0;
static long check_failed_ = 0;

/* Record one check; print the message if it failed. Returns cond. */
static int check_report_(int cond, const char *file, int line, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

#include <stdarg.h>
static int check_report_(int cond, const char *file, int line, const char *fmt, ...)
{
    check_count_++;
    if (!cond) {
        va_list ap;
        check_failed_++;
        fprintf(stderr, "%s:%d: FAILED: ", file, line);
        va_start(ap, fmt);
        vfprintf(stderr, fmt, ap);
        va_end(ap);
        fputc('\n', stderr);
    }
    return cond;
}

#define CHECK(cond, ...) check_report_(!!(cond), __FILE__, __LINE__, __VA_ARGS__)

static int check_near_(double a, double b, double tol, const char *ea, const char *eb, const char *file, int line)
{
    double e = fabs(a - b);
    return check_report_(e <= tol, file, line, "%s = %.17g vs %s = %.17g: |diff| %.3g > tol %.3g", ea, a, eb, b, e,
                         tol);
}

static int check_rel_(double a, double b, double rel, double floor_, const char *ea, const char *eb, const char *file,
                      int line)
{
    double s = fabs(a) > fabs(b) ? fabs(a) : fabs(b);
    double e = fabs(a - b);
    if (s < floor_) s = floor_;
    return check_report_(e <= rel * s, file, line, "%s = %.17g vs %s = %.17g: rel diff %.3g > %.3g (floor %.3g)", ea, a,
                         eb, b, s > 0 ? e / s : e, rel, floor_);
}

#define CHECK_NEAR(a, b, tol) check_near_((a), (b), (tol), #a, #b, __FILE__, __LINE__)
#define CHECK_REL(a, b, rel, abs_floor) check_rel_((a), (b), (rel), (abs_floor), #a, #b, __FILE__, __LINE__)

static int check_summary(void)
{
    printf("%ld checks, %ld failed\n", check_count_, check_failed_);
    return check_failed_ == 0 ? 0 : 1;
}

static long check_failures(void) { return check_failed_; }

/* ------------------------------------------------------------------ RNG */

typedef struct rng {
    uint64_t s;
} rng;

static rng rng_seed(uint64_t seed)
{
    rng r;
    r.s = seed;
    return r;
}

/* splitmix64 */
static uint64_t rng_u64(rng *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* uniform in [0, 1) with 53 random bits */
static double rng_unit(rng *r) { return (double)(rng_u64(r) >> 11) * (1.0 / 9007199254740992.0); }

/* uniform in [a, b) */
static double rng_range(rng *r, double a, double b) { return a + (b - a) * rng_unit(r); }

/* a uniformly distributed unit vector */
static void rng_unit_vector(rng *r, double u[3])
{
    for (;;) {
        double n2;
        u[0] = rng_range(r, -1, 1);
        u[1] = rng_range(r, -1, 1);
        u[2] = rng_range(r, -1, 1);
        n2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        if (n2 > 1e-4 && n2 <= 1.0) {
            double n = sqrt(n2);
            u[0] /= n;
            u[1] /= n;
            u[2] /= n;
            return;
        }
    }
}

/* Silence "defined but not used" for the helpers a test does not call. */
static inline void check_unused_(void)
{
    (void)check_failures;
    (void)rng_seed;
    (void)rng_range;
    (void)rng_unit_vector;
    (void)check_near_;
    (void)check_rel_;
}

#endif
