/* Counter-based random numbers. A stream is keyed by (seed, item, sample),
 * where the item is a pixel or a particle; the n-th number of a stream is a
 * hash of its key and n. Results therefore do not depend on work-group size,
 * device or scheduling. */
#ifndef LV_RNG_H
#define LV_RNG_H

#include "../shared_types.h"

/* lv_hash, the hash every stream is made of, is in shared_types.h. */

typedef struct {
    uint key;
    uint counter;
    uint shift;  /* a camera stream's per-pixel lattice shift key; 0: none */
    uint sample; /* its sample index */
} lv_rng;

inline lv_rng lv_rng_make(uint seed, uint item, uint sample)
{
    lv_rng r;
    r.key = lv_hash(lv_hash(lv_hash(seed) ^ item) + sample * 0x9e3779b9u);
    r.counter = 0;
    r.shift = 0;
    r.sample = sample;
    return r;
}

/* A camera sample's first LV_LATTICE_DIMS numbers (its pixel jitter, then
 * in a path its first vertex's samples and its second's light sample, in
 * the gather its lookup, light sample and what follows) come from a
 * rank-1 lattice over the pixel's samples: sample s, dimension d is
 * s g_d + u_d mod 1, with g the 12-dimensional R sequence's generator
 * (Roberts 2018) and u a random shift per pixel and dimension (Cranley and
 * Patterson 1976). Every sample is still uniform in the unit cube, so each
 * is unbiased; a pixel's samples are correlated along the lattice instead
 * of independent, which lowers the images' error (docs/design.md,
 * "Sampling"). In 32-bit integers, so every device computes the same
 * numbers. LV_LATTICE_DIMS and the generator are in shared_types.h, for
 * the tests. */
__constant uint lv_lattice_generators[LV_LATTICE_DIMS] = LV_LATTICE_GENERATORS;

inline lv_rng lv_rng_make_lattice(uint seed, uint pixel, uint sample)
{
    lv_rng r = lv_rng_make(seed, pixel, sample);
    r.shift = lv_hash(lv_hash(seed) ^ pixel) | 1u;
    return r;
}

/* The key of a stream forked from r where it stands, for a side walk that
 * must not move r's numbers (a shadow ray's way on through glass, which a
 * wavefront walks in another kernel than the path's next scatter). */
inline uint lv_rng_fork_key(const lv_rng *r)
{
    return lv_hash(r->key ^ lv_hash(r->counter + 0x2545f491u));
}

inline lv_rng lv_rng_keyed(uint key)
{
    lv_rng r;
    r.key = key;
    r.counter = 0;
    r.shift = 0;
    r.sample = 0;
    return r;
}

/* Uniform in [0, 1): the top 24 bits, so 1 is never returned. */
inline float lv_rng_next(lv_rng *r)
{
    uint n = r->counter++;
    uint h = r->shift && n < LV_LATTICE_DIMS
        ? lv_hash(r->shift + n * 0x9e3779b9u) + r->sample * lv_lattice_generators[n]
        : lv_hash(r->key ^ lv_hash(n + 0x632be5abu));
    return (float)(h >> 8) * 0x1p-24f;
}

/* Two and three numbers in stream order. A vector literal's components
 * are not sequenced in C, so each draw is a statement of its own: a
 * compiler that evaluated (float3)(next2, next) right to left would give
 * another image. */
inline float2 lv_rng_next2(lv_rng *r)
{
    float a = lv_rng_next(r);
    return (float2)(a, lv_rng_next(r));
}

inline float3 lv_rng_next3(lv_rng *r)
{
    float2 a = lv_rng_next2(r);
    return (float3)(a, lv_rng_next(r));
}

#endif
