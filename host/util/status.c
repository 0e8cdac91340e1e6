#include "status.h"

#include <stdarg.h>
#include <stdio.h>

lvcl_error lvcl_fail(lvcl_status *st, lvcl_error code, const char *fmt, ...)
{
    if (st) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(st->message, sizeof st->message, fmt, ap);
        va_end(ap);
        /* Messages from libraries may span lines; an error is one line. */
        for (char *c = st->message; *c; c++)
            if (*c == '\n' || *c == '\r') *c = ' ';
        st->code = code;
    }
    return code;
}

void lvcl_warn(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("lvcl: warning: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}
