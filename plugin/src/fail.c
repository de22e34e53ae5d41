/* The cloth's last error (dClothGetLastError): set where a call fails. */
#include <stdarg.h>
#include <stdio.h>
#include "dcloth_internal.h"

cloth_status dcloth_fail(dClothID c, cloth_status code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c->err, sizeof c->err, fmt, ap);
    va_end(ap);
    return code;
}
