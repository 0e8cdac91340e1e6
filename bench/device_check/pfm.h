/* Writing a PFM file, shared by the device-check bundle's image I/O
 * (image_io_pfm.c) and its reference converter (to_pfm.c). */
#ifndef LVCL_DEVICE_CHECK_PFM_H
#define LVCL_DEVICE_CHECK_PFM_H

#include <stdio.h>

/* width x height RGB floats, row 0 at the top. PFM stores rows bottom
 * first; a negative scale says little-endian. Returns 1 on success. */
static int pfm_write(const char *path, const float *rgb, int width, int height)
{
    FILE *f = fopen(path, "wb");
    if (!f) return 0;
    fprintf(f, "PF\n%d %d\n-1.0\n", width, height);
    size_t row = (size_t)width * 3;
    int ok = 1;
    for (int y = height - 1; y >= 0; y--) ok &= fwrite(rgb + (size_t)y * row, sizeof(float), row, f) == row;
    ok &= fclose(f) == 0;
    return ok;
}

#endif
