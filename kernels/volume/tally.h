/* Adding to the light volume's 64-bit fixed-point tallies (paper eq. 5):
 * integer atomics, so the result does not depend on the order of work. */
#ifndef LV_VOLUME_TALLY_H
#define LV_VOLUME_TALLY_H

#if defined(cl_khr_int64_base_atomics) && !defined(LV_EMULATE_INT64_ATOMICS)
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#define LV_NATIVE_INT64_ATOMICS
#elif !defined(__ENDIAN_LITTLE__)
#error "64-bit tallies from two 32-bit atomics need a little-endian device"
#endif

#include "direction_map.h"
#include "grid.h"

/* Adds an amount to a 64-bit tally. A device without 64-bit atomics
 * (cl_khr_int64_base_atomics is optional; tests force this path with
 * LV_EMULATE_INT64_ATOMICS) adds the low word and carries into the high
 * one: every add's carry lands exactly once, so the tally is exact (modulo
 * 2^64, which a negative amount relies on) once the trace has finished,
 * which is when it is read. */
inline void lv_tally_atomic_add(__global long *tally, long units)
{
#ifdef LV_NATIVE_INT64_ATOMICS
    atom_add((volatile __global long *)tally, units);
#else
    volatile __global uint *word = (volatile __global uint *)tally;
    uint low = (uint)units, high = (uint)((ulong)units >> 32);
    uint before = atomic_add(&word[0], low);
    if (before + low < before) high++;
    if (high) atomic_add(&word[1], high);
#endif
}

/* What a tally takes of an amount (in tally units of 1): non-finite or
 * negative amounts are dropped; huge ones are clamped, so no bin can
 * overflow (see LV_TALLY_MAX_CONTRIBUTION). */
inline float3 lv_tally_accepted(float3 amount)
{
    return select((float3)(0.0f), fmin(amount, LV_TALLY_MAX_CONTRIBUTION), amount > 0.0f && isfinite(amount));
}

/* Adds an RGB amount (in tally units of 1) to the bin at t. */
inline void lv_tally_add(__global long *t, float3 amount)
{
    float3 accepted = lv_tally_accepted(amount);
    float a[3] = {accepted.x, accepted.y, accepted.z};
    for (int c = 0; c < 3; c++) {
        long units = (long)(a[c] * LV_TALLY_SCALE + 0.5f); /* rounded, not cut */
        if (units > 0) lv_tally_atomic_add(&t[c], units);
    }
}

/* Adds, for a piece of concentrated light (a lamp seen through glass or in
 * a mirror, which fills a corner of its bin) that tallied `amount` along
 * dir into bin `bin` of the `bins` that `table` describes, its axis
 * corrections (shared_types.h) to `axes`: per axis normal, the luminance
 * tallied times the piece's exact cosine to it (a surface facing +x
 * receives light travelling along -x) minus the mean cosine its bin is
 * read with. Done at once, not queued: in lv few pieces are concentrated
 * (in lv-all every lamp's own segment is). */
inline void lv_tally_correct(__global long *axes, float3 amount, float3 dir, __global const float *table, uint bins,
                             uint bin)
{
    float l = lv_luminance(lv_tally_accepted(amount));
    for (uint a = 0; a < LV_AXES; a++) {
        float3 n = lv_axis_normal(a);
        float exact = fmax(-dot(dir, n), 0.0f), binned = lv_bin_mean_cosine(table, bins, bin, n);
        long units = convert_long_rte(l * (exact - binned) * LV_TALLY_SCALE);
        if (units != 0) lv_tally_atomic_add(&axes[a], units);
    }
}

/* Adds a piece of concentrated light that tallied `amount` along dir to
 * its set's lobe sums (shared_types.h): its luminance times dir, and its
 * luminance. Done at once, as the axis corrections are. */
inline void lv_tally_lobe(__global long *lobe, float3 amount, float3 dir)
{
    float l = lv_luminance(lv_tally_accepted(amount)) * LV_TALLY_SCALE;
    float v[LV_LOBE_LONGS] = {l * dir.x, l * dir.y, l * dir.z, l};
    for (uint i = 0; i < LV_LOBE_LONGS; i++) {
        long units = convert_long_rte(v[i]);
        if (units != 0) lv_tally_atomic_add(&lobe[i], units);
    }
}

/* A segment's atomics, held back and done together on CPU devices
 * (LV_PRELOAD_TALLIES, set by the host). Each cell's bin is a random cache
 * line of a volume far larger than the caches, and on a CPU a locked add
 * or or is a full fence: done as the walk meets the cells, each miss waits
 * for the one before. So each piece's line is prefetched (for writing)
 * when the piece is queued, and the atomics run when the batch is full,
 * by which time the walk has covered the misses (the particle trace 5%
 * faster than reading the batch's lines in one burst before its atomics,
 * and that was 15-20% faster than no batch; docs/performance.md). A GPU
 * does its atomics in its caches, so there the batch is one add, done at
 * once (not yet run on a GPU).
 * Integer adds and ors commute, so the order changes no tally and no mask. */
#ifdef LV_PRELOAD_TALLIES
#define LV_TALLY_BATCH 16
#else
#define LV_TALLY_BATCH 1
#endif

typedef struct {
    __global long *bin[LV_TALLY_BATCH];
    float3 amount[LV_TALLY_BATCH];
    __global uint *mask[LV_TALLY_BATCH];
    uint2 bits[LV_TALLY_BATCH];
    uint count;
} lv_tally_batch;

inline void lv_tally_flush(lv_tally_batch *b)
{
    for (uint i = 0; i < b->count; i++) {
        lv_tally_add(b->bin[i], b->amount[i]);
        if (b->bits[i].x) atomic_or(&b->mask[i][0], b->bits[i].x);
        if (b->bits[i].y) atomic_or(&b->mask[i][1], b->bits[i].y);
    }
    b->count = 0u;
}

/* Queues amount for bin and, where bits are new, an or of bits into mask. */
inline void lv_tally_queue(lv_tally_batch *b, __global long *bin, float3 amount, __global uint *mask, uint2 bits)
{
#ifdef LV_PRELOAD_TALLIES
    /* OpenCL 1.2's prefetch() compiles to nothing on PoCL, and clang's
     * builtin takes no __global pointer there; on a CPU device every
     * address space is the one flat memory, so the address is passed as
     * a plain one. CPU devices only (the host sets LV_PRELOAD_TALLIES). */
    __builtin_prefetch((const void *)(size_t)bin, 1, 3);
#endif
    b->bin[b->count] = bin;
    b->amount[b->count] = amount;
    b->mask[b->count] = mask;
    b->bits[b->count] = bits;
    if (++b->count == LV_TALLY_BATCH) lv_tally_flush(b);
}

#endif
