/* A rendering session: a scene made ready on one or more devices (BVHs
 * built once, buffers uploaded and kernels built on each) and the passes run
 * on them. lvcl's main, the tests and the benchmarks all render through this. */
#ifndef LVCL_SESSION_H
#define LVCL_SESSION_H

#include "../accel/accel.h"
#include "../scene/camera.h"
#include "../device/device_scene.h"
#include "../device/program.h"
#include "image_pass.h"
#include "light_volume.h"
#include "../scene/scene.h"

typedef struct {
    const char *device;  /* --device value: cpu, gpu, an index, a list "0,2" or "all"; NULL for the default */
    unsigned seed;
    int max_depth;
    int fast_math;
    uint64_t device_memory; /* act as a device of this many bytes (a quarter in one buffer); 0 = the device's own */
} lvcl_session_config;

/* The scene on one device, and that device's share of the last render. */
typedef struct {
    lvcl_device device;
    lvcl_device_scene device_scene;
    lvcl_program program;
    lvcl_light_volume volume; /* lv modes only; its particles and timings are this device's */
    lvcl_pass_device pass;    /* bands, pixels and time of the last camera pass */
} lvcl_session_device;

#define LVCL_MAX_DEVICES 16

typedef struct {
    lvcl_scene scene;
    lvcl_accel accel;
    lvcl_packed_scene packed;
    lvcl_session_device devices[LVCL_MAX_DEVICES];
    int device_count;
    double merge_seconds;     /* adding the devices' light volumes */
    unsigned features;
    double bvh_build_seconds;
} lvcl_session;

typedef enum { LVCL_MODE_PT, LVCL_MODE_LV, LVCL_MODE_LV_ALL } lvcl_mode;

typedef struct {
    lvcl_mode mode;
    int width, height;          /* 0 = from the camera's aspect */
    lvcl_pass_settings pass;
    lvcl_volume_settings volume;
    int integrate;              /* the gather integrates over all bins instead of sampling one */
    double threshold;           /* near-hit distance in metres; 0 = the cell diagonal */
} lvcl_render_request;

/* Loads a scene from a .gltf/.glb path or an embedded scene name. */
lvcl_error lvcl_scene_load(const char *name, lvcl_scene *scene, lvcl_status *st);

/* Takes ownership of *scene (left zeroed) and prepares it on the device.
 * On failure the session is closed again. */
lvcl_error lvcl_session_open(lvcl_session *s, lvcl_scene *scene, const lvcl_session_config *cfg, lvcl_status *st);

/* Renders an image: path tracing, or particle trace then final gather. */
lvcl_error lvcl_session_render(lvcl_session *s, const lvcl_render_request *req, lvcl_render_result *out,
                               lvcl_status *st);

/* Path-traces a width x height image (0 = from the camera's aspect). */
lvcl_error lvcl_session_render_pt(lvcl_session *s, int width, int height, const lvcl_pass_settings *settings,
                                  lvcl_render_result *out, lvcl_status *st);

void lvcl_session_close(lvcl_session *s);

#endif
