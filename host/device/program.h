/* The OpenCL program: built from the embedded kernel source with a few
 * feature switches, and cached on disk as a device binary keyed by device,
 * driver, options and source, so a second run does not compile again. */
#ifndef LVCL_PROGRAM_H
#define LVCL_PROGRAM_H

#include "../scene/materials.h"
#include "kernel_args.h"

/* The scene's feature switches (LVCL_FEATURE_*) are in scene/materials.h.
 * Not a scene feature: 64-bit tallies from 32-bit atomics, as devices
 * without cl_khr_int64_base_atomics build them anyway (tests use it). */
#define LVCL_BUILD_EMULATED_INT64_ATOMICS 8u

typedef struct {
    cl_program program;
    double build_seconds;
    int from_cache; /* 1 if loaded from lvcl's binary cache */
    char options[256];
} lvcl_program;

/* Builds (or loads from the cache) the program with the given features.
 * fast_math selects -cl-fast-relaxed-math. announce: say on stderr before
 * compiling from source, which takes seconds on PoCL and half a minute on
 * NVIDIA's driver, so that a first run does not seem to hang. */
lvcl_error lvcl_program_build(const lvcl_device *dev, unsigned features, int fast_math, int announce,
                              lvcl_program *prog, lvcl_status *st);

/* The -D options that turn on the kernels' code for `features`. */
void lvcl_program_feature_defines(unsigned features, char *defines, size_t size);

/* The same for another program source (the tests' and the benchmarks' kernels), with `defines`
 * appended to the options. */
lvcl_error lvcl_program_build_source(const lvcl_device *dev, const unsigned char *source, size_t size,
                                     const char *defines, int fast_math, lvcl_program *prog, lvcl_status *st);

void lvcl_program_release(lvcl_program *prog);

/* Creates a kernel of the program by name. */
lvcl_error lvcl_kernel_create(const lvcl_program *prog, const char *name, cl_kernel *kernel, lvcl_status *st);

/* Work-items per work-group: 64, fastest on PoCL and a whole number of
 * NVIDIA warps and AMD wavefronts. Kernels take a count and ignore the
 * work-items past it, so every launch pads to this. */
#define LVCL_LOCAL_SIZE 64

/* Enqueues 1-D kernel k over `count` work-items (padded; nothing if 0) on
 * dev's queue, with fewer per work-group where a driver allows k fewer.
 * On failure st says "<what> failed: ...". */
lvcl_error lvcl_kernel_enqueue(const lvcl_device *dev, cl_kernel k, size_t count, const char *what, lvcl_status *st);

#endif
