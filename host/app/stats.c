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
    const lvcl_device *dev = lvcl_session_device(ss, 0);
    const lvcl_device_scene *ds = lvcl_session_device_scene(ss, 0);
    const lvcl_program *prog = lvcl_session_program(ss, 0);
    const lvcl_accel *accel = lvcl_session_accel(ss);
    const lvcl_packed_scene *packed = lvcl_session_packed_scene(ss);
    json_string(f, dev->name);
    fprintf(f, ",\n  \"device_index\": %d,\n  \"platform\": ", dev->index);
    json_string(f, dev->platform_name);
    fprintf(f,
            ",\n  \"triangles\": %zu,\n  \"triangles_skipped\": %zu,\n  \"meshes\": %zu,\n  \"instances\": %zu,\n"
            "  \"instanced_triangles\": %zu,\n  \"bvh_nodes\": %zu,\n  \"bvh_width\": %d,\n  \"bvh_depth\": %d,\n"
            "  \"bvh_stack_need\": %d,\n  \"bvh_bytes\": %zu,\n"
            "  \"device_bytes\": %zu,\n  \"scene_tables_split\": %d,\n",
            accel->triangle_count, accel->skipped, accel->mesh_count, accel->instance_count, accel->instanced_triangles,
            packed->node_count, packed->bvh_width, accel->depth, packed->stack_need,
            packed->node_count * sizeof(lv_wide_node), ds->device_bytes, ds->split_tables);
    fprintf(f, "  \"kernel_options\": ");
    json_string(f, prog->options);
    fprintf(f,
            ",\n  \"kernel_from_cache\": %s,\n  \"kernel_build_seconds\": %.4f,\n"
            "  \"scene_load_seconds\": %.4f,\n  \"bvh_build_seconds\": %.4f,\n  \"startup_seconds\": %.4f,\n"
            "  \"first_launch_seconds\": %.4f,\n  \"render_seconds\": %.4f,\n",
            prog->from_cache ? "true" : "false", prog->build_seconds, s->scene_load_seconds,
            lvcl_session_bvh_build_seconds(ss), s->startup_seconds, r->first_launch_seconds, r->render_seconds);
    fprintf(f,
            "  \"width\": %d,\n  \"height\": %d,\n  \"spp\": %d,\n  \"interrupted\": %s,\n  \"adaptive\": %s,\n"
            "  \"samples_per_second\": %.1f,\n  \"seed\": %u,\n  \"max_depth\": %d,\n  \"see_through\": %s,\n"
            "  \"view_odds\": %s",
            r->width, r->height, r->samples, s->interrupted_by ? "true" : "false", r->adaptive ? "true" : "false",
            r->render_seconds > 0 ? pixel_samples / r->render_seconds : 0.0, s->options->seed, s->options->max_depth,
            r->see_through ? "true" : "false", r->view_odds ? "true" : "false");
    /* The light volume: the grid is every device's; the work adds up,
     * over every rank's devices where several shared it. */
    int devices = lvcl_session_device_count(ss);
    uint64_t particles = 0, segments = 0, visibility_rays = 0;
    double trace_seconds = lvcl_session_volume_seconds(ss);
    for (int d = 0; d < devices; d++) {
        const lvcl_light_volume *dv = lvcl_session_volume(ss, d);
        if (!dv) continue;
        lvcl_volume_stats w = lvcl_volume_stats_of(dv);
        particles += w.particles;
        segments += w.segments;
        visibility_rays += w.visibility_rays;
    }
    if (s->ranks && particles) {
        particles = segments = 0;
        for (int r = 0; r < s->rank_count; r++) {
            particles += s->ranks[r].particles;
            segments += s->ranks[r].segments;
        }
    }
    if (particles) {
        const lvcl_light_volume *v = lvcl_session_volume(ss, 0);
        uint64_t checksum;
        lvcl_error e = lvcl_volume_checksum(v, &checksum, st);
        if (e) {
            fclose(f);
            return e;
        }
        const lv_grid_info *g = lvcl_volume_grid(v);
        lvcl_volume_stats vw = lvcl_volume_stats_of(v);
        fprintf(f,
                ",\n  \"grid\": [%u, %u, %u],\n  \"cell_size\": %g,\n  \"dirs\": %u,\n  \"cells_allocated\": %u,\n"
                "  \"tally_sets\": %u,\n  \"merged_cells\": %zu,\n  \"split_cells\": %zu,\n  \"fine_dir_slots\": "
                "%zu,\n  \"mixed_slots\": %zu,\n  \"light_volume_bytes\": %zu,\n  \"axis_sums_bytes\": "
                "%zu,\n  \"particles\": "
                "%llu,\n  \"particle_trace_seconds\": %.4f,\n"
                "  \"particles_per_second\": %.1f,\n  \"segments\": %llu,\n  \"segments_per_second\": %.1f,\n"
                "  \"subcells\": %u,\n  \"visibility_rays\": %llu,\n  \"light_volume_buffers\": %d,\n"
                "  \"light_volume_checksum\": \"%016llx\"",
                g->dims[0], g->dims[1], g->dims[2], g->cell_size, g->dirs, g->slot_count, g->tally_sets,
                vw.merged_cells, vw.split_cells, vw.fine_slots, vw.mixed_slots, vw.device_bytes, vw.axis_sums_bytes,
                (unsigned long long)particles, trace_seconds,
                trace_seconds > 0 ? (double)particles / trace_seconds : 0.0, (unsigned long long)segments,
                trace_seconds > 0 ? (double)segments / trace_seconds : 0.0, g->subcells,
                (unsigned long long)visibility_rays, vw.tally_buffers, (unsigned long long)checksum);
    }
    const lvcl_budget_report *b = lvcl_session_budget(ss);
    if (b->used)
        fprintf(f,
                ",\n  \"budget\": {\"seconds\": %.4f, \"volume_noise\": %.6g, \"gather_noise\": %.6g, "
                "\"gather_noise_per_particle\": %.6g, \"adaptive_share\": %.4g, "
                "\"seconds_per_particle\": %.6g, \"seconds_per_sample\": %.6g, \"warm_up_seconds\": %.4f, "
                "\"measure_seconds\": %.4f, \"planned_particles\": %llu, \"spent_seconds\": %.4f}",
                s->options->time_limit, b->volume_noise, b->gather_noise, b->gather_noise_per_particle,
                b->adaptive_share, b->seconds_per_particle, b->seconds_per_sample, b->warm_up_seconds,
                b->measure_seconds, (unsigned long long)b->planned_particles, b->spent_seconds);
    const lvcl_guided_report *g = lvcl_session_guided(ss);
    if (g->used)
        fprintf(f,
                ",\n  \"guided_choice\": {\"guided_cost\": %.6g, \"plain_cost\": %.6g, \"paths\": \"%s\", "
                "\"guided_cost_error\": %.6g, \"plain_cost_error\": %.6g, \"guide_noise\": %.6g, "
                "\"guide_noise_per_particle\": %.6g, \"seconds_per_particle\": %.6g, "
                "\"planned_particles\": %llu, \"measure_seconds\": %.4f, \"pilot_seconds\": %.4f, "
                "\"pilot_spp\": %d}",
                g->guided_cost, g->plain_cost, g->plain ? "plain" : "guided", g->guided_cost_error, g->plain_cost_error,
                g->guide_noise, g->guide_noise_per_particle, g->seconds_per_particle,
                (unsigned long long)g->planned_particles, g->measure_seconds, g->pilot_seconds, g->pilot_spp);
    /* Each device's share of the work. */
    fprintf(f, ",\n  \"devices\": [");
    for (int d = 0; d < devices; d++) {
        const lvcl_device *sdev = lvcl_session_device(ss, d);
        const lvcl_light_volume *dv = lvcl_session_volume(ss, d);
        lvcl_volume_stats w = dv ? lvcl_volume_stats_of(dv) : (lvcl_volume_stats){0};
        lvcl_pass_share pass = lvcl_session_pass_share(ss, d);
        fprintf(f, "%s\n    {\"name\": ", d ? "," : "");
        json_string(f, sdev->name);
        fprintf(f,
                ", \"index\": %d, \"compute_units\": %u, \"particles\": %llu, \"particle_trace_seconds\": %.4f, "
                "\"bands\": %d, \"pixels\": %zu, \"render_busy_seconds\": %.4f}",
                sdev->index, sdev->compute_units, (unsigned long long)w.particles, w.trace_seconds, pass.bands,
                pass.pixels, pass.busy_seconds);
    }
    fprintf(f, "\n  ]");
    /* Each rank's share and its communication, per phase. */
    if (s->ranks) {
        fprintf(f, ",\n  \"ranks\": [");
        for (int r = 0; r < s->rank_count; r++) {
            const lvcl_rank_share *k = &s->ranks[r];
            fprintf(f, "%s\n    {\"rank\": %d, \"host\": ", r ? "," : "", r);
            json_string(f, k->host);
            fprintf(f,
                    ", \"devices\": %d, \"particles\": %llu, \"particle_trace_seconds\": %.4f, \"bands\": %d, "
                    "\"pixels\": %llu, \"render_busy_seconds\": %.4f, \"comm_seconds\": {\"setup\": %.4f, "
                    "\"particles\": %.4f, \"image\": %.4f}, \"reduce_seconds\": {\"particles\": %.4f, \"image\": "
                    "%.4f}, \"comm_bytes\": {\"setup\": %llu, \"particles\": %llu, \"image\": %llu}}",
                    k->devices, (unsigned long long)k->particles, k->particle_trace_seconds, k->bands,
                    (unsigned long long)k->pixels, k->render_busy_seconds, k->comm_seconds[LVCL_PHASE_SETUP],
                    k->comm_seconds[LVCL_PHASE_PARTICLES], k->comm_seconds[LVCL_PHASE_IMAGE],
                    k->reduce_seconds[LVCL_PHASE_PARTICLES], k->reduce_seconds[LVCL_PHASE_IMAGE],
                    (unsigned long long)k->comm_bytes[LVCL_PHASE_SETUP],
                    (unsigned long long)k->comm_bytes[LVCL_PHASE_PARTICLES],
                    (unsigned long long)k->comm_bytes[LVCL_PHASE_IMAGE]);
        }
        fprintf(f, "\n  ]");
    }
    fprintf(f, "\n}\n");
    if (fclose(f) != 0) return lvcl_fail(st, LVCL_ERR_IO, "cannot write stats to %s", path);
    return LVCL_OK;
}
