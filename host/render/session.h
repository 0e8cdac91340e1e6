/* A rendering session: a scene made ready on one or more devices (BVHs
 * built once, buffers uploaded and kernels built on each) and the passes run
 * on them. lvcl's main, the tests and the benchmarks all render through
 * this. An opaque handle, opened and closed like Embree's devices and
 * scenes; what it did is read back through the accessors below. */
#ifndef LVCL_SESSION_H
#define LVCL_SESSION_H

#include "../accel/accel.h"
#include "../device/device_list.h"
#include "../device/device_scene.h"
#include "../device/program.h"
#include "../scene/camera.h"
#include "../scene/scene.h"
#include "../scene/scene_load.h"
#include "cluster.h"
#include "image_pass.h"
#include "light_volume.h"

typedef struct lvcl_session lvcl_session;

typedef struct {
    const char *device; /* --device value: cpu, gpu, an index, a list "0,2" or "all"; NULL for the default */
    unsigned seed;
    int max_depth;
    int fast_math;
    uint64_t device_memory; /* act as a device of this many bytes (a quarter in one buffer); 0 = the device's own */
    unsigned build_flags;   /* LVCL_BUILD_* switches for the kernels, besides the scene's features */
    lvcl_cluster *cluster;  /* other processes sharing every render (lvcl-mpi); NULL: alone */
    int announce_builds;    /* say on stderr when a device's kernels compile from source */
} lvcl_session_config;

/* pt: path tracing; lv, lv-all: the light volume answers for indirect or
 * all light; guided: path tracing with the light volume as a sampling guide. */
typedef enum { LVCL_MODE_PT, LVCL_MODE_LV, LVCL_MODE_LV_ALL, LVCL_MODE_GUIDED } lvcl_mode;

typedef struct {
    lvcl_mode mode;
    int width, height; /* 0 = from the camera's aspect */
    lvcl_pass_settings pass;
    lvcl_volume_settings volume;
    int integrate;    /* the gather integrates over all bins instead of sampling one */
    int see_through;  /* light samples find lamps seen through glass (lv: the volume leaves that light out) */
    double threshold; /* near-hit distance in metres; 0 = half the cell diagonal */
} lvcl_render_request;

/* How an lv render under a time limit spent it (session_budget.c). */
typedef struct {
    int used;                         /* the last render ran under a time budget */
    double volume_noise;              /* A: the volume's share of the image's relMSE, times particles */
    double gather_noise;              /* B0: the gather's share, times samples per pixel, sampling uniformly */
    double gather_noise_per_particle; /* B1: the gather's noise is B0 + B1 / N over a volume of N particles */
    double adaptive_share;            /* of B, what adaptive sampling leaves (1: off or not measured) */
    double seconds_per_particle;      /* measured on the second pass, then on the trace as it runs */
    double seconds_per_sample;        /* one sample per pixel of the image, measured on the pilots */
    double warm_up_seconds;           /* first launches before the clock started (not counted) */
    double measure_seconds;           /* the two first passes and the pilot images */
    uint64_t planned_particles;       /* what the split chose (or --particles) */
    double spent_seconds;             /* the whole render: trace, pilots and gather */
} lvcl_budget_report;

/* How a guided render under a time limit planned its guide and chose its
 * paths (session_guided.c). A cost is a kind of paths' relMSE per sample
 * times its seconds per sample, as pilots measure it. */
typedef struct {
    int used;                 /* the last render was guided, under a time limit */
    double guided_cost;       /* guided paths' cost over the measured guide (of 2 x 2^17 particles, or --particles) */
    double plain_cost;        /* the path tracer's */
    double guided_cost_error; /* the two costs' standard errors */
    double plain_cost_error;
    double guide_noise;              /* C0: guided paths' cost is C0 + C1 / N over a guide of N particles */
    double guide_noise_per_particle; /* C1 (0 where only one guide was measured, or its cost fell by less than noise) */
    double seconds_per_particle;     /* the trace's, measured on its second pass */
    uint64_t planned_particles;      /* the guide's particles by the plan (the trace may stop short at its deadline) */
    int plain;                       /* the path tracer's paths rendered the image: the plan's error was the lower */
    double measure_seconds;          /* the measured passes and their pilots */
    double pilot_seconds;            /* the pilots alone */
    int pilot_spp;                   /* samples per pixel of each pilot, by the budget and a warm-up sample's time */
} lvcl_guided_report;

/* One device's share of the last camera pass. */
typedef struct {
    int bands;           /* bands rendered */
    size_t pixels;       /* pixels rendered */
    double busy_seconds; /* time spent rendering them */
} lvcl_pass_share;

/* Takes ownership of *scene (left zeroed) and prepares it on the devices
 * cfg names; *session is NULL on failure. */
lvcl_error lvcl_session_open(lvcl_scene *scene, const lvcl_session_config *cfg, lvcl_session **session,
                             lvcl_status *st);

/* Renders an image: path tracing, or particle trace then final gather.
 * With req->pass.time_limit the whole render keeps to it (one device
 * and one process only); in lv modes with req->volume.particles 0 the particle count is
 * chosen by measurement (session_budget.c). */
lvcl_error lvcl_session_render(lvcl_session *s, const lvcl_render_request *req, lvcl_render_result *out,
                               lvcl_status *st);

/* Path-traces a width x height image (0 = from the camera's aspect). */
lvcl_error lvcl_session_render_pt(lvcl_session *s, int width, int height, const lvcl_pass_settings *settings,
                                  lvcl_render_result *out, lvcl_status *st);

/* Builds the light volume on every device as lv modes do (each takes
 * batches of particles, the tallies are added, the lit volumes computed),
 * with settings->store_emitted as given. With a cluster, over every
 * device of every process: each ends with the same volume. */
lvcl_error lvcl_session_trace_volume(lvcl_session *s, const lvcl_volume_settings *settings, lvcl_status *st);

/* Releases everything; NULL is allowed. */
void lvcl_session_close(lvcl_session *s);

/* ---- what the session holds and did ---- */
int lvcl_session_device_count(const lvcl_session *s);
const lvcl_device *lvcl_session_device(const lvcl_session *s, int d);
const lvcl_device_scene *lvcl_session_device_scene(const lvcl_session *s, int d);
const lvcl_program *lvcl_session_program(const lvcl_session *s, int d);
/* Device d's light volume: its grid is every device's, its particles and
 * timings its own; NULL before an lv render or lvcl_session_trace_volume. */
const lvcl_light_volume *lvcl_session_volume(const lvcl_session *s, int d);
lvcl_pass_share lvcl_session_pass_share(const lvcl_session *s, int d);
const lvcl_scene *lvcl_session_scene(const lvcl_session *s);
unsigned lvcl_session_features(const lvcl_session *s); /* LVCL_FEATURE_* the scene uses */
/* Whether req's render sees lamps through glass (kernels/integrator/
 * see_through.h): asked for, a scene with glass, and any mode but lv-all
 * (whose volume holds all light). */
int lvcl_session_sees_through(const lvcl_session *s, const lvcl_render_request *req);
const lvcl_accel *lvcl_session_accel(const lvcl_session *s);
const lvcl_packed_scene *lvcl_session_packed_scene(const lvcl_session *s);
double lvcl_session_bvh_build_seconds(const lvcl_session *s);
/* The light volume's build: the slowest device's particle trace plus
 * adding the devices' volumes; 0 without a volume. */
double lvcl_session_volume_seconds(const lvcl_session *s);
/* The last render's time budget; its `used` is 0 without one. */
const lvcl_budget_report *lvcl_session_budget(const lvcl_session *s);
/* The last render's choice between guided and plain paths; `used` is 0
 * unless it was guided under a time limit. */
const lvcl_guided_report *lvcl_session_guided(const lvcl_session *s);

#endif
