#include "program.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../util/timer.h"

/* Generated at build time from kernels/lvcl.cl (host/embed). */
extern const unsigned char lvcl_kernel_source[];
extern const size_t lvcl_kernel_source_size;

static uint64_t fnv1a(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

static void cache_path(const lvcl_device *dev, const char *options, const unsigned char *source, size_t source_size,
                       char *path, size_t size)
{
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv1a(h, dev->name, strlen(dev->name));
    h = fnv1a(h, dev->platform_name, strlen(dev->platform_name));
    h = fnv1a(h, dev->driver_version, strlen(dev->driver_version));
    h = fnv1a(h, options, strlen(options));
    h = fnv1a(h, source, source_size);
    snprintf(path, size, "%s/program-%016llx.bin", lvcl_cache_dir(), (unsigned long long)h);
}

static unsigned char *read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    unsigned char *data = NULL;
    if (fseek(f, 0, SEEK_END) == 0) {
        long n = ftell(f);
        if (n > 0 && fseek(f, 0, SEEK_SET) == 0 && (data = malloc((size_t)n)) &&
            fread(data, 1, (size_t)n, f) != (size_t)n) {
            free(data);
            data = NULL;
        }
        *size = (size_t)n;
    }
    fclose(f);
    return data;
}

/* Writes to a temporary name and renames, so readers never see half a file. */
static void write_cache(const char *path, const unsigned char *data, size_t size)
{
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.%d.tmp", path, (int)getpid());
    FILE *f = fopen(tmp, "wb");
    if (!f) return;
    int ok = fwrite(data, 1, size, f) == size;
    ok &= fclose(f) == 0;
    if (!ok || rename(tmp, path)) remove(tmp);
}

static void save_binary(cl_program program, const char *path)
{
    size_t size = 0;
    if (clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof size, &size, NULL) != CL_SUCCESS || size == 0) return;
    unsigned char *data = malloc(size);
    if (!data) return;
    unsigned char *ptrs[1] = {data};
    if (clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof ptrs, ptrs, NULL) == CL_SUCCESS)
        write_cache(path, data, size);
    free(data);
}

static lvcl_error build_log_error(const lvcl_device *dev, cl_program program, cl_int err, lvcl_status *st)
{
    char log[4096] = "";
    if (clGetProgramBuildInfo(program, dev->id, CL_PROGRAM_BUILD_LOG, sizeof log - 1, log, NULL) != CL_SUCCESS)
        log[0] = 0; /* no log to show; the error below still names the failure */
    /* The log goes to stderr in full; the error message stays one line. */
    if (log[0]) fprintf(stderr, "%s\n", log);
    return lvcl_fail(st, LVCL_ERR_DEVICE, "kernel build failed on %s: %s", dev->name, lvcl_cl_error_name(err));
}

void lvcl_program_feature_defines(unsigned features, char *defines, size_t size)
{
    snprintf(defines, size, "%s%s%s%s", features & LVCL_FEATURE_GLASS ? " -DLV_FEATURE_GLASS" : "",
             features & LVCL_FEATURE_TEXTURES ? " -DLV_FEATURE_TEXTURES" : "",
             features & LVCL_FEATURE_PUNCTUAL ? " -DLV_FEATURE_PUNCTUAL" : "",
             features & LVCL_BUILD_EMULATED_INT64_ATOMICS ? " -DLV_EMULATE_INT64_ATOMICS" : "");
}

/* CPU devices prefetch a piece's tally line when they queue its atomics
 * (kernels/volume/tally.h); not the simulator, which has no caches to
 * fill. */
static int preloads_tallies(const lvcl_device *dev)
{
    return (dev->type & CL_DEVICE_TYPE_CPU) && !lvcl_device_is_simulator(dev);
}

static lvcl_error build(const lvcl_device *dev, const unsigned char *source, size_t source_size, const char *defines,
                        int fast_math, int announce, lvcl_program *prog, lvcl_status *st);

lvcl_error lvcl_program_build(const lvcl_device *dev, unsigned features, int fast_math, int announce,
                              lvcl_program *prog, lvcl_status *st)
{
    char defines[192];
    lvcl_program_feature_defines(features, defines, sizeof defines);
    if (preloads_tallies(dev)) strncat(defines, " -DLV_PRELOAD_TALLIES", sizeof defines - strlen(defines) - 1);
    return build(dev, lvcl_kernel_source, lvcl_kernel_source_size, defines, fast_math, announce, prog, st);
}

lvcl_error lvcl_program_build_source(const lvcl_device *dev, const unsigned char *source, size_t source_size,
                                     const char *defines, int fast_math, lvcl_program *prog, lvcl_status *st)
{
    return build(dev, source, source_size, defines, fast_math, 0, prog, st);
}

static lvcl_error build(const lvcl_device *dev, const unsigned char *source, size_t source_size, const char *defines,
                        int fast_math, int announce, lvcl_program *prog, lvcl_status *st)
{
    memset(prog, 0, sizeof *prog);
    /* -w: some PoCL builds print clang's "N warnings generated." to stderr
     * on a cold cache, which broke lvcl's one-line errors. */
    snprintf(prog->options, sizeof prog->options, "-cl-std=CL1.2 -w%s%s", fast_math ? " -cl-fast-relaxed-math" : "",
             defines);
    char path[4096];
    cache_path(dev, prog->options, source, source_size, path, sizeof path);
    double start = lvcl_seconds();
    cl_int err;

    size_t size = 0;
    unsigned char *binary = read_file(path, &size);
    if (binary) {
        const unsigned char *bins[1] = {binary};
        cl_int status;
        prog->program = clCreateProgramWithBinary(dev->context, 1, &dev->id, &size, bins, &status, &err);
        free(binary);
        if (err == CL_SUCCESS && status == CL_SUCCESS &&
            clBuildProgram(prog->program, 1, &dev->id, prog->options, NULL, NULL) == CL_SUCCESS) {
            prog->from_cache = 1;
            prog->build_seconds = lvcl_seconds() - start;
            return LVCL_OK;
        }
        /* A stale or foreign binary: rebuild from source and replace it. */
        if (prog->program) clReleaseProgram(prog->program);
        prog->program = NULL;
    }

    if (announce) fprintf(stderr, "lvcl: compiling the kernels for %s (cached for later runs)\n", dev->name);
    const char *src = (const char *)source;
    prog->program = clCreateProgramWithSource(dev->context, 1, &src, &source_size, &err);
    if (err != CL_SUCCESS)
        return lvcl_fail(st, LVCL_ERR_DEVICE, "cannot create the kernel program: %s", lvcl_cl_error_name(err));
    err = clBuildProgram(prog->program, 1, &dev->id, prog->options, NULL, NULL);
    if (err != CL_SUCCESS) {
        lvcl_error e = build_log_error(dev, prog->program, err, st);
        clReleaseProgram(prog->program);
        prog->program = NULL;
        return e;
    }
    save_binary(prog->program, path);
    prog->build_seconds = lvcl_seconds() - start;
    return LVCL_OK;
}

void lvcl_program_release(lvcl_program *prog)
{
    if (prog->program) clReleaseProgram(prog->program);
    prog->program = NULL;
}

lvcl_error lvcl_kernel_create(const lvcl_program *prog, const char *name, cl_kernel *kernel, lvcl_status *st)
{
    cl_int err;
    *kernel = clCreateKernel(prog->program, name, &err);
    if (err != CL_SUCCESS)
        return lvcl_fail(st, LVCL_ERR_DEVICE, "cannot create kernel %s: %s", name, lvcl_cl_error_name(err));
    return LVCL_OK;
}

lvcl_error lvcl_kernel_enqueue(const lvcl_device *dev, cl_kernel k, size_t count, const char *what, lvcl_status *st)
{
    size_t global = (count + LVCL_LOCAL_SIZE - 1) / LVCL_LOCAL_SIZE * LVCL_LOCAL_SIZE, local = LVCL_LOCAL_SIZE;
    if (global == 0) return LVCL_OK;
    /* A GPU driver may allow a register-hungry kernel fewer work-items per
     * group; a power of two below 64 still divides the padded size. */
    size_t allowed = 0;
    if (clGetKernelWorkGroupInfo(k, dev->id, CL_KERNEL_WORK_GROUP_SIZE, sizeof allowed, &allowed, NULL) == CL_SUCCESS &&
        allowed > 0)
        while (local > allowed) local /= 2;
    return lvcl_cl_check(clEnqueueNDRangeKernel(dev->queue, k, 1, NULL, &global, &local, 0, NULL, NULL), what, st);
}
