/* Adaptive cells (host/render/volume_adapt.c): blocks of cells free of
 * geometry share one tally set where the particles cannot tell their cells
 * apart. Checked on the Cornell box at 12 and 20 cells:
 *
 * (a) merging only adds: every set holds the sum of its slots' tallies in
 *     a volume traced without merging, and its lit volume the sum of
 *     theirs, when the decision is taken after a first pass and the rest
 *     of the particles are traced into the merged sets;
 * (b) the same tallies make the same decision (two runs, bit for bit);
 * (c) a larger tolerance merges at least as much, and something merges;
 * (d) the image's mean moves by under 1% (the merge blurs, it does not
 *     lose light). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "../harness.h"
#include "../../host/render/light_volume.h"

typedef struct {
    lvcl_light_volume *volume;
    int64_t *tallies;
    float *lit;
} read_volume;

/* Traces [0, first) into a new volume of session ss, adapts it expecting
 * vs->particles (tolerance 0: not at all), traces the rest and reads it
 * back. */
static int trace(const lvcl_session *ss, const lvcl_volume_settings *vs, uint64_t first, double tolerance,
                 read_volume *out)
{
    lvcl_status st = {0};
    lvcl_volume_settings pass = *vs;
    pass.merge_tolerance = tolerance;
    memset(out, 0, sizeof *out);
    lvcl_error e =
        lvcl_volume_create(lvcl_session_device(ss, 0), lvcl_session_packed_scene(ss), &pass, &out->volume, &st);
    const lvcl_program *prog = lvcl_session_program(ss, 0);
    const lvcl_device_scene *ds = lvcl_session_device_scene(ss, 0);
    pass.particles = first;
    if (!e) e = lvcl_volume_trace(out->volume, prog, ds, &pass, &st);
    if (!e) e = lvcl_volume_adapt(out->volume, (double)vs->particles, tolerance, &st);
    pass.first_particle = first;
    pass.particles = vs->particles;
    if (!e && first < vs->particles) e = lvcl_volume_trace(out->volume, prog, ds, &pass, &st);
    if (!e) e = lvcl_volume_finish(out->volume, prog, &st);
    if (!e) e = lvcl_volume_read(out->volume, &out->tallies, NULL, &st);
    if (!e) e = lvcl_volume_read_lit(out->volume, &out->lit, &st);
    if (e) CHECK("adaptive cells: trace", 0, "%s", st.message);
    return !e;
}

static void release(read_volume *v)
{
    lvcl_volume_release(v->volume);
    free(v->tallies);
    free(v->lit);
}

static void test_merged_sums(const lvcl_session *ss, int cells)
{
    lvcl_volume_settings vs = {.cells = cells, .dirs = 4, .subcells = 4, .particles = 200000};
    read_volume plain, merged, again;
    if (!trace(ss, &vs, vs.particles / 4, 0, &plain)) return;
    if (!trace(ss, &vs, vs.particles / 4, 1.0, &merged) || !trace(ss, &vs, vs.particles / 4, 1.0, &again)) {
        release(&plain);
        return;
    }
    const lv_grid_info *g = lvcl_volume_grid(merged.volume);
    size_t per_set = LV_SET_LONGS(g->bins), sets = g->tally_sets;
    int64_t *sum = calloc(sets * per_set, sizeof(int64_t));
    double *lit = calloc(sets, sizeof(double));
    if (!sum || !lit) exit(1);
    for (uint32_t s = 0; s < g->slot_count; s++) {
        uint32_t t = lvcl_volume_tally_set(merged.volume, s);
        for (size_t i = 0; i < per_set; i++) sum[t * per_set + i] += plain.tallies[s * per_set + i];
        lit[t] += plain.lit[s];
    }
    int same_tallies = !memcmp(sum, merged.tallies, sets * per_set * sizeof(int64_t)), same_lit = 1;
    for (uint32_t s = 0; s < g->slot_count; s++)
        same_lit &= merged.lit[s] == (float)lit[lvcl_volume_tally_set(merged.volume, s)];
    size_t merged_cells = lvcl_volume_stats_of(merged.volume).merged_cells;
    printf("  %d cells: %u slots, %zu tally sets, %zu slots merged\n", cells, g->slot_count, sets, merged_cells);
    CHECK("adaptive cells: a merged set holds the sum of its cells' tallies, traced before and after the merge",
          same_tallies && merged_cells > 0 && sets < g->slot_count, "%d cells: tallies %s, %zu of %u slots merged",
          cells, same_tallies ? "equal" : "differ", merged_cells, g->slot_count);
    CHECK("adaptive cells: a merged set's lit volume is the sum of its cells'", same_lit, "%d cells", cells);
    const lv_grid_info *ga = lvcl_volume_grid(again.volume);
    int same_run =
        ga->tally_sets == g->tally_sets && !memcmp(again.tallies, merged.tallies, sets * per_set * sizeof(int64_t));
    for (uint32_t s = 0; s < g->slot_count && same_run; s++)
        same_run = lvcl_volume_tally_set(again.volume, s) == lvcl_volume_tally_set(merged.volume, s);
    CHECK("adaptive cells: the same tallies merge the same blocks, bit for bit", same_run, "%d cells", cells);
    free(sum);
    free(lit);
    release(&plain);
    release(&merged);
    release(&again);
}

static void test_tolerance(const lvcl_session *ss)
{
    lvcl_volume_settings vs = {.cells = 16, .dirs = 4, .subcells = 4, .particles = 100000};
    const double tolerances[] = {0.25, 4, 1e12};
    size_t merged[3] = {0};
    for (int i = 0; i < 3; i++) {
        read_volume v;
        if (!trace(ss, &vs, vs.particles, tolerances[i], &v)) return;
        merged[i] = lvcl_volume_stats_of(v.volume).merged_cells;
        release(&v);
    }
    printf("  tolerance 0.25 / 4 / 1e12: %zu / %zu / %zu slots merged\n", merged[0], merged[1], merged[2]);
    CHECK("adaptive cells: a larger tolerance merges at least as many cells",
          merged[0] <= merged[1] && merged[1] <= merged[2] && merged[2] > merged[0], "%zu / %zu / %zu", merged[0],
          merged[1], merged[2]);
}

static double image_mean(double tolerance)
{
    lvcl_scene scene;
    lvcl_status st = {0};
    double mean = -1;
    lvcl_render_request req = harness_request(LVCL_MODE_LV, 48, 16, 16, 300000);
    req.volume.merge_tolerance = tolerance;
    if (lvcl_scene_load("cornell", &scene, &st) || harness_render_mean(&scene, 3, &req, &mean, &st))
        CHECK("adaptive cells: render", 0, "%s", st.message);
    return mean;
}

int main(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    lvcl_session *ss = harness_session("cornell", 7);
    test_merged_sums(ss, 12);
    test_merged_sums(ss, 20);
    test_tolerance(ss);
    lvcl_session_close(ss);
    double off = image_mean(0), on = image_mean(1.0);
    printf("  image mean: %.5f without merging, %.5f with\n", off, on);
    CHECK("adaptive cells: the image's mean moves by under 1%", off > 0 && fabs(on / off - 1) < 0.01,
          "%.5f against %.5f", on, off);
    CHECK_EXIT();
}
