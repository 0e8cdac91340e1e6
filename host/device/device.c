/* madvise and MADV_HUGEPAGE (huge_page_buffer) are beyond POSIX. */
#define _DEFAULT_SOURCE

#include "device.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#define MAX_DEVICES 64

typedef struct {
    cl_platform_id platform;
    cl_device_id device;
    int rank; /* platform_rank */
} device_ref;

/* The implementations the project adds to check its kernels against
 * (Makefile: opencl-vendors) are numbered after the machine's own, so that
 * device 0 and the default stay what they were without them: Intel's CPU
 * runtime, then the Oclgrind simulator, which is never chosen by default
 * or by --device all (it checks every access, at a thousandth of the speed). */
enum { RANK_OWN, RANK_ADDED_CPU, RANK_SIMULATOR };
static int is_simulator_platform(const char *platform_name)
{
    return strstr(platform_name, "Oclgrind") != NULL;
}

static int platform_rank(cl_platform_id p)
{
    char name[256] = {0};
    if (clGetPlatformInfo(p, CL_PLATFORM_NAME, sizeof name - 1, name, NULL) != CL_SUCCESS) return RANK_OWN;
    if (is_simulator_platform(name)) return RANK_SIMULATOR;
    return strcmp(name, "Intel(R) OpenCL") ? RANK_OWN : RANK_ADDED_CPU;
}

int lvcl_device_is_simulator(const lvcl_device *dev)
{
    return is_simulator_platform(dev->platform_name);
}

static int make_dirs(const char *path)
{
    char buf[PATH_MAX];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/') continue;
        *p = 0;
        if (mkdir(buf, 0755) && errno != EEXIST) return -1;
        *p = '/';
    }
    return mkdir(buf, 0755) && errno != EEXIST ? -1 : 0;
}

const char *lvcl_cache_dir(void)
{
    static char dir[PATH_MAX];
    if (dir[0]) return dir;
    const char *env = getenv("LVCL_CACHE_DIR");
    if (env && *env) {
        snprintf(dir, sizeof dir, "%s", env);
    } else {
        char exe[PATH_MAX];
        ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
        if (n <= 0) {
            snprintf(dir, sizeof dir, "lvcl-cache");
        } else {
            exe[n] = 0;
            char *slash = strrchr(exe, '/');
            if (slash) *slash = 0;
            snprintf(dir, sizeof dir, "%s/cache", exe);
        }
    }
    if (make_dirs(dir)) lvcl_warn("cannot create cache directory %s: %s", dir, strerror(errno));
    return dir;
}

/* The build's ICD directory (Makefile: opencl-vendors) beside the
 * executable or up to two folders above it (tests/, asan/tests/), if any. */
static int find_vendors_dir(char *dir, size_t size)
{
    char exe[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0) return 0;
    exe[n] = 0;
    for (int up = 0; up < 3; up++) {
        char *slash = strrchr(exe, '/');
        if (!slash) return 0;
        *slash = 0;
        struct stat sb;
        snprintf(dir, size, "%s/opencl-vendors", exe);
        if (stat(dir, &sb) == 0 && S_ISDIR(sb.st_mode)) return 1;
    }
    return 0;
}

void lvcl_device_prepare_environment(void)
{
    char pocl[PATH_MAX];
    snprintf(pocl, sizeof pocl, "%s/pocl", lvcl_cache_dir());
    make_dirs(pocl);
    setenv("POCL_CACHE_DIR", pocl, 0);
    char vendors[PATH_MAX];
    if (!getenv("OCL_ICD_VENDORS") && find_vendors_dir(vendors, sizeof vendors)) setenv("OCL_ICD_VENDORS", vendors, 0);
}

/* All devices of all platforms, in a fixed order: the loader's, with the
 * added implementations after (platform_rank). */
static int enumerate(device_ref *refs, int max)
{
    cl_uint np = 0;
    cl_platform_id platforms[16];
    if (clGetPlatformIDs(16, platforms, &np) != CL_SUCCESS) return 0;
    int count = 0, ranks[16];
    for (cl_uint p = 0; p < np && p < 16; p++) ranks[p] = platform_rank(platforms[p]);
    for (int rank = RANK_OWN; rank <= RANK_SIMULATOR; rank++)
        for (cl_uint p = 0; p < np && p < 16; p++) {
            cl_uint nd = 0;
            cl_device_id ids[MAX_DEVICES];
            if (ranks[p] != rank ||
                clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, MAX_DEVICES, ids, &nd) != CL_SUCCESS)
                continue;
            for (cl_uint d = 0; d < nd && d < MAX_DEVICES && count < max; d++)
                refs[count++] = (device_ref){platforms[p], ids[d], rank};
        }
    return count;
}

int lvcl_device_count(int simulators)
{
    device_ref refs[MAX_DEVICES];
    int n = enumerate(refs, MAX_DEVICES);
    while (!simulators && n > 0 && refs[n - 1].rank == RANK_SIMULATOR) n--;
    return n;
}

static lvcl_error describe(device_ref r, int index, lvcl_device *dev, lvcl_status *st)
{
    memset(dev, 0, sizeof *dev);
    dev->platform = r.platform;
    dev->id = r.device;
    dev->index = index;
    lvcl_error e = lvcl_cl_check(clGetDeviceInfo(r.device, CL_DEVICE_NAME, sizeof dev->name - 1, dev->name, NULL),
                                 "asking a device's name", st);
    if (!e)
        e = lvcl_cl_check(
            clGetDeviceInfo(r.device, CL_DRIVER_VERSION, sizeof dev->driver_version - 1, dev->driver_version, NULL),
            "asking a device's driver version", st);
    if (!e)
        e = lvcl_cl_check(
            clGetPlatformInfo(r.platform, CL_PLATFORM_NAME, sizeof dev->platform_name - 1, dev->platform_name, NULL),
            "asking a platform's name", st);
    if (!e)
        e = lvcl_cl_check(clGetDeviceInfo(r.device, CL_DEVICE_TYPE, sizeof dev->type, &dev->type, NULL),
                          "asking a device's type", st);
    if (!e)
        e = lvcl_cl_check(
            clGetDeviceInfo(r.device, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof dev->global_mem, &dev->global_mem, NULL),
            "asking a device's memory", st);
    if (!e)
        e = lvcl_cl_check(
            clGetDeviceInfo(r.device, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof dev->max_alloc, &dev->max_alloc, NULL),
            "asking a device's largest allocation", st);
    if (!e)
        e = lvcl_cl_check(clGetDeviceInfo(r.device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof dev->compute_units,
                                          &dev->compute_units, NULL),
                          "asking a device's compute units", st);
    return e;
}

static const char *type_name(cl_device_type t)
{
    if (t & CL_DEVICE_TYPE_GPU) return "gpu";
    if (t & CL_DEVICE_TYPE_CPU) return "cpu";
    if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
    return "other";
}

lvcl_error lvcl_device_list(FILE *out, lvcl_status *st)
{
    device_ref refs[MAX_DEVICES];
    int n = enumerate(refs, MAX_DEVICES);
    if (n == 0)
        return lvcl_fail(st, LVCL_ERR_DEVICE, "no OpenCL device found (is an ICD such as pocl-opencl-icd installed?)");
    for (int i = 0; i < n; i++) {
        lvcl_device d;
        lvcl_error e = describe(refs[i], i, &d, st);
        if (e) return e;
        fprintf(out, "%d  %-4s  %s  [%s, %u compute units, %.1f GiB]%s\n", i, type_name(d.type), d.name,
                d.platform_name, d.compute_units, (double)d.global_mem / (1u << 30),
                refs[i].rank == RANK_SIMULATOR ? "  (simulator: only by index)" : "");
    }
    return LVCL_OK;
}

lvcl_error lvcl_device_open(const char *spec, lvcl_device *dev, lvcl_status *st)
{
    device_ref refs[MAX_DEVICES];
    int n = enumerate(refs, MAX_DEVICES);
    if (n == 0)
        return lvcl_fail(st, LVCL_ERR_DEVICE, "no OpenCL device found (is an ICD such as pocl-opencl-icd installed?)");

    int chosen = -1;
    if (spec == NULL || !strcmp(spec, "gpu") || !strcmp(spec, "cpu")) {
        cl_device_type want = (spec && !strcmp(spec, "cpu")) ? CL_DEVICE_TYPE_CPU : CL_DEVICE_TYPE_GPU;
        for (int i = 0; i < n && chosen < 0; i++) {
            cl_device_type t = 0;
            lvcl_error e = lvcl_cl_check(clGetDeviceInfo(refs[i].device, CL_DEVICE_TYPE, sizeof t, &t, NULL),
                                         "asking a device's type", st);
            if (e) return e;
            if ((t & want) && refs[i].rank != RANK_SIMULATOR) chosen = i;
        }
        if (chosen < 0 && spec)
            return lvcl_fail(st, LVCL_ERR_DEVICE, "no OpenCL %s device found (see --list-devices)", spec);
        if (chosen < 0) chosen = 0;
    } else {
        char *end;
        long v = strtol(spec, &end, 10);
        if (*spec == 0 || *end != 0 || v < 0)
            return lvcl_fail(st, LVCL_ERR_USAGE,
                             "unknown device '%s' (expected cpu, gpu or an index from --list-devices)", spec);
        if (v >= n)
            return lvcl_fail(st, LVCL_ERR_DEVICE,
                             "device %ld does not exist: there are %d OpenCL devices (see --list-devices)", v, n);
        chosen = (int)v;
    }

    lvcl_error e = describe(refs[chosen], chosen, dev, st);
    if (e) return e;
    cl_int err;
    cl_context_properties props[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)dev->platform, 0};
    dev->context = clCreateContext(props, 1, &dev->id, NULL, NULL, &err);
    if (err != CL_SUCCESS)
        return lvcl_fail(st, LVCL_ERR_DEVICE, "cannot create an OpenCL context on %s: %s", dev->name,
                         lvcl_cl_error_name(err));
    dev->queue = clCreateCommandQueue(dev->context, dev->id, 0, &err);
    if (err != CL_SUCCESS) {
        clReleaseContext(dev->context);
        return lvcl_fail(st, LVCL_ERR_DEVICE, "cannot create an OpenCL queue on %s: %s", dev->name,
                         lvcl_cl_error_name(err));
    }
    return LVCL_OK;
}

void lvcl_device_limit_memory(lvcl_device *dev, uint64_t bytes)
{
    if (dev->global_mem > bytes) dev->global_mem = bytes;
    if (dev->max_alloc > bytes / 4) dev->max_alloc = bytes / 4;
}

void lvcl_device_close(lvcl_device *dev)
{
    if (dev->queue) clReleaseCommandQueue(dev->queue);
    if (dev->context) clReleaseContext(dev->context);
    memset(dev, 0, sizeof *dev);
}

lvcl_error lvcl_cl_check(cl_int err, const char *what, lvcl_status *st)
{
    if (err == CL_SUCCESS) return LVCL_OK;
    if (err == CL_OUT_OF_HOST_MEMORY)
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "%s failed: out of host memory (CL_OUT_OF_HOST_MEMORY)", what);
    lvcl_error code =
        err == CL_MEM_OBJECT_ALLOCATION_FAILURE || err == CL_OUT_OF_RESOURCES || err == CL_INVALID_BUFFER_SIZE
        ? LVCL_ERR_TOO_LARGE
        : LVCL_ERR_DEVICE;
    return lvcl_fail(st, code, "%s failed: %s", what, lvcl_cl_error_name(err));
}

/* Buffers from this size up live, on a CPU device, in memory lvcl
 * allocates on 2 MiB boundaries and asks the kernel to back with huge
 * pages: the light volume's tallies and a large scene's BVH are read and
 * added to at random, and with 4 KiB pages nearly every such access also
 * missed the TLB (the particle trace 4-6% faster on the kitchen's 89 MB
 * volume; docs/performance.md, "Huge pages"). */
#define HUGE_PAGE_BYTES ((size_t)2 << 20)
#define HUGE_BUFFER_BYTES ((size_t)4 << 20)

#ifdef MADV_HUGEPAGE
static void CL_CALLBACK free_host_memory(cl_mem buffer, void *memory)
{
    (void)buffer;
    free(memory);
}
#endif

/* The buffer over host memory of its own, or NULL with *err CL_SUCCESS
 * where huge pages do not apply (then the caller creates it as usual). */
static cl_mem huge_page_buffer(const lvcl_device *dev, cl_mem_flags flags, size_t bytes, void *host, cl_int *err)
{
    *err = CL_SUCCESS;
#ifdef MADV_HUGEPAGE
    if (!(dev->type & CL_DEVICE_TYPE_CPU) || lvcl_device_is_simulator(dev) || bytes < HUGE_BUFFER_BYTES ||
        (flags & (CL_MEM_USE_HOST_PTR | CL_MEM_ALLOC_HOST_PTR)))
        return NULL;
    size_t rounded = (bytes + HUGE_PAGE_BYTES - 1) / HUGE_PAGE_BYTES * HUGE_PAGE_BYTES;
    void *memory = NULL;
    if (posix_memalign(&memory, HUGE_PAGE_BYTES, rounded)) {
        *err = CL_OUT_OF_HOST_MEMORY;
        return NULL;
    }
    madvise(memory, rounded, MADV_HUGEPAGE); /* a hint: without it the buffer works as well */
    if (flags & CL_MEM_COPY_HOST_PTR) memcpy(memory, host, bytes);
    cl_mem buffer = clCreateBuffer(dev->context, (flags & ~(cl_mem_flags)CL_MEM_COPY_HOST_PTR) | CL_MEM_USE_HOST_PTR,
                                   bytes, memory, err);
    if (buffer && clSetMemObjectDestructorCallback(buffer, free_host_memory, memory) != CL_SUCCESS) {
        clReleaseMemObject(buffer);
        buffer = NULL;
    }
    if (!buffer) {
        free(memory);
        *err = CL_SUCCESS; /* as usual, then */
    }
    return buffer;
#else
    (void)dev, (void)flags, (void)bytes, (void)host;
    return NULL;
#endif
}

cl_mem lvcl_buffer_create(const lvcl_device *dev, cl_mem_flags flags, size_t bytes, void *host, cl_int *err)
{
    cl_mem buffer = huge_page_buffer(dev, flags, bytes, host, err);
    if (buffer || *err != CL_SUCCESS) return buffer;
    if (dev->type & CL_DEVICE_TYPE_CPU) {
        void *probe = malloc(bytes ? bytes : 1);
        if (!probe) {
            *err = CL_OUT_OF_HOST_MEMORY;
            return NULL;
        }
        free(probe);
    }
    return clCreateBuffer(dev->context, flags, bytes, host, err);
}

const char *lvcl_cl_error_name(cl_int err)
{
    switch (err) {
    case CL_DEVICE_NOT_FOUND:
        return "CL_DEVICE_NOT_FOUND";
    case CL_DEVICE_NOT_AVAILABLE:
        return "CL_DEVICE_NOT_AVAILABLE";
    case CL_COMPILER_NOT_AVAILABLE:
        return "CL_COMPILER_NOT_AVAILABLE";
    case CL_MEM_OBJECT_ALLOCATION_FAILURE:
        return "CL_MEM_OBJECT_ALLOCATION_FAILURE";
    case CL_OUT_OF_RESOURCES:
        return "CL_OUT_OF_RESOURCES";
    case CL_OUT_OF_HOST_MEMORY:
        return "CL_OUT_OF_HOST_MEMORY";
    case CL_BUILD_PROGRAM_FAILURE:
        return "CL_BUILD_PROGRAM_FAILURE";
    case CL_INVALID_VALUE:
        return "CL_INVALID_VALUE";
    case CL_INVALID_BINARY:
        return "CL_INVALID_BINARY";
    case CL_INVALID_BUILD_OPTIONS:
        return "CL_INVALID_BUILD_OPTIONS";
    case CL_INVALID_KERNEL_ARGS:
        return "CL_INVALID_KERNEL_ARGS";
    case CL_INVALID_ARG_SIZE:
        return "CL_INVALID_ARG_SIZE";
    case CL_INVALID_WORK_GROUP_SIZE:
        return "CL_INVALID_WORK_GROUP_SIZE";
    case CL_INVALID_BUFFER_SIZE:
        return "CL_INVALID_BUFFER_SIZE";
    default: {
        static char buf[32];
        snprintf(buf, sizeof buf, "OpenCL error %d", err);
        return buf;
    }
    }
}
