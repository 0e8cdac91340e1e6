/* The plan of a guided render under a time limit (docs/guided.md, step 9):
 * from what the measured passes found, how many particles the guide gets
 * and whether guided or plain paths render the image. Pure functions, so
 * that they are tested without a device (tests/render/test_guide_plan.c). */
#ifndef LVCL_GUIDE_PLAN_H
#define LVCL_GUIDE_PLAN_H

#include <stdint.h>

/* The most of the time left that a plan traces for: with C0 >= 0 the
 * least error never lies further (at C0 = 0 it lies at
 * N = (left + traced tp) / (2 tp), just inside), so the scan stops there,
 * and the paths keep at least half the time. */
#define LVCL_PLAN_TRACE_SHARE_MAX 0.5
/* The most particles a plan traces. */
#define LVCL_GUIDE_PARTICLES_MAX ((uint64_t)1 << 28)
/* Standard errors a measured difference must exceed to count: the fall
 * of guided paths' cost between the two guides, and guided paths' gain
 * over plain ones. Where it does not, the guide is not traced on, and
 * plain paths render: the path tracer is what the guide has to beat. */
#define LVCL_PLAN_SIGNIFICANCE 2.0

/* What the passes measured. A cost is a kind of paths' relMSE per sample
 * times its seconds per sample (pilots measure it up to a factor every
 * kind shares), so that t seconds of it leave an image of error cost / t;
 * each comes with its standard error. */
typedef struct {
    double guide_noise;              /* C0: guided paths' cost is C0 + C1 / N over a guide of N particles */
    double guide_noise_per_particle; /* C1 */
    double guided_cost_error;        /* the standard error of guided paths' cost over the last guide measured */
    double first_cost_error;         /* and over the first, where C1 came from two (else 0) */
    double plain_cost;               /* the path tracer's paths' cost */
    double plain_cost_error;
    double seconds_per_particle; /* the trace's */
} lvcl_guide_costs;

typedef struct {
    uint64_t particles;  /* the guide's, at least those traced */
    int plain;           /* plain paths render the image */
    double guided_error; /* the error guided paths are expected to leave (cost / seconds) */
    double plain_error;  /* and plain paths */
} lvcl_guide_plan;

/* C0 and C1 of *c through guided paths' costs over a guide of `first`
 * particles (cost_first, with standard error error_first) and of
 * 2 first (cost_second, error_second): C1 = 2 first (cost_first -
 * cost_second) where that fall exceeds LVCL_PLAN_SIGNIFICANCE standard
 * errors of the difference, else 0; both kept >= 0. Sets the two errors
 * too. */
void lvcl_fit_guide_costs(double cost_first, double error_first, double cost_second, double error_second,
                          uint64_t first, lvcl_guide_costs *c);

/* With `traced` particles in the guide and `left` seconds to go: the
 * particle count N that leaves guided paths the least
 * (C0 + C1 / N) / (left - (N - traced) tp), tracing for at most
 * LVCL_PLAN_TRACE_SHARE_MAX of the time, scanned over 256 counts spaced
 * evenly in log N (a deterministic grid); plain paths unless guided paths'
 * expected error is below plain paths' plain_cost / left by more than
 * LVCL_PLAN_SIGNIFICANCE standard errors of the two costs' difference.
 * Tracing on from `traced` to N extrapolates the cost measured there by
 * the fit, C(N) = (1 + f) C(traced) - f C(traced / 2) with
 * f = 1 - traced / N, so its standard error grows to
 * sqrt((1 + f)^2 e2^2 + f^2 e1^2) (e1, e2 the two costs' errors). */
lvcl_guide_plan lvcl_plan_guide(const lvcl_guide_costs *c, uint64_t traced, double left);

#endif
