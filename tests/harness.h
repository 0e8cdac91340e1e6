/* Shared set-up for the tests that run kernels: a device, the test program
 * (tests/kernels/unit_tests.cl) and scenes made from triangle lists. */
#ifndef LVCL_TEST_HARNESS_H
#define LVCL_TEST_HARNESS_H

#include "../host/render/session.h"

/* Opens device `spec` (NULL: $LVCL_TEST_DEVICE or the default) and builds
 * the test program on it. Exits the test program with a message on failure. */
void harness_open(const char *spec, lvcl_device *dev, lvcl_program *prog);
void harness_close(lvcl_device *dev, lvcl_program *prog);

/* Builds the test program on an open device (a session's, say). */
void harness_build(const lvcl_device *dev, lvcl_program *prog);

/* A scene of `count` triangles given as 9 floats each, all one diffuse
 * material; the scene owns copies. */
void harness_triangle_scene(const float *tris, size_t count, lvcl_scene *scene);

/* The arguments of the test program's tracing kernels (t_trace, t_surface,
 * t_trace_brute_force, tests/kernels/unit_tests.cl): the scene block, then
 * these; t_offset_rays takes its re-shoot records before the results. */
enum { T_TRACE_ARG_RAYS = LV_SCENE_ARG_COUNT, T_TRACE_ARG_COUNT, T_TRACE_ARG_RESULTS };
enum { T_OFFSET_ARG_RESHOOT = T_TRACE_ARG_RESULTS, T_OFFSET_ARG_RESULTS };

/* Traces rays (8 floats each, the layout of t_trace) through the scene with
 * kernel `kernel_name`; results get 4 floats per ray. */
void harness_trace(const lvcl_device *dev, const lvcl_program *prog, const lvcl_scene *scene,
                   const char *kernel_name, const float *rays, size_t count, float *results);

/* A square size x size render request: the path tracer, or the light volume
 * of `cells` cells and `particles` particles (8 x 8 bins per hemisphere,
 * 4 subcells, integrating gather). */
lvcl_render_request harness_request(lvcl_mode mode, int size, int spp, int cells, uint64_t particles);

/* Opens a session on `scene` (consumed) on `device` with `seed` and renders
 * req into out (zeroed on failure, with st saying why). */
lvcl_error harness_render(lvcl_scene *scene, const char *device, unsigned seed, const lvcl_render_request *req,
                          lvcl_render_result *out, lvcl_status *st);

/* Runs a 1-D kernel over `global` items (padded to LVCL_LOCAL_SIZE) and waits. */
void harness_run(const lvcl_device *dev, cl_kernel k, size_t global);

/* Deterministic random numbers (splitmix64): seed s, then uniform in [0, 1). */
typedef struct {
    uint64_t s;
} harness_rng;
double harness_uniform(harness_rng *r);

/* Aborts the test program with a message if err is not CL_SUCCESS. */
void harness_cl(cl_int err, const char *what);

#endif
