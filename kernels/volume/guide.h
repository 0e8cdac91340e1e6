/* The light volume as a sampling density for guided path tracing
 * (docs/guided.md). At a rough surface the guide picks one of the cell's
 * 2 n^2 bins with probability proportional to its tally's luminance times
 * the cosine of the bin's central direction to the surface, then a
 * direction uniform in the bin's solid angle. Its density is exact and
 * cheap to evaluate for any direction, so a path tracer can mix it with
 * BSDF sampling and weigh light samples against the mixture: the image is
 * unbiased whatever the volume holds. */
#ifndef LV_VOLUME_GUIDE_H
#define LV_VOLUME_GUIDE_H

#include "lookup.h"
#include "../light/light_directions.h"

/* The guide's share of a mixture with BSDF sampling where the cell holds
 * light from many particles. With share g every sample's weight is at most
 * 1 / (1 - g) times BSDF sampling's, so a useless guide at most doubles the
 * second moment of a scattering step (docs/guided.md). */
#define LV_GUIDE_SHARE 0.5f
/* A guided path samples by the guide at its first this many rough
 * surfaces, by the BSDF alone at the rest: past them a path carries little
 * of the image's noise, and a guide costs about as much as the rest of the
 * vertex (docs/guided.md). */
#define LV_GUIDE_VERTICES 2u
/* A set whose brightest bin holds less than this many times its mean bin
 * gets no guide: its light is nearly even, which the BSDF's cosine already
 * follows, and setting up the guide would only cost time. */
#define LV_GUIDE_MIN_PEAK 8.0f
/* A cell whose bins hold this many particle pieces gets half the share,
 * more pieces up to all of it: a guide from a few pieces is a few spikes. */
#define LV_GUIDE_TRUSTED_PIECES 256.0f
/* The bins toward the lights must hold this much of a guide's light before
 * directions toward the lights get a share of their own (lv_guide_at). */
#define LV_GUIDE_MIN_LIGHT_MASS 0.02f
/* A set's lobe of concentrated light (lv_guide_lobe) is sampled where it
 * holds this many particle pieces, with a mean resultant length (how
 * closely their directions agree; 1: all alike) of at least this, and at
 * most this concentration (a cone of about 0.02 rad). */
#define LV_GUIDE_LOBE_MIN_PIECES 1.0f
#define LV_GUIDE_LOBE_MIN_LENGTH 0.6f
#define LV_GUIDE_LOBE_MAX_KAPPA 5000.0f

/* The weight of a tally set's bin before the cosine: its luminance (the
 * guide table, one float per bin, filled once after the trace). */
inline float lv_guide_luminance(__global const long *t)
{
    return LV_LUMINANCE((float)t[0], (float)t[1], (float)t[2]);
}

/* The volume a guided path tracer reads. */
typedef struct {
    lv_grid grid;
    lv_bin_tables tables;
    __global const float *luminance; /* per tally set and bin (lv_guide_luminance), as the tallies are laid out */
    __global const float *stats;     /* per tally set: its bins' summed and largest luminance */
    __global const float *lobes;     /* per tally set: its lobe's mean direction of travel and luminance */
    lv_light_candidates lights;      /* the lights that guided paths may aim at (lv_guide_at) */
} lv_guide;

/* The guide at one surface point: the bins of the cell region in front of
 * it, the normals their cosines are taken to, and the sum of their weights. */
typedef struct {
    __global const float *luminance; /* the slot's bins' */
    __global const float *table;
    uint n, bins;
    float3 p;      /* the surface point */
    float3 ns, ng; /* shading normal and geometric normal, both on the side light arrives from */
    float total;
    float share;       /* probability of sampling the guide (lv_guide_prepare), 0 where it holds no light */
    float bin_share;   /* the part of it that samples the bins */
    float light_share; /* and the part that aims at the lights */
    float lobe_share;  /* and the part that samples the lobe of concentrated light */
    float3 lobe_mu;    /* the lobe's mean direction of travel (light arrives from -lobe_mu) */
    float lobe_kappa;  /* and its concentration (lv_sample_vmf) */
    const lv_light_candidates *lights;
    lv_light_odds odds; /* the lights' odds here */
} lv_guide_vertex;

/* A bin's weight: its luminance times the cosine of its central direction
 * c to the shading normal (light travels along c, so it arrives from -c);
 * 0 where -c is behind either normal. */
inline float lv_guide_weight(float luminance, float cos_s, float cos_g)
{
    return cos_s > 0.0f && cos_g > 0.0f ? cos_s * luminance : 0.0f;
}

/* Which lanes of the group from bin `first` are bins of gv's set. */
inline int16 lv_guide_lanes(const lv_guide_vertex *gv, uint first)
{
    int16 lane = (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    return lane < (int16)((int)(gv->bins - first));
}

/* The weights of bins first .. first + LV_BIN_GROUP - 1 (first a multiple
 * of LV_BIN_GROUP) at once; 0 past the last bin (the guide table is padded
 * for this read). */
inline float16 lv_guide_group(const lv_guide_vertex *gv, uint first)
{
    __global const float *group = gv->table + (size_t)(first / LV_BIN_GROUP) * LV_BIN_GROUP_FLOATS;
    float16 cx = vload16(0, group), cy = vload16(1, group), cz = vload16(2, group);
    float16 cs = -(cx * gv->ns.x + cy * gv->ns.y + cz * gv->ns.z);
    float16 cg = -(cx * gv->ng.x + cy * gv->ng.y + cz * gv->ng.z);
    int16 use = (cs > 0.0f) & (cg > 0.0f) & lv_guide_lanes(gv, first);
    return select((float16)(0.0f), cs * vload16(0, gv->luminance + first), use);
}

inline float lv_sum16(float16 v)
{
    float8 s8 = v.lo + v.hi;
    float4 s4 = s8.lo + s8.hi;
    return (s4.x + s4.y) + (s4.z + s4.w);
}

/* Finishes setting up gv once its bins and normals are in: the total, and
 * the share given. Returns 0 (share 0) where the bins hold no light from
 * the front. */
inline int lv_guide_prepare(lv_guide_vertex *gv, float share)
{
    float16 sum = (float16)(0.0f);
    for (uint first = 0; first < gv->bins; first += LV_BIN_GROUP) sum += lv_guide_group(gv, first);
    gv->total = lv_sum16(sum);
    gv->share = gv->bin_share = gv->total > 0.0f && isfinite(gv->total) ? share : 0.0f;
    gv->light_share = 0.0f;
    return gv->share > 0.0f;
}

/* The summed luminance of a tally set's bins, from its `rooms` entries of
 * the guide table's stats (a set of fine bins takes four sets' room, each
 * with its own), and their largest in *top. */
inline float lv_guide_set_stats(__global const float *stats, uint rooms, float *top)
{
    float sum = 0.0f;
    *top = 0.0f;
    for (uint r = 0; r < rooms; r++) {
        sum += stats[2 * r];
        *top = fmax(*top, stats[2 * r + 1]);
    }
    return sum;
}

/* The share the guide of a tally set of `bins` bins gets, from the sum and
 * the largest of their luminance in the guide table: over `rooms` entries,
 * as a set of fine bins takes four sets' room, each with its own. Their
 * summed luminance comes back in *sum. */
inline float lv_guide_share(__global const float *stats, uint rooms, uint bins, float *sum, int *peaked)
{
    float top;
    *sum = lv_guide_set_stats(stats, rooms, &top);
    /* Luminance weights add to 1, so the luminance counts pieces as one
     * channel does (pieces that lost power count as less than one). */
    float pieces = *sum * (1.0f / (LV_TALLY_SCALE * LV_PIECE_TALLY));
    *peaked = top * (float)bins >= LV_GUIDE_MIN_PEAK * *sum;
    if (!(*sum > 0.0f)) return 0.0f;
    return LV_GUIDE_SHARE * pieces / (pieces + LV_GUIDE_TRUSTED_PIECES);
}

/* The lobe of concentrated light of tally set `set` (light that reached
 * the cell from a lamp through glass or off mirrors only: a lamp's image,
 * often far smaller than a bin), as a von Mises-Fisher lobe about its
 * pieces' mean direction, its concentration from their mean resultant
 * length r (Banerjee et al.'s estimate r (3 - r^2) / (1 - r^2)), for a
 * surface with normals ns and ng on the side light arrives from. Returns
 * the part of the guide's share `trusted` it gets, 0 where it has too few
 * pieces, is too spread or lies behind the surface. A lobe holding a share
 * m of the light the surface gathers gets sqrt(m) of the share (at most
 * all of it): a one-sample mixture's variance is least with a
 * share near m sqrt(K) / (m sqrt(K) + 1 - m) for a lobe K times narrower
 * than what BSDF sampling spreads over, and K is large and unknown. */
inline float lv_guide_lobe(const lv_guide *g, uint set, float sum, float trusted, float3 ns, float3 ng,
                           lv_guide_vertex *gv)
{
    __global const float *lobe = g->lobes + 4 * (size_t)set;
    float3 v = vload3(0, lobe);
    float luminance = lobe[3], r = length(v);
    if (!(luminance >= LV_GUIDE_LOBE_MIN_PIECES * LV_TALLY_SCALE * LV_PIECE_TALLY) || !(r >= LV_GUIDE_LOBE_MIN_LENGTH))
        return 0.0f;
    float3 mu = v / r;
    float cs = -dot(mu, ns), cg = -dot(mu, ng);
    if (!(cs > 0.0f) || !(cg > 0.0f)) return 0.0f;
    /* A surface gathers about a quarter of what the set's two hemispheres
     * hold (half of them lie in front, at a mean cosine of a half). */
    float m = fmin(1.0f, 4.0f * luminance * cs / sum);
    r = fmin(r, 0.9999f);
    gv->lobe_mu = mu;
    gv->lobe_kappa = fmin(r * (3.0f - r * r) / (1.0f - r * r), LV_GUIDE_LOBE_MAX_KAPPA);
    return trusted * fmin(1.0f, sqrt(m));
}

/* Light that the bins hold from the directions of the lights has come
 * through glass (the guide's volume leaves the lights' own segments to
 * light samples), and a direction toward the light itself finds it better
 * than one uniform in its bin. Finds the bin of each of gv's candidate
 * lights (gv->bins where it cannot light the surface), and in *fresh a
 * bit for each candidate that is the first in its bin; returns the share
 * of the set's luminance, sum_luminance, in those bins (each bin once), a
 * cheap first look over both hemispheres. */
inline float lv_guide_light_bins(const lv_guide_vertex *gv, float sum_luminance, uint *bins, uint *fresh)
{
    const lv_light_candidates *c = gv->lights;
    float mass = 0.0f;
    *fresh = 0u;
    for (uint k = 0; k < c->count; k++) {
        float3 d = c->v0[k] + (c->e1[k] + c->e2[k]) * (1.0f / 3.0f) - gv->p;
        bins[k] = gv->bins;
        if (!(dot(d, gv->ng) > 0.0f) || !(dot(d, c->n[k]) < 0.0f)) continue;
        bins[k] = lv_direction_bin(-normalize(d), gv->n); /* light from the candidate travels along -d */
        int seen = 0;
        for (uint j = 0; j < k; j++) seen |= bins[j] == bins[k];
        if (!seen) {
            mass += gv->luminance[bins[k]];
            *fresh |= 1u << k;
        }
    }
    return mass / sum_luminance;
}

/* Once gv's bins are prepared: weighs each candidate by the guide's weight
 * of its bin and returns those bins' share of the guide (each bin once:
 * the candidates of lv_guide_light_bins's `fresh`). */
inline float lv_guide_light_mass(lv_guide_vertex *gv, const uint *bins, uint fresh)
{
    float w[LV_LIGHT_CANDIDATES], mass = 0.0f;
    for (uint k = 0; k < gv->lights->count; k++) {
        w[k] = 0.0f;
        if (bins[k] == gv->bins) continue;
        float3 centre = lv_bin_centre(gv->table, bins[k]);
        w[k] = lv_guide_weight(gv->luminance[bins[k]], -dot(centre, gv->ns), -dot(centre, gv->ng));
        if (fresh & (1u << k)) mass += w[k];
    }
    return lv_light_odds_set(gv->lights, w, &gv->odds) ? fmin(mass / gv->total, 1.0f) : 0.0f;
}

/* A guide of the lobe alone: where the bins get no share. */
inline int lv_guide_lobe_only(lv_guide_vertex *gv, float lobe)
{
    gv->share = gv->lobe_share = lobe;
    gv->bin_share = gv->light_share = 0.0f;
    return lobe > 0.0f;
}

/* The slot whose light a rough surface reads (geometric normal ng, on the
 * side light arrives from): the region of the cell just in front of
 * `from`, where rays leave the surface point (lv_leave_point; as the
 * gather's lookup points, lv_lookup_point, so that a point on the end of a
 * wall, which lies on the plane of the wall it meets, reads its own side). */
inline uint lv_guide_slot(const lv_guide *g, float3 from, float3 ng)
{
    return lv_grid_slot_at(&g->grid, lv_front_point(&g->grid, from, ng));
}

/* The mean radiance (luminance, over all its bins) of the indirect light
 * that slot holds, 0 where it holds none: how much light a path going on
 * from there can expect to find, up to the surface's reflectance. */
inline float lv_guide_level(const lv_guide *g, uint slot)
{
    if (slot == LV_EMPTY_CELL) return 0.0f;
    float lit = g->grid.lit_volume[slot];
    if (!(lit > 0.0f)) return 0.0f;
    uint n = lv_slot_dirs(&g->grid, slot), bins = 2u * n * n, rooms = bins / g->grid.g.bins;
    float top, sum = lv_guide_set_stats(g->stats + 2 * (size_t)LV_TALLY_SET_OF(g->grid.tally_slot[slot]), rooms, &top);
    return sum / (float)bins * lv_tally_to_radiance(&g->grid, lit, n);
}

/* Roulette by the volume's light (guided paths): where a path reaches a
 * part of the scene brighter than its first rough surface with light (the
 * slots' levels), its odds of going on rise in proportion, up to
 * LV_ROULETTE_BRIGHTER times plain roulette's (and at most its 0.95), so
 * that paths into the lit room behind a door ajar live on. Returns the
 * factor for roulette's reference (scatter.h), between
 * 1 / LV_ROULETTE_BRIGHTER and 1, and keeps the first level in *first.
 * The odds never fall below plain roulette's, so a wrong volume costs
 * time, never noise; any odds keep the estimate unbiased. */
#define LV_ROULETTE_BRIGHTER 16.0f
inline float lv_guide_roulette(const lv_guide *g, uint slot, float *first)
{
    float level = lv_guide_level(g, slot);
    if (!(*first > 0.0f)) *first = level;
    return level > *first ? fmax(*first / level, 1.0f / LV_ROULETTE_BRIGHTER) : 1.0f;
}

/* Sets up the guide at surface point p, with shading normal ns and
 * geometric normal ng on the side light arrives from. Reads `slot`, the
 * region of the cell in front of p (lv_guide_slot), where that side's
 * light is tallied. Its lobe of concentrated light takes its part of the
 * guide's share first (lv_guide_lobe), the bins the rest where their peak
 * test passes. Where the bins toward the lights hold a share m of its
 * light (at least LV_GUIDE_MIN_LIGHT_MASS), directions toward the lights
 * get m of the bins' share. Returns 0 (share 0) where the volume holds no
 * light there, or none worth a guide. */
inline int lv_guide_at(const lv_guide *g, uint slot, float3 p, float3 ns, float3 ng, lv_guide_vertex *gv)
{
    gv->share = gv->lobe_share = 0.0f;
    if (slot == LV_EMPTY_CELL) return 0;
    uint set = LV_TALLY_SET_OF(g->grid.tally_slot[slot]);
    gv->n = lv_slot_dirs(&g->grid, slot);
    gv->bins = 2u * gv->n * gv->n;
    __global const float *stats = g->stats + 2 * (size_t)set;
    uint rooms = gv->bins / g->grid.g.bins;
    int peaked;
    float sum, trusted = lv_guide_share(stats, rooms, gv->bins, &sum, &peaked);
    if (!(trusted > 0.0f)) return 0; /* no guide: the cost of setting one up is saved too */
    float lobe = lv_guide_lobe(g, set, sum, trusted, ns, ng, gv), share = trusted - lobe;
    gv->p = p;
    gv->ns = ns;
    gv->ng = ng;
    if (!peaked) return lv_guide_lobe_only(gv, lobe); /* the bins' light is even: no bins */
    gv->luminance = g->luminance + (size_t)set * g->grid.g.bins;
    gv->table = lv_bin_table_for(&g->tables, &g->grid, gv->n);
    gv->lights = &g->lights;
    /* The first look asks of the lights' bins what the peak test asks of
     * the brightest: LV_GUIDE_MIN_PEAK times the mean bin, each. (Where
     * the brightest fails, so do they, and no guide is set up.) */
    uint bins[LV_LIGHT_CANDIDATES], fresh;
    float first = lv_guide_light_bins(gv, sum, bins, &fresh);
    uint distinct = popcount(fresh);
    int aim = distinct && first * (float)gv->bins >= LV_GUIDE_MIN_PEAK * (float)distinct;
    if (!lv_guide_prepare(gv, share)) return lv_guide_lobe_only(gv, lobe);
    float m = aim ? lv_guide_light_mass(gv, bins, fresh) : 0.0f;
    gv->light_share = m >= LV_GUIDE_MIN_LIGHT_MASS ? share * m : 0.0f;
    gv->bin_share = share - gv->light_share;
    gv->lobe_share = lobe;
    gv->share = share + lobe;
    return 1;
}

/* The guide's density (per steradian) of light arriving from world
 * direction wi. */
inline float lv_guide_pdf(const lv_guide_vertex *gv, float3 wi)
{
    if (!(gv->bin_share > 0.0f)) return 0.0f;
    uint bin = lv_direction_bin(-wi, gv->n); /* light arriving from wi travels along -wi */
    float3 c = lv_bin_centre(gv->table, bin);
    return lv_guide_weight(gv->luminance[bin], -dot(c, gv->ns), -dot(c, gv->ng)) /
        (gv->total * lv_bin_solid_angle(gv->n));
}

/* Draws a world direction light arrives from: a bin by u.x, a point in it
 * by u.yz. *pdf is the guide's density there. Returns 0 if none. */
inline int lv_guide_sample(const lv_guide_vertex *gv, float3 u, float3 *wi, float *pdf)
{
    /* The group, then the bin, whose stretch of the running sum holds u.x
     * times the total; where rounding leaves the sum short, the last group
     * and its last bin with weight. */
    float target = u.x * gv->total, below = 0.0f;
    uint first = 0;
    float16 w = lv_guide_group(gv, 0);
    for (;;) {
        float sum = lv_sum16(w);
        if (below + sum > target || first + LV_BIN_GROUP >= gv->bins) break;
        below += sum;
        first += LV_BIN_GROUP;
        w = lv_guide_group(gv, first);
    }
    float ws[LV_BIN_GROUP];
    vstore16(w, 0, ws);
    uint chosen = gv->bins;
    float weight = 0.0f;
    for (uint l = 0; l < LV_BIN_GROUP; l++)
        if (ws[l] > 0.0f && below <= target) {
            chosen = first + l;
            weight = ws[l];
            below += ws[l];
        }
    if (chosen == gv->bins) return 0;
    *wi = -lv_bin_direction(chosen, gv->n, u.yz);
    *pdf = weight / (gv->total * lv_bin_solid_angle(gv->n));
    return 1;
}

/* The density of aiming at gv's lights, at world direction wi. */
inline float lv_guide_light_pdf(const lv_guide_vertex *gv, float3 wi)
{
    return gv->light_share > 0.0f ? lv_light_directions_pdf(gv->lights, &gv->odds, gv->p, wi) : 0.0f;
}

/* The density of gv's lobe at world direction wi (light arriving from wi
 * travels along -wi). */
inline float lv_guide_lobe_pdf(const lv_guide_vertex *gv, float3 wi)
{
    return gv->lobe_share > 0.0f ? lv_vmf_pdf(gv->lobe_mu, gv->lobe_kappa, -wi) : 0.0f;
}

/* Draws a world direction light arrives from by gv's lobe. */
inline float3 lv_guide_lobe_sample(const lv_guide_vertex *gv, float2 u)
{
    return -lv_sample_vmf(gv->lobe_mu, gv->lobe_kappa, u);
}

/* The density of the one-sample mixture of BSDF sampling, the bins, the
 * lights and the lobe, from each one's density. */
inline float lv_guide_mix(const lv_guide_vertex *gv, float bsdf_pdf, float bin_pdf, float light_pdf, float lobe_pdf)
{
    return (1.0f - gv->share) * bsdf_pdf + gv->bin_share * bin_pdf + gv->light_share * light_pdf +
        gv->lobe_share * lobe_pdf;
}

/* The mixture's density at world direction wi, whose BSDF density is bsdf_pdf. */
inline float lv_guide_density(const lv_guide_vertex *gv, float bsdf_pdf, float3 wi)
{
    return lv_guide_mix(gv, bsdf_pdf, lv_guide_pdf(gv, wi), lv_guide_light_pdf(gv, wi), lv_guide_lobe_pdf(gv, wi));
}

#endif
