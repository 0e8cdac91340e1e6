/* The regions of cut cells (docs/light-volume.md, "Regions"): for every
 * stored cell, up to LV_GEOMETRY_PLANES planes of the geometry through it,
 * which split it into 2^P region slots so that light on the two sides of a
 * wall through the cell is tallied apart. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "light_volume_internal.h"

/* Triangles join a cluster whose normal is within 25 degrees of theirs
 * (either way round: both faces of a thin wall join) and whose offset is
 * within a quarter cell, unless they face each other across it (a leg's
 * top 1 mm under a table top, a cupboard beside a wall) or one is of solid
 * glass and the other not, or they are the two faces of a glass slab:
 * joined, the gap's air, or the glass's inside with the light that total
 * internal reflection traps there, would share a region with what lies
 * beyond, and a lookup would read that light. The two faces of an opaque
 * wall join: nothing lives between them. */
#define SAME_OFFSET 0.25 /* cells */
/* A plane must cut the cell by more than this (cells) to split it. */
#define CUT_MARGIN 1e-3
/* A part of a mesh's tree that spans at most two cells along every axis
 * and holds more triangles than this offers an evenly spaced sample of
 * this many, each weighing for its share: a tile of 500,000 ripples then
 * costs a few hundred triangles per placement, not all of them. */
#define SAMPLED_TRIANGLES 256

typedef struct {
    double ref[3];   /* the first triangle's normal */
    double sum_n[3]; /* area x normal, turned to ref's side */
    double sum_d;    /* area x offset, on ref's side */
    double area;
    /* Of the triangles whose front faces along +ref and along -ref: area
     * x offset (on ref's side), and area. */
    double facing_d[2], facing_area[2];
    int clear; /* it holds faces of solid glass */
    int next;  /* the cell's next cluster, -1 at the end */
} cluster;

typedef struct {
    cluster *pool;
    size_t count, capacity;
    int *head; /* per stored cell */
    int failed;
} clusters;

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Makes n's largest component positive (and d with it), so that a plane
 * has one orientation whatever triangle it came from. Returns -1 where it
 * turned n, else 1. */
static double canonical(double n[3], double *d)
{
    int k = fabs(n[0]) >= fabs(n[1]) && fabs(n[0]) >= fabs(n[2]) ? 0 : fabs(n[1]) >= fabs(n[2]) ? 1 : 2;
    if (n[k] >= 0) return 1.0;
    for (int i = 0; i < 3; i++) n[i] = -n[i];
    *d = -*d;
    return -1.0;
}

/* Whether plane n.x = d passes through the cell with corner lo and side h
 * by more than the margin. */
static int cuts_cell(const double n[3], double d, const double lo[3], double h)
{
    double centre = 0, radius = 0;
    for (int k = 0; k < 3; k++) {
        centre += n[k] * (lo[k] + 0.5 * h);
        radius += 0.5 * h * fabs(n[k]);
    }
    return fabs(centre - d) < radius - CUT_MARGIN * h;
}

/* Whether two parallel planes at offsets da and db (on one side) whose
 * triangles' fronts face along that side (1), against it (-1) or both
 * ways (0), of solid glass where clear_a, clear_b, stay apart: glass and
 * opaque geometry never join, nor do opposite fronts where they face each
 * other across a gap or are glass. */
static int stay_apart(double fa, double da, int clear_a, double fb, double db, int clear_b)
{
    if (clear_a != clear_b) return 1;
    if (!(fa * fb < 0)) return 0;
    return clear_a || (fa > 0 ? db > da : db < da);
}

/* Whether a triangle at offset d along ref (on ref's side) whose front
 * faces along +ref (front > 0) or -ref, of solid glass where clear, stays
 * apart from cluster k's triangles of the opposite front (stay_apart). */
static int keeps_apart(const cluster *k, double d, double front, int clear)
{
    int other = front > 0 ? 1 : 0; /* the opposite front's index: 0 is +ref, 1 is -ref */
    int any = k->facing_area[other] > 0;
    return stay_apart(front, d, clear, any ? -front : 0.0, any ? k->facing_d[other] / k->facing_area[other] : d,
                      k->clear);
}

/* Adds a triangle's plane n . x = d (n canonical; front: +1 where the
 * triangle's front faces along n, else -1; clear: of solid glass) to the
 * cell's clusters. */
static void add_to_cell(clusters *c, int cell, const double n[3], double d, double front, int clear, double area,
                        double h)
{
    for (int i = c->head[cell]; i >= 0; i = c->pool[i].next) {
        cluster *k = &c->pool[i];
        double cosine = dot3(n, k->ref);
        if (fabs(cosine) <= LVCL_SAME_NORMAL) continue;
        double s = cosine > 0 ? 1.0 : -1.0;
        if (fabs(s * d - k->sum_d / k->area) >= SAME_OFFSET * h) continue;
        if (keeps_apart(k, s * d, s * front, clear)) continue;
        for (int j = 0; j < 3; j++) k->sum_n[j] += s * area * n[j];
        k->sum_d += s * area * d;
        k->area += area;
        k->facing_d[s * front > 0 ? 0 : 1] += s * area * d;
        k->facing_area[s * front > 0 ? 0 : 1] += area;
        k->clear |= clear;
        return;
    }
    if (c->count == c->capacity) {
        size_t cap = c->capacity ? 2 * c->capacity : 4096;
        cluster *p = realloc(c->pool, cap * sizeof *p);
        if (!p) {
            c->failed = 1;
            return;
        }
        c->pool = p;
        c->capacity = cap;
    }
    cluster *k = &c->pool[c->count];
    for (int j = 0; j < 3; j++) k->ref[j] = n[j], k->sum_n[j] = area * n[j];
    k->sum_d = area * d;
    k->area = area;
    k->facing_d[front > 0 ? 0 : 1] = area * d;
    k->facing_area[front > 0 ? 0 : 1] = area;
    k->facing_d[front > 0 ? 1 : 0] = k->facing_area[front > 0 ? 1 : 0] = 0.0;
    k->clear = clear;
    k->next = c->head[cell];
    c->head[cell] = (int)c->count++;
}

/* Adds one placed triangle, weighing `weight` times its area, to the
 * clusters of every stored cell its box (grown by a hundredth of a cell)
 * overlaps and its plane cuts. */
static void add_triangle(clusters *c, const lv_grid_info *g, const uint32_t *stored, const float v[9], int clear,
                         double weight)
{
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; k++) e1[k] = (double)v[3 + k] - v[k], e2[k] = (double)v[6 + k] - v[k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double len = sqrt(dot3(n, n));
    if (!(len > 0) || !isfinite(len)) return;
    for (int k = 0; k < 3; k++) n[k] /= len;
    double p0[3] = {v[0], v[1], v[2]}, d = dot3(n, p0), h = g->cell_size;
    double front = canonical(n, &d); /* the winding's front: along n (1) or against it (-1) */
    /* No triangle has more area inside a cube than its largest section. */
    double area = weight * fmin(0.5 * len, sqrt(2.0) * h * h);
    int lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        double a = fmin(v[k], fmin(v[3 + k], v[6 + k])), b = fmax(v[k], fmax(v[3 + k], v[6 + k]));
        lo[k] = (int)floor((a - g->origin[k]) / h - 0.01);
        hi[k] = (int)floor((b - g->origin[k]) / h + 0.01);
        if (lo[k] < 0) lo[k] = 0;
        if (hi[k] > (int)g->dims[k] - 1) hi[k] = (int)g->dims[k] - 1;
    }
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++)
            for (int x = lo[0]; x <= hi[0]; x++) {
                uint32_t s = stored[lvcl_volume_cell_index(g, x, y, z)];
                if (s == LV_EMPTY_CELL) continue;
                double corner[3] = {g->origin[0] + x * h, g->origin[1] + y * h, g->origin[2] + z * h};
                if (cuts_cell(n, d, corner, h)) add_to_cell(c, (int)s, n, d, front, clear, area, h);
            }
}

/* The triangles below node n, which lie in one run of the leaf order (the
 * tree is stored depth first): from its leftmost leaf to its rightmost. */
static void subtree_triangles(const lvcl_packed_scene *p, const lvcl_bvh_node *n, size_t *first, size_t *count)
{
    const lvcl_bvh_node *left = n, *right = n;
    while (left->count == 0) left = left + 1;
    while (right->count == 0) right = &p->tree_nodes[right->index];
    *first = (size_t)left->index;
    *count = (size_t)(right->index + right->count) - *first;
}

/* Whether node n, as instance inst places it, spans at most two cells along every axis. */
static int spans_few_cells(const lv_grid_info *g, const lv_instance *inst, const lvcl_bvh_node *n)
{
    float lo_w[3], hi_w[3];
    int lo[3], hi[3];
    lvcl_transform_box(inst->world_from_object, n->bmin, n->bmax, lo_w, hi_w);
    return lvcl_volume_box_cells(g, lo_w, hi_w, lo, hi);
}

/* The planes of one stored cell (corner lo): the heaviest clusters that
 * cut it, in cell units from its corner. Returns their count. */
static int choose_planes(const clusters *c, int cell, const double lo[3], double h, float planes[][4])
{
    int chosen[LV_GEOMETRY_PLANES], count = 0;
    double pn[LV_GEOMETRY_PLANES][3], pd[LV_GEOMETRY_PLANES], pf[LV_GEOMETRY_PLANES];
    int pclear[LV_GEOMETRY_PLANES];
    for (int round = 0; round < LV_GEOMETRY_PLANES; round++) {
        int best = -1;
        /* The heaviest cluster not yet taken; the earliest made on a tie. */
        for (int i = c->head[cell]; i >= 0; i = c->pool[i].next) {
            int taken = 0;
            for (int j = 0; j < round; j++) taken |= chosen[j] == i;
            if (!taken && (best < 0 || c->pool[i].area >= c->pool[best].area)) best = i;
        }
        if (best < 0) break;
        chosen[round] = best;
        const cluster *k = &c->pool[best];
        double n[3], len = sqrt(dot3(k->sum_n, k->sum_n));
        if (!(len > 0)) continue;
        for (int j = 0; j < 3; j++) n[j] = k->sum_n[j] / len;
        double d = k->sum_d / k->area;
        canonical(n, &d);
        if (!cuts_cell(n, d, lo, h)) continue;
        /* Its triangles' front, along n (1), against it (-1), or both (0). */
        double along = dot3(n, k->ref) > 0 ? 1.0 : -1.0;
        double f = k->facing_area[1] == 0 ? along : k->facing_area[0] == 0 ? -along : 0.0;
        int same = 0;
        for (int j = 0; j < count; j++) {
            double s = dot3(n, pn[j]) > 0 ? 1.0 : -1.0, dj = s * d, fj = s * f; /* on plane j's side */
            same |= fabs(dot3(n, pn[j])) > LVCL_SAME_NORMAL && fabs(dj - pd[j]) < SAME_OFFSET * h &&
                !stay_apart(pf[j], pd[j], pclear[j], fj, dj, k->clear);
        }
        if (same) continue;
        for (int j = 0; j < 3; j++) pn[count][j] = n[j];
        pd[count] = d;
        pf[count] = f;
        pclear[count] = k->clear;
        /* n . (lo + h u) = d  <=>  n . u = (d - n . lo) / h */
        for (int j = 0; j < 3; j++) planes[count][j] = (float)n[j];
        planes[count][3] = (float)((d - dot3(n, lo)) / h);
        count++;
    }
    return count;
}

lvcl_error lvcl_volume_build_regions(const lvcl_packed_scene *p, lv_grid_info *g, size_t cells, uint32_t *slot,
                                     lv_slot_region **regions, float **shares, size_t *share_count, lvcl_status *st)
{
    *regions = NULL;
    *shares = NULL;
    *share_count = 0;
    size_t stored = g->slot_count;
    clusters c = {0};
    c.head = malloc((stored ? stored : 1) * sizeof *c.head);
    lvcl_cell_planes *planes = malloc((stored ? stored : 1) * sizeof *planes);
    if (!c.head || !planes) {
        free(c.head);
        free(planes);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the cells' planes");
    }
    for (size_t i = 0; i < stored; i++) c.head[i] = -1;
    /* Every placed triangle, leaf by leaf, or a sample of a small part's. */
    int stack[LVCL_BVH_MAX_DEPTH + 1];
    for (size_t in = 0; in < p->instance_count && !c.failed; in++) {
        const lv_instance *inst = &p->instances[in];
        int top = 0;
        stack[top++] = (int)p->mesh_tree_root[inst->mesh];
        while (top > 0 && !c.failed) {
            const lvcl_bvh_node *n = &p->tree_nodes[stack[--top]];
            size_t first, count;
            subtree_triangles(p, n, &first, &count);
            if (n->count > 0 || (count > SAMPLED_TRIANGLES && spans_few_cells(g, inst, n))) {
                size_t taken = count > SAMPLED_TRIANGLES ? SAMPLED_TRIANGLES : count;
                for (size_t i = 0; i < taken; i++) {
                    float v[9];
                    size_t t = first + i * count / taken;
                    lvcl_packed_triangle_world(p, in, t, v);
                    int clear = p->materials[p->triangles[t].material].bsdf == LV_BSDF_GLASS;
                    add_triangle(&c, g, slot, v, clear, (double)count / (double)taken);
                }
            } else {
                stack[top++] = (int)(n - p->tree_nodes) + 1;
                stack[top++] = n->index;
            }
        }
    }
    if (!c.failed)
        for (size_t z = 0, i = 0; z < g->dims[2]; z++)
            for (size_t y = 0; y < g->dims[1]; y++)
                for (size_t x = 0; x < g->dims[0]; x++, i++) {
                    uint32_t s = slot[i];
                    if (s == LV_EMPTY_CELL) continue;
                    double lo[3] = {g->origin[0] + (double)x * g->cell_size, g->origin[1] + (double)y * g->cell_size,
                                    g->origin[2] + (double)z * g->cell_size};
                    planes[s].count = (uint8_t)choose_planes(&c, (int)s, lo, g->cell_size, planes[s].planes);
                }
    int failed = c.failed;
    free(c.head);
    free(c.pool);
    lvcl_error e = failed
        ? lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the cells' planes")
        : lvcl_volume_lay_out_regions(g, cells, planes, NULL, NULL, slot, regions, shares, share_count, st);
    free(planes);
    return e;
}

lvcl_error lvcl_volume_lay_out_regions(lv_grid_info *g, size_t cells, const lvcl_cell_planes *planes,
                                       lvcl_known_shares known, void *ctx, uint32_t *slot, lv_slot_region **regions,
                                       float **shares, size_t *share_count, lvcl_status *st)
{
    *regions = NULL;
    *shares = NULL;
    *share_count = 0;
    size_t stored = g->slot_count;
    /* Per stored cell: its first slot, its pattern -> slot offsets,
     * which patterns have a region of their own and where their shares
     * start. */
    enum { MAX_PATTERNS = 1 << LV_REGION_PLANES, OFFSET_WORDS = MAX_PATTERNS / 4 };
    uint32_t k = g->subcells, per = 1u + (k ? k * k * k : 1u);
    size_t total = 0, share_total = 0, share_cap = 0;
    uint32_t *base = malloc((stored ? stored : 1) * sizeof *base);
    uint32_t *offsets = calloc((stored ? stored : 1) * OFFSET_WORDS, sizeof *offsets);
    uint32_t *first = malloc((stored ? stored : 1) * sizeof *first);
    uint64_t *kept = malloc((stored ? stored : 1) * sizeof *kept);
    float *sh = NULL, *tmp = malloc(MAX_PATTERNS * (1u + LV_SUBCELL_MAX) * sizeof *tmp);
    int failed = !base || !offsets || !first || !kept || !tmp;
    for (size_t s = 0; s < stored && !failed; s++) {
        uint32_t count = planes[s].count;
        base[s] = (uint32_t)total;
        first[s] = LV_NO_SHARES;
        kept[s] = 1;
        if (!count) {
            total++;
            continue;
        }
        /* The exact shares (volume_shares.c); a pattern whose region
         * has under a millionth of the cell gets no slot. */
        uint32_t patterns = 1u << count, index[MAX_PATTERNS], n = 0;
        if (!known || !known(ctx, (uint32_t)s, tmp))
            lvcl_region_shares((const float(*)[4])planes[s].planes, (int)count, k, tmp);
        kept[s] = 0;
        for (uint32_t m = 0; m < patterns; m++)
            if (tmp[m * per] > 1e-6f) kept[s] |= (uint64_t)1 << m, index[m] = n++;
        if (!n) kept[s] = 1, index[0] = n++; /* rounding only: keep one */
        for (uint32_t m = 0; m < patterns; m++) {
            /* An empty pattern reads the kept one fewest planes away. */
            uint32_t best = m;
            for (uint32_t q = 0; !(kept[s] >> best & 1u) && q < patterns; q++)
                if (kept[s] >> q & 1u) best = q;
            for (uint32_t q = 0; q < patterns && !(kept[s] >> m & 1u); q++)
                if (kept[s] >> q & 1u && __builtin_popcount(q ^ m) < __builtin_popcount(best ^ m)) best = q;
            offsets[s * OFFSET_WORDS + m / 4] |= index[best] << (8u * (m % 4));
        }
        if (share_total + (size_t)n * per > share_cap) {
            size_t cap = share_cap ? 2 * share_cap : 65536;
            while (cap < share_total + (size_t)n * per) cap *= 2;
            float *grown = realloc(sh, cap * sizeof *sh);
            if (!grown) {
                failed = 1;
                break;
            }
            sh = grown;
            share_cap = cap;
        }
        first[s] = (uint32_t)share_total;
        for (uint32_t m = 0; m < patterns; m++)
            if (kept[s] >> m & 1u) {
                memcpy(sh + share_total, tmp + m * per, per * sizeof *sh);
                share_total += per;
            }
        total += n;
    }
    lv_slot_region *r = NULL;
    if (!failed && !sh) sh = calloc(1, sizeof *sh);
    if (!failed && sh && total < LV_CUT_CELL - 1) r = calloc(total + 1, sizeof *r);
    if (!r) {
        free(base);
        free(offsets);
        free(first);
        free(kept);
        free(tmp);
        free(sh);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the cells' regions");
    }
    for (size_t s = 0; s < stored; s++)
        for (uint32_t m = 0, j = 0; m < 1u << planes[s].count; m++) {
            if (!(kept[s] >> m & 1u)) continue;
            lv_slot_region *e = &r[base[s] + j];
            memcpy(e->planes, planes[s].planes, sizeof e->planes);
            memcpy(e->offsets, &offsets[s * OFFSET_WORDS], sizeof e->offsets);
            e->plane_count = planes[s].count;
            e->base_slot = base[s];
            e->region = m;
            e->shares = planes[s].count ? first[s] + j * per : LV_NO_SHARES;
            j++;
        }
    r[total].shares = LV_NO_SHARES;
    *shares = sh;
    *share_count = share_total;
    for (size_t i = 0; i < cells; i++)
        if (slot[i] != LV_EMPTY_CELL) slot[i] = base[slot[i]] | (planes[slot[i]].count ? LV_CUT_CELL : 0u);
    g->slot_count = (lv_u32)total;
    free(base);
    free(offsets);
    free(first);
    free(kept);
    free(tmp);
    *regions = r;
    return LVCL_OK;
}
