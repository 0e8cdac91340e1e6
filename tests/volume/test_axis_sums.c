/* The integrating gather's axis sums (kernels/integrator/gather.h,
 * host/render/volume_axis_sums.c): a Lambertian surface facing exactly
 * along an axis reads its cosine-weighted sum of the cell's bins from them
 * instead of visiting every bin. On the Cornell box, traced in two parts
 * with the sums taken after each:
 *
 * (a) after the second part every slot's six sums equal the sums over its
 *     bins computed afresh for the six axis normals (within 1e-6: the test
 *     kernels are built apart from the renderer's), so the sums follow the
 *     volume the gather reads, axis by axis, slot by slot;
 * (b) lv_axis_of numbers the axes as the sums do, and a normal tilted by
 *     a milliradian is not an axis;
 * (c) the same with every cell split and every slot with light given fine
 *     bins between the parts (the slots change in number and in bins).
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

static void check_sums(const lvcl_session *ss, int refine, const char *what)
{
    const lvcl_device *dev = lvcl_session_device(ss, 0);
    const lvcl_program *prog = lvcl_session_program(ss, 0);
    const lvcl_device_scene *ds = lvcl_session_device_scene(ss, 0);
    lvcl_volume_settings vs = {.cells = 12, .dirs = 4, .subcells = 4, .particles = 100000};
    lvcl_light_volume *vol = NULL;
    lvcl_status st = {0};
    cl_mem sums = NULL;
    lvcl_error e = lvcl_volume_create(dev, lvcl_session_packed_scene(ss), &vs, &vol, &st);
    lvcl_volume_settings pass = vs;
    pass.particles = 25000;
    if (!e) e = lvcl_volume_trace(vol, prog, ds, &pass, &st);
    if (!e) e = lvcl_volume_finish(vol, prog, &st);
    if (!e) e = lvcl_volume_axis_sums(vol, prog, &sums, &st); /* of the first part */
    if (refine) {
        pass.refine_density = pass.refine_peak = 1e-6;
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

int main(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    lvcl_session *ss = harness_session("cornell", 7);
    check_sums(ss, 0, "axis sums: equal the sums over the bins after a second part of the trace");
    check_sums(ss, 1, "axis sums: the same after cells split and slots took fine bins");
    lvcl_session_close(ss);
    CHECK_EXIT();
}
