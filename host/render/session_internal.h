/* The session's private parts, shared by session.c (opening, closing,
 * accessors), session_volume.c (the light volume over every device),
 * session_render.c (the camera passes), session_budget.c (one time
 * budget for an lv render), session_guided.c (guided renders) and
 * session_view.c (the lights' odds learned from the view). */
#ifndef LVCL_SESSION_INTERNAL_H
#define LVCL_SESSION_INTERNAL_H

#include "session.h"

/* The scene on one device, and that device's share of the last render. */
typedef struct {
    lvcl_device device;
    lvcl_device_scene device_scene;
    lvcl_program program;
    lvcl_light_volume *volume; /* lv modes only */
    lvcl_pass_share pass;
} session_device;

struct lvcl_session {
    lvcl_scene scene;
    lvcl_accel accel;
    lvcl_packed_scene packed;
    session_device devices[LVCL_MAX_DEVICES];
    int device_count;
    lvcl_cluster *cluster; /* NULL: alone */
    double merge_seconds;
    unsigned features;
    double bvh_build_seconds;
    lvcl_budget_report budget;
    lvcl_guided_report guided;
    double *gather_odds; /* session_view.c: per light group, the weights the view gave light samples, or NULL */
    int view_odds;       /* session_view.c: the light table now holds the view's odds */
};

/* Whether req's lv render's volume leaves out lamps seen through glass,
 * which its gather finds (lvcl_session_sees_through in lv mode). */
int lvcl_session_volume_sees_through(const lvcl_session *s, const lvcl_render_request *req);

/* Replaces device d's light volume by a new, empty one of these settings. */
lvcl_error lvcl_session_new_volume(lvcl_session *s, int d, const lvcl_volume_settings *settings, lvcl_status *st);

/* A camera pass of req's mode over every device, of width x height (0 =
 * from the camera's aspect), with these pass settings; the light volume
 * must be traced for lv modes. */
lvcl_error lvcl_session_camera_pass(lvcl_session *s, const lvcl_render_request *req, int width, int height,
                                    const lvcl_pass_settings *pass, lvcl_render_result *out, lvcl_status *st);

/* Particles of a timed render's warm-up trace: one launch of at least
 * 65,536 work-items, the size class of the trace's batches on PoCL. */
#define LVCL_WARM_UP_PARTICLES (1u << 16)

/* Before a timed pass: one sample of a 256 x 256 and of an 8 x 8 image in
 * req's mode, thrown away, so that the pass's clock does not count the
 * machine code PoCL compiles at a kernel's first launch of each size class
 * (up to 2 s on a cold cache). */
lvcl_error lvcl_session_warm_camera_pass(lvcl_session *s, const lvcl_render_request *req, lvcl_status *st);

/* Light odds learned from the view (session_view.c). view_start: the
 * lights' odds return to the packed ones and, with `follow` and where the
 * odds may follow the view, every device's volume starts a view probe of
 * the camera's regions. view_decide: after the probed part of the trace,
 * the particles' odds follow the light the probes found scattered (with
 * store_emitted, all they found), on every device, and the probes end.
 * view_gather: after the trace, the light samples' odds follow the light
 * the probes found straight from the lights (nothing without a probe). */
lvcl_error lvcl_session_view_start(lvcl_session *s, int follow, lvcl_status *st);
lvcl_error lvcl_session_view_decide(lvcl_session *s, int store_emitted, lvcl_status *st);
lvcl_error lvcl_session_view_gather(lvcl_session *s, lvcl_status *st);
/* The particles a trace of vs traces before view_decide: the refinement's
 * split point, or with a view probe and no split a quarter of them; 0:
 * none (nothing to split or probe). */
uint64_t lvcl_session_first_part(const lvcl_session *s, const lvcl_volume_settings *vs);

/* An lv render that keeps to req->pass.time_limit on one device. */
lvcl_error lvcl_session_render_budget(lvcl_session *s, const lvcl_render_request *req, lvcl_render_result *out,
                                      lvcl_status *st);

/* A pilot image of spp samples from index `first`, at the image's width
 * and height over `scale` (at least 8), without progress
 * (session_pilots.c). */
lvcl_error lvcl_session_pilot(lvcl_session *s, const lvcl_render_request *req, int scale, int first, int spp,
                              lvcl_render_result *out, lvcl_status *st);
/* relMSE's denominators (value^2 + LVCL_RELMSE_GUARD) from the mean of
 * `count` pilots of one size, averaged over 3 x 3 pixels so that their
 * noise does not weigh; malloc'ed, NULL when out of memory. */
float *lvcl_pilot_denominators(const lvcl_render_result *img, int count);
/* mean((a - b)^2 / den) over n values; with `error`, its standard error
 * there, the RGB pixel as the unit (n a multiple of 3): a pixel's three
 * channels are not independent. */
double lvcl_weighted_difference(const float *a, const float *b, const float *den, size_t n, double *error);

/* A guided render: the light volume, then guided camera paths; under a
 * time limit the guide is traced in measured passes and a plan
 * (guide_plan.h) sets its particles and picks guided or plain paths for
 * the rest (session_guided.c). */
lvcl_error lvcl_session_render_guided(lvcl_session *s, const lvcl_render_request *req, lvcl_render_result *out,
                                      lvcl_status *st);

#endif
