/* OpenCL devices: enumeration across platforms, choice by the --device
 * argument, and a context and in-order queue on the chosen one. */
#ifndef LVCL_DEVICE_H
#define LVCL_DEVICE_H

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>
#include <stdint.h>
#include <stdio.h>

#include "../util/status.h"

typedef struct {
    cl_platform_id platform;
    cl_device_id id;
    cl_context context;
    cl_command_queue queue;
    int index; /* position in the --list-devices order */
    char name[256];
    char platform_name[256];
    char driver_version[128];
    cl_device_type type;
    cl_ulong global_mem;
    cl_ulong max_alloc;
    cl_uint compute_units;
} lvcl_device;

/* Points the OpenCL drivers' own caches (PoCL's kernel cache) into lvcl's
 * cache directory, and the ICD loader at the build's opencl-vendors folder
 * (the machine's implementations and those the project adds) when there
 * is one and OCL_ICD_VENDORS is unset. Call before any other OpenCL call. */
void lvcl_device_prepare_environment(void);

/* The directory for cached program binaries: $LVCL_CACHE_DIR, or cache/
 * beside the executable. Created on first use. */
const char *lvcl_cache_dir(void);

/* 1 if dev is the Oclgrind simulator (a strict checker, not a device to
 * render on). */
int lvcl_device_is_simulator(const lvcl_device *dev);

/* Prints one line per device: index, type, name, platform. */
lvcl_error lvcl_device_list(FILE *out, lvcl_status *st);

/* Number of devices over all platforms (0 if there is no OpenCL at all);
 * simulators, numbered last, count only if `simulators` is set. */
int lvcl_device_count(int simulators);

/* Opens the device that `spec` names: "cpu", "gpu", a list index, or NULL
 * for the default (first GPU, else first CPU, else the first device). A
 * simulator is opened only by its index. */
lvcl_error lvcl_device_open(const char *spec, lvcl_device *dev, lvcl_status *st);

/* Makes dev act as a device of `bytes` bytes (--device-memory): no more
 * memory than that, and a quarter of it in one buffer, as OpenCL promises
 * and GPUs often allow no more. */
void lvcl_device_limit_memory(lvcl_device *dev, uint64_t bytes);

void lvcl_device_close(lvcl_device *dev);

/* A short name for an OpenCL error code, for messages. */
const char *lvcl_cl_error_name(cl_int err);

/* clCreateBuffer on dev. A CPU device's memory is the host's, and PoCL
 * aborts (an assertion) when it cannot allocate a buffer's memory on
 * first use, so there a host allocation of the same size is tried first:
 * if it fails, *err is CL_OUT_OF_HOST_MEMORY and no buffer is made. There
 * a buffer of 4 MiB or more lives in host memory lvcl allocates for it, in
 * huge pages where the system allows (CL_MEM_USE_HOST_PTR; freed when the
 * buffer is released). */
cl_mem lvcl_buffer_create(const lvcl_device *dev, cl_mem_flags flags, size_t bytes, void *host, cl_int *err);

/* The one check of OpenCL results: LVCL_OK if err is CL_SUCCESS; else
 * records "<what> failed: <error>" in st (LVCL_ERR_OUT_OF_MEMORY when the
 * host ran out, LVCL_ERR_TOO_LARGE for a buffer the device cannot hold,
 * else LVCL_ERR_DEVICE). */
lvcl_error lvcl_cl_check(cl_int err, const char *what, lvcl_status *st);

#endif
