/* The final gather (paper section 5; docs/light-volume.md, "The final
 * gather"): camera paths that let the light volume answer at the first
 * rough surface. There shadow rays give direct light (unless the volume
 * holds all light), lamps seen through glass included (see_through.h),
 * and the volume, read at a jittered point around the surface, the rest.
 * The paper's way (sampled) follows one BSDF ray: if it meets a surface
 * without a delta lobe closer than the threshold the path goes on,
 * otherwise the volume's bin in its direction answers. The integrating way
 * sums the BSDF over every bin and still follows one BSDF ray: where that
 * ray hits close, the path's radiance replaces the volume's for its
 * direction, so near geometry (corners, contact shadows), which a cell
 * average cannot resolve, is path traced as in the paper while far light
 * stays noise-free. */
#ifndef LV_INTEGRATOR_GATHER_H
#define LV_INTEGRATOR_GATHER_H

#include "../volume/lookup.h"
#include "see_through.h"

/* How the final gather reads the light volume. */
typedef struct {
    lv_grid grid;
    lv_bin_tables tables;
    __global const float *axis_sums; /* lv_axis_sums's, per slot */
    uint flags;                      /* LV_GATHER_* (shared_types.h) */
    float threshold;                 /* a BSDF ray hitting closer than this continues as a path */
} lv_gather;

/* The sum of a tally set's bins (RGB), each weighted by its exact mean
 * cosine to the shading normal ns (lv_bin_mean_cosines): what a Lambertian
 * surface gathers, before its albedo and the volume's scale. */
inline float3 lv_cosine_weighted_tallies(__global const float *table, __global const long *tallies, uint bins,
                                         float3 ns, float3 ng)
{
    float3 sum = (float3)(0.0f);
    for (uint first = 0; first < bins; first += LV_BIN_GROUP) {
        float w[LV_BIN_GROUP];
        lv_bin_mean_cosines(table, bins, first, ns, ng, w);
        for (uint l = 0; l < LV_BIN_GROUP && first + l < bins; l++)
            if (w[l] > 0.0f) sum += w[l] * lv_bin_tally(tallies + 3 * (first + l));
    }
    return sum;
}

/* 0 to 5 where the shading and true normals are both exactly +x, -x, +y,
 * -y, +z or -z, else -1: such a surface (walls, floors, tables) reads its
 * cosine-weighted sum from the axis sums instead of visiting every bin. */
inline int lv_axis_of(float3 ns, float3 ng)
{
    if (any(ns != ng)) return -1;
    if (ns.y == 0.0f && ns.z == 0.0f && fabs(ns.x) == 1.0f) return ns.x > 0.0f ? 0 : 1;
    if (ns.x == 0.0f && ns.z == 0.0f && fabs(ns.y) == 1.0f) return ns.y > 0.0f ? 2 : 3;
    if (ns.x == 0.0f && ns.y == 0.0f && fabs(ns.z) == 1.0f) return ns.z > 0.0f ? 4 : 5;
    return -1;
}

/* What a Lambertian surface facing along axis a (lv_axis_of's numbering)
 * gathers from slot's tallies, before its albedo and the volume's scale:
 * the bins weighted by their mean cosines, scaled by the set's axis
 * correction. The mean cosine assumes a bin's light spread evenly over
 * it; a lamp seen through glass fills a corner of its bins, which 8 x 8
 * bins per hemisphere read 3% dark on a floor below it. The correction
 * adds, for such concentrated light, each piece's own cosine in place of
 * its bin's mean (docs/light-volume.md, "Axis corrections"). */
inline float3 lv_axis_sum(const lv_grid *grid, const lv_bin_tables *tables, uint slot, uint a)
{
    uint n = lv_slot_dirs(grid, slot);
    float3 normal = lv_axis_normal(a);
    float3 sum = lv_cosine_weighted_tallies(lv_bin_table_for(tables, grid, n), lv_tally_bin(grid, slot, 0u), 2u * n * n,
                                            normal, normal);
    float binned = lv_luminance(sum), exact = binned + (float)lv_axis_corrections(grid, slot)[a];
    return binned > 0.0f ? sum * (fmax(exact, 0.0f) / binned) : (float3)(0.0f);
}

/* The BSDF-weighted sum of the volume's radiance over every bin of the cell
 * at p. */
inline float3 lv_gather_integrate(const lv_gather *g, const lv_shading *sh, float3 p)
{
    uint slot = lv_grid_slot_at(&g->grid, p);
    if (slot == LV_EMPTY_CELL) return (float3)(0.0f);
    __global const long *tallies = lv_tally_bin(&g->grid, slot, 0u); /* a slot's bins are consecutive */
    uint n = lv_slot_dirs(&g->grid, slot), bins = 2u * n * n;
    __global const float *table = lv_bin_table_for(&g->tables, &g->grid, n);
    float3 sum = (float3)(0.0f);
    if (sh->b.type == LV_BSDF_DIFFUSE) {
        /* f cos is base / pi times cos: weigh each bin by its exact mean
         * cosine and apply the rest once (most gathers). */
        if (sh->wo.z <= 0.0f) return (float3)(0.0f);
        int axis = lv_axis_of(sh->f.n, sh->ng_out);
        sum = axis >= 0 ? vload3((size_t)slot * LV_AXES + (uint)axis, g->axis_sums)
                        : lv_cosine_weighted_tallies(table, tallies, bins, sh->f.n, sh->ng_out);
        sum *= sh->b.base * LV_INV_PI;
    } else {
        /* Other BSDFs are read at each bin's central direction. Light
         * arriving from wi travels along -wi. The gather runs on reflecting
         * surfaces only; a direction the shading normal allows but the true
         * surface does not would read light leaving the surface itself. */
        for (uint bin = 0; bin < bins; bin++) {
            float3 t = lv_bin_tally(tallies + 3 * bin);
            if (lv_max3(t) <= 0.0f) continue;
            float3 wiw = -lv_bin_centre(table, bin);
            float3 wi = lv_to_local(sh->f, wiw);
            if (wi.z <= 0.0f || dot(wiw, sh->ng_out) <= 0.0f) continue;
            float3 fcos = lv_bsdf_eval(&sh->b, sh->wo, wi, LV_RADIANCE, 0);
            if (lv_max3(fcos) > 0.0f) sum += fcos * t;
        }
    }
    return sum * (lv_tally_to_radiance(&g->grid, g->grid.lit_volume[slot], n) * lv_bin_solid_angle(n));
}

/* What the ray just traced owes the light volume once it lands. */
#define LV_LOOKUP_NONE 0
#define LV_LOOKUP_READ 1    /* a far hit reads the volume in the ray's direction */
#define LV_LOOKUP_CORRECT 2 /* a near hit takes back the volume's share: the path answers instead */

/* Radiance arriving along r at its origin. */
inline float3 lv_gather_radiance(const lv_scene *sc, lv_ray r, lv_rng *rng, uint max_depth, const lv_gather *g)
{
    int all_light = (g->flags & LV_GATHER_ALL) != 0u;
    float3 radiance = (float3)(0.0f);
    float3 beta = (float3)(1.0f);
    float eta_scale = 1.0f; /* roulette's reference (scatter.h) */
    lv_bsdf_sample bs;
    bs.pdf = 0.0f;
    bs.delta = 1; /* the camera ray counts as a delta sample: no MIS */
    int lookup = LV_LOOKUP_NONE;
    float3 lookup_point = (float3)(0.0f);
    int lookup_lit = 0; /* the volume at lookup_point holds light that reaches the surface */
    /* Delta scatters since the last vertex whose path went on past a rough
     * surface where the volume could not be read (lv_lookup_point): its
     * light sample saw lamps through glass, so what the path finds through
     * the same glass shares that light by MIS, as in pt. */
    lv_glass_chain chain = lv_glass_chain_start((float3)(0.0f), (float3)(0.0f), 0.0f, 0);
    for (uint depth = 1; depth <= max_depth; depth++) {
        lv_hit h = lv_trace(sc, r, 0);
        lv_surface s;
        __global const lv_material *m = 0;
        int far = h.tri == LV_NO_HIT;
        if (h.tri != LV_NO_HIT) {
            s = lv_surface_at(sc, r, h);
            m = &sc->materials[s.material];
            /* A near hit continues the path unless its surface has a
             * delta lobe: a mirror or smooth glass would lead on to
             * caustics, which the volume holds already. A glossy surface
             * too smooth to gather at goes on as a rough one does: read
             * from the volume, its light would be a cell's average, and
             * where it meets the gather point's surface (a glossy wall at
             * a ceiling) that average is brighter than the corner. */
            far = lookup != LV_LOOKUP_NONE && (h.t > g->threshold || lv_bsdf_delta_at(m->bsdf, m->alpha));
            /* With all light in the volume a gather point ends the path,
             * and no vertex sends light samples: emission that a path
             * meets (past mirrors, glass, smooth or untrusted surfaces) is
             * found by that path alone. */
            float3 le = LV_F3(m->emission);
            if (s.front && lv_max3(le) > 0.0f)
                radiance += beta * le *
                    (all_light      ? 1.0f
                         : bs.delta ? lv_glass_chain_weight(sc, &chain, h, r.dir, s.ng)
                                    : lv_emission_weight(sc, h, r.dir, s.ng, bs.pdf, 0));
        }
        if (lookup != LV_LOOKUP_NONE) {
            /* A far hit of the integrating gather: the volume has answered. */
            if (far && lookup == LV_LOOKUP_CORRECT) break;
            /* Light arriving from r.dir travels along -r.dir. */
            float3 volume = lookup_lit ? beta * lv_volume_radiance(&g->grid, lookup_point, -r.dir) : (float3)(0.0f);
            if (far) {
                if (lookup == LV_LOOKUP_READ) radiance += volume;
                break;
            }
            if (lookup == LV_LOOKUP_CORRECT) radiance -= volume;
            lookup = LV_LOOKUP_NONE;
        }
        if (h.tri == LV_NO_HIT) break;
        if (lv_inside_glass(m, &s)) beta *= exp(-LV_F3(m->attenuation) * h.t);
        if (depth == max_depth) break;

        lv_shading sh;
        if (!lv_shading_at(sc, &s, r.dir, &sh)) break;
        int rough = lv_bsdf_gathers(sh.b.type, sh.b.alpha);
        int point = rough
            ? lv_lookup_point(&g->grid, sc, sh.ng_out,
                              lv_leave_point(s.p, s.arrived, sh.ng_out, -r.dir, h.t, sc->info.scene_scale), rng,
                              &lookup_point)
            : LV_POINT_DARK;
        /* Where the volume mixes both sides of a surface the path goes on
         * as in pt, to a surface where it can be read. */
        int gather = rough && point != LV_POINT_UNTRUSTED;
        int integrate = gather && (g->flags & LV_GATHER_INTEGRATE);
        int lit_here = point == LV_POINT_LIT;
        uint see_through = rough && (g->flags & LV_GATHER_SEE_THROUGH)
            ? (gather ? LV_SEE_THROUGH_MAX : min((uint)LV_SEE_THROUGH_MAX, max_depth - depth - 1u))
            : 0u;

        if (depth + 1 <= max_depth && lv_bsdf_has_lobe(&sh.b) && !all_light)
            radiance += beta * lv_gather_direct_light(sc, &s, h, &sh, see_through, !gather, rng);
        if (integrate) {
            if (lit_here) radiance += beta * lv_gather_integrate(g, &sh, lookup_point);
            if (all_light) break; /* no threshold: the volume answers for every direction */
        }

        /* The ray a gather point sends on only settles the lookup. */
        lv_walk walk = {LV_RADIANCE, gather ? LV_ROULETTE_NONE : LV_ROULETTE_ON, (float3)(eta_scale)};
        if (!lv_scatter(sc, &s, h, &sh, walk, depth, rng, &beta, &r, &bs)) break;
        eta_scale *= bs.eta_scale;
        if (bs.delta) lv_glass_chain_step(&chain, m, &s, r.dir);
        else chain = lv_glass_chain_start(s.p, r.dir, bs.pdf, !gather && see_through && !all_light);
        if (gather) {
            if (all_light) { /* no threshold: the volume answers at once */
                if (lit_here) radiance += beta * lv_volume_radiance(&g->grid, lookup_point, -r.dir);
                break;
            }
            lookup = integrate ? LV_LOOKUP_CORRECT : LV_LOOKUP_READ;
            lookup_lit = lit_here;
        }
    }
    return lv_finite3(radiance) ? radiance : (float3)(0.0f);
}

#endif
