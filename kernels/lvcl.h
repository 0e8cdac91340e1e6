/* The device code the passes share, layer by layer: each layer uses only
 * those above it. Every header includes what it uses, so it can be read
 * (and included by a test) on its own; this list fixes the order in which
 * the program's source holds them, since a reordering can change how the
 * fast-math build rounds (tests/data/golden.txt pins the images).
 *
 * util/geometry.h comes first: it switches floating-point contraction off
 * for everything after it. */
#ifndef LV_LVCL_H
#define LV_LVCL_H

#include "util/geometry.h"
#include "util/rng.h"
#include "util/sampling.h"
#include "scene_buffers.h"
#include "bvh/traverse.h"
#include "closure/bsdf.h"
#include "scene/surface.h"
#include "scene/camera.h"
#include "light/lights.h"
#include "volume/direction_map.h"
#include "volume/grid.h"
#include "volume/tally.h"
#include "volume/segment.h"
#include "volume/subcells.h"
#include "volume/lookup.h"
#include "volume/guide.h"
#include "integrator/scatter.h"
#include "integrator/direct_light.h"
#include "integrator/path_tracer.h"
#include "integrator/gather.h"
#include "integrator/particle_trace.h"

#endif
