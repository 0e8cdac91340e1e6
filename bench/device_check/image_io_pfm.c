/* host/io/image_io.h over PFM files, for the device-check bundle only
 * (bundle.sh): OpenImageIO and the 260 libraries it loads are too large to
 * carry to a borrowed GPU machine, and PFM needs no library. Reading X.exr
 * reads X.pfm from $LVCL_PFM_DIR, where bundle.sh converted the references. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../host/io/image_io.h"
#include "pfm.h"

static int is_pfm(const char *path)
{
    size_t n = strlen(path);
    return n > 4 && strcmp(path + n - 4, ".pfm") == 0;
}

lvcl_error lvcl_image_format_check(const char *path, lvcl_status *st)
{
    return is_pfm(path) ? LVCL_OK : lvcl_fail(st, LVCL_ERR_IO, "cannot write %s: this build writes .pfm only", path);
}

lvcl_error lvcl_image_write(const char *path, const float *rgb, int width, int height, float exposure, lvcl_status *st)
{
    (void)exposure;
    lvcl_error e = lvcl_image_format_check(path, st);
    if (e) return e;
    return pfm_write(path, rgb, width, height) ? LVCL_OK : lvcl_fail(st, LVCL_ERR_IO, "cannot write %s", path);
}

lvcl_error lvcl_image_read(const char *path, float **rgb, int *width, int *height, lvcl_status *st)
{
    char converted[4096];
    const char *dir = getenv("LVCL_PFM_DIR"), *base = strrchr(path, '/');
    if (!is_pfm(path) && dir) {
        snprintf(converted, sizeof converted, "%s/%s", dir, base ? base + 1 : path);
        char *dot = strrchr(converted, '.');
        if (dot && (size_t)(dot - converted) + 5 <= sizeof converted) strcpy(dot, ".pfm");
        path = converted;
    }
    *rgb = NULL;
    FILE *f = fopen(path, "rb");
    float scale;
    if (!f) return lvcl_fail(st, LVCL_ERR_IO, "cannot read image %s", path);
    if (fscanf(f, "PF %d %d %f", width, height, &scale) != 3 || fgetc(f) == EOF || *width <= 0 || *height <= 0) {
        fclose(f);
        return lvcl_fail(st, LVCL_ERR_IO, "cannot read image %s: not a little-endian RGB PFM", path);
    }
    size_t row = (size_t)*width * 3;
    float *out = malloc(row * (size_t)*height * sizeof(float));
    int ok = out != NULL;
    for (int y = *height - 1; ok && y >= 0; y--) ok = fread(out + (size_t)y * row, sizeof(float), row, f) == row;
    fclose(f);
    if (!ok) {
        free(out);
        return lvcl_fail(st, LVCL_ERR_IO, "cannot read image %s", path);
    }
    *rgb = out;
    return LVCL_OK;
}
