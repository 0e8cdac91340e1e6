#include "device_scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* One table to upload: count elements of `size` bytes, in buffers of
 * per_part elements (UINT32_MAX: one buffer; for a table of one buffer at
 * most, found from its own size). */
typedef struct {
    cl_mem *parts;    /* max_parts slots */
    int max_parts;    /* LV_SCENE_PARTS for the tables the kernels read split, else 1 */
    const void *data; /* NULL: allocated uninitialised (the kernels never read it) */
    size_t count, size;
    uint32_t per_part;
    const char *what;
} table;

/* Elements per buffer for tables of `count` elements, the largest
 * `largest` bytes each: all in one buffer if they fit, else as many as the
 * largest allocation holds (0 if not even one does). */
static uint32_t elements_per_part(size_t count, size_t largest, cl_ulong max_alloc)
{
    cl_ulong fit = max_alloc / largest;
    if (count <= fit) return UINT32_MAX;
    return (uint32_t)fit; /* count < 2^32, so fit is too */
}

static size_t part_count(const table *t)
{
    if (t->per_part == UINT32_MAX) return 1;
    return t->per_part ? (t->count + t->per_part - 1) / t->per_part : SIZE_MAX;
}

static lvcl_error upload_table(const lvcl_device *dev, const table *t, lvcl_status *st)
{
    size_t parts = part_count(t);
    for (size_t k = 0; k < parts; k++) {
        size_t first = k * (size_t)t->per_part, n = t->count - first;
        if (parts > 1 && n > t->per_part) n = t->per_part;
        cl_int err;
        cl_mem_flags flags = CL_MEM_READ_ONLY | (t->data ? CL_MEM_COPY_HOST_PTR : 0);
        void *host = t->data ? (char *)t->data + first * t->size : NULL;
        t->parts[k] = lvcl_buffer_create(dev, flags, n * t->size, host, &err);
        if (err != CL_SUCCESS) {
            char what[200];
            snprintf(what, sizeof what, "allocating %.1f MiB for %s on %s", n * t->size / 1048576.0, t->what,
                     dev->name);
            return lvcl_cl_check(err, what, st);
        }
    }
    return LVCL_OK;
}

/* Where each table's elements come from (a table of the contract without
 * an entry here does not compile). OpenCL refuses zero-sized buffers, so
 * empty tables get a dummy entry. */
#define AT_LEAST_ONE(n) ((n) ? (n) : 1)
#define SOURCE_nodes (p->nodes, p->node_count)
#define SOURCE_instances (p->instances, p->instance_count)
#define SOURCE_tri_groups (p->tri_groups, p->group_count)
#define SOURCE_triangles (p->triangles, p->triangle_count)
#define SOURCE_normals (scene->normals, vertices)
#define SOURCE_uvs (scene->uvs, vertices)
#define SOURCE_materials (p->materials, AT_LEAST_ONE(p->material_count))
#define SOURCE_textures (p->textures, AT_LEAST_ONE(p->texture_count))
#define SOURCE_texels (p->texels, AT_LEAST_ONE(p->texel_count))
#define SOURCE_lights (p->lights, AT_LEAST_ONE(p->light_count))
#define SOURCE_punctuals (scene->punctuals, AT_LEAST_ONE(scene->punctual_count))
#define EXPAND(x) x
#define DATA_AND_COUNT(data, count) data, count
#define COUNT_ONLY(data, count) (count)
#define COUNT(name) EXPAND(COUNT_ONLY SOURCE_##name)

/* Tables read with the same index split at the same element: the largest
 * element among them sets how many fit a buffer. */
#define LARGEST_ELEMENT(type, name, stride, per_part, what) \
    if ((stride) * sizeof(type) > largest.per_part) largest.per_part = (lv_u32)((stride) * sizeof(type));
#define PER_PART(type, name, stride, per_part, what) \
    in->per_part = elements_per_part(COUNT(name), largest.per_part, dev->max_alloc);
#define TABLE_SPLIT(type, name, stride, per_part, what)                             \
    {ds->buffers.name,        LV_SCENE_PARTS, EXPAND(DATA_AND_COUNT SOURCE_##name), \
     (stride) * sizeof(type), in->per_part,   what},
#define TABLE_ONE(type, name, what) {&ds->buffers.name, 1, EXPAND(DATA_AND_COUNT SOURCE_##name), sizeof(type), 0, what},

lvcl_error lvcl_device_scene_upload(const lvcl_device *dev, const lvcl_scene *scene, const lvcl_packed_scene *p,
                                    lvcl_device_scene *ds, lvcl_status *st)
{
    memset(ds, 0, sizeof *ds);
    ds->buffers.info = p->info;
    size_t vertices = AT_LEAST_ONE(scene->vertex_count);
    lv_scene_info *in = &ds->buffers.info, largest = {0};
    LV_SCENE_BUFFERS(LARGEST_ELEMENT, LV_IGNORE_ONE)
    LV_SCENE_BUFFERS(PER_PART, LV_IGNORE_ONE)
    table list[] = {LV_SCENE_BUFFERS(TABLE_SPLIT, TABLE_ONE)};
    size_t count = sizeof list / sizeof list[0];
    size_t total = 0;
    for (size_t i = 0; i < count; i++) {
        table *t = &list[i];
        size_t bytes = t->count * t->size;
        if (t->max_parts == 1) t->per_part = elements_per_part(t->count, t->size, dev->max_alloc);
        size_t parts = part_count(t);
        if (parts > (size_t)t->max_parts)
            return lvcl_fail(st, LVCL_ERR_TOO_LARGE,
                             "the scene's %s need %.1f MiB, but %s allows %.1f MiB in one buffer (%d buffer%s at most)",
                             t->what, bytes / 1048576.0, dev->name, dev->max_alloc / 1048576.0, t->max_parts,
                             t->max_parts > 1 ? "s" : "");
        if (parts > 1) ds->split_tables++;
        total += bytes;
    }
    if (total > dev->global_mem)
        return lvcl_fail(st, LVCL_ERR_TOO_LARGE, "the scene needs %.1f MiB of device memory, but %s has %.1f MiB",
                         total / 1048576.0, dev->name, dev->global_mem / 1048576.0);

    for (size_t i = 0; i < count; i++) {
        lvcl_error e = upload_table(dev, &list[i], st);
        if (e) {
            lvcl_device_scene_release(ds);
            return e;
        }
    }
    ds->device_bytes = total;
    return LVCL_OK;
}

lvcl_error lvcl_device_scene_update_lights(const lvcl_device *dev, const lvcl_packed_scene *p, lvcl_device_scene *ds,
                                           lvcl_status *st)
{
    if (!p->light_count) return LVCL_OK;
    return lvcl_cl_check(clEnqueueWriteBuffer(dev->queue, ds->buffers.lights, CL_TRUE, 0,
                                              p->light_count * sizeof(lv_light), p->lights, 0, NULL, NULL),
                         "updating the light table", st);
}

void lvcl_device_scene_release(lvcl_device_scene *ds)
{
    lvcl_scene_buffers_release(&ds->buffers);
    memset(ds, 0, sizeof *ds);
}

lvcl_error lvcl_device_scene_bind(const lvcl_device_scene *ds, cl_kernel k, cl_uint first, lvcl_status *st)
{
    return lvcl_scene_buffers_bind(&ds->buffers, k, first, st);
}
