/* Dot and cross products of double 3-vectors, for the host's geometry: the
 * light volume's cells (regions and their shares) and the host's rays
 * against the packed scene. */
#ifndef LVCL_VEC3_H
#define LVCL_VEC3_H

static inline double lvcl_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void lvcl_cross3(const double a[3], const double b[3], double r[3])
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

#endif
