#include "aa_error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

int aa_error_set(aa_error *err, int code, const char *field, const char *fmt, ...)
{
    if (!err)
        return code;
    err->code = code;
    snprintf(err->field, sizeof err->field, "%s", field ? field : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    return code;
}

const char *aa_strerror(int code)
{
    switch (code) {
    case AA_OK:
        return "ok";
    case AA_EINVAL:
        return "invalid argument";
    case AA_ENOMEM:
        return "out of memory";
    case AA_ERANGE:
        return "out of range";
    case AA_ECANCELED:
        return "cancelled";
    default:
        return "unknown error";
    }
}
