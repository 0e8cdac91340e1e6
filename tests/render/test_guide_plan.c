/* The plan of a time-limited guided render (host/render/guide_plan.c):
 * over costs C0 + C1 / N it picks the particle count whose expected error
 * (C0 + C1 / N) / (left - (N - traced) tp) is least, to within its grid,
 * as the closed form says; traces nothing more where the guide does not
 * improve; traces for at most half the time left; and picks guided paths
 * exactly where their expected error is below plain paths' by more than
 * twice the costs' standard error. The fit takes C1 only from a fall of
 * the cost beyond twice its standard error. Swept over costs, trace
 * speeds, budgets and counts already traced. */
#include <math.h>

#include "../../host/render/guide_plan.h"
#include "../check.h"

/* The expected error of guided paths over N particles. */
static double error_at(const lvcl_guide_costs *c, double traced, double left, double n)
{
    return (c->guide_noise + c->guide_noise_per_particle / n) / (left - (n - traced) * c->seconds_per_particle);
}

/* The least of error_at over N >= traced, without the cap: where its
 * derivative vanishes, C0 tp N^2 + 2 C1 tp N - C1 T = 0 with
 * T = left + traced tp (for C0 = 0, N = T / (2 tp)). */
static double optimum(const lvcl_guide_costs *c, double traced, double left)
{
    double tp = c->seconds_per_particle, c0 = c->guide_noise, c1 = c->guide_noise_per_particle, t = left + traced * tp;
    double n = c0 > 0 ? (-c1 * tp + sqrt(c1 * c1 * tp * tp + c0 * c1 * tp * t)) / (c0 * tp) : t / (2 * tp);
    return n > traced ? n : traced;
}

int main(void)
{
    const double c0s[] = {0.0, 1e-3, 0.02}, c1s[] = {10.0, 300.0, 1e4, 1e6}, tps[] = {1e-6, 5e-6};
    const double lefts[] = {2.0, 30.0, 600.0}, traceds[] = {131072.0, 262144.0, 1e6};
    int cases = 0, off_grid = 0, over_share = 0, below = 0, worse = 0;
    double worst_ratio = 1;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 4; b++)
            for (int p = 0; p < 2; p++)
                for (int l = 0; l < 3; l++)
                    for (int t = 0; t < 3; t++) {
                        lvcl_guide_costs c = {.guide_noise = c0s[a],
                                              .guide_noise_per_particle = c1s[b],
                                              .plain_cost = 1e30, /* guided paths */
                                              .seconds_per_particle = tps[p]};
                        double traced = traceds[t], left = lefts[l];
                        lvcl_guide_plan plan = lvcl_plan_guide(&c, (uint64_t)traced, left);
                        double cap = traced + LVCL_PLAN_TRACE_SHARE_MAX * left / c.seconds_per_particle;
                        if (cap > (double)LVCL_GUIDE_PARTICLES_MAX) cap = (double)LVCL_GUIDE_PARTICLES_MAX;
                        double want = fmin(optimum(&c, traced, left), cap);
                        double n = (double)plan.particles;
                        /* One step of the grid: 256 counts evenly in log N over [traced, cap]. */
                        double step = pow(cap / traced, 1.0 / 255.0);
                        cases++;
                        if (n < traced) below++;
                        if (n > cap * (1 + 1e-9)) over_share++;
                        if (n < want / step / (1 + 1e-9) || n > want * step * (1 + 1e-9)) off_grid++;
                        double ratio = plan.guided_error / error_at(&c, traced, left, want);
                        if (ratio > worst_ratio) worst_ratio = ratio;
                        if (ratio > 1.001 ||
                            fabs(plan.guided_error - error_at(&c, traced, left, fmax(n, traced))) >
                                1e-6 * plan.guided_error)
                            worse++;
                    }
    CHECK("guide plan: the count is the closed form's optimum within a step of the grid", off_grid == 0,
          "%d of %d cases off", off_grid, cases);
    CHECK("guide plan: its expected error is within 0.1% of the least, and is that of its count", worse == 0,
          "%d of %d cases; worst ratio %.6f", worse, cases, worst_ratio);
    CHECK("guide plan: never fewer particles than traced, never tracing for more than half the time left",
          below == 0 && over_share == 0, "%d below, %d over of %d", below, over_share, cases);

    /* A guide that did not improve between the passes traces no more. */
    lvcl_guide_costs flat = {.guide_noise = 0.01, .plain_cost = 0.02, .seconds_per_particle = 2e-6};
    lvcl_guide_plan p = lvcl_plan_guide(&flat, 262144, 30.0);
    CHECK("guide plan: C1 = 0 traces no more and expects C0 / left",
          p.particles == 262144 && fabs(p.guided_error - 0.01 / 30.0) < 1e-15 && !p.plain,
          "%llu particles, error %g, plain %d", (unsigned long long)p.particles, p.guided_error, p.plain);

    /* Guided paths exactly where their expected error is below plain
     * paths' by more than twice its standard error: plain costs either
     * side of that line, without errors, with errors, and with the error
     * of the cost the plan extrapolated from (the line computed here from
     * the header's formula). */
    int right = 1;
    lvcl_guide_plan g = {0};
    const double errors[3][3] = {{0, 0, 0}, {0.0006, 0, 0.0008}, {0.0006, 0.0005, 0.0008}};
    for (int v = 0; v < 3; v++) {
        lvcl_guide_costs c = {.guide_noise = 0.01, .guide_noise_per_particle = 2000.0, .seconds_per_particle = 3e-6};
        c.guided_cost_error = errors[v][0], c.first_cost_error = errors[v][1], c.plain_cost_error = errors[v][2];
        c.plain_cost = 1e30;
        g = lvcl_plan_guide(&c, 262144, 30.0);
        double f = 1.0 - 262144.0 / (double)g.particles, paths = 30.0 - ((double)g.particles - 262144.0) * 3e-6;
        double eg = sqrt(pow((1 + f) * errors[v][0], 2) + pow(f * errors[v][1], 2)) / paths, ep = errors[v][2] / 30.0;
        double line = 30.0 * (g.guided_error + LVCL_PLAN_SIGNIFICANCE * sqrt(eg * eg + ep * ep));
        for (int k = -3; k <= 3; k++) {
            if (k == 0) continue; /* on the line: either, by rounding */
            c.plain_cost = line * (1.0 + 0.01 * k);
            lvcl_guide_plan q = lvcl_plan_guide(&c, 262144, 30.0);
            right &= q.plain == (k < 0) && fabs(q.plain_error - c.plain_cost / 30.0) < 1e-15 &&
                q.particles == (k < 0 ? 262144 : g.particles);
        }
    }
    CHECK("guide plan: guided paths exactly where they win by more than twice the standard error",
          right && g.particles > 262144, "guided error %g over %llu particles", g.guided_error,
          (unsigned long long)g.particles);

    /* An extrapolated gain beyond the errors of the costs measured at the
     * last guide and of plain paths, but within the extrapolation's own,
     * picks plain paths: guided 0.28 +- 0.025 over 2^17 particles after
     * 0.37 +- 0.025 over 2^16 (a significant fall: C1 > 0, the plan traces
     * on to about 7.8 x 10^5), plain 0.314 +- 0.026 (costs of the size
     * measured on the Cornell spheres). */
    lvcl_guide_costs spheres = {.plain_cost = 0.314, .plain_cost_error = 0.026, .seconds_per_particle = 2.5e-6};
    lvcl_fit_guide_costs(0.37, 0.025, 0.280, 0.025, 65536, &spheres);
    lvcl_guide_plan sp = lvcl_plan_guide(&spheres, 131072, 28.0);
    spheres.plain_cost = 1e30;
    lvcl_guide_plan sp_guided = lvcl_plan_guide(&spheres, 131072, 28.0);
    CHECK("guide plan: a gain within the extrapolation's error picks plain paths",
          spheres.guide_noise_per_particle > 0 && sp.plain && sp_guided.particles > 700000 &&
              sp_guided.guided_error < sp.plain_error,
          "C1 %g, plain %d, guided error %g over %llu particles, plain error %g", spheres.guide_noise_per_particle,
          sp.plain, sp_guided.guided_error, (unsigned long long)sp_guided.particles, sp.plain_error);

    /* Measuring took the whole budget: nothing more is traced, and the
     * choice still follows the costs. */
    lvcl_guide_costs late = {
        .guide_noise = 0.01, .guide_noise_per_particle = 5000.0, .plain_cost = 0.02, .seconds_per_particle = 3e-6};
    lvcl_guide_plan z = lvcl_plan_guide(&late, 262144, -1.0);
    late.plain_cost = 0.04;
    lvcl_guide_plan z2 = lvcl_plan_guide(&late, 262144, 0.0);
    CHECK("guide plan: with no time left it traces nothing and still picks the cheaper paths",
          z.particles == 262144 && z.plain && z2.particles == 262144 && !z2.plain, "%llu %d, %llu %d",
          (unsigned long long)z.particles, z.plain, (unsigned long long)z2.particles, z2.plain);

    /* The fit: a fall beyond twice the difference's standard error gives
     * C1 = 2 first (fall) and C0 the rest; a fall within it, or a rise,
     * gives C1 = 0 and C0 the second cost; C0 stays >= 0. */
    lvcl_guide_costs f = {0};
    int fits = 1;
    lvcl_fit_guide_costs(0.012, 0.0003, 0.010, 0.0004, 131072, &f); /* fall 0.002 > 2 x 0.0005 */
    fits &= fabs(f.guide_noise_per_particle - 262144 * 0.002) < 1e-6 && fabs(f.guide_noise - 0.008) < 1e-12 &&
        f.guided_cost_error == 0.0004;
    lvcl_fit_guide_costs(0.0109, 0.0003, 0.010, 0.0004, 131072, &f); /* fall 0.0009 < 0.001 */
    fits &= f.guide_noise_per_particle == 0 && f.guide_noise == 0.010;
    lvcl_fit_guide_costs(0.009, 0.0003, 0.010, 0.0004, 131072, &f); /* a rise */
    fits &= f.guide_noise_per_particle == 0 && f.guide_noise == 0.010;
    lvcl_fit_guide_costs(0.05, 0.0001, 0.010, 0.0001, 131072, &f); /* a fall past the second cost: C0 = 0 */
    fits &= fabs(f.guide_noise_per_particle - 262144 * 0.010) < 1e-6 && fabs(f.guide_noise) < 1e-15;
    CHECK("guide plan: the fit takes C1 from a fall beyond twice its standard error, C0 and C1 >= 0", fits,
          "C0 %g, C1 %g", f.guide_noise, f.guide_noise_per_particle);
    CHECK_EXIT();
}
