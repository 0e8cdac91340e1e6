/* The helpers lvcl-bench's subcommands share (bench/bench.h). */
#include <stdio.h>
#include <stdlib.h>

#include "bench.h"

lvcl_error bench_open(const char *scene_name, const char *device, unsigned seed, int max_depth, lvcl_scene *scene,
                      lvcl_session **s, lvcl_status *st)
{
    lvcl_device_prepare_environment();
    lvcl_session_config cfg = {.device = device, .seed = seed, .max_depth = max_depth, .fast_math = 1};
    lvcl_error e = lvcl_scene_load(scene_name, scene, st);
    return e ? e : lvcl_session_open(scene, &cfg, s, st);
}

lvcl_error bench_build_program(lvcl_session *s, const unsigned char *source, size_t size, lvcl_program *prog,
                               lvcl_status *st)
{
    char defines[160];
    lvcl_program_feature_defines(lvcl_session_features(s), defines, sizeof defines);
    return lvcl_program_build_source(lvcl_session_device(s, 0), source, size, defines, 1, prog, st);
}

void bench_json_string(char *out, size_t size, const char *s)
{
    size_t n = 0;
    out[n++] = '"';
    for (; *s && n + 3 < size; s++) {
        if ((unsigned char)*s < 0x20) continue;
        if (*s == '"' || *s == '\\') out[n++] = '\\';
        out[n++] = *s;
    }
    out[n++] = '"';
    out[n] = '\0';
}

cl_mem bench_device_buffer(lvcl_session *s, size_t bytes, const void *data, lvcl_status *st)
{
    cl_int err;
    cl_mem m = clCreateBuffer(lvcl_session_device(s, 0)->context, CL_MEM_READ_WRITE | (data ? CL_MEM_COPY_HOST_PTR : 0),
                              bytes ? bytes : 16, (void *)data, &err);
    char what[64];
    snprintf(what, sizeof what, "allocating %.1f MiB", bytes / 1048576.0);
    if (lvcl_cl_check(err, what, st)) return NULL;
    return m;
}

lvcl_error bench_launch(lvcl_session *s, cl_kernel k, size_t count, const char *what, lvcl_status *st)
{
    lvcl_error e = lvcl_kernel_enqueue(lvcl_session_device(s, 0), k, count, what, st);
    return e ? e : lvcl_cl_check(clFinish(lvcl_session_device(s, 0)->queue), what, st);
}

lvcl_error bench_read_back(lvcl_session *s, cl_mem m, size_t bytes, void *out, lvcl_status *st)
{
    return lvcl_cl_check(
        clEnqueueReadBuffer(lvcl_session_device(s, 0)->queue, m, CL_TRUE, 0, bytes, out, 0, NULL, NULL), "reading back",
        st);
}

static int compare_seconds(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double bench_median(double *t, int n)
{
    qsort(t, (size_t)n, sizeof *t, compare_seconds);
    return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}
