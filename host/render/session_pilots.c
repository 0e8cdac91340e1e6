/* Pilot images, small renders that measure an image's noise before a time
 * budget is spent (session_budget.c, session_guided.c), and the weighted
 * differences between two of them that measure it. */
#include <math.h>
#include <stdlib.h>

#include "../io/metrics.h"
#include "session_internal.h"

lvcl_error lvcl_session_pilot(lvcl_session *s, const lvcl_render_request *req, int scale, int first, int spp,
                              lvcl_render_result *out, lvcl_status *st)
{
    int w, h;
    lvcl_image_size(&s->scene.camera, req->width, req->height, &w, &h);
    w = w / scale > 8 ? w / scale : 8;
    h = h / scale > 8 ? h / scale : 8;
    lvcl_pass_settings pass = {.spp = spp, .first_sample = first};
    return lvcl_session_camera_pass(s, req, w, h, &pass, out, st);
}

double lvcl_weighted_difference(const float *a, const float *b, const float *den, size_t n, double *error)
{
    double sum = 0, pixel_sum = 0, pixel_sum_sq = 0, pixel = 0;
    for (size_t i = 0; i < n; i++) {
        double d = (double)a[i] - b[i], x = d * d / den[i];
        sum += x;
        pixel += x / 3.0;
        if (i % 3 == 2) pixel_sum += pixel, pixel_sum_sq += pixel * pixel, pixel = 0;
    }
    if (error) {
        double pixels = (double)(n / 3), mean = pixel_sum / pixels;
        double var = pixels > 1 ? (pixel_sum_sq / pixels - mean * mean) / (pixels - 1) : 0;
        *error = var > 0 ? sqrt(var) : 0;
    }
    return n ? sum / (double)n : 0;
}

float *lvcl_pilot_denominators(const lvcl_render_result *img, int count)
{
    int w = img[0].width, h = img[0].height;
    float *den = malloc((size_t)w * h * 3 * sizeof(float));
    if (!den) return NULL;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++) {
                double sum = 0;
                int n = 0;
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int xx = x + dx, yy = y + dy;
                        if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                        for (int i = 0; i < count; i++) sum += img[i].rgb[((size_t)yy * w + xx) * 3 + c];
                        n += count;
                    }
                double m = sum / n;
                den[((size_t)y * w + x) * 3 + c] = (float)(m * m + LVCL_RELMSE_GUARD);
            }
    return den;
}
