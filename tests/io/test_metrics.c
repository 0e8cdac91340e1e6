/* The image metrics lvcl-compare and the tests report (host/io/metrics.c),
 * against values worked out by hand. */
#include <math.h>

#include "../../host/io/metrics.h"
#include "../check.h"

/* Fills a w x h RGB image with v in every channel. */
static void fill(float *im, int w, int h, float v)
{
    for (int i = 0; i < 3 * w * h; i++) im[i] = v;
}

static void test_block_ratios(void)
{
    enum { W = 20, H = 16 }; /* two whole 8 x 8 blocks across, two down; a strip of 4 columns left over */
    float a[3 * W * H], ref[3 * W * H];
    fill(ref, W, H, 0.5f);
    fill(a, W, H, 0.5f);
    /* One block 20% dark in one channel of every pixel: its sum falls by a fifteenth. */
    for (int y = 8; y < 16; y++)
        for (int x = 0; x < 8; x++) a[3 * (y * W + x) + 1] = 0.3f;
    /* The leftover strip, not a whole block, three times too bright: left out. */
    for (int y = 0; y < H; y++)
        for (int x = 16; x < W; x++)
            for (int c = 0; c < 3; c++) a[3 * (y * W + x) + c] = 1.5f;
    double lo, hi;
    size_t n = lvcl_block_ratios(a, ref, W, H, 8, &lo, &hi);
    CHECK("block ratios: whole blocks only, the dark one's sum", n == 4 && fabs(lo - 1.3 / 1.5) < 1e-6 && hi == 1.0,
          "%zu blocks, %g to %g, not 4, %g to 1", n, lo, hi, 1.3 / 1.5);
    /* A black reference block is not compared; a brighter block raises hi. */
    for (int y = 0; y < 8; y++)
        for (int x = 0; x < 8; x++)
            for (int c = 0; c < 3; c++) ref[3 * (y * W + x) + c] = 0.0f, a[3 * (y * W + x + 8) + c] = 0.6f;
    n = lvcl_block_ratios(a, ref, W, H, 8, &lo, &hi);
    CHECK("block ratios: black reference blocks left out", n == 3 && fabs(hi - 1.2) < 1e-6,
          "%zu blocks, largest %g, not 3 and 1.2", n, hi);
    n = lvcl_block_ratios(a, ref, 4, 4, 8, &lo, &hi);
    CHECK("block ratios: an image smaller than a block has none", n == 0 && lo == 1.0 && hi == 1.0,
          "%zu blocks, %g to %g", n, lo, hi);
}

int main(void)
{
    test_block_ratios();
    CHECK_EXIT();
}
