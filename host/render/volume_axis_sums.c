/* The axis sums of the integrating gather (kernels/integrator/gather.h):
 * per slot and axis normal, the cosine-weighted sum of its bins, so that a
 * Lambertian surface facing along an axis (most walls, floors and tables)
 * reads 3 floats where it would visit every bin of its cell. Computed on
 * the device, by the gather's own function, after each trace a gather
 * reads. */
#include "light_volume_internal.h"

lvcl_error lvcl_volume_axis_sums(lvcl_light_volume *vol, const lvcl_program *prog, cl_mem *out, lvcl_status *st)
{
    const lvcl_device *dev = vol->dev;
    const lv_grid_info *g = &vol->buf.info;
    size_t work = (size_t)g->slot_count * LV_AXES, bytes = work * 3 * sizeof(float);
    lvcl_error e;
    cl_int err;
    if (bytes > dev->max_alloc)
        return lvcl_fail(st, LVCL_ERR_TOO_LARGE,
                         "the gather's axis sums need %.1f MiB but %s allows %.1f MiB in one buffer; use fewer "
                         "--cells",
                         bytes / 1048576.0, dev->name, dev->max_alloc / 1048576.0);
    if (vol->axis_sums_slots != g->slot_count) { /* refining adds slots */
        if (vol->axis_sums_buf) clReleaseMemObject(vol->axis_sums_buf);
        vol->axis_sums_buf = lvcl_buffer_create(dev, CL_MEM_READ_WRITE, bytes, NULL, &err);
        if ((e = lvcl_cl_check(err, "allocating the gather's axis sums", st))) {
            vol->axis_sums_buf = NULL;
            vol->axis_sums_slots = 0;
            return e;
        }
        vol->axis_sums_slots = g->slot_count;
        vol->axis_sums_current = 0;
    }
    if (!vol->axis_sums_current) {
        cl_kernel k;
        if ((e = lvcl_kernel_create(prog, "lv_axis_sums", &k, st))) return e;
        lvcl_axis_sums_args args = {.volume = &vol->buf,
                                    .bin_table = lvcl_volume_bin_table(vol),
                                    .fine_bin_table = lvcl_volume_fine_bin_table(vol),
                                    .axis_sums = vol->axis_sums_buf};
        if (!(e = lvcl_bind_lv_axis_sums(k, &args, st)) &&
            !(e = lvcl_kernel_enqueue(dev, k, work, "summing the volume for axis-aligned surfaces", st)))
            e = lvcl_cl_check(clFinish(dev->queue), "summing the volume for axis-aligned surfaces", st);
        clReleaseKernel(k);
        if (e) return e;
        vol->axis_sums_current = 1;
    }
    *out = vol->axis_sums_buf;
    return LVCL_OK;
}
