/* The light volume on the host (paper section 4): a grid chosen over the
 * scene, cells stored only where geometry is (and where a jittered lookup
 * can land), the particle trace run into it on a device, and what the
 * lookups need computed after it. An opaque handle: the buffers stay with
 * the volume; tests and stats read it through the accessors below. */
#ifndef LVCL_LIGHT_VOLUME_H
#define LVCL_LIGHT_VOLUME_H

#include <pthread.h>
#include <stdint.h>

#include "../device/device_scene.h"
#include "../device/program.h"
#include "cluster.h"

typedef struct lvcl_light_volume lvcl_light_volume;

/* Hands out batches of particle indices to the devices tracing one volume
 * together, so that a faster device traces more (lvcl_particle_source_init);
 * with a cluster, to the devices of every process. */
typedef struct {
    pthread_mutex_t lock;
    uint64_t next, end;
    lvcl_cluster *cluster; /* shared: batches come from the cluster's counter, from `next` on */
    lvcl_error e;          /* the cluster failed to hand out a batch */
    lvcl_status st;
} lvcl_particle_source;

/* Hands out the particle indices [first, end), here or (cluster shared, its
 * counter restarted) over every process. */
void lvcl_particle_source_init(lvcl_particle_source *src, uint64_t first, uint64_t end, lvcl_cluster *cluster);
void lvcl_particle_source_destroy(lvcl_particle_source *src);

/* The default share of surface hits that cast a subcell visibility ray
 * (docs/light-volume.md has the measurements behind it). */
#define LVCL_VISIBILITY_RATE 0.25

typedef struct {
    int cells;                    /* cells along the longest axis (used if cell_size is 0) */
    double cell_size;             /* metres; 0 = from `cells` */
    double offset;                /* shift of the grid against the bounds, in cells, [0, 1) */
    int dirs;                     /* n: n x n bins per hemisphere */
    int subcells;                 /* k: k x k x k subcells per cell (0 to 4), 0 = the lit volume is the whole cell */
    double visibility_rate;       /* share of surface hits that cast a visibility ray; 0 = LVCL_VISIBILITY_RATE */
    uint64_t particles;           /* trace the particle indices [first_particle, particles), over every device */
    int restarted_only;           /* a retrace after lvcl_volume_refine: see lvcl_volume_trace */
    uint64_t first_particle;      /* 0: the volume is cleared first; else the trace adds to it (a pass) */
    double deadline;              /* lvcl_seconds() after which no batch starts; 0 = none */
    lvcl_particle_source *source; /* several devices: take batches from here; NULL: trace them all */
    int store_emitted;            /* lv-all: tally the segments leaving the lights too */
    int see_through;              /* lv: leave out lamps seen through glass, which its gather finds */
    double merge_tolerance;       /* adaptive cells: see lvcl_volume_adapt; 0 = every cell keeps its tallies */
    double refine_density;        /* refined cells: see lvcl_volume_refine; 0 = no cell is split */
    double refine_focus;          /* refined cells: the least share of focused light a cell splits with; 0 = any */
    double refine_peak;           /* refined directions: see lvcl_volume_refine; 0 = no fine bins */
    uint64_t refine_memory;       /* bytes a refined volume may take on the device; 0 = twice the unrefined */
    int view_odds;                /* lv renders: after the first part the lights' odds follow what the camera
                                     sees (host/render/session_view.c); 0 = the packed odds throughout */
    int progress;
} lvcl_volume_settings;

/* What a volume holds and what its trace did (this device's share). */
typedef struct {
    size_t tally_bytes;       /* all tally buffers */
    size_t device_bytes;      /* everything the volume holds on the device but the axis sums */
    size_t axis_sums_bytes;   /* the gather's axis sums (lvcl_volume_axis_sums), once made */
    int tally_buffers;        /* buffers the tallies are split over */
    uint64_t particles;       /* traced here */
    uint64_t segments;        /* straight path pieces traced */
    uint64_t visibility_rays; /* subcell visibility rays cast (paper 4.1) */
    size_t merged_cells;      /* slots sharing a merged block's tally set (lvcl_volume_adapt) */
    size_t split_cells;       /* cells split by lvcl_volume_refine */
    size_t fine_slots;        /* slots it gave fine bins */
    size_t mixed_slots;       /* slots no lookup reads (LV_REGION_MIXED) */
    int see_through;          /* lamps seen through glass were left to the gather */
    double trace_seconds;
} lvcl_volume_stats;

/* Chooses the grid over the packed scene's bounds and allocates, on dev
 * (which must outlive the volume), the cells that triangles touch, grown by
 * one cell in every direction. */
lvcl_error lvcl_volume_create(const lvcl_device *dev, const lvcl_packed_scene *packed,
                              const lvcl_volume_settings *settings, lvcl_light_volume **vol, lvcl_status *st);

/* Traces the particles [first_particle, particles) (or the batches it takes
 * from settings->source) into the volume, which first_particle 0 clears
 * first, until the deadline. Particle i draws its random numbers from i
 * alone, and the tallies do not depend on the particle count (it divides
 * them only where they are read), so passes traced one after another, or
 * batches traced apart and added, make the volume traced at once.
 *
 * With settings->restarted_only, after lvcl_volume_refine: retraces the
 * particles before the split into the slots whose tallies restarted there
 * alone (they walk as they first did, and nothing else changes), so that
 * those slots too hold every particle. The range, over every device and
 * process together, must be all of [0, the particle count at the split);
 * it is traced whole, whatever the deadline. */
lvcl_error lvcl_volume_trace(lvcl_light_volume *vol, const lvcl_program *prog, const lvcl_device_scene *ds,
                             const lvcl_volume_settings *settings, lvcl_status *st);

/* Adaptive cells (docs/light-volume.md, "Adaptive cells"): after a trace
 * and before lvcl_volume_finish, the stored cells of every block of
 * 2 x 2 x 2 cells with no geometry inside whose cells' light differs, at
 * expected_particles, by less than merge_tolerance times its noise share
 * one tally set, the sum of theirs, from then on (later passes tally into
 * it). Once per volume (later calls do nothing); merge_tolerance or
 * expected_particles 0 merges nothing. The decision reads only integer
 * tallies and subcell records, so it is the same on every device and in
 * every run; merging adds integers, so each set equals the sum of its
 * cells' tallies traced without merging. The volume must have been created
 * with settings->merge_tolerance > 0. */
lvcl_error lvcl_volume_adapt(lvcl_light_volume *vol, double expected_particles, double merge_tolerance,
                             lvcl_status *st);

/* A fixed-count trace with refined cells or directions refines after this
 * share (1 / LVCL_SPLIT_AFTER) of its particles, or after
 * LVCL_SPLIT_MAX_PARTICLES where that comes first (the particles a time
 * budget splits after): the particles before the split are traced twice
 * (the retrace), and scoring the cells needs a number of particles, not a
 * share. The particle it refines at, or 0 where the settings refine nothing. */
#define LVCL_SPLIT_AFTER 4
#define LVCL_SPLIT_MAX_PARTICLES ((uint64_t)1 << 18)
static inline uint64_t lvcl_volume_split_point(const lvcl_volume_settings *s)
{
    uint64_t share = s->particles / LVCL_SPLIT_AFTER;
    return s->refine_density > 0 || s->refine_peak > 0
        ? (share < LVCL_SPLIT_MAX_PARTICLES ? share : LVCL_SPLIT_MAX_PARTICLES)
        : 0;
}
/* --refine on: the density D that a cell's pieces per particle x N must
 * reach, D sqrt(N), to split (docs/light-volume.md, "Refined cells and
 * directions"). With the focus rule below only cells of focused light
 * compete, and 0.5 splits nearly all of those the memory allows: 4 left
 * the caustic's cells whole on most grid offsets ("Split every focused
 * cell"). */
#define LVCL_REFINE_DENSITY 0.5
/* The density a slot's pieces must reach the same way to take fine bins
 * (--refine-dirs), whatever --refine asks: a restart costs a slot its
 * first particles, which only a dense slot can spare. */
#define LVCL_FINE_DENSITY 4.0
/* --refine on: the share of a cell's light (luminance) that must have come
 * by specular scatters alone, its lobe's over its bins', for it to split.
 * Focused light (caustics) has edges that a cell's average blurs; diffuse
 * light varies slowly, and the densest diffuse cells are those every
 * particle crosses, where a split only slows the trace
 * (docs/light-volume.md, "Only where the light is focused"). */
#define LVCL_REFINE_FOCUS 0.1

/* Refined cells and directions (docs/light-volume.md): after a part of
 * the trace and before lvcl_volume_finish, splits the stored cells whose
 * tallies say the particles cross them densely (pieces per particle x
 * expected_particles at least settings->refine_density x
 * sqrt(expected_particles)) and whose light came by specular scatters
 * alone for at least settings->refine_focus of its luminance (the lobe
 * sums over the bins), the densest first, by planes through their
 * middle along the axes their own planes leave free; then gives the
 * slots of other cells whose brightest bin holds settings->refine_peak
 * times their mean bin and whose pieces reach LVCL_FINE_DENSITY x
 * sqrt(expected_particles) 2n x 2n bins, the most concentrated first; all
 * while the volume stays within settings->refine_memory bytes on the
 * device (0: twice its size). A refined slot's tallies restart from the
 * particles traced so far (LV_RESTARTED); a retrace of those particles
 * (lvcl_volume_trace, restarted_only) gives them back, and until then its
 * lit volume scales for the particles it holds, so each region's estimate
 * stays unbiased either way. Once per volume; density and peak 0
 * refine nothing. The decision reads only integer tallies: the same on
 * every device and run. Not with merged cells (--merge-tolerance). */
lvcl_error lvcl_volume_refine(lvcl_light_volume *vol, double expected_particles, const lvcl_volume_settings *settings,
                              lvcl_status *st);

/* Empties the tallies and subcell records but keeps the particle count:
 * after lvcl_volume_merge, on every device but the first, so that the
 * next merge counts the particles traced so far once. */
lvcl_error lvcl_volume_empty(lvcl_light_volume *vol, lvcl_status *st);

/* After the trace: the per-cell lit volumes the lookups read (lv_lit_volumes). */
lvcl_error lvcl_volume_finish(lvcl_light_volume *vol, const lvcl_program *prog, lvcl_status *st);

/* Adds the tallies and subcell records of every volume (the same grid on
 * several devices, each with its own particles) and stores the sum, and the
 * particles of all, in each.
 * Integer tallies and counters make the sum exact and order-free. */
lvcl_error lvcl_volume_merge(lvcl_light_volume *const *vols, int count, lvcl_status *st);

/* Collective over the cluster: adds every process's volume (each the sum
 * of its devices', in vols[0]) as lvcl_volume_merge adds devices', and
 * stores the sum, and the particles of all, in each of the count volumes. */
lvcl_error lvcl_volume_reduce(lvcl_light_volume *const *vols, int count, lvcl_cluster *cluster, lvcl_status *st);

/* A 64-bit FNV-1a hash of the volume as the lookups read it: tallies,
 * subcell records and lit volumes (valid after lvcl_volume_finish), to
 * compare volumes built apart bit for bit. */
lvcl_error lvcl_volume_checksum(const lvcl_light_volume *vol, uint64_t *hash, lvcl_status *st);

/* Reads the tallies back (tally_sets x bins x 3 int64, malloc'ed) and, if
 * records is not NULL, the subcell records in one block: LV_MARK_WORDS per
 * slot (one spare slot more), then LV_RAY_WORDS per subcell entry, then a
 * lit point per entry (shared_types.h). */
lvcl_error lvcl_volume_read(const lvcl_light_volume *vol, int64_t **tallies, uint32_t **records, lvcl_status *st);
/* The bytes of that block of subcell records. */
size_t lvcl_volume_record_bytes(const lvcl_light_volume *vol);

/* Reads back the lit volume of every slot as lv_lit_volumes computed it
 * (cell units, malloc'ed; valid after lvcl_volume_finish). */
lvcl_error lvcl_volume_read_lit(const lvcl_light_volume *vol, float **lit, lvcl_status *st);

const lv_grid_info *lvcl_volume_grid(const lvcl_light_volume *vol);

/* From the next trace on (retraces excepted), each particle adds the light
 * it brings to a surface to the sum of the region in front of it (on its
 * side) and of its light group (lv_light.group, below `groups`), where
 * seen[slot] (slot_count + 1 entries) numbers that region among `count`
 * the camera sees, else is LV_EMPTY_CELL (host/render/session_view.c).
 * seen NULL: no more (st may then be NULL). */
lvcl_error lvcl_volume_view_probe(lvcl_light_volume *vol, const uint32_t *seen, size_t count, size_t groups,
                                  lvcl_status *st);
/* Whether the volume is probing the view, and its sums' count (count x
 * groups x 2; 0 without a probe). */
int lvcl_volume_view_probing(const lvcl_light_volume *vol);
size_t lvcl_volume_view_sums(const lvcl_light_volume *vol);
/* The probe's sums, count x groups x 2 (units of 2^-20 of the lights'
 * power: the light straight from the lights, then after scattering); all 0
 * without a probe. */
lvcl_error lvcl_volume_view_light(const lvcl_light_volume *vol, int64_t *units, lvcl_status *st);

/* The first slot of cell (x, y, z) (its region 0), or LV_EMPTY_CELL. */
uint32_t lvcl_volume_slot(const lvcl_light_volume *vol, uint32_t x, uint32_t y, uint32_t z);

/* The tally set of a slot: its own, or its merged block's (lvcl_volume_adapt),
 * with its flags (LV_FINE_DIRS, LV_RESTARTED; LV_TALLY_SET_OF drops them). */
uint32_t lvcl_volume_tally_set(const lvcl_light_volume *vol, uint32_t slot);

/* The slot of the region holding world point p (the lookups' slot), or
 * LV_EMPTY_CELL. */
uint32_t lvcl_volume_slot_at(const lvcl_light_volume *vol, const float p[3]);

lvcl_volume_stats lvcl_volume_stats_of(const lvcl_light_volume *vol);

/* The buffers the kernels take (the volume block of the contract) and the
 * bin table (kernels/shared_types.h), for binding kernels that read the
 * volume. */
const lvcl_volume_buffers *lvcl_volume_kernel_buffers(const lvcl_light_volume *vol);
cl_mem lvcl_volume_bin_table(const lvcl_light_volume *vol);
/* The bin table of 2n x 2n bins (the coarse one while no slot has fine bins). */
cl_mem lvcl_volume_fine_bin_table(const lvcl_light_volume *vol);

/* Guided mode, after lvcl_volume_finish: fills the guide table
 * (kernels/volume/guide.h), which lvcl_volume_guide_table then returns
 * (NULL before). */
lvcl_error lvcl_volume_fill_guide(lvcl_light_volume *vol, const lvcl_program *prog, lvcl_status *st);
cl_mem lvcl_volume_guide_table(const lvcl_light_volume *vol);

/* The gather's axis sums (kernels/integrator/gather.h) of the volume as
 * lvcl_volume_finish left it, computed on the first call after each
 * finish: *out is the buffer the gather pass takes, owned by vol. */
lvcl_error lvcl_volume_axis_sums(lvcl_light_volume *vol, const lvcl_program *prog, cl_mem *out, lvcl_status *st);

/* Releases everything; NULL is allowed. */
void lvcl_volume_release(lvcl_light_volume *vol);

#endif
