/* Guided path tracing (docs/guided.md): the light volume, traced as lv
 * mode traces it (indirect light only: light samples find the direct),
 * guides the camera paths' scattering (kernels/volume/guide.h). */
#include <math.h>

#include "session_internal.h"
#include "../util/timer.h"

/* Under a time limit, the most of it the trace may take (it stops at the
 * first batch past it); the paths take the rest. A first choice, not
 * measured against others (docs/guided.md, "Open"). */
#define GUIDE_TIME_SHARE 0.1
/* Particles a time-limited trace stops at if its share of the time has not
 * ended it first. */
#define GUIDE_PARTICLES_MAX (1u << 24)

/* Traces the volume vs asks for on every device and fills each device's
 * guide table from it. */
static lvcl_error trace_guide(lvcl_session *s, const lvcl_volume_settings *vs, lvcl_status *st)
{
    lvcl_error e = lvcl_session_trace_volume(s, vs, st);
    for (int d = 0; d < s->device_count && !e; d++)
        e = lvcl_volume_fill_guide(s->devices[d].volume, &s->devices[d].program, st);
    return e;
}

/* Before a timed render: a small trace, its guide table and the warm-up
 * images (lvcl_session_warm_camera_pass), thrown away (the timed trace
 * starts a new volume), so that the budget does not pay for PoCL's
 * first-launch compiles. */
static lvcl_error warm_up(lvcl_session *s, const lvcl_render_request *req, const lvcl_volume_settings *vs,
                          lvcl_status *st)
{
    lvcl_volume_settings warm = *vs;
    warm.particles = LVCL_WARM_UP_PARTICLES;
    warm.progress = 0;
    lvcl_error e = trace_guide(s, &warm, st);
    return e ? e : lvcl_session_warm_camera_pass(s, req, st);
}

lvcl_error lvcl_session_render_guided(lvcl_session *s, const lvcl_render_request *req, lvcl_render_result *out,
                                      lvcl_status *st)
{
    lvcl_volume_settings vs = req->volume;
    vs.store_emitted = 0;
    /* The guide reads bins only: no subcells, so no lit points or
     * visibility rays (a quarter of the trace's time). */
    vs.subcells = 0;
    lvcl_pass_settings pass = req->pass;
    lvcl_error e = pass.time_limit > 0 ? warm_up(s, req, &vs, st) : LVCL_OK;
    if (e) return e;
    double start = lvcl_seconds();
    if (pass.time_limit > 0) {
        if (!vs.particles) vs.particles = GUIDE_PARTICLES_MAX;
        vs.deadline = start + GUIDE_TIME_SHARE * pass.time_limit;
    }
    e = trace_guide(s, &vs, st);
    if (e == LVCL_ERR_CLUSTER || (e = lvcl_cluster_agree(s->cluster, e, st))) return e;
    /* At least one sample is taken, however long the trace took. */
    if (pass.time_limit > 0) pass.time_limit = fmax(pass.time_limit - (lvcl_seconds() - start), 1e-3);
    return lvcl_session_camera_pass(s, req, req->width, req->height, &pass, out, st);
}
