/* The guide table of guided path tracing (kernels/volume/guide.h): one
 * float per tally set and bin, the luminance of its tallies, so that a
 * path vertex weighs a cell's bins with one read each instead of three
 * 64-bit ones, and per set the sum and the largest of them, which decide
 * its guide's share before any bin is read. Filled on the device after
 * the trace. */
#include "light_volume_internal.h"

lvcl_error lvcl_volume_fill_guide(lvcl_light_volume *vol, const lvcl_program *prog, lvcl_status *st)
{
    const lvcl_device *dev = vol->dev;
    const lv_grid_info *g = &vol->buf.info;
    size_t bytes = LV_GUIDE_TABLE_FLOATS(*g) * sizeof(float);
    if (bytes > dev->max_alloc)
        return lvcl_fail(st, LVCL_ERR_TOO_LARGE,
                         "the guide table needs %.1f MiB but %s allows %.1f MiB in one buffer; use fewer --cells "
                         "or --dirs",
                         bytes / 1048576.0, dev->name, dev->max_alloc / 1048576.0);
    lvcl_error e;
    cl_int err;
    if (vol->guide_table_buf) clReleaseMemObject(vol->guide_table_buf);
    vol->guide_table_buf = lvcl_buffer_create(dev, CL_MEM_READ_WRITE, bytes, NULL, &err);
    if ((e = lvcl_cl_check(err, "allocating the guide table", st))) return e;
    cl_kernel k;
    if ((e = lvcl_kernel_create(prog, "lv_guide_table", &k, st))) return e;
    lvcl_guide_table_args args = {.volume = &vol->buf, .fine_pass = 0, .guide_table = vol->guide_table_buf};
    if (!(e = lvcl_bind_lv_guide_table(k, &args, st)) &&
        !(e = lvcl_kernel_enqueue(dev, k, (size_t)g->tally_sets + 1, "filling the guide table", st)) &&
        vol->fine_slots) { /* the slots of fine bins' rooms, after the sets' (kernels/passes/guided.cl) */
        args.fine_pass = 1;
        if (!(e = lvcl_bind_lv_guide_table(k, &args, st)))
            e = lvcl_kernel_enqueue(dev, k, g->slot_count, "filling the guide table's fine bins", st);
    }
    if (!e) e = lvcl_cl_check(clFinish(dev->queue), "filling the guide table", st);
    clReleaseKernel(k);
    return e;
}

cl_mem lvcl_volume_guide_table(const lvcl_light_volume *vol)
{
    return vol->guide_table_buf;
}
