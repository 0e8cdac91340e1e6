#include "light_volume.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../util/progress.h"
#include "../util/timer.h"

/* Particles per launch: big enough to keep a device busy, small enough for
 * progress and for --time-limit to be checked often. */
#define BATCH (1u << 18)

static size_t cell_index(const lv_grid_info *g, int x, int y, int z)
{
    return (size_t)x + g->dims[0] * ((size_t)y + g->dims[1] * (size_t)z);
}

/* Cell coordinates covering the world box lo..hi (clamped to the grid). A
 * surface lying on a cell boundary belongs to the cells on both sides. */
static void cell_range(const lv_grid_info *g, float inv, const float lo_w[3], const float hi_w[3], int lo[3], int hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = (int)floorf((lo_w[k] - g->origin[k]) * inv - 1e-4f);
        hi[k] = (int)floorf((hi_w[k] - g->origin[k]) * inv + 1e-4f);
        if (lo[k] < 0) lo[k] = 0;
        if (hi[k] > (int)g->dims[k] - 1) hi[k] = (int)g->dims[k] - 1;
    }
}

static void mark_range(const lv_grid_info *g, const int lo[3], const int hi[3], uint8_t *mark)
{
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++)
            for (int x = lo[0]; x <= hi[0]; x++) mark[cell_index(g, x, y, z)] = 1;
}

/* Marks the cells the geometry touches: each placed triangle's bounding box
 * (conservative for slanted triangles; see docs/light-volume.md), except
 * that a part of a mesh's tree whose placed box spans at most two cells
 * along every axis marks that box whole. A tile instanced hundreds of
 * times then costs a few boxes, not its 500,000 triangles. */
static void mark_geometry(const lvcl_packed_scene *p, const lv_grid_info *g, uint8_t *mark)
{
    float inv = 1.0f / g->cell_size;
    int stack[LVCL_BVH_MAX_DEPTH + 1];
    for (size_t in = 0; in < p->instance_count; in++) {
        const lv_instance *inst = &p->instances[in];
        int top = 0;
        stack[top++] = (int)inst->root;
        while (top > 0) {
            const lv_bvh_node *n = &p->nodes[stack[--top]];
            float lo_w[3], hi_w[3];
            int lo[3], hi[3];
            lvcl_transform_box(inst->world_from_object, n->bmin, n->bmax, lo_w, hi_w);
            cell_range(g, inv, lo_w, hi_w, lo, hi);
            if (hi[0] - lo[0] <= 1 && hi[1] - lo[1] <= 1 && hi[2] - lo[2] <= 1) {
                mark_range(g, lo, hi, mark);
            } else if (n->count > 0) {
                for (int t = n->index; t < n->index + n->count; t++) {
                    float v[9];
                    lvcl_packed_triangle_world(p, in, (size_t)t, v);
                    for (int k = 0; k < 3; k++) {
                        lo_w[k] = fminf(v[k], fminf(v[3 + k], v[6 + k]));
                        hi_w[k] = fmaxf(v[k], fmaxf(v[3 + k], v[6 + k]));
                    }
                    cell_range(g, inv, lo_w, hi_w, lo, hi);
                    mark_range(g, lo, hi, mark);
                }
            } else {
                stack[top++] = (int)(n - p->nodes) + 1;
                stack[top++] = n->index;
            }
        }
    }
}

/* A lookup jitters up to half a cell from a surface, so the cells next to
 * geometry cells are stored too. */
static size_t assign_slots(const lv_grid_info *g, const uint8_t *mark, uint32_t *slot)
{
    size_t count = 0;
    for (int z = 0; z < (int)g->dims[2]; z++)
        for (int y = 0; y < (int)g->dims[1]; y++)
            for (int x = 0; x < (int)g->dims[0]; x++) {
                int near = 0;
                for (int dz = -1; dz <= 1 && !near; dz++)
                    for (int dy = -1; dy <= 1 && !near; dy++)
                        for (int dx = -1; dx <= 1 && !near; dx++) {
                            int a = x + dx, b = y + dy, c = z + dz;
                            if (a < 0 || b < 0 || c < 0 || a >= (int)g->dims[0] || b >= (int)g->dims[1] ||
                                c >= (int)g->dims[2])
                                continue;
                            near = mark[cell_index(g, a, b, c)];
                        }
                slot[cell_index(g, x, y, z)] = near ? (uint32_t)count++ : LV_EMPTY_CELL;
            }
    return count;
}

lvcl_error lvcl_volume_create(const lvcl_device *dev, const lvcl_packed_scene *p, const lvcl_volume_settings *s,
                              lvcl_light_volume *vol, lvcl_status *st)
{
    memset(vol, 0, sizeof *vol);
    if (s->dirs < 1 || s->dirs > 64) return lvcl_fail(st, LVCL_ERR_USAGE, "--dirs must be from 1 to 64");
    if (s->subcells < 0 || s->subcells > 4) return lvcl_fail(st, LVCL_ERR_USAGE, "--subcells must be from 0 to 4");
    if (s->offset < 0 || s->offset >= 1) return lvcl_fail(st, LVCL_ERR_USAGE, "--grid-offset must be in [0, 1)");
    lv_grid_info *g = &vol->buf.info;
    float extent[3], longest = 0.0f;
    for (int k = 0; k < 3; k++) {
        extent[k] = p->bounds_max[k] - p->bounds_min[k];
        longest = fmaxf(longest, extent[k]);
    }
    g->cell_size = s->cell_size > 0 ? (float)s->cell_size : longest / (float)(s->cells > 0 ? s->cells : 1);
    if (!(g->cell_size > 0.0f)) return lvcl_fail(st, LVCL_ERR_UNSUPPORTED, "the scene has no extent for a light volume");
    /* One spare cell on every side holds lookups jittered off the bounds;
     * an offset shifts the grid by a fraction of a cell (one more cell). */
    double cells = 1.0;
    for (int k = 0; k < 3; k++) {
        double d = ceil(extent[k] / g->cell_size) + (s->offset > 0 ? 3.0 : 2.0);
        if (d < 1.0) d = 1.0;
        g->dims[k] = (lv_u32)d;
        g->origin[k] = p->bounds_min[k] - g->cell_size * (1.0f + (float)s->offset);
        cells *= d;
    }
    if (cells > 1 << 28)
        return lvcl_fail(st, LVCL_ERR_TOO_LARGE, "a %ux%ux%u light-volume grid is too large (cell size %g m)",
                         g->dims[0], g->dims[1], g->dims[2], g->cell_size);
    g->dirs = (lv_u32)s->dirs;
    g->bins = 2 * g->dirs * g->dirs;
    g->total_power = p->info.total_light_power;
    g->subcells = (lv_u32)s->subcells;
    g->visibility_rate = (float)(s->visibility_rate > 0 ? s->visibility_rate : LVCL_VISIBILITY_RATE);

    vol->cell_count = (size_t)cells;
    uint8_t *mark = calloc(vol->cell_count, 1);
    vol->cell_slot = malloc(vol->cell_count * sizeof(uint32_t));
    if (!mark || !vol->cell_slot) {
        free(mark);
        lvcl_volume_release(vol);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for a %zu-cell grid", vol->cell_count);
    }
    mark_geometry(p, g, mark);
    g->slot_count = (lv_u32)assign_slots(g, mark, vol->cell_slot);
    free(mark);

    /* The tallies go in as few buffers as the device's largest allocation
     * allows (GPUs often allow a quarter of their memory in one). */
    size_t slot_bytes = (size_t)g->bins * 3 * sizeof(int64_t);
    vol->tally_bytes = (size_t)g->slot_count * slot_bytes;
    size_t per_part = dev->max_alloc / slot_bytes;
    if (per_part > UINT32_MAX) per_part = UINT32_MAX;
    size_t parts = per_part ? ((size_t)g->slot_count + per_part - 1) / per_part : SIZE_MAX;
    /* Beside the tallies: the cell index, and per slot a subcell record and a lit volume (one buffer each). */
    size_t records = ((size_t)g->slot_count + 1) * (LV_SUBCELL_STRIDE + 1) * sizeof(uint32_t);
    vol->device_bytes = vol->tally_bytes + vol->cell_count * sizeof(uint32_t) + records;
    if (parts > LV_TALLY_PARTS || records > dev->max_alloc || vol->device_bytes > dev->global_mem) {
        lvcl_error e = lvcl_fail(st, LVCL_ERR_TOO_LARGE,
                                 "the light volume needs %.1f MiB (%u cells x %u bins) but %s allows %.1f MiB in one "
                                 "buffer (at most %d buffers) and %.1f MiB in all; use fewer --cells or --dirs",
                                 vol->device_bytes / 1048576.0, g->slot_count, g->bins, dev->name,
                                 dev->max_alloc / 1048576.0, LV_TALLY_PARTS, dev->global_mem / 1048576.0);
        lvcl_volume_release(vol);
        return e;
    }
    vol->tally_parts = parts ? (int)parts : 1;
    g->slots_per_part = (lv_u32)(parts > 1 ? per_part : (g->slot_count ? g->slot_count : 1));
    cl_int err;
    vol->buf.cell_slot = clCreateBuffer(dev->context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                        vol->cell_count * sizeof(uint32_t), vol->cell_slot, &err);
    for (int i = 0; i < vol->tally_parts && err == CL_SUCCESS; i++)
        vol->buf.tallies[i] = clCreateBuffer(dev->context, CL_MEM_READ_WRITE, lvcl_volume_part_bytes(vol, i), NULL, &err);
    if (err == CL_SUCCESS)
        vol->buf.subcells = clCreateBuffer(dev->context, CL_MEM_READ_WRITE,
                                          ((size_t)g->slot_count + 1) * LV_SUBCELL_STRIDE * sizeof(cl_uint), NULL, &err);
    if (err == CL_SUCCESS)
        vol->buf.lit_volume = clCreateBuffer(dev->context, CL_MEM_READ_WRITE, ((size_t)g->slot_count + 1) * sizeof(float),
                                             NULL, &err);
    if (err == CL_SUCCESS)
        vol->bin_directions_buf = clCreateBuffer(dev->context, CL_MEM_READ_WRITE, g->bins * 4 * sizeof(float), NULL,
                                                 &err);
    if (err != CL_SUCCESS) {
        char what[300];
        snprintf(what, sizeof what, "allocating the light volume on %s", dev->name);
        lvcl_volume_release(vol);
        return lvcl_fail(st, LVCL_ERR_TOO_LARGE, "%s failed: %s", what, lvcl_cl_error_name(err));
    }
    return LVCL_OK;
}

size_t lvcl_volume_part_bytes(const lvcl_light_volume *vol, int part)
{
    size_t slot_bytes = (size_t)vol->buf.info.bins * 3 * sizeof(int64_t);
    size_t first = (size_t)part * vol->buf.info.slots_per_part;
    size_t slots = vol->buf.info.slot_count > first ? vol->buf.info.slot_count - first : 0;
    if (slots > vol->buf.info.slots_per_part) slots = vol->buf.info.slots_per_part;
    return slots ? slots * slot_bytes : 8; /* OpenCL refuses empty buffers */
}

/* Runs lv_bin_directions: the table of the bins' central directions. */
static lvcl_error fill_bin_directions(const lvcl_device *dev, const lvcl_program *prog, lvcl_light_volume *vol,
                                      lvcl_status *st)
{
    cl_kernel k;
    lvcl_error e = lvcl_kernel_create(prog, "lv_bin_directions", &k, st);
    if (e) return e;
    lvcl_bin_directions_args args = {.n = vol->buf.info.dirs, .directions = vol->bin_directions_buf};
    if (!(e = lvcl_bind_lv_bin_directions(k, &args, st)))
        e = lvcl_kernel_enqueue(dev, k, vol->buf.info.bins, "computing the bin directions", st);
    clReleaseKernel(k);
    return e;
}

lvcl_error lvcl_volume_finish(const lvcl_device *dev, const lvcl_program *prog, lvcl_light_volume *vol,
                              lvcl_status *st)
{
    cl_kernel k;
    lvcl_error e = lvcl_kernel_create(prog, "lv_lit_volumes", &k, st);
    if (e) return e;
    lvcl_lit_volumes_args args = {.volume = &vol->buf};
    if (!(e = lvcl_bind_lv_lit_volumes(k, &args, st)) &&
        !(e = lvcl_kernel_enqueue(dev, k, vol->buf.info.slot_count, "computing the lit volumes", st)))
        e = lvcl_cl_check(clFinish(dev->queue), "computing the lit volumes", st);
    clReleaseKernel(k);
    return e;
}

void lvcl_particle_source_init(lvcl_particle_source *src, uint64_t particles)
{
    pthread_mutex_init(&src->lock, NULL);
    src->next = 0;
    src->end = particles;
}

void lvcl_particle_source_destroy(lvcl_particle_source *src)
{
    pthread_mutex_destroy(&src->lock);
}

/* The next batch of particle indices: from the shared source, or else the
 * next slice of all the particles (cursor). Returns 0 when none is left. */
static int next_batch(const lvcl_volume_settings *s, uint64_t *cursor, uint64_t *first, cl_uint *count)
{
    uint64_t end = s->particles;
    if (s->source) {
        pthread_mutex_lock(&s->source->lock);
        cursor = &s->source->next;
        end = s->source->end;
    }
    *first = *cursor;
    *count = (cl_uint)(end - *cursor < BATCH ? end - *cursor : BATCH);
    *cursor += *count;
    if (s->source) pthread_mutex_unlock(&s->source->lock);
    return *count > 0;
}

lvcl_error lvcl_volume_trace(const lvcl_device *dev, const lvcl_program *prog, const lvcl_device_scene *ds,
                             const lvcl_volume_settings *s, lvcl_light_volume *vol, lvcl_status *st)
{
    lvcl_error e;
    if ((e = fill_bin_directions(dev, prog, vol, st))) return e;
    if (s->particles == 0 || s->particles > UINT32_MAX)
        return lvcl_fail(st, LVCL_ERR_USAGE, "--particles must be from 1 to %u", UINT32_MAX);
    cl_long zero = 0;
    for (int i = 0; i < vol->tally_parts; i++)
        if ((e = lvcl_cl_check(clEnqueueFillBuffer(dev->queue, vol->buf.tallies[i], &zero, sizeof zero, 0,
                                           lvcl_volume_part_bytes(vol, i), 0, NULL, NULL),
                       "clearing the light volume", st)))
            return e;
    cl_uint none = 0;
    if ((e = lvcl_cl_check(clEnqueueFillBuffer(dev->queue, vol->buf.subcells, &none, sizeof none, 0,
                                       ((size_t)vol->buf.info.slot_count + 1) * LV_SUBCELL_STRIDE * sizeof(cl_uint), 0, NULL,
                                       NULL),
                   "clearing the subcells", st)))
        return e;
    vol->buf.info.particles = (float)s->particles;
    cl_int err;
    /* Per batch: segments traced, visibility rays cast. */
    cl_mem counter = clCreateBuffer(dev->context, CL_MEM_READ_WRITE, 2 * sizeof(cl_uint), NULL, &err);
    if ((e = lvcl_cl_check(err, "allocating the ray counters", st))) return e;
    cl_kernel k;
    if ((e = lvcl_kernel_create(prog, "lv_particle_trace", &k, st))) {
        clReleaseMemObject(counter);
        return e;
    }
    lvcl_particle_trace_args args = {.scene = &ds->buffers,
                                     .volume = &vol->buf,
                                     .inv_total_particles = (float)(1.0 / (double)s->particles),
                                     .store_emitted = s->store_emitted ? 1u : 0u,
                                     .ray_counts = counter};
    if ((e = lvcl_bind_lv_particle_trace(k, &args, st))) {
        clReleaseKernel(k);
        clReleaseMemObject(counter);
        return e;
    }
    lvcl_progress bar;
    lvcl_progress_start(&bar, "particles", s->progress);
    double start = lvcl_seconds();
    vol->segments = vol->visibility_rays = vol->particles = 0;
    uint64_t cursor = 0, first;
    cl_uint count;
    while (next_batch(s, &cursor, &first, &count)) {
        /* 32-bit counts per batch cannot overflow; the totals are 64-bit. */
        cl_uint counts[2] = {0, 0};
        cl_uint f = (cl_uint)first;
        if ((e = lvcl_kernel_arg(k, LV_ARG(lv_particle_trace, first), sizeof f, &f, "the batch's first particle", st)) ||
            (e = lvcl_kernel_arg(k, LV_ARG(lv_particle_trace, count), sizeof count, &count, "the batch's size", st)) ||
            (e = lvcl_cl_check(clEnqueueWriteBuffer(dev->queue, counter, CL_FALSE, 0, sizeof counts, counts, 0, NULL, NULL),
                       "clearing the ray counters", st)) ||
            (e = lvcl_kernel_enqueue(dev, k, count, "launching the particle trace", st)) ||
            (e = lvcl_cl_check(clEnqueueReadBuffer(dev->queue, counter, CL_TRUE, 0, sizeof counts, counts, 0, NULL, NULL),
                       "running the particle trace", st)))
            break;
        vol->segments += counts[0];
        vol->visibility_rays += counts[1];
        vol->particles += count;
        lvcl_progress_update(&bar, (double)(first + count), (double)s->particles, "particles");
    }
    lvcl_progress_finish(&bar);
    clReleaseKernel(k);
    clReleaseMemObject(counter);
    vol->trace_seconds = lvcl_seconds() - start;
    return e;
}

lvcl_error lvcl_volume_read(const lvcl_device *dev, const lvcl_light_volume *vol, int64_t **tallies,
                            uint32_t **masks, lvcl_status *st)
{
    size_t mask_bytes = ((size_t)vol->buf.info.slot_count + 1) * LV_SUBCELL_STRIDE * sizeof(uint32_t);
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

double lvcl_volume_lit_fraction(const lv_grid_info *g, const uint32_t *rec)
{
    uint32_t k = g->subcells;
    if (k == 0) return 1.0;
    double lit = 0.0;
    for (uint32_t i = 0; i < k * k * k; i++) {
        if (!(rec[i >> 5] & (1u << (i & 31u)))) continue;
        uint32_t cast = rec[LV_SUBCELL_CAST + i];
        lit += cast ? (double)rec[LV_SUBCELL_OPEN + i] / cast : 1.0;
    }
    return (lit > 1.0 ? lit : 1.0) / (k * k * k);
}

double lvcl_volume_radiance(const lv_grid_info *g, int64_t tally, double lit_fraction)
{
    double omega = 2.0 * 3.14159265358979 / ((double)g->dirs * g->dirs);
    return (double)g->total_power * ((double)tally / LV_TALLY_SCALE) /
           ((double)g->cell_size * g->cell_size * lit_fraction * omega);
}

lvcl_error lvcl_volume_merge(const lvcl_device *const *devs, lvcl_light_volume *const *vols, int count,
                             lvcl_status *st)
{
    int64_t *sum = NULL, *t = NULL;
    uint32_t *rec_sum = NULL, *rec = NULL;
    const lv_grid_info *g = &vols[0]->buf.info;
    size_t words = ((size_t)g->slot_count + 1) * LV_SUBCELL_STRIDE, tally_count = vols[0]->tally_bytes / sizeof(int64_t);
    lvcl_error e = lvcl_volume_read(devs[0], vols[0], &sum, &rec_sum, st);
    for (int d = 1; d < count && !e; d++) {
        if ((e = lvcl_volume_read(devs[d], vols[d], &t, &rec, st))) break;
        for (size_t i = 0; i < tally_count; i++) sum[i] += t[i];
        for (size_t s = 0; s <= g->slot_count; s++) {
            uint32_t *a = &rec_sum[s * LV_SUBCELL_STRIDE], *b = &rec[s * LV_SUBCELL_STRIDE];
            a[0] |= b[0]; /* the masks */
            a[1] |= b[1];
            for (size_t w = 2; w < LV_SUBCELL_LIT_POINT; w++) a[w] += b[w]; /* the ray counters */
            for (size_t w = LV_SUBCELL_LIT_POINT; w < LV_SUBCELL_STRIDE; w++) /* the largest lit point, as on one device */
                if (b[w] > a[w]) a[w] = b[w];
        }
        free(t);
        free(rec);
        t = NULL;
        rec = NULL;
    }
    for (int d = 0; d < count && !e; d++) {
        cl_int err = CL_SUCCESS;
        size_t offset = 0;
        for (int i = 0; i < vols[d]->tally_parts && err == CL_SUCCESS && vols[d]->tally_bytes; i++) {
            err = clEnqueueWriteBuffer(devs[d]->queue, vols[d]->buf.tallies[i], CL_TRUE, 0,
                                       lvcl_volume_part_bytes(vols[d], i), (char *)sum + offset, 0, NULL, NULL);
            offset += lvcl_volume_part_bytes(vols[d], i);
        }
        if (err == CL_SUCCESS)
            err = clEnqueueWriteBuffer(devs[d]->queue, vols[d]->buf.subcells, CL_TRUE, 0, words * sizeof(uint32_t),
                                       rec_sum, 0, NULL, NULL);
        e = lvcl_cl_check(err, "storing the merged light volume", st);
    }
    free(sum);
    free(rec_sum);
    return e;
}

void lvcl_volume_release(lvcl_light_volume *vol)
{
    lvcl_volume_buffers_release(&vol->buf);
    if (vol->bin_directions_buf) clReleaseMemObject(vol->bin_directions_buf);
    free(vol->cell_slot);
    memset(vol, 0, sizeof *vol);
}
