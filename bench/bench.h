/* lvcl-bench's subcommands (bench/main.c dispatches) and the helpers they
 * share: device buffers, launches and read-backs on a session's first
 * device, medians, JSON strings. */
#ifndef LVCL_BENCH_H
#define LVCL_BENCH_H

#include "../host/render/session.h"

/* lvcl-bench rays ... (bench/rays.c) and lvcl-bench wavefront ...
 * (bench/wavefront.c): argv[1] is the subcommand; return the exit status. */
int bench_rays(int argc, char **argv);
int bench_wavefront(int argc, char **argv);

/* Loads scene_name (a path or an embedded name) into *scene and opens a
 * session on `device` with fast math, as the renderer builds its kernels
 * by default, so what is measured is what lvcl renders with. */
lvcl_error bench_open(const char *scene_name, const char *device, unsigned seed, int max_depth, lvcl_scene *scene,
                      lvcl_session **s, lvcl_status *st);

/* Builds a benchmark's own program on the session's first device with the
 * scene's features and fast math, as the renderer builds its own. */
lvcl_error bench_build_program(lvcl_session *s, const unsigned char *source, size_t size, lvcl_program *prog,
                               lvcl_status *st);

/* s as a quoted JSON string (control characters dropped). */
void bench_json_string(char *out, size_t size, const char *s);

/* A read-write buffer of `bytes` on the session's first device, filled
 * from data where it is not NULL; NULL (and *st set) on failure. */
cl_mem bench_device_buffer(lvcl_session *s, size_t bytes, const void *data, lvcl_status *st);

/* Launches k over count work-items and waits for it. */
lvcl_error bench_launch(lvcl_session *s, cl_kernel k, size_t count, const char *what, lvcl_status *st);

lvcl_error bench_read_back(lvcl_session *s, cl_mem m, size_t bytes, void *out, lvcl_status *st);

/* Sorts the n timings t; returns their median. */
double bench_median(double *t, int n);

#endif
