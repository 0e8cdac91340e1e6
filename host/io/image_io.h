/* Image files through OpenImageIO: EXR (linear float) and 8-bit formats
 * such as PNG (sRGB-encoded after an exposure scale of 2^exposure). */
#ifndef LVCL_IMAGE_IO_H
#define LVCL_IMAGE_IO_H

#include "../util/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Writes width x height RGB floats (row 0 at the top). The format follows
 * the file extension: .exr or .hdr keep linear floats; others get sRGB 8-bit. */
lvcl_error lvcl_image_write(const char *path, const float *rgb, int width, int height, float exposure, lvcl_status *st);

/* Whether lvcl_image_write knows the format of path (by its extension),
 * so that a render is not thrown away for want of it. */
lvcl_error lvcl_image_format_check(const char *path, lvcl_status *st);

/* Reads an image as linear RGB floats (malloc'ed; the caller frees *rgb).
 * 8-bit images are decoded from sRGB. */
lvcl_error lvcl_image_read(const char *path, float **rgb, int *width, int *height, lvcl_status *st);

#ifdef __cplusplus
}
#endif
#endif
