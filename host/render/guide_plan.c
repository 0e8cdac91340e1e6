#include "guide_plan.h"

#include <math.h>

void lvcl_fit_guide_costs(double cost_first, double error_first, double cost_second, double error_second,
                          uint64_t first, lvcl_guide_costs *c)
{
    double fall = cost_first - cost_second, n2 = 2.0 * (double)first;
    int counts = fall > LVCL_PLAN_SIGNIFICANCE * sqrt(error_first * error_first + error_second * error_second);
    c->guide_noise_per_particle = counts ? fmin(n2 * fall, n2 * cost_second) : 0;
    c->guide_noise = cost_second - c->guide_noise_per_particle / n2;
    c->guided_cost_error = error_second;
    c->first_cost_error = error_first;
}

lvcl_guide_plan lvcl_plan_guide(const lvcl_guide_costs *c, uint64_t traced, double left)
{
    if (!(left > 1e-3)) left = 1e-3; /* the paths take at least one sample, however late */
    double lo = traced > 0 ? (double)traced : 1.0, tp = c->seconds_per_particle;
    double best = lo, error = (c->guide_noise + c->guide_noise_per_particle / lo) / left;
    double most = tp > 0 ? lo + LVCL_PLAN_TRACE_SHARE_MAX * left / tp : lo;
    if (most > (double)LVCL_GUIDE_PARTICLES_MAX) most = (double)LVCL_GUIDE_PARTICLES_MAX;
    for (int i = 1; most > lo && c->guide_noise_per_particle > 0 && i <= 255; i++) {
        double n = lo * pow(most / lo, i / 255.0);
        double e = (c->guide_noise + c->guide_noise_per_particle / n) / (left - (n - lo) * tp);
        if (e < error) error = e, best = n;
    }
    uint64_t particles = best > (double)traced ? (uint64_t)best : traced;
    /* The two errors' standard errors, in error (cost per second of paths). */
    double f = 1.0 - lo / (double)particles, paths = left - ((double)particles - lo) * tp;
    double e2 = (1.0 + f) * c->guided_cost_error, e1 = f * c->first_cost_error;
    double guided = sqrt(e2 * e2 + e1 * e1) / paths, plain = c->plain_cost_error / left;
    lvcl_guide_plan p = {.particles = particles, .guided_error = error, .plain_error = c->plain_cost / left};
    p.plain = !(p.guided_error < p.plain_error - LVCL_PLAN_SIGNIFICANCE * sqrt(guided * guided + plain * plain));
    if (p.plain) p.particles = traced;
    return p;
}
