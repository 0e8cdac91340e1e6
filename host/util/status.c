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

static int warnings_muted;

void lvcl_warn_mute(int mute)
{
    warnings_muted = mute;
}

void lvcl_warn(const char *fmt, ...)
{
    if (warnings_muted) return;
    va_list ap;
    va_start(ap, fmt);
    fputs("lvcl: warning: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

const char *lvcl_bytes_text(double bytes, char buf[32])
{
    static const char *const units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    int u = 0;
    while (bytes >= 1024.0 && u < 6) bytes /= 1024.0, u++;
    snprintf(buf, 32, u ? "%.1f %s" : "%.0f %s", bytes, units[u]);
    return buf;
}
