/* Reading a light volume back, and adding the volumes of several devices. */
#include <stdlib.h>
#include <string.h>

#include "light_volume_internal.h"

/* Moves the subcell records between the device's three buffers and the
 * host's one block (lvcl_volume_read). */
static cl_int move_records(const lvcl_light_volume *vol, uint32_t *records, int write)
{
    size_t bytes[3], at = 0;
    lvcl_volume_record_sections(vol, bytes);
    cl_mem bufs[3];
    lvcl_volume_record_buffers(vol, bufs);
    cl_int err = CL_SUCCESS;
    for (int i = 0; i < 3 && err == CL_SUCCESS; at += bytes[i], i++)
        if (bytes[i])
            err = write ? clEnqueueWriteBuffer(vol->dev->queue, bufs[i], CL_TRUE, 0, bytes[i], (char *)records + at, 0,
                                               NULL, NULL)
                        : clEnqueueReadBuffer(vol->dev->queue, bufs[i], CL_TRUE, 0, bytes[i], (char *)records + at, 0,
                                              NULL, NULL);
    return err;
}

lvcl_error lvcl_volume_read(const lvcl_light_volume *vol, int64_t **tallies, uint32_t **records, lvcl_status *st)
{
    const lvcl_device *dev = vol->dev;
    size_t record_bytes = lvcl_volume_record_bytes(vol);
    *tallies = malloc(vol->tally_bytes ? vol->tally_bytes : 8);
    if (records) *records = malloc(record_bytes);
    if (!*tallies || (records && !*records)) {
        free(*tallies);
        if (records) free(*records);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory reading the light volume");
    }
    cl_int err = CL_SUCCESS;
    size_t offset = 0;
    for (int i = 0; i < vol->tally_parts && err == CL_SUCCESS && vol->tally_bytes; i++) {
        err = clEnqueueReadBuffer(dev->queue, vol->buf.tallies[i], CL_TRUE, 0, lvcl_volume_part_bytes(vol, i),
                                  (char *)*tallies + offset, 0, NULL, NULL);
        offset += lvcl_volume_part_bytes(vol, i);
    }
    if (err == CL_SUCCESS && records) err = move_records(vol, *records, 0);
    lvcl_error e = lvcl_cl_check(err, "reading the light volume", st);
    if (e) {
        free(*tallies);
        *tallies = NULL;
        if (records) {
            free(*records);
            *records = NULL;
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
    if (err == CL_SUCCESS && records) err = move_records(vol, (uint32_t *)records, 1);
    return lvcl_cl_check(err, what, st);
}

lvcl_error lvcl_volume_write_lit(lvcl_light_volume *vol, const float *lit, const char *what, lvcl_status *st)
{
    return lvcl_cl_check(clEnqueueWriteBuffer(vol->dev->queue, vol->buf.lit_volume, CL_TRUE, 0,
                                              (size_t)vol->buf.info.slot_count * sizeof(float), lit, 0, NULL, NULL),
                         what, st);
}

/* How the subcell records add up, a section of the host's block at a time
 * (lvcl_volume_read): the marks OR, the ray counters add, and the lit point
 * is the largest, as on one device. */
static const lvcl_reduce_op record_ops[3] = {LVCL_REDUCE_OR_U32, LVCL_REDUCE_SUM_U32, LVCL_REDUCE_MAX_U32};

static uint32_t combine(lvcl_reduce_op op, uint32_t a, uint32_t b)
{
    return op == LVCL_REDUCE_OR_U32 ? a | b : op == LVCL_REDUCE_SUM_U32 ? a + b : a > b ? a : b;
}

/* The particles of every volume, stored in each as the lookups' normalisation. */
static uint64_t local_particles(lvcl_light_volume *const *vols, int count)
{
    uint64_t particles = 0;
    for (int d = 0; d < count; d++) particles += vols[d]->particles;
    return particles;
}

static lvcl_error store_sum(lvcl_light_volume *const *vols, int count, uint64_t particles, const int64_t *tallies,
                            const uint32_t *records, lvcl_status *st)
{
    lvcl_error e = LVCL_OK;
    for (int d = 0; d < count && !e; d++) {
        vols[d]->buf.info.particles = (float)particles;
        e = lvcl_volume_write(vols[d], tallies, records, "storing the merged light volume", st);
    }
    return e;
}

lvcl_error lvcl_volume_merge(lvcl_light_volume *const *vols, int count, lvcl_status *st)
{
    int64_t *sum = NULL, *t = NULL;
    uint32_t *rec_sum = NULL, *rec = NULL;
    size_t tally_count = vols[0]->tally_bytes / sizeof(int64_t);
    lvcl_error e = lvcl_volume_read(vols[0], &sum, &rec_sum, st);
    for (int d = 1; d < count && !e; d++) {
        if ((e = lvcl_volume_read(vols[d], &t, &rec, st))) break;
        for (size_t i = 0; i < tally_count; i++) sum[i] += t[i];
        size_t bytes[3], at = 0;
        lvcl_volume_record_sections(vols[0], bytes);
        for (int p = 0; p < 3; at += bytes[p] / sizeof(uint32_t), p++)
            for (size_t w = at; w < at + bytes[p] / sizeof(uint32_t); w++)
                rec_sum[w] = combine(record_ops[p], rec_sum[w], rec[w]);
        free(t);
        free(rec);
        t = NULL;
        rec = NULL;
    }
    if (!e) e = store_sum(vols, count, local_particles(vols, count), sum, rec_sum, st);
    free(sum);
    free(rec_sum);
    return e;
}

lvcl_error lvcl_volume_reduce(lvcl_light_volume *const *vols, int count, lvcl_cluster *cluster, lvcl_status *st)
{
    int64_t *tallies = NULL;
    uint32_t *records = NULL;
    uint64_t particles = local_particles(vols, count);
    lvcl_error e = lvcl_volume_read(vols[0], &tallies, &records, st);
    if (!e) e = cluster->reduce(cluster, tallies, vols[0]->tally_bytes / sizeof(int64_t), LVCL_REDUCE_SUM_I64, st);
    size_t bytes[3], at = 0;
    lvcl_volume_record_sections(vols[0], bytes);
    for (int p = 0; p < 3 && !e; at += bytes[p] / sizeof(uint32_t), p++)
        if (bytes[p]) e = cluster->reduce(cluster, records + at, bytes[p] / sizeof(uint32_t), record_ops[p], st);
    if (!e) e = cluster->reduce(cluster, &particles, 1, LVCL_REDUCE_SUM_U64, st);
    if (!e) e = store_sum(vols, count, particles, tallies, records, st);
    free(tallies);
    free(records);
    return e;
}

/* FNV-1a over `bytes` bytes, continuing from h. */
static uint64_t fnv1a(uint64_t h, const void *data, size_t bytes)
{
    const unsigned char *b = data;
    for (size_t i = 0; i < bytes; i++) h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
}

lvcl_error lvcl_volume_checksum(const lvcl_light_volume *vol, uint64_t *hash, lvcl_status *st)
{
    int64_t *tallies = NULL;
    uint32_t *records = NULL;
    float *lit = NULL;
    lvcl_error e = lvcl_volume_read(vol, &tallies, &records, st);
    if (!e) e = lvcl_volume_read_lit(vol, &lit, st);
    if (!e) {
        uint64_t h = fnv1a(0xcbf29ce484222325ull, tallies, vol->tally_bytes);
        h = fnv1a(h, records, lvcl_volume_record_bytes(vol));
        /* The lit volumes lv_lit_volumes computes (the last entry is never written). */
        *hash = fnv1a(h, lit, (size_t)vol->buf.info.slot_count * sizeof(float));
    }
    free(tallies);
    free(records);
    free(lit);
    return e;
}
