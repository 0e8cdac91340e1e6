/* Converts an image lvcl reads (EXR, PNG, ...) to PFM, for the device-check
 * bundle's references (bundle.sh). Built against the full library. */
#include <stdio.h>
#include <stdlib.h>

#include "../../host/io/image_io.h"
#include "pfm.h"

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
    int ok = pfm_write(argv[2], rgb, w, h);
    free(rgb);
    if (!ok) fprintf(stderr, "to_pfm: error: cannot write %s\n", argv[2]);
    return ok ? 0 : 1;
}
