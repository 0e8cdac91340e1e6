/* Reading a light volume back, and adding the volumes of several devices. */
#include <stdlib.h>
#include <string.h>

#include "light_volume_internal.h"

lvcl_error lvcl_volume_read(const lvcl_light_volume *vol, int64_t **tallies, uint32_t **masks, lvcl_status *st)
{
    const lvcl_device *dev = vol->dev;
    size_t mask_bytes = lvcl_volume_record_bytes(vol);
    *tallies = malloc(vol->tally_bytes ? vol->tally_bytes : 8);
    if (masks) *masks = malloc(mask_bytes);
    if (!*tallies || (masks && !*masks)) {
        free(*tallies);
        if (masks) free(*masks);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory reading the light volume");
    }
    cl_int err = CL_SUCCESS;
    size_t offset = 0;
    for (int i = 0; i < vol->tally_parts && err == CL_SUCCESS && vol->tally_bytes; i++) {
        err = clEnqueueReadBuffer(dev->queue, vol->buf.tallies[i], CL_TRUE, 0, lvcl_volume_part_bytes(vol, i),
                                  (char *)*tallies + offset, 0, NULL, NULL);
        offset += lvcl_volume_part_bytes(vol, i);
    }
    if (err == CL_SUCCESS && masks)
        err = clEnqueueReadBuffer(dev->queue, vol->buf.subcells, CL_TRUE, 0, mask_bytes, *masks, 0, NULL, NULL);
    lvcl_error e = lvcl_cl_check(err, "reading the light volume", st);
    if (e) {
        free(*tallies);
        *tallies = NULL;
        if (masks) {
            free(*masks);
            *masks = NULL;
        }
    }
    return e;
}

lvcl_error lvcl_volume_read_lit(const lvcl_light_volume *vol, float **lit, lvcl_status *st)
{
    size_t bytes = ((size_t)vol->buf.info.slot_count + 1) * sizeof(float);
    *lit = malloc(bytes);
    if (!*lit) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory reading the lit volumes");
    lvcl_error e =
        lvcl_cl_check(clEnqueueReadBuffer(vol->dev->queue, vol->buf.lit_volume, CL_TRUE, 0, bytes, *lit, 0, NULL, NULL),
                      "reading the lit volumes", st);
    if (e) {
        free(*lit);
        *lit = NULL;
    }
    return e;
}

lvcl_error lvcl_volume_write(lvcl_light_volume *vol, const int64_t *tallies, const uint32_t *records, const char *what,
                             lvcl_status *st)
{
    cl_int err = CL_SUCCESS;
    size_t offset = 0;
    for (int i = 0; i < vol->tally_parts && err == CL_SUCCESS && vol->tally_bytes; i++) {
        err = clEnqueueWriteBuffer(vol->dev->queue, vol->buf.tallies[i], CL_TRUE, 0, lvcl_volume_part_bytes(vol, i),
                                   (const char *)tallies + offset, 0, NULL, NULL);
        offset += lvcl_volume_part_bytes(vol, i);
    }
    if (err == CL_SUCCESS && records)
        err = clEnqueueWriteBuffer(vol->dev->queue, vol->buf.subcells, CL_TRUE, 0, lvcl_volume_record_bytes(vol),
                                   records, 0, NULL, NULL);
    return lvcl_cl_check(err, what, st);
}

lvcl_error lvcl_volume_write_lit(lvcl_light_volume *vol, const float *lit, const char *what, lvcl_status *st)
{
    return lvcl_cl_check(clEnqueueWriteBuffer(vol->dev->queue, vol->buf.lit_volume, CL_TRUE, 0,
                                              (size_t)vol->buf.info.slot_count * sizeof(float), lit, 0, NULL, NULL),
                         what, st);
}

lvcl_error lvcl_volume_merge(lvcl_light_volume *const *vols, int count, lvcl_status *st)
{
    int64_t *sum = NULL, *t = NULL;
    uint32_t *rec_sum = NULL, *rec = NULL;
    const lv_grid_info *g = &vols[0]->buf.info;
    size_t tally_count = vols[0]->tally_bytes / sizeof(int64_t);
    lvcl_error e = lvcl_volume_read(vols[0], &sum, &rec_sum, st);
    for (int d = 1; d < count && !e; d++) {
        if ((e = lvcl_volume_read(vols[d], &t, &rec, st))) break;
        for (size_t i = 0; i < tally_count; i++) sum[i] += t[i];
        for (size_t s = 0; s <= g->slot_count; s++) {
            uint32_t *a = &rec_sum[s * LV_SUBCELL_STRIDE], *b = &rec[s * LV_SUBCELL_STRIDE];
            a[0] |= b[0]; /* the masks */
            a[1] |= b[1];
            for (size_t w = 2; w < LV_SUBCELL_LIT_POINT; w++) a[w] += b[w]; /* the ray counters */
            for (size_t w = LV_SUBCELL_LIT_POINT; w < LV_SUBCELL_STRIDE;
                 w++) /* the largest lit point, as on one device */
                if (b[w] > a[w]) a[w] = b[w];
        }
        free(t);
        free(rec);
        t = NULL;
        rec = NULL;
    }
    uint64_t particles = 0;
    for (int d = 0; d < count; d++) particles += vols[d]->particles;
    for (int d = 0; d < count && !e; d++) {
        vols[d]->buf.info.particles = (float)particles; /* the lookups' normalisation */
        e = lvcl_volume_write(vols[d], sum, rec_sum, "storing the merged light volume", st);
    }
    free(sum);
    free(rec_sum);
    return e;
}
