/* lvcl-bench: kernel benchmarks, each printing JSON lines.
 *   lvcl-bench rays ...       ray throughput, against Embree (bench/rays.c)
 *   lvcl-bench wavefront ...  the path tracer as wavefront kernels against
 *                             the megakernel (bench/wavefront.c) */
#include <stdio.h>
#include <string.h>

#include "bench.h"

int main(int argc, char **argv)
{
    if (argc >= 2 && !strcmp(argv[1], "rays")) return bench_rays(argc, argv);
    if (argc >= 2 && !strcmp(argv[1], "wavefront")) return bench_wavefront(argc, argv);
    fprintf(stderr, "usage: lvcl-bench rays|wavefront [options] SCENE (lvcl-bench rays -h for the options)\n");
    return 2;
}
