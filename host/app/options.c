#include "options.h"

#include "../render/image_pass.h"
#include "../render/light_volume.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_SCENE "cornell"
/* Light-volume defaults, chosen by measurement (docs/light-volume.md). */
#define LVCL_DEFAULT_CELLS 32
#define LVCL_DEFAULT_PARTICLES 1e6
#define LVCL_DEFAULT_SPP 64
/* 8 x 8 bins per hemisphere: at equal time less error than the paper's 11 x 11
 * on the Cornell box, the glass table and the kitchen, in 60% of the memory
 * (docs/light-volume.md, "Passes and one time budget"). */
#define LVCL_DEFAULT_DIRS 8
#define LVCL_MAX_SPP (1 << 24)
#define LVCL_DEFAULT_SUBCELLS 4
#define LVCL_DEFAULT_MERGE_TOLERANCE 0
/* --refine-dirs on: how many times its mean bin a slot's brightest bin
 * must hold for the slot to take fine bins (docs/light-volume.md). */
#define LVCL_REFINE_PEAK 8.0

/* on, off or a number above 0 (on: `on`). */
static lvcl_error parse_switch(const char *flag, const char *s, double on, double *out, lvcl_status *st)
{
    char *end;
    if (!strcmp(s, "off")) *out = 0;
    else if (!strcmp(s, "on")) *out = on;
    else if (!(*out = strtod(s, &end), *s && !*end && *out > 0 && *out < 1e12))
        return lvcl_fail(st, LVCL_ERR_USAGE, "%s expects on, off or a number above 0, not '%s'", flag, s);
    return LVCL_OK;
}

/* For a number above a flag's limit, why the limit is there (with the
 * memory the value would need where memory is the reason), as the end of
 * the error message; "" for other flags and values. */
static const char *limit_reason(const char *flag, const char *s, double hi, char *out, size_t n)
{
    char *end;
    double v = strtod(s, &end);
    out[0] = '\0';
    if (*s == 0 || *end != 0 || !(v > hi)) return out;
    char size[32];
    if (!strcmp(flag, "--width") || !strcmp(flag, "--height"))
        snprintf(out, n, ": a %.0f x %.0f image would need %s of device memory (%zu bytes a pixel)", v, v,
                 lvcl_bytes_text(v * v * (double)LVCL_PIXEL_DEVICE_BYTES, size), (size_t)LVCL_PIXEL_DEVICE_BYTES);
    else if (!strcmp(flag, "--cells"))
        snprintf(out, n, ": a grid of %.3g cells would need %s for its cell index alone (4 bytes a cell)", v * v * v,
                 lvcl_bytes_text(v * v * v * 4.0, size));
    else if (!strcmp(flag, "--spp"))
        snprintf(out, n,
                 ": beyond 2^24 a pixel's float sample count stops counting exactly (average images "
                 "of different --seed instead)");
    else if (!strcmp(flag, "--particles"))
        snprintf(out, n, ": particles are numbered in 32 bits (average volumes of different --seed instead)");
    return out;
}

static lvcl_error parse_int(const char *flag, const char *s, long lo, long hi, long *out, lvcl_status *st)
{
    char *end, why[256];
    errno = 0;
    long v = strtol(s, &end, 10);
    if (*s == 0 || *end != 0 || errno || v < lo || v > hi)
        return lvcl_fail(st, LVCL_ERR_USAGE, "%s expects an integer from %ld to %ld, not '%s'%s", flag, lo, hi, s,
                         limit_reason(flag, s, (double)hi, why, sizeof why));
    *out = v;
    return LVCL_OK;
}

static lvcl_error parse_real(const char *flag, const char *s, double lo, double hi, double *out, lvcl_status *st)
{
    char *end, why[256];
    errno = 0;
    double v = strtod(s, &end);
    if (*s == 0 || *end != 0 || errno || !isfinite(v) || v < lo || v > hi)
        return lvcl_fail(st, LVCL_ERR_USAGE, "%s expects a number from %g to %g, not '%s'%s", flag, lo, hi, s,
                         limit_reason(flag, s, hi, why, sizeof why));
    *out = v;
    return LVCL_OK;
}

/* Defaults that depend on other flags: under a time limit the samples, and
 * in lv modes the particles, are as many as the time allows. */
static void fill_defaults(lvcl_options *o)
{
    o->spp_given = o->spp != 0;
    if (!o->spp) o->spp = o->time_limit > 0 ? LVCL_MAX_SPP : LVCL_DEFAULT_SPP;
    if (!o->particles && !(o->time_limit > 0)) o->particles = LVCL_DEFAULT_PARTICLES;
}

lvcl_error lvcl_options_parse(int argc, char **argv, lvcl_options *o, lvcl_status *st)
{
    memset(o, 0, sizeof *o);
    o->mode = "lv";
    o->max_depth = 64;
    o->fast_math = 1;
    o->cells = LVCL_DEFAULT_CELLS;
    o->dirs = LVCL_DEFAULT_DIRS;
    o->subcells = LVCL_DEFAULT_SUBCELLS;
    o->merge_tolerance = LVCL_DEFAULT_MERGE_TOLERANCE;
    o->refine_density = -1; /* not given: see below */
    o->refine_focus = LVCL_REFINE_FOCUS;
    o->gather = "integrate";
    o->adaptive = "on";
    o->see_through = "on";
    o->view_odds = "on";
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        /* Flags that take no value. */
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            o->help = 1;
            continue;
        }
        if (!strcmp(a, "--version")) {
            o->version = 1;
            continue;
        }
        if (!strcmp(a, "--list-devices")) {
            o->list_devices = 1;
            continue;
        }
        if (!strcmp(a, "--quiet") || !strcmp(a, "-q")) {
            o->quiet = 1;
            continue;
        }
        if (!strcmp(a, "--no-fast-math")) {
            o->fast_math = 0;
            continue;
        }
        if (a[0] != '-' || a[1] == 0) {
            if (o->scene)
                return lvcl_fail(st, LVCL_ERR_USAGE, "more than one scene given ('%s' and '%s')", o->scene, a);
            o->scene = a;
            continue;
        }
        /* Flags that take a value. */
        static const char *with_value[] = {"--device",
                                           "--mode",
                                           "-o",
                                           "--output",
                                           "--stats",
                                           "--spp",
                                           "--width",
                                           "--height",
                                           "--seed",
                                           "--max-depth",
                                           "--exposure",
                                           "--time-limit",
                                           "--cells",
                                           "--cell-size",
                                           "--grid-offset",
                                           "--dirs",
                                           "--subcells",
                                           "--particles",
                                           "--threshold",
                                           "--gather",
                                           "--adaptive",
                                           "--see-through",
                                           "--view-odds",
                                           "--device-memory",
                                           "--visibility-rate",
                                           "--merge-tolerance",
                                           "--refine",
                                           "--refine-dirs",
                                           "--refine-focus",
                                           "--refine-memory"};
        int known = 0;
        for (size_t k = 0; k < sizeof with_value / sizeof *with_value; k++) known |= !strcmp(a, with_value[k]);
        if (!known) return lvcl_fail(st, LVCL_ERR_USAGE, "unknown option '%s' (see --help)", a);
        if (i + 1 >= argc) return lvcl_fail(st, LVCL_ERR_USAGE, "%s needs a value", a);
        const char *v = argv[++i];
        long n = 0;
        double x = 0;
        lvcl_error e = LVCL_OK;
        if (!strcmp(a, "--device")) o->device = v;
        else if (!strcmp(a, "--mode")) o->mode = v;
        else if (!strcmp(a, "-o") || !strcmp(a, "--output")) o->output = v;
        else if (!strcmp(a, "--stats")) o->stats = v;
        else if (!strcmp(a, "--spp")) {
            e = parse_int(a, v, 1, LVCL_MAX_SPP, &n, st);
            o->spp = (int)n;
        } else if (!strcmp(a, "--width")) {
            e = parse_int(a, v, 1, 16384, &n, st);
            o->width = (int)n;
        } else if (!strcmp(a, "--height")) {
            e = parse_int(a, v, 1, 16384, &n, st);
            o->height = (int)n;
        } else if (!strcmp(a, "--seed")) {
            e = parse_int(a, v, 0, UINT_MAX, &n, st);
            o->seed = (unsigned)n;
        } else if (!strcmp(a, "--max-depth")) {
            e = parse_int(a, v, 1, 1024, &n, st);
            o->max_depth = (int)n;
        } else if (!strcmp(a, "--exposure")) {
            e = parse_real(a, v, -64, 64, &x, st);
            o->exposure = x;
        } else if (!strcmp(a, "--time-limit")) {
            e = parse_real(a, v, 0, 1e9, &x, st);
            o->time_limit = x;
        } else if (!strcmp(a, "--cells")) {
            e = parse_int(a, v, 1, 1024, &n, st);
            o->cells = (int)n;
        } else if (!strcmp(a, "--cell-size")) {
            e = parse_real(a, v, 1e-9, 1e9, &x, st);
            o->cell_size = x;
        } else if (!strcmp(a, "--grid-offset")) {
            e = parse_real(a, v, 0, 0.999, &x, st);
            o->grid_offset = x;
        } else if (!strcmp(a, "--dirs")) {
            e = parse_int(a, v, 1, 64, &n, st);
            o->dirs = (int)n;
        } else if (!strcmp(a, "--subcells")) {
            e = parse_int(a, v, 0, 4, &n, st);
            o->subcells = (int)n;
        } else if (!strcmp(a, "--visibility-rate")) {
            e = parse_real(a, v, 0.001, 1, &x, st);
            o->visibility_rate = x;
        } else if (!strcmp(a, "--merge-tolerance")) {
            e = parse_real(a, v, 0, 1e12, &x, st);
            o->merge_tolerance = x;
        } else if (!strcmp(a, "--particles")) {
            e = parse_real(a, v, 1, 4294967295.0, &x, st);
            o->particles = floor(x);
        } else if (!strcmp(a, "--threshold")) {
            e = parse_real(a, v, 1e-12, 1e12, &x, st);
            o->threshold = x;
        } else if (!strcmp(a, "--gather")) o->gather = v;
        else if (!strcmp(a, "--adaptive")) o->adaptive = v;
        else if (!strcmp(a, "--see-through")) o->see_through = v;
        else if (!strcmp(a, "--view-odds")) o->view_odds = v;
        else if (!strcmp(a, "--refine")) e = parse_switch(a, v, LVCL_REFINE_DENSITY, &o->refine_density, st);
        else if (!strcmp(a, "--refine-dirs")) e = parse_switch(a, v, LVCL_REFINE_PEAK, &o->refine_peak, st);
        else if (!strcmp(a, "--refine-focus")) {
            e = parse_real(a, v, 0, 1, &x, st);
            o->refine_focus = x;
        } else if (!strcmp(a, "--refine-memory")) {
            e = parse_real(a, v, 1, 1e9, &x, st);
            o->refine_memory_mib = x;
        } else if (!strcmp(a, "--device-memory")) {
            e = parse_real(a, v, 0.01, 1e9, &x, st);
            o->device_memory_mib = x;
        }
        if (e) return e;
    }
    if (strcmp(o->mode, "pt") && strcmp(o->mode, "lv") && strcmp(o->mode, "lv-all") && strcmp(o->mode, "guided"))
        return lvcl_fail(st, LVCL_ERR_USAGE, "unknown mode '%s' (expected pt, lv, lv-all or guided)", o->mode);
    if (strcmp(o->gather, "sample") && strcmp(o->gather, "integrate"))
        return lvcl_fail(st, LVCL_ERR_USAGE, "unknown gather '%s' (expected sample or integrate)", o->gather);
    if (strcmp(o->adaptive, "on") && strcmp(o->adaptive, "off"))
        return lvcl_fail(st, LVCL_ERR_USAGE, "unknown --adaptive '%s' (expected on or off)", o->adaptive);
    if (strcmp(o->see_through, "on") && strcmp(o->see_through, "off"))
        return lvcl_fail(st, LVCL_ERR_USAGE, "unknown --see-through '%s' (expected on or off)", o->see_through);
    if (strcmp(o->view_odds, "on") && strcmp(o->view_odds, "off"))
        return lvcl_fail(st, LVCL_ERR_USAGE, "unknown --view-odds '%s' (expected on or off)", o->view_odds);
    /* Refined cells by default in lv mode, where they split only cells
     * whose light is focused (LVCL_REFINE_FOCUS); the guide of guided paths
     * gains nothing from them, and merged cells exclude them. */
    if (o->refine_density < 0)
        o->refine_density = !strcmp(o->mode, "lv") && !(o->merge_tolerance > 0) ? LVCL_REFINE_DENSITY : 0;
    if ((o->refine_density > 0 || o->refine_peak > 0) && o->merge_tolerance > 0)
        return lvcl_fail(st, LVCL_ERR_USAGE, "--refine cannot be combined with --merge-tolerance");
    if (!o->scene) o->scene = DEFAULT_SCENE;
    fill_defaults(o);
    return LVCL_OK;
}

void lvcl_options_print_help(const char *program)
{
    printf(
        "usage: %s [options] [SCENE]\n"
        "\n"
        "Renders SCENE, a .gltf/.glb file or the name of an embedded scene\n"
        "(cornell, furnace, kitchen; default cornell).\n"
        "\n"
        "  --device cpu|gpu|N   OpenCL device (default: first GPU, else CPU); a list N,M,... or\n"
        "                       all renders on several at once\n"
        "  --list-devices       list OpenCL devices and exit\n"
        "  --device-memory MIB  act as a device of MIB MiB, a quarter of it in one buffer (default: the device's own)\n"
        "  --mode lv|pt|lv-all|guided  lv: light volume for indirect light, shadow rays for direct\n"
        "                       (default); pt: path tracing; lv-all: the light volume answers all\n"
        "                       light; guided: path tracing that samples by the light volume too\n"
        "                       (unbiased)\n"
        "  --particles N        light volume: particles traced (default 1e6; under --time-limit\n"
        "                       as many as the measured split of the time gives)\n"
        "  --cells N            light volume: cells along the longest axis (default 32)\n"
        "  --cell-size M        light volume: cell size in metres (overrides --cells)\n"
        "  --grid-offset F      light volume: shift the grid by F cells against the scene (0 to 0.999)\n"
        "  --dirs N             light volume: N x N direction bins per hemisphere (default 8)\n"
        "  --subcells K         light volume: K x K x K subcells per cell estimate its lit volume\n"
        "                       (0 to 4, default 4; 0 = the whole cell)\n"
        "  --visibility-rate R  light volume: share of particle hits that cast a subcell visibility\n"
        "                       ray (0.001 to 1, default 0.25)\n"
        "  --merge-tolerance T  light volume: adaptive cells: 2x2x2 blocks with no geometry inside share one\n"
        "                       tally set where their cells differ by less than T times their noise at\n"
        "                       the particle count (default 0: off; 0.25 measured neutral, see docs)\n"
        "  --refine on|off|D    light volume: split the cells the particles cross most densely, where\n"
        "                       a tenth of their light came by mirrors and glass alone (caustics), into\n"
        "                       octants beside their walls' planes after a first part of the trace\n"
        "                       (default on in lv mode, else off; D: the density threshold, on = 0.5)\n"
        "  --refine-focus S     light volume: the share of a cell's light that must have come by mirrors\n"
        "                       and glass alone for it to split (default 0.1; 0: any light)\n"
        "  --refine-dirs on|off|R  light volume: after the same part of the trace, give the slots whose\n"
        "                       brightest bin holds R times their mean 2n x 2n bins per hemisphere\n"
        "                       (default off; on = 8; see docs)\n"
        "  --refine-memory MIB  light volume: memory the refined volume may take (default: twice\n"
        "                       the unrefined volume's)\n"
        "  --threshold M        lv: BSDF rays meeting a surface closer than M metres continue as\n"
        "                       paths, but at mirrors and smooth glass (default half the cell diagonal)\n"
        "  --gather integrate|sample  lv: integrate the BSDF over all bins of the cell (default),\n"
        "                       or read the bin of one BSDF-sampled direction\n"
        "  --see-through on|off shadow rays blocked by glass go on through it, so lamps seen through\n"
        "                       glass light rough surfaces sharply and with little noise (pt, guided,\n"
        "                       lv; lv's volume then leaves that light out; default on)\n"
        "  --view-odds on|off   lv, lv-all: after a quarter of the particles (or the refinement's\n"
        "                       split), choose the lights whose particles reach what the camera sees\n"
        "                       more often, for the rest and for light samples (scenes of two or more\n"
        "                       lamp materials; default on)\n"
        "  --spp N              samples per pixel (default 64; under --time-limit as many as fit)\n"
        "  --adaptive on|off    after the first 8 samples per pixel, give each further 8 (on average)\n"
        "                       to the pixels whose neighbours show the most error (default on)\n"
        "  --width N, --height N  image size (default 512 wide, height from the camera's aspect)\n"
        "  --seed N             random seed (default 0); the same seed gives the same image\n"
        "  --max-depth N        longest path in segments (default 64; 1 = emitters only)\n"
        "  -o, --output FILE    .exr (linear float) or .png (sRGB); default out/SCENE.exr and .png\n"
        "  --exposure EV        scale by 2^EV before writing 8-bit images (default 0)\n"
        "  --time-limit S       render for about S seconds, loading and kernel builds not counted;\n"
        "                       lv modes split them between particles and gather by measurement;\n"
        "                       guided measures its guide in passes, then traces on and picks\n"
        "                       guided or plain paths by the measured gain\n"
        "                       (at least one sample is taken; one device and one process only)\n"
        "  --stats FILE.json    write timings, sizes and device facts as JSON\n"
        "  --no-fast-math       build kernels without -cl-fast-relaxed-math\n"
        "  -q, --quiet          no progress bar\n"
        "  --version            print the version and exit\n"
        "  -h, --help           this text\n"
        "\n"
        "Ctrl-C (SIGINT), SIGTERM or SIGUSR2 while rendering stops sampling after the launch in\n"
        "flight and writes the image so far (exit status 130, 143 or 140); a second signal ends\n"
        "lvcl at once.\n"
        "Over MPI: mpirun -np N build/lvcl-mpi [options] SCENE renders one frame on every rank's\n"
        "devices (docs/distributed.md); SIGUSR2 to mpirun stops it and keeps the image.\n"
        "Devices: --list-devices; the build's opencl-vendors folder adds Intel's CPU runtime and\n"
        "the Oclgrind simulator (used only when named by index).\n",
        program);
}
