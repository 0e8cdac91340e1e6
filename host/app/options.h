/* The command line of lvcl. */
#ifndef LVCL_OPTIONS_H
#define LVCL_OPTIONS_H

#include "../util/status.h"

typedef struct {
    const char *scene;  /* file path or embedded scene name */
    const char *device; /* NULL = default choice */
    const char *mode;
    const char *output; /* NULL = out/<scene>.exr and .png */
    const char *stats;
    int spp;
    int spp_given;     /* --spp was given (else the default, or under a time limit as many as fit) */
    int width, height; /* 0 = from the camera's aspect */
    unsigned seed;
    int max_depth;
    double exposure;
    int cells;                /* light volume: cells along the longest axis */
    double cell_size;         /* metres, 0 = from cells */
    double grid_offset;       /* fraction of a cell */
    int dirs;                 /* n x n bins per hemisphere */
    int subcells;             /* k x k x k subcells per cell, 0 = none */
    double visibility_rate;   /* share of surface hits casting a visibility ray, 0 = default */
    double merge_tolerance;   /* adaptive cells: blocks merge below this mean tally per bin, 0 = never */
    double refine_density;    /* refined cells: density threshold, 0 = off */
    double refine_peak;       /* refined directions: peak over mean bin, 0 = off */
    double refine_focus;      /* refined cells: the least share of focused light a cell splits with */
    double refine_memory_mib; /* refined cells' memory budget, 0 = twice the unrefined volume */
    double particles;         /* 0: as many as a time limit allows */
    double threshold;         /* near-hit distance, 0 = half the cell diagonal */
    const char *gather;       /* "sample" or "integrate" */
    const char *adaptive;     /* "on" or "off": adaptive sampling */
    const char *see_through;  /* "on" or "off": lv's gather finds lamps seen through glass */
    const char *view_odds;    /* "on" or "off": lv's lights' odds follow what the camera sees */
    double device_memory_mib; /* cap on device memory, 0 = the device's own */
    double time_limit;
    int quiet;
    int fast_math;
    int list_devices;
    int help;
    int version;
} lvcl_options;

/* Parses argv; on a bad flag or value returns LVCL_ERR_USAGE with a one-line message. */
lvcl_error lvcl_options_parse(int argc, char **argv, lvcl_options *o, lvcl_status *st);

void lvcl_options_print_help(const char *program);

#endif
