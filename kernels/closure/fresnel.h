/* A smooth interface: how much of the light it reflects (Fresnel) and
 * which way reflected and refracted light leaves. Directions point away
 * from the surface. */
#ifndef LV_CLOSURE_FRESNEL_H
#define LV_CLOSURE_FRESNEL_H

#include "../util/geometry.h"

inline float3 lv_schlick3(float3 f0, float cos_theta)
{
    float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
    float m2 = m * m;
    return f0 + (1.0f - f0) * (m2 * m2 * m);
}

/* Unpolarised Fresnel reflectance of a dielectric interface; eta is the
 * inside index over the outside one and cos_i is taken from the outside
 * normal (negative: the light arrives from inside). */
inline float lv_fresnel_dielectric(float cos_i, float eta)
{
    cos_i = clamp(cos_i, -1.0f, 1.0f);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
    }
    float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 1.0f;
    float cos_t = sqrt(fmax(0.0f, 1.0f - sin2_t));
    float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5f * (rs * rs + rp * rp);
}

/* Refracts w about n; eta as above. On success writes the refracted
 * direction and eta' = n_t / n_i. */
inline int lv_refract(float3 w, float3 n, float eta, float3 *wt, float *etap)
{
    float cos_i = dot(n, w);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
        n = -n;
    }
    float sin2_t = fmax(0.0f, 1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 0;
    float cos_t = sqrt(1.0f - sin2_t);
    *wt = -w / eta + (cos_i / eta - cos_t) * n;
    *etap = eta;
    return 1;
}

inline float3 lv_reflect(float3 w, float3 n)
{
    return 2.0f * dot(w, n) * n - w;
}

/* Mirror reflection about the local normal +z. */
inline float3 lv_mirror(float3 w)
{
    return (float3)(-w.x, -w.y, w.z);
}

#endif
