#include "progress.h"

#include <stdio.h>
#include <string.h>

#include "timer.h"

#define BAR_WIDTH 30

void lvcl_progress_start(lvcl_progress *p, const char *label, int enabled)
{
    p->label = label;
    p->start = lvcl_seconds();
    p->last_draw = 0.0;
    p->enabled = enabled;
}

void lvcl_progress_update(lvcl_progress *p, double done, double total, const char *unit)
{
    if (!p->enabled) return;
    double now = lvcl_seconds();
    if (now - p->last_draw < 0.2 && done < total) return;
    p->last_draw = now;
    double f = total > 0 ? done / total : 1.0;
    if (f > 1.0) f = 1.0;
    int filled = (int)(f * BAR_WIDTH);
    char bar[BAR_WIDTH + 1];
    for (int i = 0; i < BAR_WIDTH; i++) bar[i] = i < filled ? '=' : ' ';
    bar[BAR_WIDTH] = 0;
    double elapsed = now - p->start;
    double eta = f > 0 ? elapsed * (1.0 - f) / f : 0.0;
    /* Counts whole; seconds (a time limit's bar) to a tenth, or a 2 s gather reads "1/2 s". */
    int places = strcmp(unit, "s") == 0;
    fprintf(stderr, "\r%-8s [%s] %3.0f%%  %.*f/%.*f %s  %.1fs, %.1fs left ", p->label, bar, 100.0 * f, places, done,
            places, total, unit, elapsed, eta);
    fflush(stderr);
}

void lvcl_progress_finish(lvcl_progress *p)
{
    if (!p->enabled) return;
    fputc('\n', stderr);
}
