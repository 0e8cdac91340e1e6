/* The light volume against closed forms: the estimator of paper eq. 5 in
 * front of a large emitting plane, the white furnace in lv-all mode, energy
 * (tallied track length = emitted power x mean path length), determinism
 * run to run and device to device. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../host/io/metrics.h"
#include "../check.h"
#include "../harness.h"

#include "../kernels/test_args.h"

/* Opens a session on `scene` (consumed) and builds a light volume in it as
 * the lv modes do, on a device that acts as one of device_memory bytes (0:
 * its own size), with the kernels built with build_flags (LVCL_BUILD_*)
 * besides the scene's; reads back what the kernels stored. */
static int trace_sized(lvcl_scene *scene, const char *device, unsigned seed, const lvcl_volume_settings *vs,
                       uint64_t device_memory, unsigned build_flags, harness_volume *tv)
{
    lvcl_status st = {0};
    lvcl_session_config cfg = {.device = device,
                               .seed = seed,
                               .max_depth = 64,
                               .fast_math = 1,
                               .device_memory = device_memory,
                               .build_flags = build_flags};
    if (harness_trace_volume(scene, &cfg, vs, tv, &st)) {
        CHECK("light volume trace", 0, "%s", st.message);
        return 0;
    }
    return 1;
}

static int trace(lvcl_scene *scene, const char *device, unsigned seed, const lvcl_volume_settings *vs,
                 harness_volume *tv)
{
    return trace_sized(scene, device, seed, vs, 0, 0, tv);
}

static int64_t tally(const harness_volume *tv, uint32_t slot, uint32_t bin, int c)
{
    return tv->tallies[(size_t)slot * LV_SET_LONGS(lvcl_volume_grid(tv->volume)->bins) + 3 * bin + c];
}

static uint32_t slot_of(const harness_volume *tv, int x, int y, int z)
{
    return lvcl_volume_slot(tv->volume, (uint32_t)x, (uint32_t)y, (uint32_t)z);
}

typedef LVCL_KERNEL_ARGS(T_BIN_RADIANCE_ARGS) t_bin_radiance_args;
static LVCL_DEFINE_BINDER(t_bin_radiance, T_BIN_RADIANCE_ARGS, t_bin_radiance_args)

    /* The radiance of every bin of `slot` (red channel) as the kernels compute
 * it from the volume (t_bin_radiance in tests/kernels/unit_tests.cl), on
 * the session's device; malloc'ed. A failure ends the test program with
 * a FAIL line. */
    static double *slot_radiance(const harness_volume *tv, uint32_t slot)
{
    const lvcl_device *dev = lvcl_session_device(tv->session, 0);
    uint32_t bins = lvcl_volume_grid(tv->volume)->bins;
    lvcl_program prog;
    harness_build(dev, &prog);
    lvcl_status st = {0};
    cl_kernel k = NULL;
    cl_int err;
    cl_mem out = clCreateBuffer(dev->context, CL_MEM_WRITE_ONLY, bins * 4 * sizeof(float), NULL, &err);
    float *rgbw = malloc(bins * 4 * sizeof(float));
    double *radiance = malloc(bins * sizeof(double));
    lvcl_error e = lvcl_cl_check(err, "allocating the radiance", &st);
    if (!e && (!rgbw || !radiance)) e = lvcl_fail(&st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory");
    if (!e) e = lvcl_kernel_create(&prog, "t_bin_radiance", &k, &st);
    t_bin_radiance_args args = {.volume = lvcl_volume_kernel_buffers(tv->volume), .slot = slot, .radiance = out};
    if (!e) e = lvcl_bind_t_bin_radiance(k, &args, &st);
    if (!e) e = lvcl_kernel_enqueue(dev, k, bins, "t_bin_radiance", &st);
    if (!e)
        e = lvcl_cl_check(
            clEnqueueReadBuffer(dev->queue, out, CL_TRUE, 0, bins * 4 * sizeof(float), rgbw, 0, NULL, NULL),
            "reading the radiance", &st);
    for (uint32_t b = 0; !e && b < bins; b++) radiance[b] = rgbw[4 * b];
    if (k) clReleaseKernel(k);
    if (out) clReleaseMemObject(out);
    lvcl_program_release(&prog);
    free(rgbw);
    if (e) {
        CHECK("light volume radiance from the kernels", 0, "%s", st.message);
        exit(1);
    }
    return radiance;
}

/* The direction-map convention of kernels/volume/direction_map.h: bins below n^2
 * hold directions with z >= 0. */
static int bin_goes_up(const lv_grid_info *g, uint32_t bin)
{
    return bin < g->dirs * g->dirs;
}

/* A scene of `count` triangles, all black (absorbing what returns) and
 * emitting radiance le from their front faces. */
static void black_emitter_scene(const float *tris, size_t count, float le, lvcl_scene *scene)
{
    harness_triangle_scene(tris, count, scene);
    lvcl_material_desc *m = &scene->materials[0];
    m->base_color[0] = m->base_color[1] = m->base_color[2] = 0.0f;
    m->emissive[0] = m->emissive[1] = m->emissive[2] = le;
}

/* Upward bins away from the horizon: with n x n bins per hemisphere, the
 * inner (n-2) x (n-2) hold directions within 56 degrees of vertical for
 * n = 6, which from anywhere in a 1 m cell meet a plane below it within 2 m. */
static int inner_upward_bin(const lv_grid_info *g, uint32_t b)
{
    uint32_t n = g->dirs, i = b % n, j = b / n;
    return bin_goes_up(g, b) && i > 0 && j > 0 && i < n - 1 && j < n - 1;
}

/* (a) A 6 m square emitter of radiance Le facing +z, cells of 1 m: in the
 * cell just above its middle, every upward bin away from the horizon sees
 * radiance Le, and every downward bin sees nothing. With 6 x 6 bins per
 * hemisphere the inner 4 x 4 upward bins hold directions within 56 degrees
 * of vertical, which from anywhere in the cell meet the plane within 2 m of
 * its centre. */
static void test_emitting_plane(void)
{
    const float le = 3.0f, half = 3.0f;
    /* Two triangles of the plane, counter-clockwise seen from above, and a
     * zero-area triangle 3 m up that only stretches the bounds (the BVH
     * leaves it out) so that the grid has cells above the plane. */
    const float tris[] = {-half, -half, 0,    half, -half, 0, half, half, 0, -half, -half, 0, half, half,
                          0,     -half, half, 0,    0,     0, 3,    0,    0, 3,     0,     0, 3};
    lvcl_scene scene;
    black_emitter_scene(tris, 3, le, &scene);
    lvcl_volume_settings vs = {.cell_size = 1.0, .dirs = 6, .particles = 8000000, .store_emitted = 1};
    harness_volume tv;
    if (!trace(&scene, NULL, 1, &vs, &tv)) return;
    const lv_grid_info *g = lvcl_volume_grid(tv.volume);
    /* Cell (x, y) over the plane's centre, z in [0, 1) m. */
    int cx = (int)((0.5f - g->origin[0]) / g->cell_size), cz = (int)((0.5f - g->origin[2]) / g->cell_size);
    uint32_t slot = slot_of(&tv, cx, cx, cz);
    CHECK("emitting plane: the cell above it is stored", slot != LV_EMPTY_CELL, "cell (%d,%d,%d) empty", cx, cx, cz);
    if (slot == LV_EMPTY_CELL) {
        harness_volume_release(&tv);
        return;
    }
    /* A particle crossing the cell adds about its weight 1 x (mean chord 2/3) to one
     * bin; the count of crossings gives each bin's statistical error. */
    double worst = 0.0, worst_sigmas = 0.0, mean_up = 0.0, down = 0.0;
    int up_bins = 0;
    double *radiance = slot_radiance(&tv, slot);
    for (uint32_t b = 0; b < g->bins; b++) {
        double l = radiance[b];
        if (!bin_goes_up(g, b)) {
            down += l;
            continue;
        }
        if (!inner_upward_bin(g, b)) continue; /* near the horizon */
        double crossings = (double)tally(&tv, slot, b, 0) / LV_TALLY_SCALE / (2.0 / 3.0);
        double sigma = le * 1.5 / sqrt(crossings > 1 ? crossings : 1);
        double err = fabs(l - le);
        if (err / sigma > worst_sigmas) worst_sigmas = err / sigma;
        if (err / le > worst) worst = err / le;
        mean_up += l;
        up_bins++;
    }
    free(radiance);
    mean_up /= up_bins;
    printf("  emitting plane: mean radiance of %d upward bins %.4f (Le %.1f), worst bin %.1f%% = %.1f sigma\n", up_bins,
           mean_up, le, 100 * worst, worst_sigmas);
    CHECK("emitting plane: upward bins average Le within 1%", fabs(mean_up - le) < 0.01 * le, "mean %.4f", mean_up);
    CHECK("emitting plane: every upward bin is Le within 5 sigma", worst_sigmas < 5.0, "worst %.1f sigma",
          worst_sigmas);
    CHECK("emitting plane: downward bins are empty", down == 0.0, "sum %.4g", down);
    harness_volume_release(&tv);
}

/* Subcells (paper 4.1): an emitting plane through the middle of a cell, on a
 * subcell boundary, lights the upper half of it. The cell's lit fraction is
 * then 1/2, and its upward bins give the plane's radiance; taking the whole
 * cell as lit would halve it. */
static void test_cut_cell(void)
{
    const float le = 2.0f, half = 3.0f;
    /* The plane at z = 0, and zero-area triangles at z = -2.5 and z = 3 that
     * stretch the bounds so that z = 0 falls mid-cell (cells of 1 m). */
    const float tris[] = {-half, -half, 0, half,  -half, 0,     half, half, 0,     -half, -half, 0,
                          half,  half,  0, -half, half,  0,     0,    0,    3,     0,     0,     3,
                          0,     0,     3, 0,     0,     -2.5f, 0,    0,    -2.5f, 0,     0,     -2.5f};
    lvcl_scene scene;
    black_emitter_scene(tris, 4, le, &scene);
    lvcl_volume_settings vs = {.cell_size = 1.0, .dirs = 6, .subcells = 4, .particles = 4000000, .store_emitted = 1};
    harness_volume tv;
    if (!trace(&scene, NULL, 3, &vs, &tv)) return;
    const lv_grid_info *g = lvcl_volume_grid(tv.volume);
    /* The plane cuts the cell into two regions: read the one above it. */
    const float above[3] = {0.5f, 0.5f, 0.25f};
    uint32_t slot = lvcl_volume_slot_at(tv.volume, above);
    if (slot == LV_EMPTY_CELL) {
        CHECK("cut cell: stored", 0, "the cell at (0.5, 0.5, 0.25) is empty");
        harness_volume_release(&tv);
        return;
    }
    double lit = tv.lit[slot];
    double mean_up = 0.0;
    int up_bins = 0;
    double *radiance = slot_radiance(&tv, slot);
    for (uint32_t b = 0; b < g->bins; b++) {
        if (!inner_upward_bin(g, b)) continue;
        mean_up += radiance[b];
        up_bins++;
    }
    free(radiance);
    mean_up /= up_bins;
    printf("  cut cell: lit fraction %.4f, mean upward radiance %.4f (Le %.1f)\n", lit, mean_up, le);
    CHECK("cut cell: subcells give a lit fraction of 1/2", fabs(lit - 0.5) < 1e-9, "lit fraction %.4f", lit);
    CHECK("cut cell: its upward bins give the plane's radiance within 2%", fabs(mean_up - le) < 0.02 * le, "mean %.4f",
          mean_up);
    harness_volume_release(&tv);
}

/* Visibility rays (paper 4.1): a black floor cuts a cell so that 0.3 of it
 * lies above, lit by a lamp overhead. The subcell masks alone count the
 * whole layer of subcells the floor passes through (0.5 of the cell); the
 * rays from points of those subcells back toward each particle's origin find
 * the part below the floor blocked, and the lit fraction must come out
 * within 10% of 0.3. */
static void test_visibility(void)
{
    const float z = 0.2f, f = 0.3f; /* floor height; the cell spans [z - 0.7, z + 0.3] */
    const float tris[] = {
        -3,    -3,    z,        3,     -3,   z,        3,    3,     z,
        -3,    -3,    z,        3,     3,    z,        -3,   3,     z,     /* floor, facing up */
        -0.5f, -0.5f, z + 2,    0.5f,  0.5f, z + 2,    0.5f, -0.5f, z + 2, /* lamp, facing down */
        -0.5f, -0.5f, z + 2,    -0.5f, 0.5f, z + 2,    0.5f, 0.5f,  z + 2,
        0,     0,     z - 1.7f, 0,     0,    z - 1.7f, 0,    0,     z - 1.7f, /* stretches the bounds down */
    };
    lvcl_scene scene;
    harness_triangle_scene(tris, 5, &scene);
    /* Material 0 (floor) absorbs; material 1 (lamp) emits. */
    lvcl_material_desc *m = harness_materials(&scene, 2);
    m[0].base_color[0] = m[0].base_color[1] = m[0].base_color[2] = 0.0f;
    m[1].emissive[0] = m[1].emissive[1] = m[1].emissive[2] = 5.0f;
    scene.tri_material[2] = scene.tri_material[3] = 1;
    lvcl_volume_settings vs = {.cell_size = 1.0, .dirs = 4, .subcells = 4, .particles = 2000000, .store_emitted = 1};
    harness_volume tv;
    if (!trace(&scene, NULL, 4, &vs, &tv)) return;
    /* The floor cuts the cell into two regions: the one above it is lit. */
    const float above[3] = {0.5f, 0.5f, z + 0.15f};
    uint32_t slot = lvcl_volume_slot_at(tv.volume, above);
    double lit = slot == LV_EMPTY_CELL ? 0.0 : tv.lit[slot];
    printf("  visibility: floor at %.2f of the cell's height, lit fraction %.4f (expected %.2f)\n", 1 - f, lit, f);
    CHECK("subcell visibility: a cell cut at 0.3 of its volume is lit 0.3 within 10%", fabs(lit - f) < 0.1 * f,
          "lit fraction %.4f", lit);
    harness_volume_release(&tv);
}

/* (b, c) The white furnace (a 2 m closed cube, albedo 0.5, Le 1) with the
 * grid aligned to its walls, 4 cells across so that every cell inside is
 * next to a wall and stored: the field radiance is Le / (1 - a) = 2 in every
 * cell and direction, and the tallied track length is the emitted power
 * times the mean path length: 1 / (1 - a) segments of mean chord 4V/S. */
static void test_furnace(void)
{
    lvcl_scene scene;
    lvcl_status st = {0};
    if (lvcl_scene_load("furnace", &scene, &st)) {
        CHECK("furnace scene", 0, "%s", st.message);
        return;
    }
    lvcl_volume_settings vs = {.cells = 4, .dirs = 6, .particles = 2000000, .store_emitted = 1};
    harness_volume tv;
    if (!trace(&scene, NULL, 2, &vs, &tv)) return;
    const lv_grid_info *g = lvcl_volume_grid(tv.volume);
    double worst = 0.0, total = 0.0;
    int cells = 0;
    for (int z = 1; z <= 4; z++)
        for (int y = 1; y <= 4; y++)
            for (int x = 1; x <= 4; x++) {
                uint32_t slot = slot_of(&tv, x, y, z);
                if (slot == LV_EMPTY_CELL) continue;
                double sum = 0.0, *radiance = slot_radiance(&tv, slot);
                for (uint32_t b = 0; b < g->bins; b++) {
                    sum += radiance[b];
                    total += (double)tally(&tv, slot, b, 0) / LV_TALLY_SCALE / g->particles;
                }
                free(radiance);
                double mean = sum / g->bins;
                if (fabs(mean - 2.0) > worst) worst = fabs(mean - 2.0);
                cells++;
            }
    printf("  furnace: %d cells inside, worst cell mean off by %.4f\n", cells, worst);
    CHECK("lv-all furnace: all 64 cells inside are stored", cells == 64, "%d cells", cells);
    CHECK("lv-all furnace: every cell's radiance is Le/(1-a) = 2 within 2%", worst < 0.04, "worst deviation %.4f",
          worst);
    /* Tallies hold power share x (length / h): the sum over all bins
     * times h over N is the mean tracked length per particle, in metres. */
    double mean_path = total * g->cell_size, expected = 2.0 * (4.0 * 8.0 / 24.0);
    printf("  furnace: mean tracked length per particle %.4f m, expected %.4f m\n", mean_path, expected);
    CHECK("lv-all furnace: tallied length = emitted power x mean path length within 1%",
          fabs(mean_path - expected) < 0.01 * expected, "%.4f m against %.4f m", mean_path, expected);
    harness_volume_release(&tv);
}

/* (d) The same seed gives the same volume bit for bit: run to run, and on
 * every other device present. */
static void test_determinism(void)
{
    lvcl_volume_settings vs = {.cells = 12, .dirs = 5, .subcells = 4, .particles = 300000};
    harness_volume first;
    lvcl_scene scene;
    lvcl_status st = {0};
    if (lvcl_scene_load("cornell", &scene, &st) || !trace(&scene, "0", 9, &vs, &first)) return;
    int n = lvcl_device_count(0);
    for (int d = 0; d < n; d++) {
        char device[16], name[128];
        snprintf(device, sizeof device, "%d", d);
        harness_volume again;
        if (lvcl_scene_load("cornell", &scene, &st) || !trace(&scene, device, 9, &vs, &again)) break;
        int same = lvcl_volume_stats_of(first.volume).tally_bytes == lvcl_volume_stats_of(again.volume).tally_bytes &&
            memcmp(first.tallies, again.tallies, lvcl_volume_stats_of(first.volume).tally_bytes) == 0;
        /* The subcell records: masks, ray counts and lit points. */
        size_t record_bytes = lvcl_volume_record_bytes(first.volume);
        int same_records = same && memcmp(first.masks, again.masks, record_bytes) == 0;
        const char *platform = lvcl_session_device(again.session, 0)->platform_name;
        if (d == 0) {
            CHECK("light volume: same seed, same tallies and subcell records bit for bit", same_records,
                  "the %s differ", same ? "subcell records" : "tallies");
        } else if (!strcmp(platform, lvcl_session_device(first.session, 0)->platform_name)) {
            snprintf(name, sizeof name,
                     "light volume: device %d (%s) gives device 0's tallies and subcell records bit for bit", d,
                     platform);
            CHECK(name, same_records, "the %s differ", same ? "subcell records" : "tallies");
        } else {
            /* Another compiler rounds the segments' lengths in other last
             * bits, and now and then a float test flips and a particle goes
             * another way: the tallies differ by a few units in most bins and
             * by whole paths in a few. Measured on Intel's CPU runtime: 1.6e-4
             * of their sum, no mask word; the bound, 1e-3, is still a tenth
             * of the noise of one bin at these particles (about 1e-2). */
            size_t n64 = lvcl_volume_stats_of(first.volume).tally_bytes / sizeof(int64_t), masks = 0, masks_differ = 0;
            double sum = 0, diff = 0;
            for (size_t i = 0; i < n64; i++) {
                sum += fabs((double)first.tallies[i]);
                diff += fabs((double)first.tallies[i] - (double)again.tallies[i]);
            }
            /* The block starts with every slot's mask words. */
            masks = LV_MARK_WORDS * ((size_t)lvcl_volume_grid(first.volume)->slot_count + 1);
            for (size_t i = 0; i < masks; i++) masks_differ += first.masks[i] != again.masks[i];
            snprintf(name, sizeof name, "light volume: device %d (%s) gives device 0's tallies and subcell masks", d,
                     platform);
            CHECK(name, diff <= 1e-3 * sum && masks_differ <= masks / 1000,
                  "tallies differ by %.3g of their sum, %zu of %zu mask words", diff / sum, masks_differ, masks);
            printf("  %s: tallies differ by %.3g of their sum; %zu of %zu mask words differ\n", platform, diff / sum,
                   masks_differ, masks);
        }
        harness_volume_release(&again);
    }
    /* Passes of particles traced one after another into one volume (as under
     * a time budget) give the volume traced at once, lit volumes included. */
    lvcl_light_volume *passes = NULL;
    const lvcl_session *ss = first.session;
    lvcl_volume_settings pass = vs;
    int64_t *pass_tallies = NULL;
    uint32_t *pass_masks = NULL;
    float *pass_lit = NULL;
    lvcl_error e = lvcl_volume_create(lvcl_session_device(ss, 0), lvcl_session_packed_scene(ss), &vs, &passes, &st);
    const uint64_t ends[] = {50000, 170000, vs.particles};
    for (int i = 0; i < 3 && !e; i++) {
        pass.first_particle = i ? ends[i - 1] : 0;
        pass.particles = ends[i];
        e = lvcl_volume_trace(passes, lvcl_session_program(ss, 0), lvcl_session_device_scene(ss, 0), &pass, &st);
    }
    if (!e) e = lvcl_volume_finish(passes, lvcl_session_program(ss, 0), &st);
    if (!e) e = lvcl_volume_read(passes, &pass_tallies, &pass_masks, &st);
    if (!e) e = lvcl_volume_read_lit(passes, &pass_lit, &st);
    if (e) CHECK("light volume: passes", 0, "%s", st.message);
    else {
        const lv_grid_info *g = lvcl_volume_grid(first.volume);
        size_t record_bytes = lvcl_volume_record_bytes(first.volume);
        int same = !memcmp(first.tallies, pass_tallies, lvcl_volume_stats_of(first.volume).tally_bytes) &&
            !memcmp(first.masks, pass_masks, record_bytes) &&
            !memcmp(first.lit, pass_lit, g->slot_count * sizeof(float)) &&
            lvcl_volume_grid(passes)->particles == g->particles;
        CHECK("light volume: three passes of particles give the volume traced at once, bit for bit", same,
              "tallies, records or lit volumes differ (particles %g and %g)", lvcl_volume_grid(passes)->particles,
              g->particles);
    }
    free(pass_tallies);
    free(pass_masks);
    free(pass_lit);
    lvcl_volume_release(passes);
    if (n < 2) SKIP("light volume: cross-device", "only one OpenCL device present");
    /* A device too small to hold the tallies in one buffer splits them: one
     * of twice the volume's size allows half of it in one buffer, less than
     * the tallies and more than the subcell records. */
    harness_volume split;
    uint64_t small = 2 * lvcl_volume_stats_of(first.volume).device_bytes;
    if (!lvcl_scene_load("cornell", &scene, &st) && trace_sized(&scene, "0", 9, &vs, small, 0, &split)) {
        int same = lvcl_volume_stats_of(first.volume).tally_bytes == lvcl_volume_stats_of(split.volume).tally_bytes &&
            memcmp(first.tallies, split.tallies, lvcl_volume_stats_of(first.volume).tally_bytes) == 0;
        CHECK("light volume: tallies split over buffers are the same bit for bit",
              same && lvcl_volume_stats_of(split.volume).tally_buffers > 1, "%d buffers, tallies %s",
              lvcl_volume_stats_of(split.volume).tally_buffers, same ? "equal" : "differ");
        harness_volume_release(&split);
    }
    /* The tallies of a device without 64-bit atomics (two 32-bit adds with a
     * carry) are the same too. A few cells of few bins gather thousands of
     * weight x length units (2^24 each) per bin, past 2^32, so carries and
     * high words happen. */
    lvcl_volume_settings coarse = {.cells = 4, .dirs = 3, .subcells = 4, .particles = 100000, .store_emitted = 1};
    harness_volume native, emulated;
    if (!lvcl_scene_load("cornell", &scene, &st) && trace(&scene, "0", 9, &coarse, &native)) {
        if (!lvcl_scene_load("cornell", &scene, &st) &&
            trace_sized(&scene, "0", 9, &coarse, 0, LVCL_BUILD_EMULATED_INT64_ATOMICS, &emulated)) {
            size_t n = lvcl_volume_stats_of(native.volume).tally_bytes / sizeof(int64_t), wide = 0;
            /* Past 2^32, so not a negative axis correction. */
            for (size_t i = 0; i < n; i++) wide += native.tallies[i] >= (int64_t)1 << 32;
            int same =
                lvcl_volume_stats_of(emulated.volume).tally_bytes == lvcl_volume_stats_of(native.volume).tally_bytes &&
                memcmp(native.tallies, emulated.tallies, lvcl_volume_stats_of(native.volume).tally_bytes) == 0;
            CHECK("light volume: 64-bit tallies from 32-bit atomics are the same bit for bit",
                  same && wide > 0 &&
                      strstr(lvcl_session_program(emulated.session, 0)->options, "-DLV_EMULATE_INT64_ATOMICS"),
                  "the tallies %s; %zu of %zu past 2^32; kernel options %s", same ? "equal" : "differ", wide, n,
                  lvcl_session_program(emulated.session, 0)->options);
            harness_volume_release(&emulated);
        }
        harness_volume_release(&native);
    }
    harness_volume_release(&first);
}

/* Turns every triangle's shading normal 30 degrees away from its geometric
 * one (all three corners alike). */
static void tilt_normals(lvcl_scene *s)
{
    for (size_t t = 0; t < s->triangle_count; t++) {
        const float *p[3];
        for (int c = 0; c < 3; c++) p[c] = &s->positions[3 * s->indices[3 * t + c]];
        double e1[3], e2[3], n[3], a[3], len = 0, dot = 0, alen = 0;
        for (int k = 0; k < 3; k++) e1[k] = p[1][k] - p[0][k], e2[k] = p[2][k] - p[0][k];
        n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2],
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        for (int k = 0; k < 3; k++) len += n[k] * n[k];
        for (int k = 0; k < 3; k++) n[k] /= sqrt(len);
        /* A direction in the triangle's plane to turn towards. */
        for (int k = 0; k < 3; k++) a[k] = n[(k + 1) % 3] + n[(k + 2) % 3];
        for (int k = 0; k < 3; k++) dot += a[k] * n[k];
        for (int k = 0; k < 3; k++) a[k] -= dot * n[k], alen += a[k] * a[k];
        float m[3];
        for (int k = 0; k < 3; k++) m[k] = (float)(cos(0.52) * n[k] + sin(0.52) * a[k] / sqrt(alen));
        for (int c = 0; c < 3; c++) memcpy(&s->normals[3 * s->indices[3 * t + c]], m, sizeof m);
        s->tri_flags[t] |= LV_TRI_HAS_NORMALS;
    }
}

static double mean_render(int tilted, lvcl_mode mode)
{
    lvcl_scene scene;
    lvcl_status st = {0};
    if (lvcl_scene_load("furnace", &scene, &st)) return NAN;
    if (tilted) tilt_normals(&scene);
    lvcl_render_request req = harness_request(mode, 32, mode == LVCL_MODE_PT ? 128 : 16, 8, 500000);
    lvcl_render_result r;
    if (harness_render(&scene, NULL, 1, &req, &r, &st)) return NAN;
    double m = 0;
    for (int i = 0; i < 32 * 32 * 3; i++) m += r.rgb[i];
    free(r.rgb);
    return m / (32 * 32 * 3);
}

/* Shading normals: particles must carry importance with the adjoint
 * correction (Veach 1997, 5.3), and the gather must not read bins the
 * shading normal allows but the surface does not. In the white furnace with
 * every shading normal turned 30 degrees the path tracer no longer gives 2;
 * lv-all must still stand to it as it does without the turn. Without the
 * correction lv-all came out 3.4% above the path tracer, and 5.6% when the
 * gather also read the bins below the surface. Without the turn the two
 * must agree: when the integrating gather weighed each bin by the cosine
 * of its central direction lv-all came out 1.7% bright. */
static void test_shading_normals(void)
{
    double flat = mean_render(0, LVCL_MODE_LV_ALL) / mean_render(0, LVCL_MODE_PT);
    double turned = mean_render(1, LVCL_MODE_LV_ALL) / mean_render(1, LVCL_MODE_PT);
    printf("  shading normals: lv-all / pt %.4f without the turn, %.4f with it\n", flat, turned);
    CHECK("white furnace: lv-all agrees with pt within 0.5%", fabs(flat - 1.0) < 0.005, "lv-all / pt %.4f", flat);
    CHECK("shading normals: lv-all agrees with pt as well as without them", fabs(turned - flat) < 0.015,
          "lv-all / pt %.4f with turned normals, %.4f without", turned, flat);
}

/* (f) Two sealed rooms split by a wall thinner than a subcell, the lamp
 * in one: the camera sees only the dark room, where the true radiance is 0
 * (the path tracer's is exactly 0). The whole cell used to leak the lit
 * side's light through the cells the wall cuts (mean 0.00148); the cells'
 * regions now keep the two sides' tallies apart, and a lookup must be in
 * sight of the surface (with subcells also in the lit part of its
 * subcell), so neither leaks. */
static void test_thin_wall(void)
{
    double mean[2];
    for (int subcells = 0; subcells <= 4; subcells += 4) {
        lvcl_scene scene;
        lvcl_status st = {0};
        lvcl_render_result r;
        lvcl_render_request req = harness_request(LVCL_MODE_LV, 48, 4, 32, 200000);
        req.volume.subcells = subcells;
        if (lvcl_scene_load("scenes/thin-wall.gltf", &scene, &st) || harness_render(&scene, NULL, 3, &req, &r, &st)) {
            CHECK("thin wall", 0, "%s", st.message);
            return;
        }
        double sum = 0;
        for (int i = 0; i < 3 * r.width * r.height; i++) sum += r.rgb[i];
        mean[subcells / 4] = sum / (3.0 * r.width * r.height);
        free(r.rgb);
    }
    printf("  thin wall: mean radiance in the dark room %.3g with the whole cell, %.3g with subcells\n", mean[0],
           mean[1]);
    CHECK("thin wall: no light leaks into the sealed dark room, with subcells or the whole cell",
          mean[1] == 0.0 && mean[0] == 0.0, "mean %.3g with subcells, %.3g with the whole cell", mean[1], mean[0]);
}

int main(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    setenv("POCL_DEVICES", "pthread basic", 0);
    lvcl_device_prepare_environment();
    test_emitting_plane();
    test_cut_cell();
    test_visibility();
    test_furnace();
    test_determinism();
    test_shading_normals();
    test_thin_wall();
    CHECK_EXIT();
}
