/* One scatter step, shared by the particle trace and both camera paths:
 * the shading frame at a hit, a BSDF sample, the check against the
 * geometric normal, the throughput update, the non-finite check, Russian
 * roulette and the next ray. Where the walks differ (transport mode,
 * roulette, the adjoint shading-normal factor) lv_walk says how. */
#ifndef LV_INTEGRATOR_SCATTER_H
#define LV_INTEGRATOR_SCATTER_H

#include "../scene/surface.h"
#include "../util/rng.h"
#include "../volume/guide.h"

/* Walks longer than this many segments may end by Russian roulette. */
#define LV_RR_DEPTH 5

#define LV_ROULETTE_NONE 0 /* none: the gather path, where the light volume answers next */
/* Survival q = min(max(beta) / max(reference), 0.95). A particle's
 * reference is the weight it started with, so that bright lights'
 * particles are not culled for being bright. A camera path's is the
 * product of the 1/eta'^2 its refractions put in beta (lv_bsdf_sample's
 * eta_scale), as Mitsuba's eta^2 rule: inside glass radiance is scaled by
 * 1/eta^2 until the way out gives it back, and a q taken from the scaled
 * beta would end paths in glass for nothing and return the survivors
 * eta^2 times too bright (fireflies, docs/design.md). */
#define LV_ROULETTE_ON 1

/* How a walk scatters. */
typedef struct {
    int mode;         /* LV_RADIANCE (camera paths) or LV_IMPORTANCE (particles) */
    int roulette;     /* LV_ROULETTE_* */
    float3 reference; /* LV_ROULETTE_ON: what beta is measured against (times this scatter's eta_scale) */
} lv_walk;

/* What a walk needs to scatter at a surface it arrived at. */
typedef struct {
    lv_frame f;
    lv_bsdf b;
    float3 wo;     /* back along the arriving ray, in the shading frame */
    float3 ng_out; /* the geometric normal on the side wo leaves from */
} lv_shading;

/* Sets up sh for a ray arriving along dir; 0 if the surface does not
 * scatter light on that side. */
inline int lv_shading_at(const lv_scene *sc, const lv_surface *s, float3 dir, lv_shading *sh)
{
    if (!lv_shading_frame(sc, s, dir, &sh->f)) return 0;
    sh->b = lv_surface_bsdf(sc, s);
    sh->wo = lv_to_local(sh->f, -dir);
    sh->ng_out = dot(dir, s->ng) < 0.0f ? s->ng : -s->ng;
    return 1;
}

/* Importance carried across a surface whose shading normal is not its
 * geometric one picks up |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) (Veach 1997,
 * section 5.3): without it particles would not carry the power that the
 * shading-normal BSDF of radiance transport implies. 1 without normals. */
inline float lv_shading_normal_adjoint(const lv_surface *s, float3 wo, float3 wi)
{
    if (all(s->ns == s->ng)) return 1.0f;
    float num = fabs(dot(wo, s->ns)) * fabs(dot(wi, s->ng));
    float den = fabs(dot(wo, s->ng)) * fabs(dot(wi, s->ns));
    return den > 0.0f ? num / den : 0.0f;
}

/* The rest of a scatter step once bs holds a direction: the check
 * against the geometric normal, the throughput update, roulette (one
 * number) and the next ray. */
__attribute__((always_inline)) inline int lv_scatter_along(const lv_scene *sc, const lv_surface *s, lv_hit h,
                                                           const lv_shading *sh, lv_walk w, uint depth, lv_rng *rng,
                                                           float3 *beta, lv_ray *r, const lv_bsdf_sample *bs)
{
    float3 wi = lv_to_world(sh->f, bs->wi);
    /* Reject directions that the shading normal allows but the true
     * surface does not (reflection into it, transmission out of it). */
    int reflected = dot(wi, sh->ng_out) > 0.0f;
    if (reflected != (bs->wi.z * sh->wo.z > 0.0f)) return 0;
    if (w.mode == LV_IMPORTANCE) *beta *= bs->weight * lv_shading_normal_adjoint(s, -r->dir, wi);
    else *beta *= bs->weight;
    if (!lv_finite3(*beta) || lv_max3(*beta) <= 0.0f) return 0;
    if (w.roulette != LV_ROULETTE_NONE && depth >= LV_RR_DEPTH) {
        float q = fmin(lv_max3(*beta) / (lv_max3(w.reference) * bs->eta_scale), 0.95f);
        if (lv_rng_next(rng) >= q) return 0;
        *beta /= q;
    }
    float3 n = reflected ? sh->ng_out : -sh->ng_out;
    *r =
        lv_ray_make(lv_leave_point(s->p, s->arrived, n, -r->dir, h.t, sc->info.scene_scale), wi, LV_FAR, h.inst, h.tri);
    return 1;
}

/* Scatters the walk that arrived along r at hit h (surface s, shading sh)
 * of its segment number `depth`: on success *beta carries the BSDF weight
 * (and roulette's), *bs holds the sample and *r the next ray, leaving from
 * the side of the surface it goes to. Returns 0 where the walk ends. Draws
 * three numbers, and one more for roulette. Always inlined: each walk's
 * constant lv_walk then folds away, and out of line (fast-math) the
 * particle trace's arithmetic rounds differently from the images that
 * tests/data/golden.txt pins. */
__attribute__((always_inline)) inline int lv_scatter(const lv_scene *sc, const lv_surface *s, lv_hit h,
                                                     const lv_shading *sh, lv_walk w, uint depth, lv_rng *rng,
                                                     float3 *beta, lv_ray *r, lv_bsdf_sample *bs)
{
    float3 u = lv_rng_next3(rng);
    if (!lv_bsdf_sample_dir(&sh->b, sh->wo, u, w.mode, bs)) return 0;
    return lv_scatter_along(sc, s, h, sh, w, depth, rng, beta, r, bs);
}

/* lv_scatter with the direction drawn from the one-sample mixture of the
 * BSDF and the guide gv (at a surface with no delta lobe, where the guide
 * is set up): bs->pdf is the mixture's density, which the path's MIS
 * weights need. Draws four numbers, and one more for roulette. */
__attribute__((always_inline)) inline int lv_guided_scatter(const lv_scene *sc, const lv_surface *s, lv_hit h,
                                                            const lv_shading *sh, const lv_guide_vertex *gv, lv_walk w,
                                                            uint depth, lv_rng *rng, float3 *beta, lv_ray *r,
                                                            lv_bsdf_sample *bs)
{
    /* The direction's numbers first, in the lattice dimensions a plain
     * path's BSDF sample takes (docs/design.md, "Sampling"). */
    float3 u = lv_rng_next3(rng);
    float pick = lv_rng_next(rng);
    float bsdf_pdf, bin_pdf, light_pdf, lobe_pdf;
    float3 fcos;
    if (pick < gv->share) {
        /* From the bins, the lobe or toward the lights: the sample brings
         * its own density, the others are evaluated. */
        float3 wiw;
        if (pick < gv->bin_share) {
            if (!lv_guide_sample(gv, u, &wiw, &bin_pdf)) return 0;
            light_pdf = lv_guide_light_pdf(gv, wiw);
            lobe_pdf = lv_guide_lobe_pdf(gv, wiw);
        } else if (gv->lobe_share > 0.0f && pick >= gv->bin_share + gv->light_share) {
            wiw = lv_guide_lobe_sample(gv, u.xy);
            lobe_pdf = lv_guide_lobe_pdf(gv, wiw);
            bin_pdf = lv_guide_pdf(gv, wiw);
            light_pdf = lv_guide_light_pdf(gv, wiw);
        } else {
            if (!lv_light_directions_sample(gv->lights, &gv->odds, gv->p, u, &wiw, &light_pdf)) return 0;
            bin_pdf = lv_guide_pdf(gv, wiw);
            lobe_pdf = lv_guide_lobe_pdf(gv, wiw);
        }
        bs->wi = lv_to_local(sh->f, wiw);
        fcos = lv_bsdf_eval(&sh->b, sh->wo, bs->wi, w.mode, &bsdf_pdf);
    } else {
        /* No delta lobe here: the guide serves rough surfaces only (and
         * the mixture's density would not hold for one). */
        if (!lv_bsdf_sample_dir(&sh->b, sh->wo, u, w.mode, bs) || bs->delta) return 0;
        bsdf_pdf = bs->pdf;
        fcos = bs->weight * bs->pdf;
        float3 wiw = lv_to_world(sh->f, bs->wi);
        bin_pdf = lv_guide_pdf(gv, wiw);
        light_pdf = lv_guide_light_pdf(gv, wiw);
        lobe_pdf = lv_guide_lobe_pdf(gv, wiw);
    }
    float pdf = lv_guide_mix(gv, bsdf_pdf, bin_pdf, light_pdf, lobe_pdf);
    if (!(pdf > 0.0f) || lv_max3(fcos) <= 0.0f) return 0;
    lv_bsdf_sample_lobe(bs->wi, fcos, pdf, bs);
    return lv_scatter_along(sc, s, h, sh, w, depth, rng, beta, r, bs);
}

#endif
