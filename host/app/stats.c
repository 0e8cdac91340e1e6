#include "stats.h"

#include <stdio.h>


static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"' || *s == '\\') fprintf(f, "\\%c", *s);
        else if ((unsigned char)*s < 0x20) fprintf(f, "\\u%04x", *s);
        else fputc(*s, f);
    }
    fputc('"', f);
}

lvcl_error lvcl_stats_write(const char *path, const lvcl_stats *s, lvcl_status *st)
{
    FILE *f = fopen(path, "w");
    if (!f) return lvcl_fail(st, LVCL_ERR_IO, "cannot write stats to %s", path);
    const lvcl_render_result *r = s->result;
    const lvcl_session *ss = s->session;
    double pixel_samples = (double)r->width * r->height * r->samples;
    fprintf(f, "{\n  \"scene\": ");
    json_string(f, s->options->scene);
    fprintf(f, ",\n  \"mode\": ");
    json_string(f, s->options->mode);
    fprintf(f, ",\n  \"device\": ");
    const lvcl_session_device *first = &ss->devices[0];
    json_string(f, first->device.name);
    fprintf(f, ",\n  \"device_index\": %d,\n  \"platform\": ", first->device.index);
    json_string(f, first->device.platform_name);
    fprintf(f,
            ",\n  \"triangles\": %zu,\n  \"triangles_skipped\": %zu,\n  \"meshes\": %zu,\n  \"instances\": %zu,\n"
            "  \"instanced_triangles\": %zu,\n  \"bvh_nodes\": %zu,\n  \"bvh_depth\": %d,\n  \"bvh_bytes\": %zu,\n"
            "  \"device_bytes\": %zu,\n  \"scene_tables_split\": %d,\n",
            ss->accel.triangle_count, ss->accel.skipped, ss->accel.mesh_count, ss->accel.instance_count,
            ss->accel.instanced_triangles, ss->accel.node_count, ss->accel.depth,
            ss->accel.node_count * sizeof(lv_bvh_node), first->device_scene.device_bytes,
            first->device_scene.split_tables);
    fprintf(f, "  \"kernel_options\": ");
    json_string(f, first->program.options);
    fprintf(f,
            ",\n  \"kernel_from_cache\": %s,\n  \"kernel_build_seconds\": %.4f,\n"
            "  \"scene_load_seconds\": %.4f,\n  \"bvh_build_seconds\": %.4f,\n  \"startup_seconds\": %.4f,\n"
            "  \"first_launch_seconds\": %.4f,\n  \"render_seconds\": %.4f,\n",
            first->program.from_cache ? "true" : "false", first->program.build_seconds, s->scene_load_seconds,
            ss->bvh_build_seconds, s->startup_seconds, r->first_launch_seconds, r->render_seconds);
    fprintf(f,
            "  \"width\": %d,\n  \"height\": %d,\n  \"spp\": %d,\n  \"samples_per_second\": %.1f,\n"
            "  \"seed\": %u,\n  \"max_depth\": %d",
            r->width, r->height, r->samples, r->render_seconds > 0 ? pixel_samples / r->render_seconds : 0.0,
            s->options->seed, s->options->max_depth);
    /* The light volume: the grid is every device's; the work adds up. */
    const lvcl_light_volume *v = &first->volume;
    uint64_t particles = 0, segments = 0, visibility_rays = 0;
    double trace_seconds = 0;
    for (int d = 0; d < ss->device_count; d++) {
        const lvcl_light_volume *dv = &ss->devices[d].volume;
        particles += dv->particles;
        segments += dv->segments;
        visibility_rays += dv->visibility_rays;
        if (dv->trace_seconds > trace_seconds) trace_seconds = dv->trace_seconds;
    }
    trace_seconds += ss->merge_seconds;
    if (particles) {
        const lv_grid_info *g = &v->buf.info;
        fprintf(f,
                ",\n  \"grid\": [%u, %u, %u],\n  \"cell_size\": %g,\n  \"dirs\": %u,\n  \"cells_allocated\": %u,\n"
                "  \"light_volume_bytes\": %zu,\n  \"particles\": %llu,\n  \"particle_trace_seconds\": %.4f,\n"
                "  \"particles_per_second\": %.1f,\n  \"segments\": %llu,\n  \"segments_per_second\": %.1f,\n"
                "  \"subcells\": %u,\n  \"visibility_rays\": %llu,\n  \"light_volume_buffers\": %d",
                g->dims[0], g->dims[1], g->dims[2], g->cell_size, g->dirs, g->slot_count,
                v->device_bytes, (unsigned long long)particles, trace_seconds,
                trace_seconds > 0 ? (double)particles / trace_seconds : 0.0, (unsigned long long)segments,
                trace_seconds > 0 ? (double)segments / trace_seconds : 0.0, g->subcells,
                (unsigned long long)visibility_rays, v->tally_parts);
    }
    /* Each device's share of the work. */
    fprintf(f, ",\n  \"devices\": [");
    for (int d = 0; d < ss->device_count; d++) {
        const lvcl_session_device *sd = &ss->devices[d];
        fprintf(f, "%s\n    {\"name\": ", d ? "," : "");
        json_string(f, sd->device.name);
        fprintf(f,
                ", \"index\": %d, \"compute_units\": %u, \"particles\": %llu, \"particle_trace_seconds\": %.4f, "
                "\"bands\": %d, \"pixels\": %zu, \"render_busy_seconds\": %.4f}",
                sd->device.index, sd->device.compute_units, (unsigned long long)sd->volume.particles,
                sd->volume.trace_seconds, sd->pass.bands, sd->pass.pixels, sd->pass.busy_seconds);
    }
    fprintf(f, "\n  ]");
    fprintf(f, "\n}\n");
    if (fclose(f) != 0) return lvcl_fail(st, LVCL_ERR_IO, "cannot write stats to %s", path);
    return LVCL_OK;
}
