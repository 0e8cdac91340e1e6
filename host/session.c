#include "session.h"

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
    if ((e = lvcl_bvh_build(s->scene.positions, s->scene.indices, s->scene.triangle_count, &s->bvh, st))) goto fail;
    s->bvh_build_seconds = lvcl_seconds() - t;
    if (s->bvh.skipped) lvcl_warn("%zu triangles of zero area or with non-finite vertices left out", s->bvh.skipped);

    if ((e = lvcl_device_open(cfg->device, &s->device, st))) goto fail;
    if ((e = lvcl_pack_scene(&s->scene, &s->bvh, cfg->seed, (uint32_t)cfg->max_depth, &s->packed, st))) goto fail;
    if ((e = lvcl_device_scene_upload(&s->device, &s->scene, &s->packed, &s->device_scene, st))) goto fail;
    s->features = lvcl_scene_features(&s->scene);
    if ((e = lvcl_program_build(&s->device, s->features, cfg->fast_math, &s->program, st))) goto fail;
    return LVCL_OK;
fail:
    lvcl_session_close(s);
    return e;
}

lvcl_error lvcl_session_render_pt(lvcl_session *s, int width, int height, const lvcl_pt_settings *settings,
                                  lvcl_render_result *out, lvcl_status *st)
{
    int w, h;
    lvcl_image_size(&s->scene.camera, width, height, &w, &h);
    lv_camera cam = lvcl_camera_make(&s->scene.camera, s->packed.bounds_min, s->packed.bounds_max, w, h);
    return lvcl_render_pt(&s->device, &s->program, &s->device_scene, &cam, settings, out, st);
}

void lvcl_session_close(lvcl_session *s)
{
    lvcl_program_release(&s->program);
    lvcl_device_scene_release(&s->device_scene);
    lvcl_device_close(&s->device);
    lvcl_packed_scene_free(&s->packed);
    lvcl_bvh_free(&s->bvh);
    lvcl_scene_free(&s->scene);
    memset(s, 0, sizeof *s);
}
