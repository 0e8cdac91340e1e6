/* The light volume's directional bins (docs/light-volume.md): each hemisphere
 * maps to an n x n square by an equal-area map (the concentric disk of
 * Shirley and Chiu, with z = 1 - r^2), so every one of the 2 n^2 bins spans
 * exactly 2 pi / n^2 steradians. Bins 0 .. n^2-1 hold z >= 0, the rest z < 0. */
#ifndef LV_DIRECTION_MAP_H
#define LV_DIRECTION_MAP_H

#include "../util/sampling.h"

/* Inverse of lv_square_to_disk: unit disk to [0,1]^2. */
inline float2 lv_disk_to_square(float2 d)
{
    float r = sqrt(d.x * d.x + d.y * d.y);
    if (r == 0.0f) return (float2)(0.5f, 0.5f);
    float phi = atan2(d.y, d.x); /* (-pi, pi] */
    if (phi < -LV_PI / 4.0f) phi += 2.0f * LV_PI;
    float a, b;
    if (phi < LV_PI / 4.0f) { /* right wedge */
        a = r;
        b = phi * a / (LV_PI / 4.0f);
    } else if (phi < 3.0f * LV_PI / 4.0f) { /* top */
        b = r;
        a = -(phi - LV_PI / 2.0f) * b / (LV_PI / 4.0f);
    } else if (phi < 5.0f * LV_PI / 4.0f) { /* left */
        a = -r;
        b = (phi - LV_PI) * a / (LV_PI / 4.0f);
    } else { /* bottom */
        b = -r;
        a = -(phi - 3.0f * LV_PI / 2.0f) * b / (LV_PI / 4.0f);
    }
    return (float2)(0.5f * (a + 1.0f), 0.5f * (b + 1.0f));
}

/* The bin of unit direction w with n x n bins per hemisphere. */
inline uint lv_direction_bin(float3 w, uint n)
{
    float z = fabs(w.z);
    float r = sqrt(fmax(0.0f, 1.0f - z));
    float xy = sqrt(w.x * w.x + w.y * w.y);
    float2 d = xy > 0.0f ? (float2)(w.x, w.y) * (r / xy) : (float2)(0.0f);
    float2 sq = lv_disk_to_square(d);
    uint i = min((uint)(sq.x * (float)n), n - 1u);
    uint j = min((uint)(sq.y * (float)n), n - 1u);
    return (w.z < 0.0f ? n * n : 0u) + j * n + i;
}

/* The bin of n x n per hemisphere that holds fine bin `fine` of 2n x 2n:
 * the same as lv_direction_bin(w, n) for the w that gave `fine` (the
 * products of the square's coordinates by 2n are twice those by n, exactly). */
inline uint lv_coarse_bin(uint fine, uint n)
{
    uint m = 2u * n, lower = fine >= m * m, cell = fine - (lower ? m * m : 0u);
    return (lower ? n * n : 0u) + (cell / m / 2u) * n + (cell % m) / 2u;
}

/* A direction inside bin `bin`, uniform in solid angle for uniform u. */
inline float3 lv_bin_direction(uint bin, uint n, float2 u)
{
    uint lower = bin >= n * n;
    uint cell = bin - (lower ? n * n : 0u);
    float2 sq = (float2)(((float)(cell % n) + u.x) / (float)n, ((float)(cell / n) + u.y) / (float)n);
    float2 d = lv_square_to_disk(sq);
    float r2 = d.x * d.x + d.y * d.y;
    float z = 1.0f - r2;
    float s = r2 > 0.0f ? sqrt(fmax(0.0f, 1.0f - z * z) / r2) : 0.0f;
    return (float3)(d.x * s, d.y * s, lower ? -z : z);
}

/* Fills bin `bin`'s entries of the bin table of `bins` bins (layout in
 * shared_types.h); a bin past the last writes its group's padding. The
 * map is equal-area, so a uniform grid of points in the bin's square is
 * uniform in solid angle: the mean direction is their average (32 x 32 of
 * them). The angle from the centre is greatest on the bin's edge (it has
 * no maximum inside), which is walked at 33 points a side; the radius gets
 * a margin for the gaps between them. A hemisphere's bins keep to their
 * side of z = 0 (rounding may push an edge point across). */
inline void lv_fill_bin_table(uint bin, uint n, __global float *table)
{
    uint bins = 2u * n * n;
    __global float *group = table + (size_t)(bin / LV_BIN_GROUP) * LV_BIN_GROUP_FLOATS + bin % LV_BIN_GROUP;
    if (bin >= bins) {
        for (uint k = 0; k < 7u; k++) group[k * LV_BIN_GROUP] = 0.0f;
        return;
    }
    float3 centre = lv_bin_direction(bin, n, (float2)(0.5f, 0.5f));
    float3 mean = (float3)(0.0f);
    const uint dense = 32u;
    for (uint j = 0; j < dense; j++)
        for (uint i = 0; i < dense; i++)
            mean += lv_bin_direction(bin, n, ((float2)((float)i, (float)j) + 0.5f) / (float)dense);
    mean /= (float)(dense * dense);
    float least_cos = 1.0f;
    for (uint k = 0; k <= dense; k++) {
        float t = (float)k / (float)dense;
        float2 side[4] = {(float2)(t, 0.0f), (float2)(t, 1.0f), (float2)(0.0f, t), (float2)(1.0f, t)};
        for (int e = 0; e < 4; e++) least_cos = fmin(least_cos, dot(centre, lv_bin_direction(bin, n, side[e])));
    }
    float radius = acos(clamp(least_cos, -1.0f, 1.0f)) * 1.05f + 1e-3f;
    float values[7] = {centre.x, centre.y, centre.z, radius < 0.5f * LV_PI ? sin(radius) : 1.0f,
                       mean.x,   mean.y,   mean.z};
    for (uint k = 0; k < 7u; k++) group[k * LV_BIN_GROUP] = values[k];

    __global float *edge = table + (size_t)LV_BIN_GROUPS(bins) * LV_BIN_GROUP_FLOATS + (size_t)bin * LV_BIN_EDGE_FLOATS;
    __global float *parts = edge + 3 * LV_BIN_EDGE_POINTS;
    const float2 points[LV_BIN_EDGE_POINTS] = {(float2)(0.0f, 0.0f), (float2)(0.5f, 0.0f), (float2)(1.0f, 0.0f),
                                               (float2)(1.0f, 0.5f), (float2)(1.0f, 1.0f), (float2)(0.5f, 1.0f),
                                               (float2)(0.0f, 1.0f), (float2)(0.0f, 0.5f)};
    int upper = bin < n * n;
    for (uint k = 0; k < LV_BIN_EDGE_POINTS; k++) {
        float3 w = lv_bin_direction(bin, n, points[k]);
        edge[k] = w.x;
        edge[LV_BIN_EDGE_POINTS + k] = w.y;
        edge[2 * LV_BIN_EDGE_POINTS + k] = upper ? fmax(w.z, 0.0f) : fmin(w.z, 0.0f);
    }
    for (uint j = 0; j < LV_BIN_SUBDIR_SIDE; j++)
        for (uint i = 0; i < LV_BIN_SUBDIR_SIDE; i++) {
            uint k = j * LV_BIN_SUBDIR_SIDE + i;
            float3 w = lv_bin_direction(bin, n, ((float2)((float)i, (float)j) + 0.5f) / (float)LV_BIN_SUBDIR_SIDE);
            parts[k] = w.x;
            parts[LV_BIN_SUBDIRS + k] = w.y;
            parts[2 * LV_BIN_SUBDIRS + k] = w.z;
        }
}

/* Bin `bin`'s first entry in its group of the table; its k-th value lies
 * k LV_BIN_GROUP floats on (shared_types.h). */
inline __global const float *lv_bin_entries(__global const float *table, uint bin)
{
    return table + (size_t)(bin / LV_BIN_GROUP) * LV_BIN_GROUP_FLOATS + bin % LV_BIN_GROUP;
}

/* Bin `bin`'s central direction, from the table. */
inline float3 lv_bin_centre(__global const float *table, uint bin)
{
    __global const float *group = lv_bin_entries(table, bin);
    return (float3)(group[0], group[LV_BIN_GROUP], group[2 * LV_BIN_GROUP]);
}

/* Edge points closer to a horizon than this count as on its lit side. */
#define LV_HORIZON_TOLERANCE 1e-6f

/* The mean cosine (lv_bin_mean_cosines) of a bin whose cone reaches over
 * the horizon of ns or ng; `mean` is its mean direction. If its edge
 * points lie on one side of both planes the bin does too (a plane that
 * crossed between two of them would cut off a sliver whose cosines are all
 * near 0); that settles the bins whose edge only touches a plane, as an
 * axis-aligned wall's does. Bins the horizon cuts average the cosines of
 * their parts. */
inline float lv_bin_cut_cosine(__global const float *edge, float3 mean, float3 ns, float3 ng, int same)
{
    float8 ex = vload8(0, edge), ey = vload8(1, edge), ez = vload8(2, edge);
    int front = 1;
    for (int k = 0; k < (same ? 1 : 2); k++) {
        float3 n = k ? ng : ns;
        float8 c = -(ex * n.x + ey * n.y + ez * n.z); /* light arrives against its travel */
        /* min and max, not fmin and fmax: c is finite, and PoCL builds the
         * latter with NaN handling */
        float4 lo4 = min(c.lo, c.hi), hi4 = max(c.lo, c.hi);
        float2 lo2 = min(lo4.lo, lo4.hi), hi2 = max(hi4.lo, hi4.hi);
        if (max(hi2.x, hi2.y) <= LV_HORIZON_TOLERANCE) return 0.0f;
        front = front && min(lo2.x, lo2.y) >= -LV_HORIZON_TOLERANCE;
    }
    if (front) return -dot(mean, ns);
    /* The parts 16 at a time, one lane each (the table's layout is for this). */
    __global const float *parts = edge + 3 * LV_BIN_EDGE_POINTS;
    float16 lit = (float16)(0.0f);
    for (uint k = 0; k < LV_BIN_SUBDIRS / 16; k++) {
        float16 x = vload16(k, parts), y = vload16(k, parts + LV_BIN_SUBDIRS),
                z = vload16(k, parts + 2 * LV_BIN_SUBDIRS);
        float16 c = -(x * ns.x + y * ns.y + z * ns.z);
        if (same) {
            lit += max(c, 0.0f);
        } else {
            float16 g = -(x * ng.x + y * ng.y + z * ng.z);
            lit += select((float16)(0.0f), c, (c > 0.0f) & (g > 0.0f));
        }
    }
    float8 s8 = lit.lo + lit.hi;
    float4 s4 = s8.lo + s8.hi;
    return (s4.x + s4.y + s4.z + s4.w) * (1.0f / (float)LV_BIN_SUBDIRS);
}

/* For the LV_BIN_GROUP bins from `first` (a multiple of LV_BIN_GROUP):
 * the mean, over the directions light travelling in each arrives from, of
 * their cosine to the shading normal ns, counting only those the true
 * surface (normal ng) faces too, in w[]: a Lambertian surface's exact
 * weight for the bin's radiance. A bin wholly in front of both takes the
 * cosine of its mean direction, which is the mean cosine (the cosine is
 * linear); the bin's central direction would overweigh it by about the
 * bin's spread (3% at 8 x 8 bins, tests/volume/test_direction_map.c). The
 * cones around the central directions settle most bins, a group at once. */
inline void lv_bin_mean_cosines(__global const float *table, uint bins, uint first, float3 ns, float3 ng,
                                float w[LV_BIN_GROUP])
{
    __global const float *group = table + (size_t)(first / LV_BIN_GROUP) * LV_BIN_GROUP_FLOATS;
    float16 cx = vload16(0, group), cy = vload16(1, group), cz = vload16(2, group), spread = vload16(3, group);
    float16 mx = vload16(4, group), my = vload16(5, group), mz = vload16(6, group);
    int same = all(ns == ng);
    float16 cs = -(cx * ns.x + cy * ns.y + cz * ns.z);
    float16 cg = same ? cs : -(cx * ng.x + cy * ng.y + cz * ng.z);
    int16 front = (cs >= spread) & (cg >= spread);
    int16 cut = ~front & (cs > -spread) & (cg > -spread);
    vstore16(select((float16)(0.0f), -(mx * ns.x + my * ns.y + mz * ns.z), front), 0, w);
    if (!any(cut)) return;
    int cuts[LV_BIN_GROUP];
    vstore16(cut, 0, cuts);
    __global const float *edges = table + (size_t)LV_BIN_GROUPS(bins) * LV_BIN_GROUP_FLOATS;
    for (uint l = 0; l < LV_BIN_GROUP; l++)
        if (cuts[l] && first + l < bins)
            w[l] = lv_bin_cut_cosine(
                edges + (size_t)(first + l) * LV_BIN_EDGE_FLOATS,
                (float3)(group[4 * LV_BIN_GROUP + l], group[5 * LV_BIN_GROUP + l], group[6 * LV_BIN_GROUP + l]), ns, ng,
                same);
}

/* The unit normal of axis a: +x, -x, +y, -y, +z, -z for 0 to 5 (the axis
 * sums' and corrections' order, shared_types.h). */
inline float3 lv_axis_normal(uint a)
{
    float s = (a & 1u) ? -1.0f : 1.0f;
    return (float3)(a / 2u == 0u ? s : 0.0f, a / 2u == 1u ? s : 0.0f, a / 2u == 2u ? s : 0.0f);
}

/* The weight lv_bin_mean_cosines gives bin `bin` of `bins` for a surface
 * whose shading and true normals are both n, one bin at a time (the
 * particle trace's axis corrections, tally.h). */
inline float lv_bin_mean_cosine(__global const float *table, uint bins, uint bin, float3 n)
{
    __global const float *group = lv_bin_entries(table, bin);
    float3 mean = (float3)(group[4 * LV_BIN_GROUP], group[5 * LV_BIN_GROUP], group[6 * LV_BIN_GROUP]);
    float cs = -dot(lv_bin_centre(table, bin), n), spread = group[3 * LV_BIN_GROUP];
    if (cs >= spread) return -dot(mean, n);
    if (!(cs > -spread)) return 0.0f;
    __global const float *edges = table + (size_t)LV_BIN_GROUPS(bins) * LV_BIN_GROUP_FLOATS;
    return lv_bin_cut_cosine(edges + (size_t)bin * LV_BIN_EDGE_FLOATS, mean, n, n, 1);
}

inline float lv_bin_solid_angle(uint n)
{
    return 2.0f * LV_PI / (float)(n * n);
}

#endif
