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

#include "grid.h"

/* Adds a positive amount to a 64-bit tally. A device without 64-bit
 * atomics (cl_khr_int64_base_atomics is optional; tests force this path
 * with LV_EMULATE_INT64_ATOMICS) adds the low word and carries into the
 * high one: every add's carry lands exactly once, so the tally is exact
 * once the trace has finished, which is when it is read. */
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

/* Adds an RGB amount (in tally units of 1) to the bin at t. Non-finite or
 * negative amounts are dropped; huge ones are clamped, so no bin can
 * overflow (see LV_TALLY_MAX_CONTRIBUTION). */
inline void lv_tally_add(__global long *t, float3 amount)
{
    float a[3] = {amount.x, amount.y, amount.z};
    for (int c = 0; c < 3; c++) {
        if (!(a[c] > 0.0f) || !isfinite(a[c])) continue;
        long units = (long)(fmin(a[c], LV_TALLY_MAX_CONTRIBUTION) * LV_TALLY_SCALE + 0.5f); /* rounded, not cut */
        if (units > 0) lv_tally_atomic_add(&t[c], units);
    }
}

/* A segment's atomics, held back and done together on CPU devices
 * (LV_PRELOAD_TALLIES, set by the host). Each cell's bin is a random cache
 * line of a volume far larger than the caches, and on a CPU a locked add
 * or or is a full fence: done as the walk meets the cells, each miss waits
 * for the one before. Queued, their lines are first read in one burst, so
 * the misses overlap, and the atomics then find them in the cache (the
 * particle trace 15-20% faster on PoCL; docs/performance.md). A GPU does
 * its atomics in its caches, so there the batch is one add, done at once
 * (not yet run on a GPU).
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
#ifdef LV_PRELOAD_TALLIES
    /* A plain read of words that other work-items add to atomically: OpenCL
     * 1.2 leaves its value unspecified, and it is dropped. The strict
     * simulator calls it a race, so the host leaves it to CPU devices. */
    long sink = 0;
    for (uint i = 0; i < b->count; i++) sink += *(volatile __global const long *)b->bin[i];
#endif
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
    b->bin[b->count] = bin;
    b->amount[b->count] = amount;
    b->mask[b->count] = mask;
    b->bits[b->count] = bits;
    if (++b->count == LV_TALLY_BATCH) lv_tally_flush(b);
}

#endif
