/* The one OpenCL program of lvcl: every pass's kernels, built together so
 * that one compile (and one cache entry) serves a whole run. */
#include "passes/pt.cl"
#include "passes/particles.cl"
#include "passes/gather.cl"
#include "passes/guided.cl"
