/* Kernels that exercise lvcl's device code directly, for the tests in
 * tests/<layer>/; their argument lists are in test_args.h. Built with every
 * feature switch on, so all BSDFs are present. */
#include "../../kernels/lvcl.h"
#include "test_args.h"

inline float3 uniform_sphere(float2 u)
{
    float z = 1.0f - 2.0f * u.x;
    float r = sqrt(fmax(0.0f, 1.0f - z * z));
    float phi = 2.0f * LV_PI * u.y;
    return (float3)(r * cos(phi), r * sin(phi), z);
}

/* Histogram of uniformly distributed directions over the 2 n^2 bins. */
__kernel void t_direction_histogram(LV_KERNEL_PARAMS(T_DIRECTION_HISTOGRAM_ARGS))
{
    lv_rng rng = lv_rng_make(7u, get_global_id(0), 0u);
    for (uint k = 0; k < per_item; k++) {
        uint bin = lv_direction_bin(uniform_sphere(lv_rng_next2(&rng)), n);
        atomic_inc(&counts[bin]);
    }
}

/* Directions drawn inside each bin must map back to it; counts misses. */
__kernel void t_direction_roundtrip(LV_KERNEL_PARAMS(T_DIRECTION_ROUNDTRIP_ARGS))
{
    uint bin = get_global_id(0);
    if (bin >= 2u * n * n) return;
    lv_rng rng = lv_rng_make(11u, bin, 0u);
    for (uint k = 0; k < per_item; k++) {
        /* Stay a little inside the bin: its edges are shared with neighbours. */
        float2 u = 0.02f + 0.96f * lv_rng_next2(&rng);
        float3 w = lv_bin_direction(bin, n, u);
        if (lv_direction_bin(w, n) != bin || fabs(length(w) - 1.0f) > 1e-4f) atomic_inc(misses);
    }
}

/* The bin table, as lv_bin_table fills it. */
__kernel void t_bin_table(LV_KERNEL_PARAMS(T_BIN_TABLE_ARGS))
{
    uint bin = get_global_id(0);
    if (bin < LV_BIN_GROUPS(2u * n * n) * LV_BIN_GROUP) lv_fill_bin_table(bin, n, table);
}

/* x: the table's sum of mean cosines times solid angle (the integrating
 * gather's weights); y: the same from each bin's central direction (the
 * rule it replaced); z: the integral by 32 x 32 points per bin. Normals
 * pair 2i (shading) and 2i + 1 (geometric). */
__kernel void t_bin_cosine(LV_KERNEL_PARAMS(T_BIN_COSINE_ARGS))
{
    uint i = get_global_id(0);
    if (i >= count) return;
    float3 ns = normals[2 * i].xyz, ng = normals[2 * i + 1].xyz;
    float omega = lv_bin_solid_angle(n), table_sum = 0.0f, centre_sum = 0.0f, dense_sum = 0.0f;
    const uint dense = 32u;
    uint bins = 2u * n * n;
    for (uint first = 0; first < bins; first += LV_BIN_GROUP) {
        float w[LV_BIN_GROUP];
        lv_bin_mean_cosines(table, bins, first, ns, ng, w);
        for (uint l = 0; l < LV_BIN_GROUP && first + l < bins; l++) table_sum += w[l] * omega;
    }
    for (uint bin = 0; bin < bins; bin++) {
        float3 from = -lv_bin_direction(bin, n, (float2)(0.5f));
        if (dot(from, ng) > 0.0f) centre_sum += fmax(dot(from, ns), 0.0f) * omega;
        float part = 0.0f;
        for (uint v = 0; v < dense; v++)
            for (uint u = 0; u < dense; u++) {
                float3 w = -lv_bin_direction(bin, n, ((float2)((float)u, (float)v) + 0.5f) / (float)dense);
                if (dot(w, ng) > 0.0f) part += fmax(dot(w, ns), 0.0f);
            }
        dense_sum += part / (float)(dense * dense) * omega;
    }
    sums[i] = (float4)(table_sum, centre_sum, dense_sum, 0.0f);
}

__kernel void t_guide_sampling(LV_KERNEL_PARAMS(T_GUIDE_SAMPLING_ARGS))
{
    uint i = get_global_id(0);
    lv_guide_vertex gv;
    gv.luminance = luminance;
    gv.table = table;
    gv.n = n;
    gv.bins = 2u * n * n;
    gv.ns = normals[0].xyz;
    gv.ng = normals[1].xyz;
    if (!lv_guide_prepare(&gv, LV_GUIDE_SHARE)) {
        results[i] = (float4)(-1.0f);
        return;
    }
    lv_rng rng = lv_rng_make(13u, i, 0u);
    float integral = 0.0f, mismatches = 0.0f, none = 0.0f;
    for (uint k = 0; k < per_item; k++) {
        integral += lv_guide_pdf(&gv, uniform_sphere(lv_rng_next2(&rng))) * 4.0f * LV_PI;
        float3 u = lv_rng_next3(&rng), wi;
        float pdf;
        if (!lv_guide_sample(&gv, u, &wi, &pdf)) {
            none += 1.0f;
            continue;
        }
        atomic_inc(&counts[lv_direction_bin(-wi, n)]);
        if (fabs(lv_guide_pdf(&gv, wi) - pdf) > 1e-3f * pdf) mismatches += 1.0f;
    }
    results[i] = (float4)(integral / (float)per_item, mismatches, none, gv.total);
}

__kernel void t_light_directions(LV_KERNEL_PARAMS(T_LIGHT_DIRECTIONS_ARGS))
{
    uint i = get_global_id(0);
    lv_light_candidates c;
    lv_light_odds odds;
    float w[LV_LIGHT_CANDIDATES];
    c.count = count;
    for (uint k = 0; k < count; k++) {
        float3 v0 = corners[3 * k].xyz, v1 = corners[3 * k + 1].xyz, v2 = corners[3 * k + 2].xyz;
        c.v0[k] = v0;
        c.e1[k] = v1 - v0;
        c.e2[k] = v2 - v0;
        c.n[k] = corners[3 * k].w * cross(c.e1[k], c.e2[k]);
        w[k] = weights[k];
    }
    if (!lv_light_odds_set(&c, w, &odds)) {
        results[2 * i] = results[2 * i + 1] = (float4)(-1.0f);
        return;
    }
    lv_rng rng = lv_rng_make(29u, i, 0u);
    float sum = 0.0f, sum_sq = 0.0f, support = 0.0f, inverse = 0.0f, inverse_sq = 0.0f, mismatches = 0.0f;
    float failed = 0.0f;
    for (uint k = 0; k < per_item; k++) {
        float d = lv_light_directions_pdf(&c, &odds, point[0].xyz, uniform_sphere(lv_rng_next2(&rng))) * 4.0f * LV_PI;
        sum += d;
        sum_sq += d * d;
        support += d > 0.0f ? 1.0f : 0.0f;
        float3 u = lv_rng_next3(&rng), dir;
        float pdf;
        if (!lv_light_directions_sample(&c, &odds, point[0].xyz, u, &dir, &pdf)) {
            failed += 1.0f;
            continue;
        }
        inverse += 1.0f / pdf;
        inverse_sq += 1.0f / (pdf * pdf);
        if (fabs(lv_light_directions_pdf(&c, &odds, point[0].xyz, dir) - pdf) > 1e-3f * pdf) mismatches += 1.0f;
    }
    results[2 * i] = (float4)(sum, sum_sq, support, 0.0f);
    results[2 * i + 1] = (float4)(inverse, mismatches, failed, inverse_sq);
}

/* One work-item per (pixel, sample): the first `dims` numbers of its
 * camera stream, as the camera passes draw them. */
__kernel void t_camera_streams(LV_KERNEL_PARAMS(T_CAMERA_STREAMS_ARGS))
{
    uint i = get_global_id(0), pixel = i / samples, sample = i % samples;
    lv_rng rng = lv_rng_make_lattice(seed, pixel, sample);
    for (uint d = 0; d < dims; d++) out[(size_t)i * dims + d] = lv_rng_next(&rng);
}

/* lv_cos_sin of each angle, two floats per work-item. */
__kernel void t_cos_sin(LV_KERNEL_PARAMS(T_COS_SIN_ARGS))
{
    uint i = get_global_id(0);
    vstore2(lv_cos_sin(phis[i]), i, out);
}

/* Directions from lv_sample_vmf and their density, per_item per case. */
__kernel void t_vmf(LV_KERNEL_PARAMS(T_VMF_ARGS))
{
    uint i = get_global_id(0);
    float4 c = cases[i / per_item];
    lv_rng rng = lv_rng_make(7u, i, 0u);
    float3 w = lv_sample_vmf(c.xyz, c.w, lv_rng_next2(&rng));
    out[i] = (float4)(w, lv_vmf_pdf(c.xyz, c.w, w));
}

/* Monte Carlo moments of one BSDF seen from one direction. config: 8 floats
 * per BSDF (type, base rgb, alpha, ior, specular, mode); wos: 4 floats per
 * direction. out: 8 floats per (config, wo):
 *   0  integral of pdf over the sphere (uniform sampling)
 *   1  fraction of lv_bsdf_sample_dir calls giving a non-delta direction
 *   2  integral of luminance(eval) over the sphere
 *   3  mean luminance(weight) of non-delta samples (failures count 0)
 *   4  mean luminance(weight) of all samples, delta included: the albedo
 *   5  largest relative reciprocity error f(wo,wi)/|cos wi| vs f(wi,wo)/|cos wo|
 *   6  largest relative mismatch between a sample's weight*pdf and eval
 *   7  largest relative mismatch between a sample's pdf and lv_bsdf_eval's */
__kernel void t_bsdf_moments(LV_KERNEL_PARAMS(T_BSDF_MOMENTS_ARGS))
{
    uint item = get_global_id(0);
    if (item >= count) return;
    __global const float *c = config + 8 * (item / n_wo);
    lv_bsdf b;
    b.type = (uint)c[0];
    b.base = (float3)(c[1], c[2], c[3]);
    b.alpha = c[4];
    b.ior = c[5];
    b.specular = c[6];
    int mode = (int)c[7];
    float3 wo = normalize(wos[item % n_wo].xyz);
    lv_rng rng = lv_rng_make(3u, item, 0u);

    float pdf_int = 0.0f, eval_int = 0.0f, recip = 0.0f;
    for (uint k = 0; k < samples; k++) {
        float3 w = uniform_sphere(lv_rng_next2(&rng));
        float pdf;
        float3 f = lv_bsdf_eval(&b, wo, w, mode, &pdf);
        pdf_int += pdf;
        eval_int += lv_luminance(f);
        /* Reciprocity holds for reflection; refraction is tested by energy. */
        if (wo.z * w.z > 0.0f && fabs(w.z) > 0.05f) {
            float a = lv_luminance(f) / fabs(w.z);
            float r = lv_luminance(lv_bsdf_eval(&b, w, wo, mode, 0)) / fabs(wo.z);
            float scale = fmax(fmax(a, r), 1e-3f);
            recip = fmax(recip, fabs(a - r) / scale);
        }
    }
    float ok = 0.0f, smooth_weight = 0.0f, all_weight = 0.0f, weight_err = 0.0f, pdf_err = 0.0f;
    for (uint k = 0; k < samples; k++) {
        lv_bsdf_sample s;
        float3 u = lv_rng_next3(&rng);
        if (!lv_bsdf_sample_dir(&b, wo, u, mode, &s)) continue;
        float wl = lv_luminance(s.weight);
        all_weight += wl;
        if (s.delta) continue;
        ok += 1.0f;
        smooth_weight += wl;
        float pdf;
        float e = lv_luminance(lv_bsdf_eval(&b, wo, s.wi, mode, &pdf));
        pdf_err = fmax(pdf_err, fabs(pdf - s.pdf) / fmax(pdf, 1e-3f));
        weight_err = fmax(weight_err, fabs(wl * s.pdf - e) / fmax(e, 1e-3f));
    }
    __global float *o = out + 8 * item;
    o[0] = 4.0f * LV_PI * pdf_int / (float)samples;
    o[1] = ok / (float)samples;
    o[2] = 4.0f * LV_PI * eval_int / (float)samples;
    o[3] = smooth_weight / (float)samples;
    o[4] = all_weight / (float)samples;
    o[5] = recip;
    o[6] = weight_err;
    o[7] = pdf_err;
}

/* Rays: 8 floats each (origin xyz, tmax, dir xyz, unused). Results: 4 per
 * ray (t, prim_id or -1, any-hit flag, 1 if the hit is on the front face,
 * -1 on the back, 0 on a miss). */
inline lv_ray load_test_ray(__global const float *rays, uint i)
{
    __global const float *q = rays + 8 * i;
    return lv_ray_make((float3)(q[0], q[1], q[2]), (float3)(q[4], q[5], q[6]), q[3], LV_NO_HIT, LV_NO_HIT);
}

/* Test ray i (into *r) and its closest hit. */
inline lv_hit trace_test_ray(const lv_scene *sc, __global const float *rays, uint i, lv_ray *r)
{
    *r = load_test_ray(rays, i);
    return lv_trace(sc, *r, 0);
}

__kernel void t_trace(LV_KERNEL_PARAMS(T_TRACE_ARGS))
{
    LV_SCENE_OPEN(sc);
    uint i = get_global_id(0);
    if (i >= count) return;
    lv_ray r;
    lv_hit h = trace_test_ray(&sc, rays, i, &r);
    results[4 * i + 0] = h.t;
    results[4 * i + 1] = h.tri == LV_NO_HIT ? -1.0f : (float)lv_triangle_record(&sc, h.tri).prim_id;
    results[4 * i + 2] = lv_trace(&sc, r, 1).tri == LV_NO_HIT ? 0.0f : 1.0f;
    results[4 * i + 3] = h.tri == LV_NO_HIT ? 0.0f : (lv_surface_at(&sc, r, h).front ? 1.0f : -1.0f);
}

/* The surface each ray meets: 4 floats (shading normal x and y, uv), zero
 * on a miss. */
__kernel void t_surface(LV_KERNEL_PARAMS(T_TRACE_ARGS))
{
    LV_SCENE_OPEN(sc);
    uint i = get_global_id(0);
    if (i >= count) return;
    lv_ray r;
    lv_hit h = trace_test_ray(&sc, rays, i, &r);
    float4 o = (float4)(0.0f);
    if (h.tri != LV_NO_HIT) {
        lv_surface s = lv_surface_at(&sc, r, h);
        o = (float4)(s.ns.x, s.ns.y, s.uv.x, s.uv.y);
    }
    vstore4(o, i, results);
}

/* The same rays against every triangle, without the BVH. */
__kernel void t_trace_brute_force(LV_KERNEL_PARAMS(T_TRACE_ARGS))
{
    LV_SCENE_OPEN(sc);
    uint i = get_global_id(0);
    if (i >= count) return;
    lv_ray r = load_test_ray(rays, i);
    lv_sheared_ray s = lv_shear_ray(r);
    float t = r.tmax, b1, b2;
    int best = -1;
    uint n = sc.info.triangle_count;
    for (uint g = 0; g * LV_TRI_GROUP < n; g++) {
        int lane = lv_intersect_group(&s, lv_tri_group(&sc, g), g, 0u, n, LV_NO_HIT, 0, &t, &b1, &b2);
        if (lane >= 0) best = (int)(LV_TRI_GROUP * g) + lane;
    }
    results[4 * i + 0] = t;
    results[4 * i + 1] = best < 0 ? -1.0f : (float)lv_triangle_record(&sc, best).prim_id;
    results[4 * i + 2] = best < 0 ? 0.0f : 1.0f;
}

/* Self-intersection after the principled offset: each ray's closest hit is
 * re-shot from lv_offset_origin(hit point, geometric normal on the new ray's
 * side), as the path tracer does. reshoot: per ray, the new direction in the
 * frame of that normal (xyz, z > 0) and w > 0 to stay on the side the ray
 * came from (reflection) or w < 0 to cross the surface (transmission);
 * |w| = 2 also skips the triangle left, as the renderer's rays do; |w| = 3
 * skips it too and leaves from lv_leave_point (a step back along the ray
 * first), with the new direction xyz in world space.
 * Results: 4 floats per ray (prim_id first hit or -1, prim_id the new ray
 * hits or -1, its t, distance of the new origin from the hit point). */
__kernel void t_offset_rays(LV_KERNEL_PARAMS(T_OFFSET_RAYS_ARGS))
{
    LV_SCENE_OPEN(sc);
    uint i = get_global_id(0);
    if (i >= count) return;
    __global float *o = results + 4 * i;
    lv_ray r;
    lv_hit h = trace_test_ray(&sc, rays, i, &r);
    o[0] = o[1] = -1.0f;
    o[2] = o[3] = 0.0f;
    if (h.tri == LV_NO_HIT) return;
    lv_surface s = lv_surface_at(&sc, r, h);
    float3 ng_in = dot(r.dir, s.ng) < 0.0f ? s.ng : -s.ng; /* towards the arriving ray */
    float4 l = reshoot[i];
    float3 n = l.w > 0.0f ? ng_in : -ng_in;
    int leave = fabs(l.w) > 2.5f;
    float3 from = leave ? lv_leave_point(s.p, s.arrived, n, -normalize(r.dir), h.t * length(r.dir), sc.info.scene_scale)
                        : lv_offset_origin(s.p, n, sc.info.scene_scale);
    lv_ray r2 = lv_ray_make(from, leave ? l.xyz : lv_to_world(lv_frame_make(n), l.xyz), LV_FAR, h.inst,
                            fabs(l.w) > 1.5f ? h.tri : LV_NO_HIT);
    lv_hit h2 = lv_trace(&sc, r2, 0);
    o[0] = (float)lv_triangle_record(&sc, h.tri).prim_id;
    o[1] = h2.tri == LV_NO_HIT ? -1.0f : (float)lv_triangle_record(&sc, h2.tri).prim_id;
    o[2] = h2.t;
    o[3] = length(r2.origin - s.p);
}

/* Per bin of stored cell `slot`: the radiance lv_bin_radiance gives with
 * the lit volume lv_lit_volumes stored (the lookups' formula), and that lit
 * volume in w. */
__kernel void t_bin_radiance(LV_KERNEL_PARAMS(T_BIN_RADIANCE_ARGS))
{
    lv_grid grid;
    LV_VOLUME_OPEN(grid);
    uint bin = get_global_id(0);
    if (bin >= grid.g.bins) return;
    float lit = grid.lit_volume[slot];
    radiance[bin] = (float4)(lv_bin_radiance(&grid, slot, bin, lit), lit);
}

/* The gather's axis sums against lv_axis_sum computed afresh, and
 * lv_axis_of against the axis normals spelled out here rather than from
 * lv_axis_normal. */
__kernel void t_axis_sums(LV_KERNEL_PARAMS(T_AXIS_SUMS_ARGS))
{
    uint id = get_global_id(0), slot = id / LV_AXES, a = id % LV_AXES;
    if (slot >= grid_info.slot_count) return;
    lv_grid grid;
    LV_VOLUME_OPEN(grid);
    const float3 normals[LV_AXES] = {(float3)(1.0f, 0.0f, 0.0f), (float3)(-1.0f, 0.0f, 0.0f),
                                     (float3)(0.0f, 1.0f, 0.0f), (float3)(0.0f, -1.0f, 0.0f),
                                     (float3)(0.0f, 0.0f, 1.0f), (float3)(0.0f, 0.0f, -1.0f)};
    float3 n = normals[a];
    lv_bin_tables tables = {bin_table, fine_bin_table};
    float3 sum = lv_axis_sum(&grid, &tables, slot, a);
    float3 tilted = normalize(n + (float3)(1e-3f, 2e-3f, -1e-3f));
    out[2 * id] = (float4)(vload3(id, axis_sums), (float)lv_axis_of(n, n));
    out[2 * id + 1] = (float4)(sum, (float)lv_axis_of(tilted, tilted));
}

/* Tallies known segments into the volume, one after another in one
 * work-item (test_args.h, T_AXIS_CORRECTION_ARGS). */
__kernel void t_axis_correction(LV_KERNEL_PARAMS(T_AXIS_CORRECTION_ARGS))
{
    if (get_global_id(0) != 0) return;
    lv_grid grid;
    LV_VOLUME_OPEN(grid);
    lv_bin_tables tables = {bin_table, fine_bin_table};
    for (uint i = 0; i < count; i++) {
        float4 o = segments[2 * i], d = segments[2 * i + 1];
        float3 dir = d.xyz;
        uint fine = lv_direction_bin(dir, 2u * grid.g.dirs);
        lv_tally_segment(&grid, o.xyz, dir, 0.0f, o.w, (uint2)(lv_coarse_bin(fine, grid.g.dirs), fine), (float3)(d.w),
                         (float3)(0.0f), concentrated ? &tables : 0, concentrated != 0u);
        uint slot = lv_grid_slot_at(&grid, o.xyz + dir * (0.5f * o.w));
        uint n = lv_slot_dirs(&grid, slot);
        for (uint a = 0; a < LV_AXES; a++) {
            float3 normal = lv_axis_normal(a);
            out[(size_t)i * 2 * LV_AXES + a] = lv_luminance(lv_axis_sum(&grid, &tables, slot, a));
            out[(size_t)i * 2 * LV_AXES + LV_AXES + a] = lv_luminance(lv_cosine_weighted_tallies(
                lv_bin_table_for(&tables, &grid, n), lv_tally_bin(&grid, slot, 0u), 2u * n * n, normal, normal));
        }
    }
}

/* test_args.h, T_JITTER_LOOKUP_ARGS. */
__kernel void t_jitter_lookup(LV_KERNEL_PARAMS(T_JITTER_LOOKUP_ARGS))
{
    uint i = get_global_id(0);
    if (i >= count) return;
    lv_grid grid;
    LV_VOLUME_OPEN(grid);
    lv_rng rng = lv_rng_make(5u, i, 0u);
    float3 p = points[i].xyz, most = (float3)(0.0f);
    for (uint k = 0; k < draws; k++)
        most = fmax(most, fabs(lv_jitter_lookup(&grid, p, (float3)(0.0f, 1.0f, 0.0f), &rng) - p));
    out[i] = (float4)(most / grid.g.cell_size, 0.0f);
}
