/* Exact shares of the regions of cut cells (docs/light-volume.md,
 * "Regions"): how much of each subcell (and of the whole cell) lies in each
 * region of its cell's planes. The region of sign pattern m is the box
 * clipped by the half-spaces s_i (n_i . u - c_i) >= 0, a convex polytope;
 * its volume is exact up to rounding (the lattice of points it replaces
 * measured shares in steps of 1/64 of a subcell, a bias on every cell of an
 * axis-aligned wall). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "light_volume_internal.h"
#include "../util/parallel.h"

#define MAX_VERTS 24
#define MAX_FACES 12

typedef struct {
    double v[MAX_VERTS][3];
    int n;
} polygon;

typedef struct {
    polygon f[MAX_FACES];
    int n;
} polytope;

static void sub3(const double a[3], const double b[3], double r[3])
{
    for (int k = 0; k < 3; k++) r[k] = a[k] - b[k];
}

/* The box lo + [0, size]^3 as six quadrilaterals, each in cyclic order. */
static void make_box(polytope *t, const double lo[3], double size)
{
    static const int quad[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
    double corner[8][3];
    for (int i = 0; i < 8; i++)
        for (int k = 0; k < 3; k++) corner[i][k] = lo[k] + (i >> k & 1 ? size : 0.0);
    t->n = 6;
    for (int f = 0; f < 6; f++) {
        t->f[f].n = 4;
        for (int j = 0; j < 4; j++) memcpy(t->f[f].v[j], corner[quad[f][j]], sizeof corner[0]);
    }
}

/* Keeps the part of t where s (n . u - c) >= 0, closing it with the cap
 * polygon in the plane. */
static void clip(polytope *t, const float plane[4], double s)
{
    double n[3] = {s * plane[0], s * plane[1], s * plane[2]}, c = s * plane[3];
    double cap[2 * MAX_FACES + 2 * MAX_VERTS][3];
    int caps = 0;
    polytope out;
    out.n = 0;
    for (int f = 0; f < t->n; f++) {
        const polygon *p = &t->f[f];
        polygon q;
        q.n = 0;
        for (int i = 0; i < p->n; i++) {
            const double *a = p->v[i], *b = p->v[(i + 1) % p->n];
            double da = lvcl_dot3(n, a) - c, db = lvcl_dot3(n, b) - c;
            if (da >= 0 && q.n < MAX_VERTS) memcpy(q.v[q.n++], a, sizeof q.v[0]);
            if (da == 0 && caps < (int)(sizeof cap / sizeof cap[0])) memcpy(cap[caps++], a, sizeof cap[0]);
            if ((da > 0 && db < 0) || (da < 0 && db > 0)) {
                double x[3], w = da / (da - db);
                for (int k = 0; k < 3; k++) x[k] = a[k] + w * (b[k] - a[k]);
                if (q.n < MAX_VERTS) memcpy(q.v[q.n++], x, sizeof x);
                if (caps < (int)(sizeof cap / sizeof cap[0])) memcpy(cap[caps++], x, sizeof x);
            }
        }
        if (q.n >= 3 && out.n < MAX_FACES) out.f[out.n++] = q;
    }
    /* The cap: the crossing points, without repeats, in angular order. */
    int unique = 0;
    for (int i = 0; i < caps; i++) {
        int seen = 0;
        for (int j = 0; j < unique && !seen; j++) {
            double d[3];
            sub3(cap[i], cap[j], d);
            seen = lvcl_dot3(d, d) < 1e-24;
        }
        if (!seen) memcpy(cap[unique++], cap[i], sizeof cap[0]);
    }
    if (unique >= 3 && out.n < MAX_FACES && unique <= MAX_VERTS) {
        double mid[3] = {0, 0, 0}, e1[3], e2[3], angle[MAX_VERTS];
        for (int i = 0; i < unique; i++)
            for (int k = 0; k < 3; k++) mid[k] += cap[i][k] / unique;
        double axis[3] = {fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0};
        lvcl_cross3(n, axis, e1);
        lvcl_cross3(n, e1, e2);
        for (int i = 0; i < unique; i++) {
            double d[3];
            sub3(cap[i], mid, d);
            angle[i] = atan2(lvcl_dot3(d, e2), lvcl_dot3(d, e1));
        }
        polygon *q = &out.f[out.n++];
        q->n = unique;
        for (int i = 0; i < unique; i++) {
            int rank = 0; /* insertion by rank: ties broken by index */
            for (int j = 0; j < unique; j++) rank += angle[j] < angle[i] || (angle[j] == angle[i] && j < i);
            memcpy(q->v[rank], cap[i], sizeof cap[0]);
        }
    }
    *t = out;
}

/* The volume of a convex polytope: pyramids from the mean of its vertices
 * (inside it) over every face. */
static double volume(const polytope *t)
{
    double ref[3] = {0, 0, 0};
    int count = 0;
    for (int f = 0; f < t->n; f++)
        for (int i = 0; i < t->f[f].n; i++, count++)
            for (int k = 0; k < 3; k++) ref[k] += t->f[f].v[i][k];
    if (t->n < 4 || !count) return 0.0;
    for (int k = 0; k < 3; k++) ref[k] /= count;
    double v = 0.0;
    for (int f = 0; f < t->n; f++) {
        const polygon *p = &t->f[f];
        double area[3] = {0, 0, 0};
        for (int i = 1; i + 1 < p->n; i++) {
            double a[3], b[3], x[3];
            sub3(p->v[i], p->v[0], a);
            sub3(p->v[i + 1], p->v[0], b);
            lvcl_cross3(a, b, x);
            for (int k = 0; k < 3; k++) area[k] += 0.5 * x[k];
        }
        double len = sqrt(lvcl_dot3(area, area)), d[3];
        if (!(len > 0)) continue;
        sub3(p->v[0], ref, d);
        v += len * fabs(lvcl_dot3(area, d) / len) / 3.0;
    }
    return v;
}

void lvcl_region_shares(const float planes[][4], int count, uint32_t k, float *out)
{
    uint32_t regions = 1u << count, subs = k ? k * k * k : 1u, per = 1u + subs;
    double size = k ? 1.0 / k : 1.0, whole[1 << LV_REGION_PLANES] = {0};
    for (uint32_t i = 0; i < subs; i++) {
        double lo[3] = {0, 0, 0};
        if (k) lo[0] = (i % k) * size, lo[1] = (i / k % k) * size, lo[2] = (i / (k * k)) * size;
        /* Each plane: the subcell wholly on its positive (1) or negative
         * (0) side, or cut (-1). */
        int side[LV_REGION_PLANES];
        for (int j = 0; j < count; j++) {
            double centre = 0, radius = 0;
            for (int a = 0; a < 3; a++) {
                centre += planes[j][a] * (lo[a] + 0.5 * size);
                radius += 0.5 * size * fabs(planes[j][a]);
            }
            centre -= planes[j][3];
            side[j] = centre >= radius ? 1 : centre <= -radius ? 0 : -1;
        }
        for (uint32_t m = 0; m < regions; m++) {
            int possible = 1, cut = 0;
            for (int j = 0; j < count; j++) {
                if (side[j] < 0) cut = 1;
                else if (side[j] != (int)(m >> j & 1u)) possible = 0;
            }
            double share = 0.0;
            if (possible && !cut) {
                share = 1.0;
            } else if (possible) {
                polytope t;
                make_box(&t, lo, size);
                for (int j = 0; j < count && t.n; j++)
                    if (side[j] < 0) clip(&t, planes[j], m >> j & 1u ? 1.0 : -1.0);
                share = fmin(1.0, volume(&t) / (size * size * size));
            }
            out[m * per + 1 + i] = (float)share;
            whole[m] += share / subs;
        }
    }
    for (uint32_t m = 0; m < regions; m++) out[m * per] = (float)whole[m];
}

/* A region smaller than this (of the cell) keeps its volume: it is all
 * rounding. */
#define OPEN_VOLUME_MIN 1e-3
/* The least share of its volume a region keeps, whatever its solids. */
#define OPEN_VOLUME_FLOOR 0.05

/* Keeps the part of t where s (n . u - c) >= 0, as clip does, but leaves
 * t whole where all of it is there already: clip would add the face a
 * plane through one of t's faces holds a second time as its cap. */
static void clip_if_cut(polytope *t, const float plane[4], double s)
{
    double n[3] = {s * plane[0], s * plane[1], s * plane[2]}, c = s * plane[3];
    int outside = 0;
    for (int f = 0; f < t->n && !outside; f++)
        for (int i = 0; i < t->f[f].n && !outside; i++) outside = lvcl_dot3(n, t->f[f].v[i]) - c < -1e-12;
    if (outside) clip(t, plane, s);
}

double lvcl_region_open_volume(const float planes[][4], int count, uint32_t pattern, const lvcl_cell_solids *solids)
{
    const double origin[3] = {0, 0, 0};
    polytope region;
    make_box(&region, origin, 1.0);
    for (int j = 0; j < count && region.n; j++) clip_if_cut(&region, planes[j], pattern >> j & 1u ? 1.0 : -1.0);
    double whole = volume(&region), open = whole;
    if (!(whole >= OPEN_VOLUME_MIN)) return whole;
    /* The union of the solids' parts, by inclusion and exclusion over
     * every set of them (two slabs crossing in a cell share a part). */
    for (uint32_t set = 1; set < 1u << solids->count; set++) {
        polytope inside = region;
        int members = 0;
        for (int i = 0; i < solids->count && inside.n; i++) {
            if (!(set >> i & 1u)) continue;
            const lvcl_solid_slab *s = &solids->solid[i];
            members++;
            for (int a = 0; a < 3 && inside.n; a++) {
                const float lo[4] = {s->axis[a][0], s->axis[a][1], s->axis[a][2], s->lo[a]};
                const float hi[4] = {s->axis[a][0], s->axis[a][1], s->axis[a][2], s->hi[a]};
                clip_if_cut(&inside, lo, 1.0);
                if (inside.n) clip_if_cut(&inside, hi, -1.0);
            }
        }
        if (inside.n) open += (members & 1 ? -1.0 : 1.0) * volume(&inside);
    }
    /* Never under a twentieth of the region: a slab whose faces were
     * paired wrongly must not leave a lit region next to no volume (its
     * light divided by it). A room's corner by a 30 cm shell slab keeps
     * an eighth of its region as air (a quarter read it 20% dark). */
    return fmax(open, OPEN_VOLUME_FLOOR * whole);
}

/* One thread's part of lvcl_region_shares_batch: every `stride`-th cell
 * from `first`. */
typedef struct {
    const lvcl_cell_planes *planes;
    const size_t *at;
    float *out;
    size_t first, count, stride;
    uint32_t k;
    int done;
} share_job;

static void *share_cells(void *arg)
{
    share_job *j = arg;
    for (size_t i = j->first; i < j->count; i += j->stride)
        if (j->planes[i].count)
            lvcl_region_shares((const float(*)[4])j->planes[i].planes, j->planes[i].count, j->k, j->out + j->at[i]);
    j->done = 1;
    return NULL;
}

void lvcl_region_shares_batch(const lvcl_cell_planes *planes, size_t count, uint32_t k, const size_t *at, float *out)
{
    enum { JOBS = 4 };
    share_job jobs[JOBS];
    for (int i = 0; i < JOBS; i++) jobs[i] = (share_job){planes, at, out, (size_t)i, count, JOBS, k, 0};
    lvcl_status ignored = {0};
    /* A part whose thread could not start runs here. */
    if (lvcl_run_parallel(share_cells, jobs, sizeof jobs[0], JOBS, &ignored))
        for (int i = 0; i < JOBS; i++)
            if (!jobs[i].done) share_cells(&jobs[i]);
}
