/* Status codes, messages and small shared helpers. */
#include <stdarg.h>
#include <stdio.h>
#include "internal.h"

const char *cloth_version(void) { return "0.1.0"; }

const char *cloth_status_string(cloth_status s)
{
    switch (s) {
    case CLOTH_OK: return "ok";
    case CLOTH_EINVAL: return "invalid argument";
    case CLOTH_ENOMEM: return "out of memory";
    case CLOTH_ESTEP: return "step failed";
    }
    return "unknown status";
}

const char *cloth_failure_string(cloth_failure f)
{
    switch (f) {
    case CLOTH_FAIL_NONE: return "none";
    case CLOTH_FAIL_NAN: return "NaN or inf in the state";
    case CLOTH_FAIL_CG_MAX_ITER: return "CG reached its iteration cap without converging";
    case CLOTH_FAIL_CG_INDEFINITE: return "CG met non-positive curvature (matrix not positive definite)";
    case CLOTH_FAIL_STRAIN: return "strain far past the elongation limit";
    case CLOTH_FAIL_BAD_STEP: return "step size not finite and positive";
    case CLOTH_FAIL_NEWTON: return "Newton's method did not converge within solver.newton_iterations";
    }
    return "unknown failure";
}

static cloth_status vset(char *buf, size_t n, cloth_status code, const char *fmt, va_list ap)
{
    vsnprintf(buf, n, fmt, ap);
    return code;
}

cloth_status oc_cloth_fail(cloth *c, cloth_status code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    if (c) vset(c->err, sizeof c->err, code, fmt, ap);
    va_end(ap);
    return code;
}

cloth_status oc_error_set(cloth_error *e, cloth_status code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    if (e) {
        e->code = code;
        vset(e->message, sizeof e->message, code, fmt, ap);
    }
    va_end(ap);
    return code;
}

int oc_all_finite(const double *a, size_t n)
{
    /* x - x is 0 for finite x and NaN for NaN or inf; one branch at the end. */
    double acc = 0.0;
    for (size_t k = 0; k < n; k++) acc += a[k] - a[k];
    return acc == 0.0;
}
