#include "image_pass.h"

#include <stdlib.h>
#include <string.h>

#include "progress.h"
#include "timer.h"

/* PoCL and GPUs both do well with 64; the global size is padded to it. */
#define LOCAL_SIZE 64

static lvcl_error cl_check(cl_int err, const char *what, lvcl_status *st)
{
    return err == CL_SUCCESS ? LVCL_OK : lvcl_fail(st, LVCL_ERR_DEVICE, "%s failed: %s", what, lvcl_cl_error_name(err));
}

lvcl_error lvcl_image_pass(const lvcl_device *dev, cl_kernel kernel, cl_uint camera_arg, const lv_camera *camera,
                           const lvcl_pass_settings *settings, lvcl_render_result *out, lvcl_status *st)
{
    memset(out, 0, sizeof *out);
    size_t pixels = (size_t)camera->width * camera->height;
    lvcl_error e;
    cl_int err;
    cl_mem sum = clCreateBuffer(dev->context, CL_MEM_READ_WRITE, pixels * 4 * sizeof(float), NULL, &err);
    if ((e = cl_check(err, "allocating the image", st))) return e;
    float zero = 0.0f;
    if ((e = cl_check(clEnqueueFillBuffer(dev->queue, sum, &zero, sizeof zero, 0, pixels * 4 * sizeof(float), 0,
                                          NULL, NULL),
                      "clearing the image", st)))
        goto done;

    cl_uint arg = camera_arg;
    if (clSetKernelArg(kernel, arg, sizeof *camera, camera) != CL_SUCCESS ||
        clSetKernelArg(kernel, arg + 2, sizeof(cl_mem), &sum) != CL_SUCCESS) {
        e = lvcl_fail(st, LVCL_ERR_DEVICE, "cannot set the camera pass's arguments");
        goto done;
    }
    size_t global = (pixels + LOCAL_SIZE - 1) / LOCAL_SIZE * LOCAL_SIZE, local = LOCAL_SIZE;

    lvcl_progress bar;
    lvcl_progress_start(&bar, "render", settings->progress);
    double start = lvcl_seconds();
    int s = 0;
    while (s < settings->spp) {
        cl_uint index = (cl_uint)s;
        clSetKernelArg(kernel, arg + 1, sizeof index, &index);
        if ((e = cl_check(clEnqueueNDRangeKernel(dev->queue, kernel, 1, NULL, &global, &local, 0, NULL, NULL),
                          "launching the camera pass", st)) ||
            (e = cl_check(clFinish(dev->queue), "running the camera pass", st)))
            goto done;
        s++;
        double elapsed = lvcl_seconds() - start;
        if (s == 1) out->first_launch_seconds = elapsed;
        lvcl_progress_update(&bar, s, settings->spp, "spp");
        if (settings->time_limit > 0 && elapsed >= settings->time_limit) break;
    }
    lvcl_progress_finish(&bar);
    out->render_seconds = lvcl_seconds() - start;
    out->samples = s;

    float *acc = malloc(pixels * 4 * sizeof(float));
    out->rgb = malloc(pixels * 3 * sizeof(float));
    if (!acc || !out->rgb) {
        free(acc);
        e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the image");
        goto done;
    }
    if ((e = cl_check(clEnqueueReadBuffer(dev->queue, sum, CL_TRUE, 0, pixels * 4 * sizeof(float), acc, 0, NULL, NULL),
                      "reading the image", st))) {
        free(acc);
        goto done;
    }
    for (size_t i = 0; i < pixels; i++) {
        float n = acc[4 * i + 3];
        for (int c = 0; c < 3; c++) out->rgb[3 * i + c] = n > 0 ? acc[4 * i + c] / n : 0.0f;
    }
    free(acc);
    out->width = (int)camera->width;
    out->height = (int)camera->height;
done:
    if (e) {
        free(out->rgb);
        out->rgb = NULL;
    }
    clReleaseMemObject(sum);
    return e;
}
