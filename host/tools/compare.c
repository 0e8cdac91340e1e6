/* lvcl-compare IMAGE REFERENCE: prints the error of IMAGE against REFERENCE
 * as one JSON object (relMSE, RMSE, both images' mean RGB, and the least
 * and largest ratio of IMAGE's 8 x 8-pixel block sums over REFERENCE's). */
#include <stdio.h>
#include <stdlib.h>

#include "../io/image_io.h"
#include "../io/metrics.h"

/* The side of the blocks whose ratios are reported, pixels. */
#define COMPARE_BLOCK 8

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: lvcl-compare IMAGE REFERENCE\n");
        return 2;
    }
    lvcl_status st = {0};
    float *a = NULL, *b = NULL;
    int wa, ha, wb, hb;
    if (lvcl_image_read(argv[1], &a, &wa, &ha, &st) || lvcl_image_read(argv[2], &b, &wb, &hb, &st)) {
        fprintf(stderr, "lvcl-compare: error: %s\n", st.message);
        free(a);
        return 1;
    }
    if (wa != wb || ha != hb) {
        fprintf(stderr, "lvcl-compare: error: %s is %dx%d but %s is %dx%d\n", argv[1], wa, ha, argv[2], wb, hb);
        free(a);
        free(b);
        return 1;
    }
    size_t n = (size_t)wa * ha;
    double ma[3], mb[3];
    lvcl_mean_rgb(a, n, ma);
    lvcl_mean_rgb(b, n, mb);
    double lo, hi;
    lvcl_block_ratios(a, b, wa, ha, COMPARE_BLOCK, &lo, &hi);
    printf("{\"relmse\": %.6g, \"rmse\": %.6g, \"mean\": [%.5f, %.5f, %.5f], \"reference_mean\": [%.5f, %.5f, %.5f], "
           "\"block_ratios\": [%.4f, %.4f]}\n",
           lvcl_relmse(a, b, 3 * n), lvcl_rmse(a, b, 3 * n), ma[0], ma[1], ma[2], mb[0], mb[1], mb[2], lo, hi);
    free(a);
    free(b);
    return 0;
}
