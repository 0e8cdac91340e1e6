/* Shared set-up for the tests that run kernels: a device, the test program
 * (tests/kernels/unit_tests.cl) and scenes made from triangle lists. */
#ifndef LVCL_TEST_HARNESS_H
#define LVCL_TEST_HARNESS_H

#include "../host/device/kernel_args.h"
#include "../host/render/light_volume_internal.h" /* harness_regions */
#include "../host/render/session.h"
#include "kernels/test_args.h"

/* Opens device `spec` (NULL: $LVCL_TEST_DEVICE or the default) and builds
 * the test program on it. Exits the test program with a message on failure. */
void harness_open(const char *spec, lvcl_device *dev, lvcl_program *prog);
void harness_close(lvcl_device *dev, lvcl_program *prog);

/* Builds the test program on an open device (a session's, say). */
void harness_build(const lvcl_device *dev, lvcl_program *prog);

/* A scene of `count` triangles given as 9 floats each, all one diffuse
 * material; the scene owns copies. */
void harness_triangle_scene(const float *tris, size_t count, lvcl_scene *scene);

/* Appends to the triangle list t (9 floats each, n so far) the quad from
 * corner a along edges u and v, facing u x v, the box lo..hi with its
 * faces facing out, or the room lo..hi (a box facing in); returns the new
 * count. */
size_t harness_add_quad(float *t, size_t n, const float a[3], const float u[3], const float v[3]);
size_t harness_add_box(float *t, size_t n, const float lo[3], const float hi[3]);
size_t harness_add_room(float *t, size_t n, const float lo[3], const float hi[3]);

/* The light volume's grid and the regions of its cut cells for a scene of
 * n triangles (9 floats each; the first a lamp, the rest diffuse), on the
 * host alone (host/render/volume_planes.c): `cells` along the longest
 * axis, the grid shifted by `offset` cells, k = subcells. Returns 0 (and
 * says why on stderr, after `who`) where making them failed. */
typedef struct {
    lv_grid_info g;
    uint32_t *slot; /* per cell */
    lvcl_regions regions;
} harness_regions;
int harness_build_regions(const char *who, const float *tris, size_t n, int cells, double offset, int subcells,
                          harness_regions *out);
void harness_free_regions(harness_regions *r);

/* v turned by yaw about y, then by pitch about x (degrees), about the origin. */
void harness_turn(float v[3], float yaw_deg, float pitch_deg);

/* Two closed rooms sharing a wall (issue 12; scenes/make_two_rooms.py
 * builds the same): x in [-X, X], floor y = 0 to ceiling Y, z in [-Z, Z],
 * the wall centred on x = HARNESS_WALL_X, one lamp under the ceiling of
 * each room (the room x > HARNESS_WALL_X's first). wall 0: one double-sided
 * polygon. shell > 0: the outer walls, floor and ceiling are slabs that
 * thick, else one polygon each, facing into the rooms (the walls are
 * double-sided, but the cells' planes read a solid's fronts). panel > 0:
 * a box that deep stands on the floor against the wall in the room
 * x > HARNESS_WALL_X (0.9 m high, 1 m wide: a cupboard). door > 0: a
 * doorway that wide from z = HARNESS_DOOR_Z, HARNESS_DOOR_TOP high, in
 * the wall. The whole
 * turned by yaw and pitch (harness_turn), so that no wall need face a
 * grid axis. Writes at most HARNESS_TWO_ROOMS_TRIANGLES triangles to tris;
 * returns their count, and in *walls the count before the lamps. */
#define HARNESS_ROOMS_X 2.0f
#define HARNESS_ROOMS_Y 2.5f
#define HARNESS_ROOMS_Z 1.0f
#define HARNESS_WALL_X 0.37f
#define HARNESS_DOOR_Z (-0.6f)
#define HARNESS_DOOR_TOP 2.0f
#define HARNESS_TWO_ROOMS_TRIANGLES (6 * 12 + 3 * 12 + 12 + 4)
size_t harness_two_rooms(float *tris, float wall, float shell, float panel, float door, float yaw, float pitch,
                         size_t *walls);

/* Gives scene s `count` materials, each a copy of its first (the grey
 * harness_triangle_scene made), and returns them. */
lvcl_material_desc *harness_materials(lvcl_scene *s, size_t count);
/* Makes m a lamp of the given radiance that reflects nothing. */
void harness_make_lamp(lvcl_material_desc *m, float radiance);
/* Makes m smooth solid glass of index ior that absorbs nothing. */
void harness_make_glass(lvcl_material_desc *m, float ior);

/* Points the scene's camera from eye at target, the world's y up, with a
 * vertical field of view of yfov_deg and a square image. */
void harness_look_at(lvcl_scene *s, const float eye[3], const float target[3], float yfov_deg);

/* The arguments of the test program's ray kernels (t_trace, t_surface and
 * t_trace_brute_force take T_TRACE_ARGS, t_offset_rays T_OFFSET_RAYS_ARGS:
 * tests/kernels/test_args.h) as host structs, and their binders. */
typedef LVCL_KERNEL_ARGS(T_TRACE_ARGS) t_trace_args;
typedef LVCL_KERNEL_ARGS(T_OFFSET_RAYS_ARGS) t_offset_rays_args;
lvcl_error lvcl_bind_t_trace(cl_kernel k, const t_trace_args *a, lvcl_status *st);
lvcl_error lvcl_bind_t_offset_rays(cl_kernel k, const t_offset_rays_args *a, lvcl_status *st);

/* Kernel `name` of the test program, or the test program ends with a FAIL line. */
cl_kernel harness_kernel(const lvcl_program *prog, const char *name);

/* A read-write buffer of `bytes`, holding a copy of `data` unless it is NULL. */
cl_mem harness_buffer(const lvcl_device *dev, const void *data, size_t bytes);

/* Reads `bytes` of m into out, waiting for it. */
void harness_read(const lvcl_device *dev, cl_mem m, size_t bytes, void *out);

/* Traces rays (8 floats each, the layout of t_trace) through the scene with
 * kernel `kernel_name`; results get 4 floats per ray. */
void harness_trace(const lvcl_device *dev, const lvcl_program *prog, const lvcl_scene *scene, const char *kernel_name,
                   const float *rays, size_t count, float *results);

/* A square size x size render request: the path tracer, or the light volume
 * of `cells` cells and `particles` particles (8 x 8 bins per hemisphere,
 * 4 subcells, integrating gather). */
lvcl_render_request harness_request(lvcl_mode mode, int size, int spp, int cells, uint64_t particles);

/* A session on embedded scene `name` (cornell, furnace, kitchen) on the
 * default device, with `seed`, paths of up to 64 segments and fast math, as
 * the tests that build light volumes by hand use. Exits the test program
 * with a message on failure. */
lvcl_session *harness_session(const char *name, unsigned seed);

/* Opens a session on `scene` (consumed) on `device` with `seed` and renders
 * req into out (zeroed on failure, with st saying why). */
lvcl_error harness_render(lvcl_scene *scene, const char *device, unsigned seed, const lvcl_render_request *req,
                          lvcl_render_result *out, lvcl_status *st);

/* The same with a session configuration of the caller's. */
lvcl_error harness_render_with(lvcl_scene *scene, const lvcl_session_config *cfg, const lvcl_render_request *req,
                               lvcl_render_result *out, lvcl_status *st);

/* A light volume traced in a session, and what its kernels stored, read
 * back (harness_trace_volume). */
typedef struct {
    lvcl_session *session;
    const lvcl_light_volume *volume; /* device 0's */
    int64_t *tallies;
    uint32_t *masks;
    float *lit; /* per slot, as lv_lit_volumes stored it */
} harness_volume;

/* Opens a session on `scene` (consumed) with cfg and builds a light volume
 * in it as the lv modes do; reads back its tallies, subcell masks and lit
 * volumes. On failure *out holds nothing to release and st says why. */
lvcl_error harness_trace_volume(lvcl_scene *scene, const lvcl_session_config *cfg, const lvcl_volume_settings *vs,
                                harness_volume *out, lvcl_status *st);
void harness_volume_release(harness_volume *v);

/* harness_render on the first device, and the mean of the image's values
 * (*mean -1 on an error). */
lvcl_error harness_render_mean(lvcl_scene *scene, unsigned seed, const lvcl_render_request *req, double *mean,
                               lvcl_status *st);

/* Runs a 1-D kernel over `global` items (padded to LVCL_LOCAL_SIZE) and waits. */
void harness_run(const lvcl_device *dev, cl_kernel k, size_t global);

/* Deterministic random numbers (splitmix64): seed s, then uniform in [0, 1). */
typedef struct {
    uint64_t s;
} harness_rng;
double harness_uniform(harness_rng *r);

/* Aborts the test program with a message if err is not CL_SUCCESS, or if
 * e is not LVCL_OK (naming what and st's message). */
void harness_cl(cl_int err, const char *what);
void harness_ok(lvcl_error e, const lvcl_status *st, const char *what);

#endif
