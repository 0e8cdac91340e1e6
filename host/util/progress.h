/* A progress bar on stderr, redrawn at most a few times a second. */
#ifndef LVCL_PROGRESS_H
#define LVCL_PROGRESS_H

typedef struct {
    const char *label;
    double start, last_draw;
    int enabled;
} lvcl_progress;

void lvcl_progress_start(lvcl_progress *p, const char *label, int enabled);
/* done out of total (units: e.g. samples per pixel). */
void lvcl_progress_update(lvcl_progress *p, double done, double total, const char *unit);
void lvcl_progress_finish(lvcl_progress *p);

#endif
