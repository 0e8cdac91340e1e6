#include "kernel_args.h"

#include <stdio.h>
#include <string.h>

lvcl_error lvcl_kernel_arg(cl_kernel k, cl_uint index, size_t size, const void *value, const char *what,
                           lvcl_status *st)
{
    cl_int err = clSetKernelArg(k, index, size, value);
    if (err == CL_SUCCESS) return LVCL_OK;
    char doing[160];
    snprintf(doing, sizeof doing, "setting kernel argument %u (%s)", index, what);
    return lvcl_cl_check(err, doing, st);
}

/* A split table's parts from argument `first` (unused parts: part 0). */
static lvcl_error bind_parts(cl_kernel k, cl_uint first, const cl_mem *parts, int count, const char *what,
                             lvcl_status *st)
{
    lvcl_error e = LVCL_OK;
    for (int p = 0; p < count && !e; p++)
        e = lvcl_kernel_arg(k, first + (cl_uint)p, sizeof(cl_mem), parts[p] ? &parts[p] : &parts[0], what, st);
    return e;
}

#define BIND_SCENE_SPLIT(type, name, stride, per_part, what) \
    if (!e) e = bind_parts(k, first + lv_scene_arg_##name, b->name, LV_SCENE_PARTS, "scene " #name, st);
#define BIND_SCENE_ONE(type, name, what) \
    if (!e) e = lvcl_kernel_arg(k, first + lv_scene_arg_##name, sizeof(cl_mem), &b->name, "scene " #name, st);

lvcl_error lvcl_scene_buffers_bind(const lvcl_scene_buffers *b, cl_kernel k, cl_uint first, lvcl_status *st)
{
    lvcl_error e = LVCL_OK;
    LV_SCENE_BUFFERS(BIND_SCENE_SPLIT, BIND_SCENE_ONE)
    if (!e) e = lvcl_kernel_arg(k, first + lv_scene_arg_info, sizeof b->info, &b->info, "scene info", st);
    return e;
}

#define BIND_VOLUME_SPLIT(type, name) \
    if (!e) e = bind_parts(k, first + lv_volume_arg_##name, b->name, LV_TALLY_PARTS, "volume " #name, st);
#define BIND_VOLUME_ONE(type, name) \
    if (!e) e = lvcl_kernel_arg(k, first + lv_volume_arg_##name, sizeof(cl_mem), &b->name, "volume " #name, st);

lvcl_error lvcl_volume_buffers_bind(const lvcl_volume_buffers *b, cl_kernel k, cl_uint first, lvcl_status *st)
{
    lvcl_error e = LVCL_OK;
    LV_VOLUME_BUFFERS(BIND_VOLUME_SPLIT, BIND_VOLUME_ONE)
    if (!e) e = lvcl_kernel_arg(k, first + lv_volume_arg_info, sizeof b->info, &b->info, "grid info", st);
    return e;
}

static void release_mem(cl_mem *m, int count)
{
    for (int i = 0; i < count; i++)
        if (m[i]) clReleaseMemObject(m[i]);
}

#define RELEASE_SCENE_SPLIT(type, name, stride, per_part, what) release_mem(b->name, LV_SCENE_PARTS);
#define RELEASE_SCENE_ONE(type, name, what) release_mem(&b->name, 1);
void lvcl_scene_buffers_release(lvcl_scene_buffers *b)
{
    LV_SCENE_BUFFERS(RELEASE_SCENE_SPLIT, RELEASE_SCENE_ONE)
    memset(b, 0, sizeof *b);
}

#define RELEASE_VOLUME_SPLIT(type, name) release_mem(b->name, LV_TALLY_PARTS);
#define RELEASE_VOLUME_ONE(type, name) release_mem(&b->name, 1);
void lvcl_volume_buffers_release(lvcl_volume_buffers *b)
{
    LV_VOLUME_BUFFERS(RELEASE_VOLUME_SPLIT, RELEASE_VOLUME_ONE)
    memset(b, 0, sizeof *b);
}

LVCL_DEFINE_BINDER(lv_pt_pass, LV_PT_PASS_ARGS, lvcl_pt_pass_args)
LVCL_DEFINE_BINDER(lv_gather_pass, LV_GATHER_PASS_ARGS, lvcl_gather_pass_args)
LVCL_DEFINE_BINDER(lv_guided_pass, LV_GUIDED_PASS_ARGS, lvcl_guided_pass_args)
LVCL_DEFINE_BINDER(lv_guide_table, LV_GUIDE_TABLE_ARGS, lvcl_guide_table_args)
LVCL_DEFINE_BINDER(lv_axis_sums, LV_AXIS_SUMS_ARGS, lvcl_axis_sums_args)
LVCL_DEFINE_BINDER(lv_particle_trace, LV_PARTICLE_TRACE_ARGS, lvcl_particle_trace_args)
LVCL_DEFINE_BINDER(lv_lit_volumes, LV_LIT_VOLUMES_ARGS, lvcl_lit_volumes_args)
LVCL_DEFINE_BINDER(lv_bin_table, LV_BIN_TABLE_ARGS, lvcl_bin_table_args)
