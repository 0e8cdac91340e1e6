/* The host's side of the host/kernel contract (kernels/shared_types.h): the
 * tables there expanded into the host's buffer structs and into argument
 * binders, and the one check every OpenCL call's result goes through. */
#ifndef LVCL_KERNEL_ARGS_H
#define LVCL_KERNEL_ARGS_H

#include "../../kernels/shared_types.h"
#include "device.h"

/* clSetKernelArg through lvcl_cl_check ("setting <what>"). */
lvcl_error lvcl_kernel_arg(cl_kernel k, cl_uint index, size_t size, const void *value, const char *what,
                           lvcl_status *st);

/* The scene's buffers on a device (a cl_mem per LV_SCENE_BUFFERS entry,
 * LV_SCENE_PARTS of them for a split table; parts a scene does not need
 * stay NULL and part 0 is bound in their place). */
#define LVCL_MEM_SCENE_SPLIT(type, name, stride, per_part, what) cl_mem name[LV_SCENE_PARTS];
#define LVCL_MEM_SCENE_ONE(type, name, what) cl_mem name;
typedef struct {
    LV_SCENE_BUFFERS(LVCL_MEM_SCENE_SPLIT, LVCL_MEM_SCENE_ONE)
    lv_scene_info info;
} lvcl_scene_buffers;

/* The light volume's buffers on a device (LV_VOLUME_BUFFERS). */
#define LVCL_MEM_VOLUME_SPLIT(type, name) cl_mem name[LV_TALLY_PARTS];
#define LVCL_MEM_VOLUME_ONE(type, name) cl_mem name;
typedef struct {
    LV_VOLUME_BUFFERS(LVCL_MEM_VOLUME_SPLIT, LVCL_MEM_VOLUME_ONE)
    lv_grid_info info;
} lvcl_volume_buffers;

/* Bind the scene block (LV_SCENE_ARG_COUNT arguments) or the volume block
 * (LV_VOLUME_ARG_COUNT) of kernel k from argument `first`. */
lvcl_error lvcl_scene_buffers_bind(const lvcl_scene_buffers *b, cl_kernel k, cl_uint first, lvcl_status *st);
lvcl_error lvcl_volume_buffers_bind(const lvcl_volume_buffers *b, cl_kernel k, cl_uint first, lvcl_status *st);

/* Releases every buffer and zeroes b. */
void lvcl_scene_buffers_release(lvcl_scene_buffers *b);
void lvcl_volume_buffers_release(lvcl_volume_buffers *b);

/* A kernel's arguments as a host struct, a field per list entry: the
 * blocks as pointers to their buffers, values as themselves, buffers as
 * cl_mem. lvcl_bind_<kernel> sets them all at their LV_ARG indices. */
#define LVCL_ARG_FIELD(kernel, kind, type, name) LVCL_ARG_FIELD_##kind(type, name)
#define LVCL_ARG_FIELD_SCENE(type, name) const lvcl_scene_buffers *name;
#define LVCL_ARG_FIELD_VOLUME(type, name) const lvcl_volume_buffers *name;
#define LVCL_ARG_FIELD_VALUE(type, name) type name;
#define LVCL_ARG_FIELD_BUFFER(type, name) cl_mem name;
#define LVCL_KERNEL_ARGS(LIST)            \
    struct {                              \
        LIST(LVCL_ARG_FIELD, LV_SEP_NONE) \
    }

typedef LVCL_KERNEL_ARGS(LV_PT_PASS_ARGS) lvcl_pt_pass_args;
typedef LVCL_KERNEL_ARGS(LV_GATHER_PASS_ARGS) lvcl_gather_pass_args;
typedef LVCL_KERNEL_ARGS(LV_GUIDED_PASS_ARGS) lvcl_guided_pass_args;
typedef LVCL_KERNEL_ARGS(LV_GUIDE_TABLE_ARGS) lvcl_guide_table_args;
typedef LVCL_KERNEL_ARGS(LV_AXIS_SUMS_ARGS) lvcl_axis_sums_args;
typedef LVCL_KERNEL_ARGS(LV_PARTICLE_TRACE_ARGS) lvcl_particle_trace_args;
typedef LVCL_KERNEL_ARGS(LV_LIT_VOLUMES_ARGS) lvcl_lit_volumes_args;
typedef LVCL_KERNEL_ARGS(LV_BIN_TABLE_ARGS) lvcl_bin_table_args;

lvcl_error lvcl_bind_lv_pt_pass(cl_kernel k, const lvcl_pt_pass_args *a, lvcl_status *st);
lvcl_error lvcl_bind_lv_gather_pass(cl_kernel k, const lvcl_gather_pass_args *a, lvcl_status *st);
lvcl_error lvcl_bind_lv_guided_pass(cl_kernel k, const lvcl_guided_pass_args *a, lvcl_status *st);
lvcl_error lvcl_bind_lv_guide_table(cl_kernel k, const lvcl_guide_table_args *a, lvcl_status *st);
lvcl_error lvcl_bind_lv_axis_sums(cl_kernel k, const lvcl_axis_sums_args *a, lvcl_status *st);
lvcl_error lvcl_bind_lv_particle_trace(cl_kernel k, const lvcl_particle_trace_args *a, lvcl_status *st);
lvcl_error lvcl_bind_lv_lit_volumes(cl_kernel k, const lvcl_lit_volumes_args *a, lvcl_status *st);
lvcl_error lvcl_bind_lv_bin_table(cl_kernel k, const lvcl_bin_table_args *a, lvcl_status *st);

/* Defines lvcl_error lvcl_bind_<kernel>(cl_kernel, const args_type *, lvcl_status *),
 * which binds every argument of LIST at its LV_ARG index (the production
 * kernels' binders are declared above; tests define their own). */
#define LVCL_BIND_ARG(kernel, kind, type, name) \
    if (!e) e = LVCL_BIND_ARG_##kind(k, LV_ARG(kernel, name), a->name, #kernel " " #name, st);
#define LVCL_BIND_ARG_SCENE(k, index, v, what, st) lvcl_scene_buffers_bind(v, k, index, st)
#define LVCL_BIND_ARG_VOLUME(k, index, v, what, st) lvcl_volume_buffers_bind(v, k, index, st)
#define LVCL_BIND_ARG_VALUE(k, index, v, what, st) lvcl_kernel_arg(k, index, sizeof(v), &(v), what, st)
#define LVCL_BIND_ARG_BUFFER(k, index, v, what, st) lvcl_kernel_arg(k, index, sizeof(cl_mem), &(v), what, st)
#define LVCL_DEFINE_BINDER(kernel, LIST, args_type)                                 \
    lvcl_error lvcl_bind_##kernel(cl_kernel k, const args_type *a, lvcl_status *st) \
    {                                                                               \
        lvcl_error e = LVCL_OK;                                                     \
        LIST(LVCL_BIND_ARG, LV_SEP_NONE)                                            \
        return e;                                                                   \
    }

/* The indices of the camera passes' pixel arguments (LV_PIXEL_ARGS) in
 * `kernel`: LVCL_PIXEL_ARG_INDICES(lv_pt_pass). */
#define LVCL_INDEX_FIELD(kernel, kind, type, name) cl_uint name;
#define LVCL_INDEX_INIT(kernel, kind, type, name) .name = LV_ARG(kernel, name)
typedef struct {
    LV_PIXEL_ARGS(LVCL_INDEX_FIELD, LV_SEP_NONE, _)
} lvcl_pixel_arg_indices;
#define LVCL_PIXEL_ARG_INDICES(kernel) ((lvcl_pixel_arg_indices){LV_PIXEL_ARGS(LVCL_INDEX_INIT, LV_SEP_COMMA, kernel)})

#endif
