/* Counter-based random numbers. A stream is keyed by (seed, item, sample),
 * where the item is a pixel or a particle; the n-th number of a stream is a
 * hash of its key and n. Results therefore do not depend on work-group size,
 * device or scheduling. */
#ifndef LV_RNG_H
#define LV_RNG_H

/* A 32-bit integer hash with good avalanche (a xorshift-multiply chain). */
inline uint lv_hash(uint x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

typedef struct {
    uint key;
    uint counter;
} lv_rng;

inline lv_rng lv_rng_make(uint seed, uint item, uint sample)
{
    lv_rng r;
    r.key = lv_hash(lv_hash(lv_hash(seed) ^ item) + sample * 0x9e3779b9u);
    r.counter = 0;
    return r;
}

/* Uniform in [0, 1): the top 24 bits, so 1 is never returned. */
inline float lv_rng_next(lv_rng *r)
{
    uint h = lv_hash(r->key ^ lv_hash(r->counter++ + 0x632be5abu));
    return (float)(h >> 8) * 0x1p-24f;
}

inline float2 lv_rng_next2(lv_rng *r)
{
    float a = lv_rng_next(r);
    return (float2)(a, lv_rng_next(r));
}

#endif
