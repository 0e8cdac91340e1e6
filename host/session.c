#include "session.h"

#include <math.h>
#include <string.h>
#include <sys/stat.h>

#include "embedded_scenes.h"
#include "materials.h"
#include "timer.h"

lvcl_error lvcl_scene_load(const char *name, lvcl_scene *scene, lvcl_status *st)
{
    struct stat sb;
    if (stat(name, &sb) == 0) return lvcl_scene_load_gltf_file(name, scene, st);
    const lvcl_embedded_scene *e = lvcl_embedded_scene_find(name);
    if (e) return lvcl_scene_load_gltf_memory(e->data, e->size, "", scene, st);
    return lvcl_fail(st, LVCL_ERR_IO, "no such file or embedded scene '%s' (embedded: %s)", name,
                     lvcl_embedded_scene_names());
}

lvcl_error lvcl_session_open(lvcl_session *s, lvcl_scene *scene, const lvcl_session_config *cfg, lvcl_status *st)
{
    memset(s, 0, sizeof *s);
    s->scene = *scene;
    memset(scene, 0, sizeof *scene);

    lvcl_error e;
    double t = lvcl_seconds();
    if ((e = lvcl_accel_build(&s->scene, &s->accel, st))) goto fail;
    s->bvh_build_seconds = lvcl_seconds() - t;
    if (s->accel.skipped) lvcl_warn("%zu triangles of zero area or with non-finite vertices left out", s->accel.skipped);

    if ((e = lvcl_device_open(cfg->device, &s->device, st))) goto fail;
    if (cfg->device_memory) {
        if (s->device.global_mem > cfg->device_memory) s->device.global_mem = cfg->device_memory;
        if (s->device.max_alloc > cfg->device_memory) s->device.max_alloc = cfg->device_memory;
    }
    if ((e = lvcl_pack_scene(&s->scene, &s->accel, cfg->seed, (uint32_t)cfg->max_depth, &s->packed, st))) goto fail;
    if ((e = lvcl_device_scene_upload(&s->device, &s->scene, &s->packed, &s->device_scene, st))) goto fail;
    s->features = lvcl_scene_features(&s->scene);
    if ((e = lvcl_program_build(&s->device, s->features, cfg->fast_math, &s->program, st))) goto fail;
    return LVCL_OK;
fail:
    lvcl_session_close(s);
    return e;
}

/* Sets a camera pass kernel's scene arguments (and the light volume's, for
 * the gather); returns the index of its camera argument, or -1. */
static int set_pass_args(lvcl_session *s, cl_kernel k, const lvcl_render_request *req)
{
    int a = lvcl_device_scene_set_args(&s->device_scene, k, 0);
    if (a < 0 || req->mode == LVCL_MODE_PT) return a;
    cl_uint i = (cl_uint)a;
    cl_uint flags = (req->mode == LVCL_MODE_LV_ALL ? 1u : 0u) | (req->integrate ? 2u : 0u);
    float threshold = (float)(req->threshold > 0 ? req->threshold : sqrt(3.0) * s->volume.info.cell_size);
    if (clSetKernelArg(k, i, sizeof s->volume.info, &s->volume.info) ||
        clSetKernelArg(k, i + 1, sizeof(cl_mem), &s->volume.cell_slot_buf) ||
        clSetKernelArg(k, i + 2, sizeof(cl_mem), &s->volume.tallies_buf) ||
        clSetKernelArg(k, i + 3, sizeof(cl_mem), &s->volume.subcell_buf) ||
        clSetKernelArg(k, i + 4, sizeof(cl_mem), &s->volume.lit_volume_buf) ||
        clSetKernelArg(k, i + 5, sizeof(cl_mem), &s->volume.bin_directions_buf) ||
        clSetKernelArg(k, i + 6, sizeof flags, &flags) || clSetKernelArg(k, i + 7, sizeof threshold, &threshold))
        return -1;
    return (int)i + 8;
}

lvcl_error lvcl_session_render(lvcl_session *s, const lvcl_render_request *req, lvcl_render_result *out,
                               lvcl_status *st)
{
    lvcl_error e;
    if (req->mode != LVCL_MODE_PT) {
        lvcl_volume_release(&s->volume);
        lvcl_volume_settings vs = req->volume;
        vs.store_emitted = req->mode == LVCL_MODE_LV_ALL;
        if ((e = lvcl_volume_create(&s->device, &s->packed, &vs, &s->volume, st)) ||
            (e = lvcl_volume_trace(&s->device, &s->program, &s->device_scene, &vs, &s->volume, st)))
            return e;
    }
    int w, h;
    lvcl_image_size(&s->scene.camera, req->width, req->height, &w, &h);
    lv_camera cam = lvcl_camera_make(&s->scene.camera, s->packed.bounds_min, s->packed.bounds_max, w, h);
    cl_kernel k;
    if ((e = lvcl_kernel_create(&s->program, req->mode == LVCL_MODE_PT ? "lv_pt_pass" : "lv_gather_pass", &k, st)))
        return e;
    int camera_arg = set_pass_args(s, k, req);
    e = camera_arg < 0 ? lvcl_fail(st, LVCL_ERR_DEVICE, "cannot set the camera pass's arguments")
                       : lvcl_image_pass(&s->device, k, (cl_uint)camera_arg, &cam, &req->pass, out, st);
    clReleaseKernel(k);
    return e;
}

lvcl_error lvcl_session_render_pt(lvcl_session *s, int width, int height, const lvcl_pass_settings *settings,
                                  lvcl_render_result *out, lvcl_status *st)
{
    lvcl_render_request req = {0};
    req.mode = LVCL_MODE_PT;
    req.width = width;
    req.height = height;
    req.pass = *settings;
    return lvcl_session_render(s, &req, out, st);
}

void lvcl_session_close(lvcl_session *s)
{
    lvcl_volume_release(&s->volume);
    lvcl_program_release(&s->program);
    lvcl_device_scene_release(&s->device_scene);
    lvcl_device_close(&s->device);
    lvcl_packed_scene_free(&s->packed);
    lvcl_accel_free(&s->accel);
    lvcl_scene_free(&s->scene);
    memset(s, 0, sizeof *s);
}
