/* The scene on a device: the packed tables (packed_scene.h) checked against
 * the device's memory budget and uploaded into the buffers of the scene
 * block of the host/kernel contract (kernels/shared_types.h). */
#ifndef LVCL_DEVICE_SCENE_H
#define LVCL_DEVICE_SCENE_H

#include "kernel_args.h"
#include "packed_scene.h"

/* The uploaded tables. The large ones come in up to LV_SCENE_PARTS
 * buffers (kernels/scene_buffers.h); parts a scene does not need stay NULL. */
typedef struct {
    lvcl_scene_buffers buffers;
    size_t device_bytes;
    int split_tables; /* how many of the tables take more than one buffer */
} lvcl_device_scene;

/* Uploads, splitting the large tables over up to LV_SCENE_PARTS buffers
 * where one would exceed the device's largest allocation; fails with
 * LVCL_ERR_TOO_LARGE, naming the sizes, if that is not enough or all of
 * them exceed its memory. */
lvcl_error lvcl_device_scene_upload(const lvcl_device *dev, const lvcl_scene *scene, const lvcl_packed_scene *packed,
                                    lvcl_device_scene *ds, lvcl_status *st);
/* Writes the packed scene's light table (its odds changed) to ds. */
lvcl_error lvcl_device_scene_update_lights(const lvcl_device *dev, const lvcl_packed_scene *packed,
                                           lvcl_device_scene *ds, lvcl_status *st);
void lvcl_device_scene_release(lvcl_device_scene *ds);

/* Binds the scene block (LV_SCENE_PARAMS, LV_SCENE_ARG_COUNT arguments) of
 * kernel k from argument `first`. */
lvcl_error lvcl_device_scene_bind(const lvcl_device_scene *ds, cl_kernel k, cl_uint first, lvcl_status *st);

#endif
