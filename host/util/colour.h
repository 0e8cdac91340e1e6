/* sRGB's transfer function, for the host: 8-bit colour (glTF's base
 * colour textures, PNG images) to linear values. */
#ifndef LVCL_COLOUR_H
#define LVCL_COLOUR_H

#include <math.h>

/* An sRGB-encoded value in [0, 1] as linear light. */
static inline double lvcl_srgb_to_linear(double v)
{
    return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

#endif
