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

/* Adds an RGB amount (in tally units of 1) to one bin. Non-finite or
 * negative amounts are dropped; huge ones are clamped, so no bin can
 * overflow (see LV_TALLY_MAX_CONTRIBUTION). */
inline void lv_tally_add(const lv_grid *grid, uint slot, uint bin, float3 amount)
{
    __global long *t = lv_tally_bin(grid, slot, bin);
    float a[3] = {amount.x, amount.y, amount.z};
    for (int c = 0; c < 3; c++) {
        if (!(a[c] > 0.0f) || !isfinite(a[c])) continue;
        long units = (long)(fmin(a[c], LV_TALLY_MAX_CONTRIBUTION) * LV_TALLY_SCALE + 0.5f); /* rounded, not cut */
        if (units > 0) lv_tally_atomic_add(&t[c], units);
    }
}

#endif
