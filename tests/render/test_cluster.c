/* A render shared by processes (host/render/cluster.h), with the processes
 * played by threads of this program and the cluster by shared memory: the
 * render layer's distributed paths (batches and bands from a shared
 * counter, volumes and images added, adaptive epochs planned on every
 * rank, failures agreed) without MPI, so that they run under ASan too.
 * Each thread opens a session of its own, as each rank of lvcl-mpi does;
 * the images and light volumes must equal one session's bit for bit.
 * tests/app/mpi_tests.sh checks the same over MPI. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "../harness.h"

#define MAX_RANKS 4

/* Under ASan: the rank threads build kernels, and LLVM (inside PoCL's
 * compiler) installs an alternate signal stack of its own, from malloc, on
 * the thread that compiles; ASan then fails a CHECK unmapping "its" stack
 * when such a thread exits. ASan's own alternate stack is only for
 * reporting stack overflows, so it is left out here. */
const char *__asan_default_options(void);
const char *__asan_default_options(void)
{
    return "use_sigaltstack=0";
}

/* ---- the cluster over threads ---- */
typedef struct {
    pthread_barrier_t barrier;
    pthread_mutex_t lock;
    uint64_t counter;
    void *slots[MAX_RANKS]; /* each rank's data in a collective */
} shared_memory;

static lvcl_error t_restart(lvcl_cluster *c, lvcl_cluster_phase phase, lvcl_status *st)
{
    (void)st;
    shared_memory *m = c->impl;
    c->phase = phase;
    pthread_barrier_wait(&m->barrier);
    if (c->rank == 0) m->counter = 0;
    pthread_barrier_wait(&m->barrier);
    return LVCL_OK;
}

static lvcl_error t_take(lvcl_cluster *c, uint64_t n, uint64_t *first, lvcl_status *st)
{
    (void)st;
    shared_memory *m = c->impl;
    pthread_mutex_lock(&m->lock);
    *first = m->counter;
    m->counter += n;
    pthread_mutex_unlock(&m->lock);
    return LVCL_OK;
}

/* Element i of every rank's data combined in rank order, as MPI_Allreduce's built-in operations do. */
#define COMBINE(type, expr)                                                                                           \
    for (size_t i = 0; i < n; i++) {                                                                                  \
        type acc = ((type *)m->slots[0])[i];                                                                          \
        for (int r = 1; r < c->size; r++) {                                                                           \
            type b = ((type *)m->slots[r])[i];                                                                        \
            acc = expr;                                                                                               \
        }                                                                                                             \
        ((type *)out)[i] = acc;                                                                                       \
    }

static lvcl_error t_reduce(lvcl_cluster *c, void *data, size_t n, lvcl_reduce_op op, lvcl_status *st)
{
    shared_memory *m = c->impl;
    size_t size = op == LVCL_REDUCE_SUM_I64 || op == LVCL_REDUCE_SUM_U64 ? 8 : 4;
    void *out = malloc(n > 0 ? n * size : 1);
    if (!out) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of memory in the thread cluster");
    m->slots[c->rank] = data;
    pthread_barrier_wait(&m->barrier);
    switch (op) {
    case LVCL_REDUCE_SUM_I64: COMBINE(int64_t, acc + b) break;
    case LVCL_REDUCE_SUM_U64: COMBINE(uint64_t, acc + b) break;
    case LVCL_REDUCE_SUM_U32: COMBINE(uint32_t, acc + b) break;
    case LVCL_REDUCE_OR_U32: COMBINE(uint32_t, acc | b) break;
    case LVCL_REDUCE_MAX_U32: COMBINE(uint32_t, b > acc ? b : acc) break;
    case LVCL_REDUCE_MIN_I32: COMBINE(int32_t, b < acc ? b : acc) break;
    case LVCL_REDUCE_SUM_F32: COMBINE(float, acc + b) break;
    }
    /* Every rank has read every rank's data before any overwrites its own. */
    pthread_barrier_wait(&m->barrier);
    memcpy(data, out, n * size);
    c->comm_bytes[c->phase] += n * size;
    free(out);
    return LVCL_OK;
}

static lvcl_error t_gather(lvcl_cluster *c, const void *mine, size_t bytes, void *all, lvcl_status *st)
{
    (void)st;
    shared_memory *m = c->impl;
    m->slots[c->rank] = (void *)mine;
    pthread_barrier_wait(&m->barrier);
    for (int r = 0; r < c->size; r++) memcpy((char *)all + (size_t)r * bytes, m->slots[r], bytes);
    pthread_barrier_wait(&m->barrier);
    return LVCL_OK;
}

static void t_abort(lvcl_cluster *c, int status)
{
    (void)c;
    printf("FAIL cluster: a rank aborted with status %d\n", status);
    exit(1);
}

/* ---- one rank's render ---- */
typedef struct {
    lvcl_cluster cluster;
    const char *scene;
    const char *device;
    uint64_t device_memory;
    lvcl_render_request req;
    lvcl_render_result out;
    uint64_t checksum;
    uint64_t particles, pixels; /* this rank's share */
    lvcl_error e;
    lvcl_status st;
} rank_job;

/* As lvcl_app_main does: every step agreed, then the render. */
static void *render_rank(void *arg)
{
    rank_job *j = arg;
    lvcl_cluster *c = j->cluster.size ? &j->cluster : NULL;
    lvcl_scene scene = {0};
    lvcl_session *s = NULL;
    j->e = lvcl_cluster_agree(c, lvcl_scene_load(j->scene, &scene, &j->st), &j->st);
    if (j->e) {
        lvcl_scene_free(&scene);
        return NULL;
    }
    lvcl_session_config cfg = {
        .device = j->device, .seed = 3, .max_depth = 64, .fast_math = 1, .device_memory = j->device_memory,
        .cluster = c};
    j->e = lvcl_cluster_agree(c, lvcl_session_open(&scene, &cfg, &s, &j->st), &j->st);
    if (!j->e) j->e = lvcl_session_render(s, &j->req, &j->out, &j->st);
    if (!j->e && lvcl_session_volume(s, 0)) {
        j->e = lvcl_volume_checksum(lvcl_session_volume(s, 0), &j->checksum, &j->st);
        for (int d = 0; d < lvcl_session_device_count(s); d++)
            j->particles += lvcl_volume_stats_of(lvcl_session_volume(s, d)).particles;
    }
    for (int d = 0; s && d < lvcl_session_device_count(s); d++) j->pixels += lvcl_session_pass_share(s, d).pixels;
    lvcl_session_close(s);
    return NULL;
}

/* Renders req on `ranks` threads sharing a cluster (0: one session alone).
 * jobs[r].device and device_memory may be set beforehand. */
static void render_shared(int ranks, const char *scene, const lvcl_render_request *req, rank_job *jobs)
{
    shared_memory m = {.counter = 0};
    int n = ranks ? ranks : 1;
    pthread_barrier_init(&m.barrier, NULL, (unsigned)n);
    pthread_mutex_init(&m.lock, NULL);
    pthread_t threads[MAX_RANKS];
    for (int r = 0; r < n; r++) {
        jobs[r].scene = scene;
        jobs[r].req = *req;
        if (ranks)
            jobs[r].cluster = (lvcl_cluster){.rank = r,
                                             .size = ranks,
                                             .impl = &m,
                                             .restart = t_restart,
                                             .take = t_take,
                                             .reduce = t_reduce,
                                             .gather = t_gather,
                                             .abort = t_abort};
        pthread_create(&threads[r], NULL, render_rank, &jobs[r]);
    }
    for (int r = 0; r < n; r++) pthread_join(threads[r], NULL);
    pthread_barrier_destroy(&m.barrier);
    pthread_mutex_destroy(&m.lock);
}

static void free_jobs(rank_job *jobs, int n)
{
    for (int r = 0; r < n; r++) free(jobs[r].out.rgb);
}

/* The image of every rank equals one session's bit for bit, and so does
 * the light volume; the ranks' shares add up to the whole. */
static void compare_with_one(const char *name, const char *scene, const lvcl_render_request *req, int ranks)
{
    char what[200];
    rank_job one[1], many[MAX_RANKS];
    memset(one, 0, sizeof one);
    memset(many, 0, sizeof many);
    render_shared(0, scene, req, one);
    render_shared(ranks, scene, req, many);
    snprintf(what, sizeof what, "%s: one session renders", name);
    CHECK(what, !one[0].e, "%s", one[0].st.message);
    uint64_t particles = 0, pixels = 0;
    for (int r = 0; r < ranks && !one[0].e; r++) {
        rank_job *j = &many[r];
        snprintf(what, sizeof what, "%s, rank %d of %d: the one-session image bit for bit", name, r, ranks);
        size_t values = (size_t)one[0].out.width * one[0].out.height * 3;
        CHECK(what,
              !j->e && j->out.width == one[0].out.width && j->out.height == one[0].out.height &&
                  j->out.samples == one[0].out.samples && !memcmp(j->out.rgb, one[0].out.rgb, values * sizeof(float)),
              "%s", j->e ? j->st.message : "the images differ");
        if (one[0].checksum) {
            snprintf(what, sizeof what, "%s, rank %d of %d: the one-session light volume", name, r, ranks);
            CHECK(what, j->checksum == one[0].checksum, "checksum %016llx, expected %016llx",
                  (unsigned long long)j->checksum, (unsigned long long)one[0].checksum);
        }
        particles += j->particles;
        pixels += j->pixels;
    }
    if (one[0].checksum) {
        snprintf(what, sizeof what, "%s: the ranks traced every particle once", name);
        CHECK(what, particles == req->volume.particles, "%llu of %llu", (unsigned long long)particles,
              (unsigned long long)req->volume.particles);
    }
    if (!req->pass.adaptive) {
        snprintf(what, sizeof what, "%s: the ranks rendered every pixel once", name);
        CHECK(what, pixels == (uint64_t)req->width * req->height, "%llu of %d", (unsigned long long)pixels,
              req->width * req->height);
    }
    free_jobs(one, 1);
    free_jobs(many, ranks);
}

/* One rank's failure reaches every rank, naming it. */
static void check_failure(const char *name, int ranks, int failing, const char *device, uint64_t device_memory,
                          const lvcl_render_request *req, const char *expected)
{
    rank_job jobs[MAX_RANKS];
    memset(jobs, 0, sizeof jobs);
    jobs[failing].device = device;
    jobs[failing].device_memory = device_memory;
    render_shared(ranks, "cornell", req, jobs);
    char prefix[32], what[200];
    snprintf(prefix, sizeof prefix, "rank %d: ", failing);
    for (int r = 0; r < ranks; r++) {
        snprintf(what, sizeof what, "%s: rank %d stops with rank %d's error", name, r, failing);
        CHECK(what, jobs[r].e && !strncmp(jobs[r].st.message, prefix, strlen(prefix)) &&
                        strstr(jobs[r].st.message, expected),
              "error %d: '%s'", jobs[r].e, jobs[r].st.message);
    }
    free_jobs(jobs, ranks);
}

int main(void)
{
    /* Several batches of 2^18 particles, and adaptive epochs past 8 spp. */
    lvcl_render_request lv = harness_request(LVCL_MODE_LV, 40, 20, 16, 700000);
    lv.pass.adaptive = 1;
    compare_with_one("lv, adaptive", "cornell", &lv, 3);
    lvcl_render_request lv_all = lv;
    lv_all.mode = LVCL_MODE_LV_ALL;
    lv_all.pass.adaptive = 0;
    lv_all.volume.offset = 0.37;
    compare_with_one("lv-all, uniform, offset grid", "cornell", &lv_all, 2);
    lvcl_render_request refined = lv;
    refined.volume.particles = 1200000;
    refined.volume.refine_density = 1;
    refined.volume.refine_peak = 8;
    compare_with_one("lv, refined cells and directions", "cornell", &refined, 3);
    lvcl_render_request guided = lv;
    guided.mode = LVCL_MODE_GUIDED;
    compare_with_one("guided, adaptive", "cornell", &guided, 2);
    lvcl_render_request pt = harness_request(LVCL_MODE_PT, 40, 20, 0, 0);
    pt.pass.adaptive = 1;
    compare_with_one("pt, adaptive, kitchen", "kitchen", &pt, 3);

    /* A failure on one rank only: every rank stops, naming it. */
    check_failure("a device missing on one rank", 3, 1, "99", 0, &pt, "device 99 does not exist");
    lvcl_render_request big = pt;
    big.width = big.height = 2048;
    check_failure("an image too large for one rank's device", 2, 1, NULL, 64ull << 20, &big, "2048 x 2048 image");
    CHECK_EXIT();
}
