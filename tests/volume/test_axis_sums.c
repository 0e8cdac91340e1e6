/* The integrating gather's axis sums (kernels/integrator/gather.h,
 * host/render/volume_axis_sums.c): a Lambertian surface facing exactly
 * along an axis reads its cosine-weighted sum of the cell's bins from them
 * instead of visiting every bin. On the Cornell box, traced in two parts
 * with the sums taken after each:
 *
 * (a) after the second part every slot's six sums equal lv_axis_sum (its
 *     bins' mean-cosine sum with its set's axis correction) computed
 *     afresh for the six axis normals (within 1e-6: the test kernels are
 *     built apart from the renderer's), so the sums follow the volume the
 *     gather reads, axis by axis, slot by slot;
 * (b) lv_axis_of numbers the axes as the sums do, and a normal tilted by
 *     a milliradian is not an axis;
 * (c) the same with every cell split and every slot with light given fine
 *     bins between the parts (the slots change in number and in bins);
 * (d) concentrated light (a lamp seen through glass: segments reached by
 *     specular scattering alone) is gathered with each piece's own cosine:
 *     short segments in many directions, tallied one by one into one cell,
 *     each raise the axis sum facing them by exactly weight x length x
 *     |cosine| and leave the opposite one alone, where the bins' mean
 *     cosines alone are off by up to several percent at 4 x 4 bins; and
 *     light that is not concentrated keeps the bins' mean cosines;
 * (e) the same segments add to the cell's lobe (guided paths' narrow
 *     lobe toward a lamp's image, kernels/volume/guide.h) their luminance
 *     times their direction and their luminance, to the rounding of one
 *     unit a piece, and light that is not concentrated adds nothing.
 * The images the gather makes with them are pinned, bit for bit, by the
 * golden hashes recorded before they existed (tests/render/test_golden.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "../harness.h"
#include "../kernels/test_args.h"
#include "../../host/render/light_volume.h"

typedef LVCL_KERNEL_ARGS(T_AXIS_SUMS_ARGS) t_axis_sums_args;
static LVCL_DEFINE_BINDER(t_axis_sums, T_AXIS_SUMS_ARGS, t_axis_sums_args)
typedef LVCL_KERNEL_ARGS(T_AXIS_CORRECTION_ARGS) t_axis_correction_args;
static LVCL_DEFINE_BINDER(t_axis_correction, T_AXIS_CORRECTION_ARGS, t_axis_correction_args)

static void check_sums(const lvcl_session *ss, int refine, const char *what)
{
    const lvcl_device *dev = lvcl_session_device(ss, 0);
    const lvcl_program *prog = lvcl_session_program(ss, 0);
    const lvcl_device_scene *ds = lvcl_session_device_scene(ss, 0);
    lvcl_volume_settings vs = {.cells = 12, .dirs = 4, .subcells = 4, .particles = 400000};
    lvcl_light_volume *vol = NULL;
    lvcl_status st = {0};
    cl_mem sums = NULL;
    lvcl_error e = lvcl_volume_create(dev, lvcl_session_packed_scene(ss), &vs, &vol, &st);
    lvcl_volume_settings pass = vs;
    pass.particles = 100000;
    if (!e) e = lvcl_volume_trace(vol, prog, ds, &pass, &st);
    if (!e) e = lvcl_volume_finish(vol, prog, &st);
    if (!e) e = lvcl_volume_axis_sums(vol, prog, &sums, &st); /* of the first part */
    if (refine) {
        /* The densest cells split; slots of the others dense enough for
         * fine bins (LVCL_FINE_DENSITY) take them. */
        pass.refine_density = 2 * LVCL_FINE_DENSITY;
        pass.refine_peak = 1e-6;
        pass.refine_memory = (uint64_t)1 << 32;
        if (!e) e = lvcl_volume_refine(vol, (double)vs.particles, &pass, &st);
    }
    pass.first_particle = pass.particles;
    pass.particles = vs.particles;
    if (!e) e = lvcl_volume_trace(vol, prog, ds, &pass, &st);
    if (!e) e = lvcl_volume_finish(vol, prog, &st);
    if (!e) e = lvcl_volume_axis_sums(vol, prog, &sums, &st);
    if (e) {
        CHECK(what, 0, "%s", st.message);
        lvcl_volume_release(vol);
        return;
    }
    const lv_grid_info *g = lvcl_volume_grid(vol);
    size_t work = (size_t)g->slot_count * LV_AXES;
    lvcl_program tests;
    harness_build(dev, &tests);
    cl_mem out = harness_buffer(dev, NULL, work * 2 * 4 * sizeof(float));
    float *o = malloc(work * 2 * 4 * sizeof(float));
    if (!o) exit(1);
    cl_kernel k = harness_kernel(&tests, "t_axis_sums");
    t_axis_sums_args args = {.volume = lvcl_volume_kernel_buffers(vol),
                             .bin_table = lvcl_volume_bin_table(vol),
                             .fine_bin_table = lvcl_volume_fine_bin_table(vol),
                             .axis_sums = sums,
                             .out = out};
    harness_ok(lvcl_bind_t_axis_sums(k, &args, &st), &st, "binding t_axis_sums");
    harness_run(dev, k, work);
    harness_read(dev, out, work * 2 * 4 * sizeof(float), o);
    double worst = 0;
    size_t lit = 0, numbered = 0, tilted_refused = 0;
    for (size_t i = 0; i < work; i++) {
        const float *stored = &o[8 * i], *fresh = &o[8 * i + 4];
        double size = 0;
        for (int c = 0; c < 3; c++) size = fmax(size, fabs(fresh[c]));
        for (int c = 0; c < 3; c++) worst = fmax(worst, fabs(stored[c] - fresh[c]) / fmax(size, 1.0));
        lit += size > 0;
        numbered += stored[3] == (float)(i % LV_AXES);
        tilted_refused += fresh[3] == -1.0f;
    }
    printf("  %s: %u slots (%zu split cells, %zu fine slots), %zu of %zu sums with light, worst relative difference "
           "%.3g\n",
           what, g->slot_count, lvcl_volume_stats_of(vol).split_cells, lvcl_volume_stats_of(vol).fine_slots, lit, work,
           worst);
    CHECK(what, worst <= 1e-6 && lit > work / 4, "worst relative difference %.3g, %zu of %zu sums with light", worst,
          lit, work);
    CHECK("axis sums: lv_axis_of numbers the axes as the sums do", numbered == work, "%zu of %zu", numbered, work);
    CHECK("axis sums: a tilted normal is no axis", tilted_refused == work, "%zu of %zu", tilted_refused, work);
    if (refine)
        CHECK("axis sums: the refined volume has split cells and fine slots",
              lvcl_volume_stats_of(vol).split_cells > 0 && lvcl_volume_stats_of(vol).fine_slots > 0, "none");
    free(o);
    clReleaseKernel(k);
    clReleaseMemObject(out);
    lvcl_program_release(&tests);
    lvcl_volume_release(vol);
}

#define SEGMENTS 41 /* the first of weight 0: the baseline */

/* (d): SEGMENTS - 1 directions spread over the sphere (a spiral), each a
 * segment of a fifth of a cell through the middle of the grid's middle
 * cell, tallied as concentrated light or not. */
/* The lobe sums (shared_types.h) of the set of the slot holding p. */
static int read_lobe(const lvcl_light_volume *vol, const float p[3], int64_t *lobe)
{
    const lv_grid_info *g = lvcl_volume_grid(vol);
    int64_t *tallies = NULL;
    uint32_t *masks = NULL;
    lvcl_status st = {0};
    if (lvcl_volume_read(vol, &tallies, &masks, &st)) return 0;
    uint32_t set = lvcl_volume_tally_set(vol, lvcl_volume_slot_at(vol, p));
    memcpy(lobe, tallies + (size_t)set * LV_SET_LONGS(g->bins) + 3 * (size_t)g->bins + LV_AXES,
           LV_LOBE_LONGS * sizeof *lobe);
    free(tallies);
    free(masks);
    return 1;
}

static void check_correction(const lvcl_session *ss, int concentrated)
{
    const lvcl_device *dev = lvcl_session_device(ss, 0);
    /* No subcells: the test kernel has no copy of the masks to mark. */
    lvcl_volume_settings vs = {.cells = 12, .dirs = 4, .subcells = 0, .particles = 1};
    lvcl_light_volume *vol = NULL;
    lvcl_status st = {0};
    lvcl_error e = lvcl_volume_create(dev, lvcl_session_packed_scene(ss), &vs, &vol, &st);
    if (!e) e = lvcl_volume_trace(vol, lvcl_session_program(ss, 0), lvcl_session_device_scene(ss, 0), &vs, &st);
    if (e) {
        CHECK("axis corrections: a volume to tally into", 0, "%s", st.message);
        lvcl_volume_release(vol);
        return;
    }
    const lv_grid_info *g = lvcl_volume_grid(vol);
    float seg[SEGMENTS][8], length = 0.2f * g->cell_size, centre[3];
    for (int c = 0; c < 3; c++) centre[c] = g->origin[c] + ((float)(g->dims[c] / 2) + 0.5f) * g->cell_size;
    for (int i = 0; i < SEGMENTS; i++) {
        double z = 1.0 - (2.0 * i + 1.0) / SEGMENTS, r = sqrt(1.0 - z * z), phi = 2.399963229728653 * i;
        float d[3] = {(float)(r * cos(phi)), (float)z, (float)(r * sin(phi))};
        for (int c = 0; c < 3; c++) {
            seg[i][c] = centre[c] - 0.5f * length * d[c];
            seg[i][4 + c] = d[c];
        }
        seg[i][3] = length;
        seg[i][7] = i ? 1.0f : 0.0f;
    }
    lvcl_program tests;
    harness_build(dev, &tests);
    cl_mem in = harness_buffer(dev, seg, sizeof seg), out = harness_buffer(dev, NULL, SEGMENTS * 2 * LV_AXES * 4);
    float o[SEGMENTS][2][LV_AXES];
    cl_kernel k = harness_kernel(&tests, "t_axis_correction");
    t_axis_correction_args args = {.volume = lvcl_volume_kernel_buffers(vol),
                                   .bin_table = lvcl_volume_bin_table(vol),
                                   .fine_bin_table = lvcl_volume_fine_bin_table(vol),
                                   .segments = in,
                                   .count = SEGMENTS,
                                   .concentrated = (cl_uint)concentrated,
                                   .out = out};
    harness_ok(lvcl_bind_t_axis_correction(k, &args, &st), &st, "binding t_axis_correction");
    int64_t lobe_before[LV_LOBE_LONGS], lobe_after[LV_LOBE_LONGS];
    int lobe_read = read_lobe(vol, centre, lobe_before);
    harness_run(dev, k, 1);
    harness_read(dev, out, sizeof o, o);
    lobe_read = lobe_read && read_lobe(vol, centre, lobe_after);
    /* Each piece: luminance 0.2 (weight 1 over 0.2 of a cell; the
     * luminance weights add to 1) in tally units, times its direction. */
    double lobe_expected[LV_LOBE_LONGS] = {0, 0, 0, 0}, lobe_worst = 0;
    for (int i = 1; i < SEGMENTS && concentrated; i++) {
        for (int c = 0; c < 3; c++) lobe_expected[c] += 0.2 * LV_TALLY_SCALE * seg[i][4 + c];
        lobe_expected[3] += 0.2 * LV_TALLY_SCALE;
    }
    for (int c = 0; c < LV_LOBE_LONGS; c++)
        lobe_worst = fmax(lobe_worst, fabs((double)(lobe_after[c] - lobe_before[c]) - lobe_expected[c]));
    /* Per segment: the rise of each axis sum against weight x length x
     * |cosine| (in tally units) on the axis facing the light, 0 on the other. */
    double worst = 0, worst_binned = 0, worst_same = 0;
    for (int i = 1; i < SEGMENTS; i++)
        for (int a = 0; a < LV_AXES; a++) {
            double d = seg[i][4 + a / 2], facing = (a & 1) ? d > 0 : d <= 0;
            double expected = facing ? (double)LV_TALLY_SCALE * 0.2 * fabs(d) : 0.0, scale = LV_TALLY_SCALE * 0.2;
            double rise = (double)o[i][0][a] - o[i - 1][0][a], binned = (double)o[i][1][a] - o[i - 1][1][a];
            worst = fmax(worst, fabs(rise - expected) / scale);
            worst_binned = fmax(worst_binned, fabs(binned - expected) / scale);
            worst_same = fmax(worst_same, fabs(rise - binned) / scale);
        }
    printf("  %s: of the piece's amount, the worst rise is off weight x length x |cosine| by %.3g (the bins' "
           "mean cosines alone by %.3g) and off the bins' rise by %.3g\n",
           concentrated ? "concentrated" : "not concentrated", worst, worst_binned, worst_same);
    if (concentrated) {
        CHECK("axis corrections: concentrated light raises each axis sum by its exact cosine", worst < 1e-4,
              "worst %.3g of the piece's amount", worst);
        CHECK("axis corrections: where the bins' mean cosines alone are off", worst_binned > 0.01,
              "worst %.3g of the piece's amount", worst_binned);
        CHECK("lobe: concentrated light adds its luminance times its direction, and its luminance",
              lobe_read && lobe_worst <= SEGMENTS, "off by up to %.0f units (%d pieces)", lobe_worst, SEGMENTS);
    } else {
        CHECK("lobe: light that is not concentrated adds nothing", lobe_read && lobe_worst == 0,
              "off by up to %.0f units", lobe_worst);
        CHECK("axis corrections: light that is not concentrated keeps the bins' mean cosines", worst_same < 1e-4,
              "worst %.3g of the piece's amount", worst_same);
    }
    clReleaseKernel(k);
    clReleaseMemObject(in);
    clReleaseMemObject(out);
    lvcl_program_release(&tests);
    lvcl_volume_release(vol);
}

int main(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    lvcl_session *ss = harness_session("cornell", 7);
    check_sums(ss, 0, "axis sums: equal lv_axis_sum computed afresh after a second part of the trace");
    check_sums(ss, 1, "axis sums: the same after cells split and slots took fine bins");
    check_correction(ss, 1);
    check_correction(ss, 0);
    lvcl_session_close(ss);
    CHECK_EXIT();
}
