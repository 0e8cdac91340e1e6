/* Converts an image lvcl reads (EXR, PNG, ...) to PFM, for the device-check
 * bundle's references (bundle.sh). Built against the full library. */
#include <stdio.h>
#include <stdlib.h>

#include "../../host/io/image_io.h"

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: to_pfm IMAGE OUT.pfm\n");
        return 2;
    }
    lvcl_status st = {0};
    float *rgb;
    int w, h;
    if (lvcl_image_read(argv[1], &rgb, &w, &h, &st)) {
        fprintf(stderr, "to_pfm: error: %s\n", st.message);
        return 1;
    }
    FILE *f = fopen(argv[2], "wb");
    int ok = f != NULL;
    if (ok) {
        fprintf(f, "PF\n%d %d\n-1.0\n", w, h);
        for (int y = h - 1; y >= 0; y--)
            ok &= fwrite(rgb + (size_t)y * w * 3, sizeof(float), (size_t)w * 3, f) == (size_t)w * 3;
        ok &= fclose(f) == 0;
    }
    free(rgb);
    if (!ok) fprintf(stderr, "to_pfm: error: cannot write %s\n", argv[2]);
    return ok ? 0 : 1;
}
