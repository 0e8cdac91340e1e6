/* The light volume on the host: choosing the grid, allocating cells only
 * where geometry is (and where a jittered lookup can land), and running the
 * particle trace into it on the device. */
#ifndef LVCL_LIGHT_VOLUME_H
#define LVCL_LIGHT_VOLUME_H

#include <pthread.h>
#include <stdint.h>

#include "../device/device_scene.h"
#include "../device/program.h"

/* Hands out batches of particle indices to the devices tracing one volume
 * together, so that a faster device traces more (lvcl_particle_source_init). */
typedef struct {
    pthread_mutex_t lock;
    uint64_t next, end;
} lvcl_particle_source;

void lvcl_particle_source_init(lvcl_particle_source *src, uint64_t particles);
void lvcl_particle_source_destroy(lvcl_particle_source *src);

/* The default share of surface hits that cast a subcell visibility ray
 * (docs/light-volume.md has the measurements behind it). */
#define LVCL_VISIBILITY_RATE 0.25

typedef struct {
    int cells;            /* cells along the longest axis (used if cell_size is 0) */
    double cell_size;     /* metres; 0 = from `cells` */
    double offset;        /* shift of the grid against the bounds, in cells, [0, 1) */
    int dirs;             /* n: n x n bins per hemisphere */
    int subcells;         /* k: k x k x k subcells per cell (0 to 4), 0 = the lit volume is the whole cell */
    double visibility_rate; /* share of surface hits that cast a visibility ray; 0 = LVCL_VISIBILITY_RATE */
    uint64_t particles;   /* in all, over every device */
    lvcl_particle_source *source; /* several devices: take batches from here; NULL: trace them all */
    int store_emitted;    /* lv-all: tally the segments leaving the lights too */
    int progress;
} lvcl_volume_settings;

typedef struct {
    lvcl_volume_buffers buf;  /* the grid and the buffers the kernels take (tallies: info.slots_per_part
                                 slots each, unused parts NULL) */
    uint32_t *cell_slot;      /* host copy of the index grid */
    size_t cell_count;        /* dims[0] * dims[1] * dims[2] */
    int tally_parts;
    cl_mem bin_directions_buf; /* float4 per bin, filled by lvcl_volume_trace */
    size_t tally_bytes;       /* all parts */
    size_t device_bytes;      /* everything the volume holds on the device */
    double trace_seconds;
    uint64_t particles;
    uint64_t segments;        /* straight path pieces traced */
    uint64_t visibility_rays; /* subcell visibility rays cast (paper 4.1) */
} lvcl_light_volume;

/* Chooses the grid over the packed scene's bounds and allocates the cells
 * that triangles touch, grown by one cell in every direction. */
lvcl_error lvcl_volume_create(const lvcl_device *dev, const lvcl_packed_scene *packed,
                              const lvcl_volume_settings *settings, lvcl_light_volume *vol, lvcl_status *st);

/* Traces settings->particles particles (or the batches it takes from
 * settings->source) into the (cleared) volume. Particle i draws its random
 * numbers from i alone, so batches traced apart and added make the volume
 * traced at once. */
lvcl_error lvcl_volume_trace(const lvcl_device *dev, const lvcl_program *prog, const lvcl_device_scene *ds,
                             const lvcl_volume_settings *settings, lvcl_light_volume *vol, lvcl_status *st);

/* After the trace: the per-cell lit volumes the lookups read. */
lvcl_error lvcl_volume_finish(const lvcl_device *dev, const lvcl_program *prog, lvcl_light_volume *vol,
                              lvcl_status *st);

/* Adds the tallies and subcell records of every volume (the same grid on
 * several devices, each with its own particles) and stores the sum in each.
 * Integer tallies and counters make the sum exact and order-free. */
lvcl_error lvcl_volume_merge(const lvcl_device *const *devs, lvcl_light_volume *const *vols, int count,
                             lvcl_status *st);

/* Reads the tallies back (slot_count x bins x 3 int64, malloc'ed) and, if
 * masks is not NULL, the subcell records (LV_SUBCELL_STRIDE words per slot). */
lvcl_error lvcl_volume_read(const lvcl_device *dev, const lvcl_light_volume *vol, int64_t **tallies,
                            uint32_t **masks, lvcl_status *st);

/* Bytes of tally buffer `part` (a buffer holds info.slots_per_part slots). */
size_t lvcl_volume_part_bytes(const lvcl_light_volume *vol, int part);

/* The lit fraction of a cell from its subcell record, as the kernels take
 * it (kernels/light_volume.h, lv_cell_lit_volume). */
double lvcl_volume_lit_fraction(const lv_grid_info *g, const uint32_t *record);

/* Radiance of tally value t (one channel) in a cell of lit volume fraction v. */
double lvcl_volume_radiance(const lv_grid_info *g, int64_t tally, double lit_fraction);

void lvcl_volume_release(lvcl_light_volume *vol);

#endif
