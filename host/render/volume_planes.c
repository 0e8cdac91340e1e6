/* The regions of cut cells (docs/light-volume.md, "Regions"): for every
 * stored cell, up to LV_GEOMETRY_PLANES planes of the geometry through it,
 * which split it into 2^P region slots so that light on the two sides of a
 * wall through the cell is tallied apart. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "light_volume_internal.h"

/* Parallel planes (normals within 25 degrees, either way round) within a
 * quarter cell join one cluster, as a thin wall's two faces should,
 * unless they must stay apart (cluster_cell): a surface facing another
 * across a gap (a leg's top 1 mm under a table top, a cupboard beside a
 * wall), glass and opaque geometry, a glass slab's two faces. Joined, the
 * gap's air, or the glass's inside with the light that total internal
 * reflection traps there, would share a region with what lies beyond,
 * and a lookup would read that light. */
#define SAME_OFFSET 0.25 /* cells */
/* Parallel facets (normals within a degree) of one front, one beyond the
 * other by more than this (cells), are two layers (a panel against a wall,
 * two walls of one polygon each round a narrow corridor) and stay apart:
 * joined, the air in front of the nearer would share a region with what
 * lies behind it. Facets of a curved or rippled surface within a degree of
 * each other lie side by side, their offsets far closer than this. */
#define LAYER_NORMAL 0.99985
#define LAYER_OFFSET 0.05
/* A facet that lies over the other (their extents overlap) is a layer from
 * this offset on (cells): no piece of one smooth surface lies over
 * another, and a corridor 3 cm wide in a cell of 75 cm (0.04) joined its
 * two walls at LAYER_OFFSET, so its light shared the room's region. */
#define LAYER_OVER_OFFSET 0.01
/* A plane must cut the cell by more than this (cells) to split it. */
#define CUT_MARGIN 1e-3
/* A part of a mesh's tree that spans at most two cells along every axis
 * and holds more triangles than this offers an evenly spaced sample of
 * this many, each weighing for its share: a tile of 500,000 ripples then
 * costs a few hundred triangles per placement, not all of them. */
#define SAMPLED_TRIANGLES 256
/* Triangles of one plane (normals within 0.01 degrees, offsets within
 * 10^-4 cell, one front, glass or not) make one facet as they come; a
 * cell's facets are clustered once all are in, in the order of their
 * offsets, so that no cluster reaches across another and the result does
 * not hang on the order of the triangles. */
#define FACET_NORMAL 0.99999998
#define FACET_OFFSET 1e-4 /* cells */
#define FACETS_LOOKED_AT 8
/* Planes of a cell that go first to clusters facing each other across a
 * narrow gap (choose_planes): one gap's two sides. */
#define GAP_PLANES 2
/* Planes a crowded cell takes beyond LV_GEOMETRY_PLANES, each only for the
 * other layer of a chosen cluster: two one-polygon walls round a corridor,
 * where the cell's floor and an outer wall hold two planes already. */
#define LAYER_PLANES 1

/* What a triangle's surface is (surface_kinds). */
#define SURFACE_SHEET 1      /* it has open edges */
#define SURFACE_LIT_INSIDE 2 /* closed, facing out, with a light inside: lit air behind its faces */

typedef struct {
    double n[3];                  /* the first triangle's normal, canonical */
    double sum_n[3], sum_d, area; /* area x normal, area x offset, area */
    double front;                 /* 1 where the triangles' front faces along n, else -1 */
    /* Its extent in the cell along two axes in its plane (facet_axes): the
     * first, and n x it. Floats: a large scene holds millions of facets. */
    float axis[3], lo[2], hi[2];
    int extent;                   /* 1 while every triangle's facet_axes match the first's */
    int clear;                    /* of solid glass */
    int sheet;                    /* of a surface with open edges (a wall of one polygon), not a closed solid's face */
    int lit_back;                 /* of a closed surface facing out with a light inside (SURFACE_LIT_INSIDE) */
    int next;                     /* the cell's next facet, -1 at the end */
} facet;

typedef struct {
    facet *pool;
    size_t count, capacity;
    int *head; /* per stored cell, its newest facet */
    int failed;
} facets;

/* A facet turned to the side of its group's reference normal. */
typedef struct {
    int group, order; /* the group of parallel facets; the facet's place in the cell */
    int cluster;      /* the cluster it joined (cluster_cell), or -1 where hidden */
    double n[3], d, area, front;
    double axes[2][3], lo[2], hi[2]; /* its extent in the cell (facet) */
    int extent;                      /* 1 where that is known */
    int clear, sheet, lit_back;
    int hidden; /* against a larger facet of the other front, in its plane */
} turned_facet;

/* The extent in the cell of a cluster's facets of one front. */
typedef struct {
    double axes[2][3], lo[2], hi[2];
    int known; /* 1 where every such facet's axes match the first's */
} face_extent;

typedef struct {
    double sum_n[3], sum_d, area; /* on the group's side */
    double top_along;             /* the largest offset of a front along the group's normal; -HUGE_VAL if none */
    double top_against;           /* and of a front against it */
    double along_n[3], against_n[3]; /* the normals of those two facets */
    face_extent along, against;      /* the extents of its facets of each front */
    face_extent top_along_extent, top_against_extent; /* and of those two facets */
    int clear, gap;                  /* of glass; it faces another cluster across a gap */
    int sheet;                       /* it holds a facet of a sheet */
    int group;                    /* of parallel clusters (cluster_cell) */
    int backs_onto_previous;      /* it and the group's cluster below it face away from each other (solid between) */
    int layer; /* it began beyond a parallel facet of the same front in the cluster below, or back to back with a sheet */
} cluster;

/* Scratch space for one cell's clustering, kept from cell to cell. */
typedef struct {
    turned_facet *turned;
    double (*refs)[3];
    cluster *clusters;
    size_t capacity;
} cell_scratch;

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

/* A triangle clipped by a cell: at most three corners and one more per face. */
#define CLIPPED_CORNERS 9
typedef struct {
    double p[CLIPPED_CORNERS][3];
    int count;
} clipped;

/* The extent along `axis` of something whose extent along `axes` is lo,
 * hi, in *l, *h: where one of the axes is `axis` or its opposite (within
 * a degree). Returns 0 where neither is. */
static int extent_along(const double axes[2][3], const double lo[2], const double hi[2], const double axis[3],
                        double *l, double *h)
{
    for (int k = 0; k < 2; k++) {
        double c = lvcl_dot3(axes[k], axis);
        if (fabs(c) <= LAYER_NORMAL) continue;
        *l = c > 0 ? lo[k] : -hi[k];
        *h = c > 0 ? hi[k] : -lo[k];
        return 1;
    }
    return 0;
}

/* Whether axes a and b are the same up to order and sign (within a degree). */
static int axes_match(const double a[2][3], const double b[2][3])
{
    return (fabs(lvcl_dot3(a[0], b[0])) > LAYER_NORMAL && fabs(lvcl_dot3(a[1], b[1])) > LAYER_NORMAL) ||
        (fabs(lvcl_dot3(a[0], b[1])) > LAYER_NORMAL && fabs(lvcl_dot3(a[1], b[0])) > LAYER_NORMAL);
}

/* Extends lo, hi (along axes) to hold polygon c. */
static void extend(const double axes[2][3], const clipped *c, double lo[2], double hi[2])
{
    for (int i = 0; i < c->count; i++)
        for (int k = 0; k < 2; k++) {
            double x = lvcl_dot3(c->p[i], axes[k]);
            lo[k] = fmin(lo[k], x), hi[k] = fmax(hi[k], x);
        }
}

/* Facet k's axes and extent, in doubles. */
static void facet_frame(const facet *k, double axes[2][3], double lo[2], double hi[2])
{
    for (int j = 0; j < 3; j++) axes[0][j] = k->axis[j];
    lvcl_cross3(k->n, axes[0], axes[1]);
    for (int j = 0; j < 2; j++) lo[j] = k->lo[j], hi[j] = k->hi[j];
}

/* Stores an extent in facet k's floats, rounded outwards. */
static void keep_extent(facet *k, const double lo[2], const double hi[2])
{
    for (int j = 0; j < 2; j++) {
        k->lo[j] = nextafterf((float)lo[j], -HUGE_VALF);
        k->hi[j] = nextafterf((float)hi[j], HUGE_VALF);
    }
}

/* Adds a triangle's plane n . x = d (n canonical; front: +1 where the
 * triangle's front faces along n, else -1; clear: of solid glass), its
 * part in the cell (part, weighing `area`), to the cell's facet of that
 * plane, or makes one, whose extent is measured along `axes`
 * (facet_axes of the triangle). */
static void add_to_cell(facets *f, int cell, const double n[3], double d, double front, int clear, int kind,
                        double area, const clipped *part, const double axes[2][3], double h)
{
    /* A plane's triangles mostly come one after another: looking at the
     * newest few facets keeps this step's cost flat in dense cells. */
    int looked = 0;
    for (int i = f->head[cell]; i >= 0 && looked < FACETS_LOOKED_AT; i = f->pool[i].next, looked++) {
        facet *k = &f->pool[i];
        if (lvcl_dot3(n, k->n) <= FACET_NORMAL || k->front != front || k->clear != clear ||
            fabs(d - k->sum_d / k->area) >= FACET_OFFSET * h)
            continue;
        for (int j = 0; j < 3; j++) k->sum_n[j] += area * n[j];
        k->sum_d += area * d;
        k->area += area;
        k->sheet |= (kind & SURFACE_SHEET) != 0;
        k->lit_back |= (kind & SURFACE_LIT_INSIDE) != 0;
        /* An extent along axes that some triangle's do not match would
         * depend on which triangle came first. */
        double own[2][3], lo[2], hi[2];
        facet_frame(k, own, lo, hi);
        k->extent &= axes_match(axes, (const double(*)[3])own);
        extend((const double(*)[3])own, part, lo, hi);
        keep_extent(k, lo, hi);
        return;
    }
    if (f->count == f->capacity) {
        size_t cap = f->capacity ? 2 * f->capacity : 4096;
        facet *p = realloc(f->pool, cap * sizeof *p);
        if (!p) {
            f->failed = 1;
            return;
        }
        f->pool = p;
        f->capacity = cap;
    }
    facet *k = &f->pool[f->count];
    for (int j = 0; j < 3; j++) k->n[j] = n[j], k->sum_n[j] = area * n[j];
    k->sum_d = area * d;
    k->area = area;
    k->front = front;
    for (int j = 0; j < 3; j++) k->axis[j] = (float)axes[0][j];
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    extend(axes, part, lo, hi);
    keep_extent(k, lo, hi);
    k->extent = 1;
    k->clear = clear;
    k->sheet = (kind & SURFACE_SHEET) != 0;
    k->lit_back = (kind & SURFACE_LIT_INSIDE) != 0;
    k->next = f->head[cell];
    f->head[cell] = (int)f->count++;
}

/* Two axes across triangle v's plane (canonical normal n) along which its
 * facet measures its extent: along the triangle's shortest edge (a leg of
 * a quad's half) and across it, turned by a quarter turn or more to lie
 * within [0, 90) degrees of a frame that n alone fixes. A box's faces, and
 * the faces of boxes lined up with it, get the same axes however the box
 * is turned, so their extents compare (extent_along). */
static void facet_axes(const float v[9], const double n[3], double axes[2][3])
{
    int k = fabs(n[0]) <= fabs(n[1]) && fabs(n[0]) <= fabs(n[2]) ? 0 : fabs(n[1]) <= fabs(n[2]) ? 1 : 2;
    double e[3] = {0, 0, 0}, u[3], w[3], edge[3] = {1, 0, 0}, shortest = HUGE_VAL;
    e[k] = 1;
    lvcl_cross3(n, e, u);
    double len = sqrt(lvcl_dot3(u, u));
    for (int i = 0; i < 3; i++) u[i] /= len;
    lvcl_cross3(n, u, w);
    for (int i = 0; i < 3; i++) {
        double d[3], l = 0;
        for (int j = 0; j < 3; j++) d[j] = (double)v[3 * ((i + 1) % 3) + j] - v[3 * i + j], l += d[j] * d[j];
        if (l < shortest) shortest = l, memcpy(edge, d, sizeof edge);
    }
    const double quarter_turn = 1.5707963267948966;
    double turn = fmod(atan2(lvcl_dot3(edge, w), lvcl_dot3(edge, u)) + 4.0 * quarter_turn, quarter_turn);
    for (int j = 0; j < 3; j++) {
        axes[0][j] = cos(turn) * u[j] + sin(turn) * w[j];
        axes[1][j] = -sin(turn) * u[j] + cos(turn) * w[j];
    }
}

/* The area of triangle v inside the cell with corner lo and side h (the
 * triangle clipped by the cell's six faces in turn), and that part. */
static double area_in_cell(const float v[9], const double lo[3], double h, clipped *part)
{
    double(*poly)[3] = part->p, next[CLIPPED_CORNERS][3];
    int count = 3;
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) poly[i][k] = v[3 * i + k];
    for (int face = 0; face < 6 && count > 0; face++) {
        int k = face / 2;
        double bound = face % 2 ? lo[k] + h : lo[k], sign = face % 2 ? -1.0 : 1.0; /* inside: sign (x - bound) >= 0 */
        int kept = 0;
        for (int i = 0; i < count; i++) {
            const double *a = poly[i], *b = poly[(i + 1) % count];
            double da = sign * (a[k] - bound), db = sign * (b[k] - bound);
            if (da >= 0) memcpy(next[kept++], a, sizeof next[0]);
            if ((da >= 0) != (db >= 0)) {
                double t = da / (da - db);
                for (int j = 0; j < 3; j++) next[kept][j] = a[j] + t * (b[j] - a[j]);
                kept++;
            }
        }
        count = kept;
        memcpy(poly, next, (size_t)count * sizeof poly[0]);
    }
    part->count = count;
    double sum[3] = {0, 0, 0};
    for (int i = 1; i + 1 < count; i++) {
        double e1[3], e2[3], c[3];
        for (int j = 0; j < 3; j++) e1[j] = poly[i][j] - poly[0][j], e2[j] = poly[i + 1][j] - poly[0][j];
        lvcl_cross3(e1, e2, c);
        for (int j = 0; j < 3; j++) sum[j] += c[j];
    }
    return 0.5 * sqrt(lvcl_dot3(sum, sum));
}

/* Adds one placed triangle, weighing `weight` times its area, to the
 * facets of every stored cell its box (grown by a hundredth of a cell)
 * overlaps and its plane cuts. */
static void add_triangle(facets *c, const lv_grid_info *g, const uint32_t *stored, const float v[9], int clear,
                         int kind, double weight)
{
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; k++) e1[k] = (double)v[3 + k] - v[k], e2[k] = (double)v[6 + k] - v[k];
    lvcl_cross3(e1, e2, n);
    double len = sqrt(lvcl_dot3(n, n));
    if (!(len > 0) || !isfinite(len)) return;
    for (int k = 0; k < 3; k++) n[k] /= len;
    double p0[3] = {v[0], v[1], v[2]}, d = lvcl_dot3(n, p0), h = g->cell_size;
    double front = canonical(n, &d); /* the winding's front: along n (1) or against it (-1) */
    double axes[2][3];
    facet_axes(v, n, axes);
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
                if (!cuts_cell(n, d, corner, h)) continue;
                clipped part;
                double area = area_in_cell(v, corner, h, &part);
                if (area > 0) add_to_cell(c, (int)s, n, d, front, clear, kind, weight * area, &part, axes, h);
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

/* Orders turned facets by group, then offset, then their place in the cell. */
static int by_group_and_offset(const void *pa, const void *pb)
{
    const turned_facet *a = pa, *b = pb;
    if (a->group != b->group) return a->group < b->group ? -1 : 1;
    if (a->d != b->d) return a->d < b->d ? -1 : 1;
    return (a->order > b->order) - (a->order < b->order);
}

/* Whether facet a's extent holds b's (within FACET_OFFSET cell); -1 where
 * either is unknown or their axes do not match. */
static int extent_holds(const turned_facet *a, const turned_facet *b, double h)
{
    if (!a->extent || !b->extent) return -1;
    int holds = 1;
    for (int k = 0; k < 2; k++) {
        double l, u;
        if (!extent_along(b->axes, b->lo, b->hi, a->axes[k], &l, &u)) return -1;
        holds &= a->lo[k] <= l + FACET_OFFSET * h && a->hi[k] >= u - FACET_OFFSET * h;
    }
    return holds;
}

/* Whether facet a, in b's plane, hides b: the one whose extent holds the
 * other's is the larger, else the one of larger area. Extents first, since
 * overlapping solids (a wall modelled twice, one a little off the other)
 * put two faces on the surface they stand on, whose areas add up to more
 * than that surface's part in the cell though they cover less of it. */
static int hides(const turned_facet *a, const turned_facet *b, double h)
{
    if (a->front == b->front || lvcl_dot3(a->n, b->n) <= LAYER_NORMAL) return 0;
    int a_holds = extent_holds(a, b, h), b_holds = extent_holds(b, a, h);
    if (a_holds >= 0 && b_holds >= 0 && a_holds != b_holds) return a_holds;
    return a->area > b->area || (a->area == b->area && b->front < 0);
}

/* Marks the facets (sorted by group and offset) that lie in the plane of
 * a larger parallel facet of the other front: the face a wall standing on
 * the floor, or a cupboard against a wall, hides in that surface. The
 * larger one stands for the plane; the hidden one would pair with it as
 * two faces of one solid, or as a layer beyond the facets below. Of two
 * equal ones the one against the group's normal is hidden, so the marks
 * do not hang on the triangles' order. */
static void mark_hidden(turned_facet *t, size_t m, double h)
{
    for (size_t i = 0; i < m; i++) {
        t[i].hidden = 0;
        for (size_t j = i; j-- > 0 && t[j].group == t[i].group && t[i].d - t[j].d <= FACET_OFFSET * h;)
            t[i].hidden |= hides(&t[j], &t[i], h);
        for (size_t j = i + 1; j < m && t[j].group == t[i].group && t[j].d - t[i].d <= FACET_OFFSET * h; j++)
            t[i].hidden |= hides(&t[j], &t[i], h);
    }
}

/* Extends e to hold facet t (the first of its front where `first`). */
static void extent_add(face_extent *e, int first, const turned_facet *t)
{
    if (first) {
        memcpy(e->axes, t->axes, sizeof e->axes);
        memcpy(e->lo, t->lo, sizeof e->lo);
        memcpy(e->hi, t->hi, sizeof e->hi);
        e->known = t->extent;
        return;
    }
    e->known &= t->extent;
    for (int k = 0; k < 2; k++) {
        double l, u;
        if (!extent_along(t->axes, t->lo, t->hi, e->axes[k], &l, &u)) e->known = 0;
        else e->lo[k] = fmin(e->lo[k], l), e->hi[k] = fmax(e->hi[k], u);
    }
}

/* Whether facet t lies over extent e: they overlap by more than
 * FACET_OFFSET cell along both axes; `unknown` where either extent is
 * not known or their axes do not match. */
static int lies_over(const turned_facet *t, const face_extent *e, double h, int unknown)
{
    if (!e->known || !t->extent) return unknown;
    for (int k = 0; k < 2; k++) {
        double l, u;
        if (!extent_along(t->axes, t->lo, t->hi, e->axes[k], &l, &u)) return unknown;
        if (l >= e->hi[k] - FACET_OFFSET * h || u <= e->lo[k] + FACET_OFFSET * h) return 0;
    }
    return 1;
}

/* Whether facet t lies over the facets of cluster c whose front faces
 * it (where that is not known, it is taken that it does). Facing fronts
 * that only meet at an edge or lie side by side (a doorway's side and a
 * cupboard's beside the doorway, each against its own wall) hold no thin
 * layer of air between them. */
static int faces_across(const turned_facet *t, const cluster *c, double h)
{
    return lies_over(t, &c->along, h, 1);
}

/* Clusters one cell's facets into w->clusters (w->turned then holds the
 * facets, *facet_count of them, by group and offset); returns their
 * count, or -1 out of memory. Facets fall into groups of parallel ones
 * (within 25 degrees of the group's first, either way round); each group,
 * in order of offset, is swept once: a facet joins the cluster before it
 * when it lies within a quarter cell of that cluster's mean and they do
 * not stay apart, else it starts the next. */
static int cluster_cell(const facets *f, int cell, cell_scratch *w, double h, size_t *facet_count)
{
    size_t m = 0;
    for (int i = f->head[cell]; i >= 0; i = f->pool[i].next) m++;
    *facet_count = m;
    if (m == 0) return 0;
    if (m > w->capacity) {
        size_t cap = m > 2 * w->capacity ? m : 2 * w->capacity;
        turned_facet *t = realloc(w->turned, cap * sizeof *t);
        if (t) w->turned = t;
        double(*r)[3] = realloc(w->refs, cap * sizeof *r);
        if (r) w->refs = r;
        cluster *c = realloc(w->clusters, cap * sizeof *c);
        if (c) w->clusters = c;
        if (!t || !r || !c) return -1;
        w->capacity = cap;
    }
    /* The list runs newest first; order counts from the oldest. */
    int groups = 0, order = (int)m;
    for (int i = f->head[cell]; i >= 0; i = f->pool[i].next) {
        const facet *k = &f->pool[i];
        turned_facet *t = &w->turned[--order];
        t->order = order;
        t->area = k->area;
        facet_frame(k, t->axes, t->lo, t->hi);
        t->extent = k->extent;
        t->clear = k->clear;
        t->sheet = k->sheet;
        t->lit_back = k->lit_back;
        double len = sqrt(lvcl_dot3(k->sum_n, k->sum_n)); /* > 0: a facet's triangles have area, one normal */
        for (int j = 0; j < 3; j++) t->n[j] = k->sum_n[j] / len;
        t->d = k->sum_d / k->area;
        t->front = k->front;
    }
    for (size_t i = 0; i < m; i++) {
        turned_facet *t = &w->turned[i];
        int g = 0;
        while (g < groups && fabs(lvcl_dot3(t->n, w->refs[g])) <= LVCL_SAME_NORMAL) g++;
        if (g == groups)
            for (int j = 0; j < 3; j++) w->refs[groups][j] = t->n[j];
        groups += g == groups;
        double s = lvcl_dot3(t->n, w->refs[g]) > 0 ? 1.0 : -1.0;
        t->group = g;
        t->d *= s;
        t->front *= s;
        for (int j = 0; j < 3; j++) t->n[j] *= s;
    }
    qsort(w->turned, m, sizeof *w->turned, by_group_and_offset);
    mark_hidden(w->turned, m, h);
    int count = 0;
    for (size_t i = 0; i < m; i++) {
        turned_facet *t = &w->turned[i];
        t->cluster = -1;
        if (t->hidden) continue;
        cluster *c = count > 0 && w->clusters[count - 1].group == t->group ? &w->clusters[count - 1] : NULL;
        /* A front against the group's normal faces a front along it below
         * it; within a facet's tolerance they touch. */
        int facing = c && t->front < 0 && t->d - c->top_along > FACET_OFFSET * h;
        int gap = facing && t->d - c->top_along < SAME_OFFSET * h && faces_across(t, c, h);
        if (gap) c->gap = 1;
        /* The cluster's topmost facet of t's front and of the other. */
        double top = c ? (t->front > 0 ? c->top_along : c->top_against) : -HUGE_VAL;
        double other = c ? (t->front > 0 ? c->top_against : c->top_along) : -HUGE_VAL;
        /* Glass joins no opaque facet, nor the opposite face of a slab. */
        int opposite = other > -HUGE_VAL;
        /* A layer beyond a parallel facet of the same front, nearer where
         * it lies over that facet (not where that is not known). */
        const face_extent *under = t->front > 0 ? &c->top_along_extent : &c->top_against_extent;
        int layer = top > -HUGE_VAL &&
            (t->d - top > LAYER_OFFSET * h || (t->d - top > LAYER_OVER_OFFSET * h && lies_over(t, under, h, 0))) &&
            lvcl_dot3(t->n, t->front > 0 ? c->along_n : c->against_n) > LAYER_NORMAL;
        /* Two sheets back to back (or a sheet behind a solid's face) are
         * not a solid's two faces: the space between them may hold light
         * (a hollow wall open at a doorway), so they stay apart too. */
        int back_to_back = opposite && (t->sheet || c->sheet) && t->d - other > FACET_OFFSET * h;
        layer |= back_to_back;
        if (!c || fabs(t->d - c->sum_d / c->area) >= SAME_OFFSET * h || facing || layer || t->clear != c->clear ||
            (t->clear && opposite)) {
            c = &w->clusters[count++];
            *c = (cluster){.top_along = -HUGE_VAL,
                           .top_against = -HUGE_VAL,
                           .clear = t->clear,
                           .gap = gap,
                           .group = t->group,
                           .layer = layer};
        }
        t->cluster = (int)(c - w->clusters);
        c->sheet |= t->sheet;
        for (int j = 0; j < 3; j++) c->sum_n[j] += t->area * t->n[j];
        c->sum_d += t->area * t->d;
        c->area += t->area;
        /* Sorted by offset: this facet is the cluster's topmost of its front. */
        if (t->front > 0) {
            extent_add(&c->along, c->top_along == -HUGE_VAL, t);
            extent_add(&c->top_along_extent, 1, t);
            c->top_along = t->d;
            memcpy(c->along_n, t->n, sizeof c->along_n);
        } else {
            extent_add(&c->against, c->top_against == -HUGE_VAL, t);
            extent_add(&c->top_against_extent, 1, t);
            c->top_against = t->d;
            memcpy(c->against_n, t->n, sizeof c->against_n);
        }
    }
    /* Opaque neighbours of a group whose fronts face away from each other,
     * the lower one's all against the normal and the upper one's all along
     * it: a solid's two faces (a slab thicker than a quarter cell). */
    for (int i = 1; i < count; i++) {
        const cluster *below = &w->clusters[i - 1];
        cluster *c = &w->clusters[i];
        c->backs_onto_previous = c->group == below->group && !c->clear && !below->clear &&
            below->top_along == -HUGE_VAL && c->top_against == -HUGE_VAL;
    }
    return count;
}

/* Whether cluster a is chosen before b: across a gap first (while
 * gaps_first), then those whose solid's other face is not chosen yet
 * (spare: the face it backs onto is), then the heavier, and between equal
 * weights (a room's symmetric corners) by their sums, so that the choice
 * does not hang on the triangles' order. */
static int comes_first(const cluster *a, int a_spare, const cluster *b, int b_spare, int gaps_first)
{
    if (gaps_first && a->gap != b->gap) return a->gap > b->gap;
    if (a_spare != b_spare) return b_spare;
    if (fabs(a->area - b->area) > 1e-9 * fmax(a->area, b->area)) return a->area > b->area;
    for (int j = 0; j < 3; j++)
        if (a->sum_n[j] != b->sum_n[j]) return a->sum_n[j] > b->sum_n[j];
    return a->sum_d > b->sum_d;
}

static int is_chosen(const int *chosen, int count, int cluster)
{
    for (int j = 0; j < count; j++)
        if (chosen[j] == cluster) return 1;
    return 0;
}

/* The range of axis . u over the unit cell's section by the plane n . u
 * = d (cell units): over the points where the plane crosses the cell's
 * twelve edges. */
static void section_along(const double n[3], double d, const double axis[3], double *lo, double *hi)
{
    *lo = HUGE_VAL, *hi = -HUGE_VAL;
    for (int e = 0; e < 12; e++) {
        /* Edge e runs along coordinate e / 4 at the corner given by the two
         * other coordinates' bits e % 4. */
        int along = e / 4, b = e % 4;
        double u0[3], u1[3];
        for (int j = 0, bit = 0; j < 3; j++) {
            if (j == along) u0[j] = 0, u1[j] = 1;
            else u0[j] = u1[j] = (double)(b >> bit++ & 1);
        }
        double f0 = lvcl_dot3(n, u0) - d, f1 = lvcl_dot3(n, u1) - d;
        if ((f0 < 0) == (f1 < 0) && f0 != 0) continue;
        double t = f0 == f1 ? 0 : f0 / (f0 - f1), x[3];
        for (int j = 0; j < 3; j++) x[j] = u0[j] + t * (u1[j] - u0[j]);
        double v = lvcl_dot3(axis, x);
        *lo = fmin(*lo, v), *hi = fmax(*hi, v);
    }
}

/* How close (cell units) a face's extent must come to the cell's section
 * to reach the cell's side, and a bound past any unit axis's range over
 * the cell (at most sqrt 3). */
#define SECTION_TOLERANCE 1e-3
#define SECTION_OPEN 2.0

/* A solid's slab between offsets from and to along unit n (world units),
 * bounded along the two axes by a face's extent; in cell units from the
 * corner lo, with open[k][side] taking that side to the cell's. */
static void add_slab(const double n[3], const double axes[2][3], double from, double to, const double elo[2],
                     const double ehi[2], const int open[2][2], const double lo[3], double h, lvcl_cell_solids *solids)
{
    if (solids->count >= LVCL_CELL_SOLIDS) return;
    lvcl_solid_slab *t = &solids->solid[solids->count++];
    const double *axis[3] = {n, axes[0], axes[1]};
    const double a_lo[3] = {from, elo[0], elo[1]}, a_hi[3] = {to, ehi[0], ehi[1]};
    for (int a = 0; a < 3; a++) {
        /* a . x = c  <=>  a . u = (c - a . lo) / h */
        double at = lvcl_dot3(axis[a], lo);
        for (int j = 0; j < 3; j++) t->axis[a][j] = (float)axis[a][j];
        t->lo[a] = (float)(a > 0 && open[a - 1][0] ? -SECTION_OPEN : (a_lo[a] - at) / h);
        t->hi[a] = (float)(a > 0 && open[a - 1][1] ? SECTION_OPEN : (a_hi[a] - at) / h);
    }
}

/* Which sides of the cell extent e (of a face at offset d along n, world
 * units) reaches along each of axes: reach[k][0] below along axes[k],
 * reach[k][1] above, where it comes to the edge of the cell's section by
 * the face's plane. */
static void reached_sides(const face_extent *e, const double n[3], double d, const double axes[2][3],
                          const double lo[3], double h, int reach[2][2])
{
    for (int k = 0; k < 2; k++) {
        double l, u, s_lo, s_hi;
        reach[k][0] = reach[k][1] = 0;
        if (!e->known || !extent_along(e->axes, e->lo, e->hi, axes[k], &l, &u)) continue;
        double at = lvcl_dot3(axes[k], lo);
        section_along(n, (d - lvcl_dot3(n, lo)) / h, axes[k], &s_lo, &s_hi);
        reach[k][0] = (l - at) / h <= s_lo + SECTION_TOLERANCE;
        reach[k][1] = (u - at) / h >= s_hi - SECTION_TOLERANCE;
    }
}

/* Whether extent e lies within extent f (up to FACET_OFFSET cell). */
static int extent_within(const face_extent *e, const face_extent *f, double h)
{
    for (int k = 0; k < 2; k++) {
        double l, u;
        if (!extent_along(e->axes, e->lo, e->hi, f->axes[k], &l, &u)) return 0;
        if (l < f->lo[k] - FACET_OFFSET * h || u > f->hi[k] + FACET_OFFSET * h) return 0;
    }
    return 1;
}

/* Adds to *solids the slab of an opaque solid between lower's top face
 * against the group's normal and upper's top face along it above (one
 * cluster for both, or two), apart by more than a facet's tolerance: over
 * upper's extent in the cell, which must be known, and over lower's where
 * that reaches further (a room's shell slab runs on behind the end of a
 * wall that meets it, where its inner face stops). Where both faces reach
 * the cell's side, so does the slab: a slab crossing the cell at a slant
 * holds corners of the cell that neither face's extent covers (without
 * this a room's corner by 30 cm slabs read 20-25% dark; asking only the
 * face that took the plane, a bowed wall among 1 cm slabs read up to 2.9
 * times too bright: wrongly paired faces' slabs covered lit air). In cell
 * units from the corner lo. */
static void keep_solid(const cluster *lower, const cluster *upper, const double lo[3], double h,
                       lvcl_cell_solids *solids)
{
    const cluster *k = upper;
    if (lower->clear || k->clear || lower->sheet || k->sheet || !k->along.known || lower->top_against == -HUGE_VAL ||
        k->top_along == -HUGE_VAL || !(k->top_along - lower->top_against > FACET_OFFSET * h) ||
        !(lvcl_dot3(k->along_n, lower->against_n) > LAYER_NORMAL))
        return;
    int open[2][2], other[2][2];
    reached_sides(&k->along, k->along_n, k->top_along, k->along.axes, lo, h, open);
    reached_sides(&lower->against, k->along_n, lower->top_against, k->along.axes, lo, h, other);
    for (int a = 0; a < 2; a++)
        for (int side = 0; side < 2; side++) open[a][side] &= other[a][side];
    add_slab(k->along_n, k->along.axes, lower->top_against, k->top_along, k->along.lo, k->along.hi, open, lo, h,
             solids);
    if (lower->against.known && !extent_within(&lower->against, &k->along, h))
        add_slab(k->along_n, lower->against.axes, lower->top_against, k->top_along, lower->against.lo,
                 lower->against.hi, (const int[2][2]){{0, 0}, {0, 0}}, lo, h, solids);
}

/* A cluster of an opaque solid's two faces, back to back (a wall thinner
 * than a quarter cell, whose one plane gives half its inside to each
 * side's region): the slab between them. */
static void keep_thin_solid(const cluster *k, const double lo[3], double h, lvcl_cell_solids *solids)
{
    keep_solid(k, k, lo, h, solids);
}

/* The planes of one stored cell (corner lo) from its clusters (count of
 * them in w), in cell units from its corner: those facing each other
 * across a gap narrower than a quarter cell (and wider than FACET_OFFSET:
 * things resting on each other touch), then the rest, the heaviest first
 * of each. A leg's top 1 mm under a table top then comes before the leg's
 * sides, which split air that meets around the leg anyway, while the
 * gap's thin layer of air, unsplit, would share a region with the leg's
 * inside or with what lies beyond the top. Gaps come first for
 * GAP_PLANES planes, so that a crowded cell's heaviest other surface (a
 * wall between rooms, say) still finds room. Returns their count; the
 * solids their planes stand for are added to *solids. */
static int choose_planes(const cell_scratch *w, int clusters, const double lo[3], double h, float planes[][4],
                         lvcl_cell_solids *solids)
{
    int chosen[LV_GEOMETRY_PLANES + LAYER_PLANES], count = 0, gaps = 0, rounds = 0;
    for (int round = 0; round < LV_GEOMETRY_PLANES + LAYER_PLANES; round++) {
        int best = -1, best_spare = 0;
        for (int i = 0; i < clusters; i++) {
            if (is_chosen(chosen, round, i)) continue;
            if (round >= LV_GEOMETRY_PLANES &&
                !((w->clusters[i].layer && is_chosen(chosen, round, i - 1)) ||
                  (i + 1 < clusters && w->clusters[i + 1].layer && is_chosen(chosen, round, i + 1))))
                continue;
            int spare = (w->clusters[i].backs_onto_previous && is_chosen(chosen, round, i - 1)) ||
                (i + 1 < clusters && w->clusters[i + 1].backs_onto_previous && is_chosen(chosen, round, i + 1));
            if (best < 0 || comes_first(&w->clusters[i], spare, &w->clusters[best], best_spare, gaps < GAP_PLANES))
                best = i, best_spare = spare;
        }
        if (best < 0) break;
        chosen[round] = best;
        rounds = round + 1;
        const cluster *k = &w->clusters[best];
        gaps += k->gap;
        double n[3], len = sqrt(lvcl_dot3(k->sum_n, k->sum_n));
        if (!(len > 0)) continue;
        for (int j = 0; j < 3; j++) n[j] = k->sum_n[j] / len;
        double d = k->sum_d / k->area;
        canonical(n, &d);
        if (!cuts_cell(n, d, lo, h)) continue;
        /* n . (lo + h u) = d  <=>  n . u = (d - n . lo) / h */
        for (int j = 0; j < 3; j++) planes[count][j] = (float)n[j];
        planes[count][3] = (float)((d - lvcl_dot3(n, lo)) / h);
        count++;
        keep_thin_solid(k, lo, h, solids);
    }
    /* A solid thicker than a quarter cell whose one face took a plane and
     * whose other is spare: the plane keeps its two sides apart, but the
     * region on the spare face's side holds the solid's inside too (a
     * slab of the rooms' shell, 0.7 cell thick, whose outer face took the
     * plane: the room's corner region read 20-40% dark without subcells). */
    for (int i = 1; i < clusters; i++)
        if (w->clusters[i].backs_onto_previous && is_chosen(chosen, rounds, i) != is_chosen(chosen, rounds, i - 1))
            keep_solid(&w->clusters[i - 1], &w->clusters[i], lo, h, solids);
    return count;
}

/* mixed_patterns tests a facet's sides at SIDE_SAMPLES^2 points across
 * its extent (pulled in by SIDE_INSET of it from the edges), or at the
 * four corners alone where it spans less than SIDE_SMALL cell (its
 * neighbours sample the rest of a finely tessellated surface), SIDE_STEP
 * cell off its surface: a band a tenth of a millimetre thick of the wrong
 * side's air carries a lit room's light at 1000:1. 5 x 5 points missed the
 * strip of a curved partition below a cupboard's top that stood against
 * it (tests/volume/test_mixed_regions.c; 9 x 9 and 13 x 13 still missed
 * one of its set-ups). */
#define SIDE_SAMPLES 17
#define SIDE_INSET 0.02
#define SIDE_SMALL 0.125
#define SIDE_STEP 1e-5

static int in_cell(const double lo[3], double h, const double x[3])
{
    for (int k = 0; k < 3; k++)
        if (!(x[k] >= lo[k] && x[k] <= lo[k] + h)) return 0;
    return 1;
}

/* The region pattern of world point x in the cell with corner lo and side
 * h (bit i: beyond plane i, as lv_region_of), or -1 outside the cell. */
static int pattern_at(const float planes[][4], int count, const double lo[3], double h, const double x[3])
{
    if (!in_cell(lo, h, x)) return -1;
    double u[3];
    for (int k = 0; k < 3; k++) u[k] = (x[k] - lo[k]) / h;
    int m = 0;
    for (int i = 0; i < count; i++)
        if (planes[i][0] * u[0] + planes[i][1] * u[1] + planes[i][2] * u[2] > planes[i][3]) m |= 1 << i;
    return m;
}

/* A cell casts at most this many rays per region pattern and cluster of
 * facets to tell whether a sheet's back is dark: a cell of a rippled tile
 * holds hundreds of samples whose backs all lie against the wall, and
 * after that many the rest of the cluster's in the pattern are taken to
 * be dark too. (A cap per cell, 16, let a tile's samples spend the rays a
 * region elsewhere in the cell needed; a cap per pattern let a lamp's
 * samples, its back against the ceiling, spend those of a bowed wall in
 * the same region: bench/leak_sweep.py --cells 4 --seed 124, red / blue
 * 10.9; and a cap per group of parallel facets let a room's end wall, its
 * back in the slab, spend those of a bowed partition within 25 degrees of
 * it, in a cell spanning both: --cells 4 --seed 134, red / blue 0.072.) */
#define PATTERN_RAYS 4

/* Light j of `picks` spread over the lights by their odds: light j
 * itself where there are no more lights than picks, else the light whose
 * share of the odds holds the quantile (j + 0.5) / picks. */
static size_t light_by_odds(const lvcl_packed_scene *p, size_t j, size_t picks)
{
    if (p->light_count <= picks) return j;
    float q = ((float)j + 0.5f) / (float)picks;
    size_t lo = 0, hi = p->light_count - 1;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (p->lights[mid].cdf < q) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* Emissive triangle light l's world corners v and its front normal n (not
 * unit): a mirroring instance turns the winding, not the front. */
static void emitter_front(const lvcl_packed_scene *p, const lv_light *l, float v[9], double n[3])
{
    lvcl_packed_triangle_world(p, l->instance, l->index, v);
    double e1[3], e2[3], sign = p->instances[l->instance].flags & LV_INSTANCE_MIRRORED ? -1 : 1;
    for (int k = 0; k < 3; k++) e1[k] = (double)v[3 + k] - v[k], e2[k] = (double)v[6 + k] - v[k];
    lvcl_cross3(e1, e2, n);
    for (int k = 0; k < 3; k++) n[k] *= sign;
}

/* At most this many emissive triangles are looked at for a lamp facing
 * into a pocket (pocket_lamp), picked by their odds where there are more. */
#define POCKET_LAMPS 256

/* Whether the first thing the ray from b along unit d meets, `hit` away,
 * is a lamp whose front faces b: the pocket it closes is lit. */
static int pocket_lamp(const lvcl_packed_scene *p, const double b[3], const double d[3], double hit)
{
    size_t picks = p->light_count < POCKET_LAMPS ? p->light_count : POCKET_LAMPS;
    for (size_t j = 0; j < picks; j++) {
        const lv_light *l = &p->lights[light_by_odds(p, j, POCKET_LAMPS)];
        if (l->kind != LV_LIGHT_AREA) continue;
        float v[9];
        double nrm[3];
        emitter_front(p, l, v, nrm);
        double t = lvcl_segment_meets_triangle(v, b, d, hit * (1 + 1e-6) + 1e-12);
        if (t > 0 && t >= hit * (1 - 1e-6) && lvcl_dot3(nrm, d) < 0) return 1;
    }
    return 0;
}

/* Whether the back of a sheet at point b (its front normal front) is dark:
 * a ray from b straight back meets something within a cell (a pocket: a
 * tile's back against its wall, the inside of a shoe standing on the
 * floor) other than a lamp facing b (a lamp 2 mm from a wall of one
 * polygon, shining at it, lights the gap between them, and the two, a
 * fiftieth of a cell apart, share a plane: red / blue 3.7 on the wall's
 * other side before 2026-12-07), or, where no light shines in from beyond
 * the scene, leaves the scene's bounds within a cell (a floor of one
 * polygon, whose underside faces out of the scene) or leaves the scene
 * without meeting anything. A
 * back that sees the scene beyond a cell may hold light; under a sun so
 * may one that sees open space: the outside of a building's wall of one
 * polygon, above sunlit ground, shared a region with the room's corner
 * and lit it (bench/leak_sweep.py --sun --seed 98: red / blue 0.22). */
static int sheet_back_dark(const lvcl_packed_scene *p, const double b[3], const double front[3], double h)
{
    double back[3], out = HUGE_VAL;
    for (int k = 0; k < 3; k++) {
        back[k] = -front[k];
        if (back[k] != 0) out = fmin(out, ((back[k] > 0 ? p->bounds_max[k] : p->bounds_min[k]) - b[k]) / back[k]);
    }
    double hit = lvcl_packed_first_hit(p, b, back, fmin(out, h));
    if (hit > 0) return !pocket_lamp(p, b, back, hit);
    if (p->lit_from_outside) return 0;
    if (!(out > h)) return 1;
    return !lvcl_packed_segment_hits(p, b, back, out + h); /* past the bounds: a wall may lie on them */
}

/* What mixed_patterns gathers over one group of parallel facets: per
 * pattern, the highest sample (along the group's normal) of a facet facing
 * along it and the lowest of one facing against it, and the patterns
 * found mixed so far with the rays spent on them. */
typedef struct {
    const lvcl_packed_scene *p;
    const float (*planes)[4];
    int count;
    const double *lo, *ref;
    double h;
    double along[1 << LV_REGION_PLANES], against[1 << LV_REGION_PLANES];
    int pattern_rays[1 << LV_REGION_PLANES];
    uint64_t mixed;
} side_test;

/* Tests facet t's sides at its point x (on its plane). */
static void test_sides(side_test *s, const turned_facet *t, const double x[3])
{
    double front[3], f[3], b[3];
    for (int k = 0; k < 3; k++) {
        front[k] = t->front * t->n[k];
        f[k] = x[k] + SIDE_STEP * s->h * front[k], b[k] = x[k] - SIDE_STEP * s->h * front[k];
    }
    int pf = pattern_at(s->planes, s->count, s->lo, s->h, f);
    if (pf < 0) return;
    double height = lvcl_dot3(s->ref, x);
    if (t->front > 0) s->along[pf] = fmax(s->along[pf], height);
    else s->against[pf] = fmin(s->against[pf], height);
    if (s->mixed >> pf & 1 || (!t->lit_back && !(t->sheet && s->pattern_rays[pf] < PATTERN_RAYS)) ||
        pattern_at(s->planes, s->count, s->lo, s->h, b) != pf)
        return;
    if (t->lit_back) {
        s->mixed |= (uint64_t)1 << pf; /* lit air on both sides, whatever a ray would say */
        return;
    }
    s->pattern_rays[pf]++;
    if (!sheet_back_dark(s->p, b, front, s->h)) s->mixed |= (uint64_t)1 << pf;
}

/* The point (c0, c1) of facet t's plane in its axes. */
static void facet_point(const turned_facet *t, double c0, double c1, double x[3])
{
    for (int k = 0; k < 3; k++) x[k] = t->d * t->n[k] + c0 * t->axes[0][k] + c1 * t->axes[1][k];
}

/* Tests facet t's sides just beside each line where it crosses one of the
 * cell's planes, SIDE_BESIDE cell off the line on both sides, at
 * SIDE_SAMPLES points along it within the facet's extent. Every region a
 * facet passes through meets it in a polygon whose edges are such lines
 * or the cell's faces, so this finds the regions the grid of samples steps
 * over: a layer 1 mm thick between a ceiling and a lamp just under it,
 * where a curved partition of one polygon meets the ceiling, held the
 * bright room's light at twice the dim room's own, unflagged (the leak
 * sweep's seed 93). */
#define SIDE_BESIDE 1e-4

static void test_sides_beside_planes(side_test *s, const turned_facet *t)
{
    for (int i = 0; i < s->count; i++) {
        /* The plane in world units, n . x = c, and its trace on the facet:
         * g . (c0, c1) = r. */
        const float *q = s->planes[i];
        double n[3] = {q[0], q[1], q[2]}, c = q[3] * s->h + lvcl_dot3(n, s->lo);
        double g[2] = {lvcl_dot3(n, t->axes[0]), lvcl_dot3(n, t->axes[1])}, gg = g[0] * g[0] + g[1] * g[1];
        if (gg < 1e-12 * lvcl_dot3(n, n)) continue; /* parallel to the facet */
        double r = c - t->d * lvcl_dot3(n, t->n), len = sqrt(gg);
        double base[2] = {r * g[0] / gg, r * g[1] / gg}, along[2] = {-g[1] / len, g[0] / len};
        /* The stretch of the line inside the facet's extent. */
        double from = -HUGE_VAL, to = HUGE_VAL;
        for (int j = 0; j < 2; j++) {
            if (fabs(along[j]) < 1e-12) {
                if (base[j] < t->lo[j] || base[j] > t->hi[j]) from = HUGE_VAL;
                continue;
            }
            double a = (t->lo[j] - base[j]) / along[j], b = (t->hi[j] - base[j]) / along[j];
            from = fmax(from, fmin(a, b));
            to = fmin(to, fmax(a, b));
        }
        if (!(from < to)) continue;
        for (int k = 0; k < SIDE_SAMPLES; k++) {
            double at = from + (to - from) * (SIDE_INSET + (1 - 2 * SIDE_INSET) * k / (SIDE_SAMPLES - 1));
            for (int side = -1; side <= 1; side += 2) {
                double off = side * SIDE_BESIDE * s->h / len, x[3];
                double c0 = base[0] + at * along[0] + off * g[0], c1 = base[1] + at * along[1] + off * g[1];
                if (c0 < t->lo[0] || c0 > t->hi[0] || c1 < t->lo[1] || c1 > t->hi[1]) continue; /* past its edge */
                facet_point(t, c0, c1, x);
                test_sides(s, t, x);
            }
        }
    }
}

/* The region patterns of one cell (its clustered facets in w, m of them,
 * sorted by group; its planes) that hold the air on both sides of a
 * surface. Each facet is sampled (its front points lie SIDE_STEP cell in
 * front of the samples) over its extent and beside the lines where it
 * crosses the cell's planes. Within a group of parallel
 * facets, the front points of a facet facing along the group's normal and
 * of one facing against it that lies behind it (the two faces of a solid,
 * a curved shell's outside and inside) must not share a region; and a
 * sheet's front point (a surface with open edges, such as a wall of one
 * polygon) must not share one with the point just behind it, unless its
 * back is dark (sheet_back_dark). Planes that stand for a curved wall
 * thinner than its bend across the cell, or a surface left without a
 * plane of its own, mix such points; a lookup there would read the other
 * side's light. */
static uint64_t mixed_patterns(const lvcl_packed_scene *p, const cell_scratch *w, size_t m, const float planes[][4],
                               int count, const double lo[3], double h)
{
    const turned_facet *t = w->turned;
    side_test s = {.p = p, .planes = planes, .count = count, .lo = lo, .h = h};
    for (size_t first = 0, end; first < m; first = end) {
        for (end = first + 1; end < m && t[end].group == t[first].group;) end++;
        for (int q = 0; q < 1 << count; q++) s.along[q] = -HUGE_VAL, s.against[q] = HUGE_VAL;
        s.ref = w->refs[t[first].group];
        int cluster = -1;
        for (size_t a = first; a < end; a++) {
            if (t[a].hidden) continue;
            if (t[a].cluster != cluster) { /* each cluster its own rays */
                cluster = t[a].cluster;
                for (int q = 0; q < 1 << count; q++) s.pattern_rays[q] = 0;
            }
            int side = fmax(t[a].hi[0] - t[a].lo[0], t[a].hi[1] - t[a].lo[1]) < SIDE_SMALL * h ? 2 : SIDE_SAMPLES;
            for (int i = 0; i < side * side; i++) {
                double c[2], x[3];
                for (int j = 0; j < 2; j++) {
                    int step = j ? i / side : i % side;
                    double at = SIDE_INSET + (1 - 2 * SIDE_INSET) * step / (side - 1);
                    c[j] = t[a].lo[j] + at * (t[a].hi[j] - t[a].lo[j]);
                }
                facet_point(&t[a], c[0], c[1], x);
                test_sides(&s, &t[a], x);
            }
            test_sides_beside_planes(&s, &t[a]);
        }
        for (int q = 0; q < 1 << count; q++)
            if (s.against[q] < s.along[q]) s.mixed |= (uint64_t)1 << q;
    }
    return s.mixed;
}

/* An edge of a placed triangle, its ends in order, for finding the edges
 * that only one triangle of a mesh has; key mixes the ends' bits. */
typedef struct {
    uint64_t key;
    float a[3], b[3];
    size_t tri;
} mesh_edge;

static int by_ends(const void *pa, const void *pb)
{
    const mesh_edge *x = pa, *y = pb;
    int c = memcmp(x->a, y->a, sizeof x->a);
    return c ? c : memcmp(x->b, y->b, sizeof x->b);
}

/* The bits of the edge's ends, mixed: equal edges have equal keys. */
static uint64_t edge_key(const mesh_edge *e)
{
    uint32_t w[6];
    memcpy(w, e->a, sizeof e->a);
    memcpy(w + 3, e->b, sizeof e->b);
    uint64_t h = 0;
    for (int i = 0; i < 6; i++) h = (h ^ w[i]) * 0x9e3779b97f4a7c15ull;
    return h ^ h >> 29;
}

/* Sorts e by key (least significant byte first, through tmp), then each
 * run of equal keys by its ends: equal edges end up side by side, in an
 * order that depends only on the edges (qsort of every edge by its ends
 * took a sixth of a 10^6-triangle scene's start). */
static void sort_edges(mesh_edge *e, mesh_edge *tmp, size_t n)
{
    mesh_edge *from = e, *to = tmp;
    for (int shift = 0; shift < 64; shift += 8) { /* eight passes: the last lands in e */
        size_t count[257] = {0};
        for (size_t i = 0; i < n; i++) count[(from[i].key >> shift & 255u) + 1]++;
        for (int b = 0; b < 256; b++) count[b + 1] += count[b];
        for (size_t i = 0; i < n; i++) to[count[from[i].key >> shift & 255u]++] = from[i];
        mesh_edge *t = from;
        from = to;
        to = t;
    }
    for (size_t i = 0, j; i < n; i = j) {
        for (j = i + 1; j < n && e[j].key == e[i].key; j++) continue;
        if (j - i > 1) qsort(e + i, j - i, sizeof *e, by_ends);
    }
}

/* The root of triangle t's set of triangles joined by shared edges. */
static size_t surface_of(size_t *parent, size_t t)
{
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
}

/* At most this many lights are looked for inside closed surfaces, picked
 * by their odds where there are more: each costs a pass over the
 * triangles of every mesh whose placed box holds it. */
#define INSIDE_LIGHTS 64

/* Where the lights are, for finding the closed surfaces that hold one:
 * each emissive triangle's middle, a hair in front of it (an emitter that
 * is a closed box's own face shines out of it, not into it), and each
 * point or spot light; INSIDE_LIGHTS evenly spaced quantiles of the
 * lights' odds pick them where there are more. Returns the count; *at
 * (malloc'ed, 3 doubles a light) NULL out of memory. */
static size_t light_points(const lvcl_packed_scene *p, double **at)
{
    double reach = 0;
    for (int k = 0; k < 3; k++) reach = fmax(reach, (double)p->bounds_max[k] - p->bounds_min[k]);
    size_t n = 0, picks = p->light_count < INSIDE_LIGHTS ? p->light_count : INSIDE_LIGHTS, last = p->light_count;
    *at = malloc((picks ? picks : 1) * 3 * sizeof **at);
    for (size_t j = 0; *at && j < picks; j++) {
        size_t i = light_by_odds(p, j, INSIDE_LIGHTS);
        if (i == last) continue; /* a bright light holds several quantiles */
        last = i;
        const lv_light *l = &p->lights[i];
        double *x = *at + 3 * n;
        if (l->kind == LV_LIGHT_PUNCTUAL) {
            const lv_punctual_light *u = &p->punctuals[l->index];
            if (u->type == LV_PUNCTUAL_DIRECTIONAL) continue;
            for (int k = 0; k < 3; k++) x[k] = u->position[k];
        } else {
            float v[9];
            double nrm[3];
            emitter_front(p, l, v, nrm);
            double len = sqrt(lvcl_dot3(nrm, nrm));
            if (!(len > 0)) continue;
            for (int k = 0; k < 3; k++) x[k] = ((double)v[k] + v[3 + k] + v[6 + k]) / 3 + 1e-6 * reach * nrm[k] / len;
        }
        n++;
    }
    return n;
}

/* A direction off every axis and diagonal, for the parity rays. */
static const double PARITY_DIR[3] = {0.5773, 0.5781, 0.5765};

/* Marks SURFACE_LIT_INSIDE on the closed surfaces of mesh m (roots of
 * parent, kinds in kind[]) that face out and, as some instance places
 * them, hold one of the `count` light points: a ray from the point
 * crosses them an odd number of times. odd[] and volume[] are scratch per
 * triangle, zero on entry and on return. */
static void mark_lit_insides(const lvcl_packed_scene *p, size_t m, size_t *parent, const double *lights, size_t count,
                             uint8_t *kind, uint8_t *odd, double *volume)
{
    size_t first = p->mesh_first[m], end = first + p->mesh_size[m];
    const lvcl_bvh_node *root = &p->tree_nodes[p->mesh_tree_root[m]];
    for (size_t in = 0; in < p->instance_count; in++) {
        if (p->instances[in].mesh != m) continue;
        double facing = p->instances[in].flags & LV_INSTANCE_MIRRORED ? -1 : 1; /* as lv_triangle_world */
        float lo[3], hi[3];
        lvcl_transform_box(p->instances[in].world_from_object, root->bmin, root->bmax, lo, hi);
        for (size_t l = 0; l < count; l++) {
            const double *x = lights + 3 * l;
            if (x[0] < lo[0] || x[0] > hi[0] || x[1] < lo[1] || x[1] > hi[1] || x[2] < lo[2] || x[2] > hi[2]) continue;
            for (size_t t = first; t < end; t++) {
                float v[9];
                lvcl_packed_triangle_world(p, in, t, v);
                size_t r = surface_of(parent, t);
                if (kind[r] & SURFACE_SHEET) continue;
                odd[r] ^= lvcl_segment_meets_triangle(v, x, PARITY_DIR, HUGE_VAL) > 0;
                /* Six times the volume the surface closes round x: positive where its fronts face out. */
                double a[3], b[3], c[3], bc[3];
                for (int k = 0; k < 3; k++) a[k] = v[k] - x[k], b[k] = v[3 + k] - x[k], c[k] = v[6 + k] - x[k];
                lvcl_cross3(b, c, bc);
                volume[r] += facing * lvcl_dot3(a, bc);
            }
            for (size_t t = first; t < end; t++) {
                size_t r = surface_of(parent, t);
                if (odd[r] && volume[r] > 0) kind[r] |= SURFACE_LIT_INSIDE;
                odd[r] = 0, volume[r] = 0;
            }
        }
    }
}

/* Per leaf-ordered triangle, what its surface (the triangles of its mesh
 * joined to it through shared edges, by the corners' positions as its
 * first instance places them) is: SURFACE_SHEET where the surface has an
 * edge that belongs to no other triangle, a sheet such as a wall of one
 * polygon or a dome rather than a closed solid; SURFACE_LIT_INSIDE where
 * it is closed, faces out, and holds a light (mark_lit_insides): a
 * cupboard, or a refrigerator, of one-polygon panels with a lamp inside
 * is hollow, lit air behind every panel, where a closed surface is
 * otherwise taken for a solid, dark inside. NULL out of memory. */
static uint8_t *surface_kinds(const lvcl_packed_scene *p)
{
    size_t tris = p->triangle_count ? p->triangle_count : 1;
    uint8_t *kind = calloc(tris, 1), *odd = calloc(tris, 1);
    double *volume = calloc(tris, sizeof *volume), *lights = NULL;
    size_t light_count = light_points(p, &lights);
    size_t most = 0, *placed_by = malloc((p->mesh_count ? p->mesh_count : 1) * sizeof *placed_by);
    size_t *parent = malloc(tris * sizeof *parent);
    for (size_t m = 0; m < p->mesh_count; m++) most = p->mesh_size[m] > most ? p->mesh_size[m] : most;
    mesh_edge *e = malloc((most ? 3 * most : 1) * sizeof *e), *tmp = malloc((most ? 3 * most : 1) * sizeof *tmp);
    if (!kind || !odd || !volume || !lights || !placed_by || !parent || !e || !tmp) {
        free(kind);
        kind = NULL;
        goto done;
    }
    for (size_t t = 0; t < p->triangle_count; t++) parent[t] = t;
    for (size_t m = 0; m < p->mesh_count; m++) placed_by[m] = p->instance_count;
    for (size_t in = p->instance_count; in-- > 0;) placed_by[p->instances[in].mesh] = in;
    for (size_t m = 0; m < p->mesh_count; m++) {
        size_t in = placed_by[m], n = 0;
        if (in == p->instance_count) continue;
        for (size_t t = p->mesh_first[m]; t < p->mesh_first[m] + p->mesh_size[m]; t++) {
            float v[9];
            lvcl_packed_triangle_world(p, in, t, v);
            for (int j = 0; j < 9; j++) v[j] += 0.0f; /* -0 and +0: one position, compared bitwise below */
            for (int k = 0; k < 3; k++) {
                const float *x = &v[3 * k], *y = &v[3 * ((k + 1) % 3)];
                int swap = memcmp(x, y, 3 * sizeof *x) > 0;
                memcpy(e[n].a, swap ? y : x, sizeof e[n].a);
                memcpy(e[n].b, swap ? x : y, sizeof e[n].b);
                e[n].key = edge_key(&e[n]);
                e[n++].tri = t;
            }
        }
        sort_edges(e, tmp, n);
        for (size_t i = 0; i + 1 < n; i++)
            if (!by_ends(&e[i], &e[i + 1])) parent[surface_of(parent, e[i].tri)] = surface_of(parent, e[i + 1].tri);
        for (size_t i = 0; i < n; i++) {
            int shared = (i > 0 && !by_ends(&e[i - 1], &e[i])) || (i + 1 < n && !by_ends(&e[i], &e[i + 1]));
            if (!shared) kind[surface_of(parent, e[i].tri)] = SURFACE_SHEET;
        }
        mark_lit_insides(p, m, parent, lights, light_count, kind, odd, volume);
        for (size_t t = p->mesh_first[m]; t < p->mesh_first[m] + p->mesh_size[m]; t++)
            kind[t] = kind[surface_of(parent, t)];
    }
done:
    free(odd);
    free(volume);
    free(lights);
    free(e);
    free(tmp);
    free(parent);
    free(placed_by);
    return kind;
}

void lvcl_solid_slabs_free(lvcl_solid_slabs *solids)
{
    free(solids->of_cell);
    free(solids->list);
    solids->of_cell = NULL;
    solids->list = NULL;
}

/* Keeps stored cell s's solids' slabs: its entry in
 * solids->list, grown as needed (*capacity entries). Returns 0 out of
 * memory. */
static int keep_cell_solids(lvcl_solid_slabs *solids, size_t stored, size_t s, const lvcl_cell_solids *found,
                            size_t *count, size_t *capacity)
{
    if (!solids->of_cell) {
        solids->of_cell = malloc((stored ? stored : 1) * sizeof *solids->of_cell);
        if (!solids->of_cell) return 0;
        for (size_t i = 0; i < stored; i++) solids->of_cell[i] = LVCL_NO_SOLIDS;
    }
    if (*count == *capacity) {
        size_t grown = *capacity ? 2 * *capacity : 256;
        lvcl_cell_solids *list = realloc(solids->list, grown * sizeof *list);
        if (!list) return 0;
        solids->list = list;
        *capacity = grown;
    }
    solids->list[*count] = *found;
    solids->of_cell[s] = (uint32_t)(*count)++;
    return 1;
}

lvcl_error lvcl_volume_build_regions(const lvcl_packed_scene *p, lv_grid_info *g, size_t cells, uint32_t *slot,
                                     lvcl_regions *regions, lvcl_solid_slabs *solids, lvcl_status *st)
{
    *regions = (lvcl_regions){0};
    *solids = (lvcl_solid_slabs){0};
    size_t solid_cells = 0, solid_capacity = 0;
    size_t stored = g->slot_count;
    facets c = {0};
    cell_scratch w = {0};
    c.head = malloc((stored ? stored : 1) * sizeof *c.head);
    lvcl_cell_planes *planes = malloc((stored ? stored : 1) * sizeof *planes);
    if (!c.head || !planes) {
        free(c.head);
        free(planes);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the cells' planes");
    }
    for (size_t i = 0; i < stored; i++) c.head[i] = -1;
    uint8_t *kind = surface_kinds(p);
    c.failed = !kind;
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
                    add_triangle(&c, g, slot, v, clear, kind[t], (double)count / (double)taken);
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
                    size_t facets_in = 0;
                    int clusters = cluster_cell(&c, (int)s, &w, g->cell_size, &facets_in);
                    c.failed |= clusters < 0;
                    lvcl_cell_solids found = {0};
                    planes[s].count = clusters > 0
                        ? (uint8_t)choose_planes(&w, clusters, lo, g->cell_size, planes[s].planes, &found)
                        : 0;
                    planes[s].solids = LVCL_NO_SOLIDS;
                    /* Kept for the regions' volumes, and for a later refinement's new regions. */
                    if (found.count && !c.failed)
                        c.failed = !keep_cell_solids(solids, stored, s, &found, &solid_cells, &solid_capacity);
                    if (solids->of_cell) planes[s].solids = solids->of_cell[s];
                    planes[s].mixed = clusters > 0
                        ? mixed_patterns(p, &w, facets_in, (const float(*)[4])planes[s].planes, planes[s].count, lo,
                                         g->cell_size)
                        : 0;
                }
    int failed = c.failed;
    free(kind);
    free(c.head);
    free(c.pool);
    free(w.turned);
    free(w.refs);
    free(w.clusters);
    lvcl_error e = failed ? lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the cells' planes")
                          : lvcl_volume_lay_out_regions(g, cells, planes, solids->list, NULL, NULL, slot, regions, st);
    if (e) lvcl_solid_slabs_free(solids);
    free(planes);
    return e;
}

/* The subcells (of k^3) a region has volume in, from its shares as
 * lvcl_region_shares gives them (the region's volume first): its entries in
 * the subcell records. */
static uint64_t present_subcells(const float *share, uint32_t k)
{
    uint64_t present = 0;
    for (uint32_t i = 0; k && i < k * k * k; i++)
        if (share[1 + i] > 0.0f) present |= (uint64_t)1 << i;
    return present;
}

/* Cells whose shares lvcl_volume_lay_out_regions works out at a time. */
#define SHARE_CHUNK 4096

lvcl_error lvcl_volume_lay_out_regions(lv_grid_info *g, size_t cells, const lvcl_cell_planes *planes,
                                       const lvcl_cell_solids *solids, lvcl_known_shares known, void *ctx,
                                       uint32_t *slot, lvcl_regions *regions, lvcl_status *st)
{
    *regions = (lvcl_regions){0};
    size_t stored = g->slot_count;
    /* Per stored cell: its first slot, its pattern -> slot offsets,
     * which patterns have a region of their own and where their shares
     * start; per slot, the subcells its region has volume in. */
    enum { MAX_PATTERNS = 1 << LV_REGION_PLANES, OFFSET_WORDS = MAX_PATTERNS / 4 };
    uint32_t k = g->subcells, per = 1u + (k ? k * k * k : 1u);
    uint64_t all = k ? (k == 4 ? ~(uint64_t)0 : ((uint64_t)1 << (k * k * k)) - 1) : 0;
    size_t total = 0, share_total = 0, share_cap = 0, present_cap = 0, cut_count = 0;
    uint32_t *base = malloc((stored ? stored : 1) * sizeof *base);
    uint32_t *offsets = calloc((stored ? stored : 1) * OFFSET_WORDS, sizeof *offsets);
    uint32_t *first = malloc((stored ? stored : 1) * sizeof *first);
    uint64_t *kept = malloc((stored ? stored : 1) * sizeof *kept), *present = NULL;
    float *sh = NULL, *tmp = malloc(MAX_PATTERNS * (1u + LV_SUBCELL_MAX) * sizeof *tmp);
    /* Without known shares, a chunk of cells' shares at a time are worked
     * out on threads first (at: where each cell's start in `batch`). */
    size_t *at = known ? NULL : malloc(SHARE_CHUNK * sizeof *at), batch_cap = 0;
    float *batch = NULL;
    int failed = !base || !offsets || !first || !kept || !tmp || (!known && !at);
    for (size_t s = 0; s < stored && !failed; s++) {
        uint32_t count = planes[s].count, patterns = 1u << count, index[MAX_PATTERNS], n = 0;
        if (!known && s % SHARE_CHUNK == 0) {
            size_t chunk = stored - s < SHARE_CHUNK ? stored - s : SHARE_CHUNK, floats = 0;
            for (size_t i = 0; i < chunk; i++) {
                at[i] = floats;
                floats += planes[s + i].count ? ((size_t)1 << planes[s + i].count) * per : 0;
            }
            if (floats > batch_cap) {
                float *grown = realloc(batch, floats * sizeof *batch);
                if (!grown) {
                    failed = 1;
                    break;
                }
                batch = grown, batch_cap = floats;
            }
            lvcl_region_shares_batch(planes + s, chunk, k, at, batch);
        }
        base[s] = (uint32_t)total;
        first[s] = LV_NO_SHARES;
        kept[s] = 1;
        int computed = 0; /* its shares, not the known ones */
        const float *shares_of = tmp;
        if (count) {
            /* The exact shares (volume_shares.c); a pattern whose region
             * has under a millionth of the cell gets no slot. */
            if (!known) {
                computed = 1;
                shares_of = batch + at[s % SHARE_CHUNK];
            } else if ((computed = !known(ctx, (uint32_t)s, tmp))) {
                lvcl_region_shares((const float(*)[4])planes[s].planes, (int)count, k, tmp);
            }
            kept[s] = 0;
            for (uint32_t m = 0; m < patterns; m++)
                if (shares_of[m * per] > 1e-6f) kept[s] |= (uint64_t)1 << m, index[m] = n++;
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
        } else {
            n = 1;
        }
        if (total + n > present_cap || share_total + (size_t)n * per > share_cap) {
            size_t pc = present_cap ? 2 * present_cap : 65536, sc = share_cap ? 2 * share_cap : 65536;
            while (pc < total + n) pc *= 2;
            while (sc < share_total + (size_t)n * per) sc *= 2;
            uint64_t *grown_present = realloc(present, pc * sizeof *present);
            if (grown_present) present = grown_present, present_cap = pc;
            float *grown = realloc(sh, sc * sizeof *sh);
            if (grown) sh = grown, share_cap = sc;
            if (!grown_present || !grown) {
                failed = 1;
                break;
            }
        }
        if (!count) {
            present[total++] = all;
            continue;
        }
        /* Each kept region's volume, then its entries' shares. */
        first[s] = (uint32_t)share_total;
        for (uint32_t m = 0; m < patterns; m++)
            if (kept[s] >> m & 1u) {
                const float *from = shares_of + m * per;
                uint64_t mask = present_subcells(from, k);
                present[total++] = mask;
                /* The region's volume less its solids' slabs, where light
                 * never goes: without subcells its lit volume, with them
                 * the most its lit volume may be (lv_cell_lit_volume). */
                sh[share_total++] = computed && solids && planes[s].solids != LVCL_NO_SOLIDS
                    ? (float)lvcl_region_open_volume((const float(*)[4])planes[s].planes, (int)count, m,
                                                     &solids[planes[s].solids])
                    : from[0];
                for (uint32_t i = 0; k && i < k * k * k; i++)
                    if (mask >> i & 1u) sh[share_total++] = from[1 + i];
            }
    }
    lv_slot_region *r = NULL;
    lv_cell_cut *cuts = NULL;
    for (size_t s = 0; !failed && s < stored; s++) cut_count += planes[s].count != 0;
    if (!failed && !sh) sh = calloc(1, sizeof *sh);
    if (!failed && sh && total < LV_CUT_CELL - 1) r = calloc(total + 1, sizeof *r);
    if (r) cuts = calloc(cut_count ? cut_count : 1, sizeof *cuts);
    if (!cuts) free(r), r = NULL;
    uint64_t entries = 0;
    for (size_t s = 0, cut = 0; r && s < stored; s++) {
        lv_cell_cut *c = planes[s].count ? &cuts[cut++] : NULL;
        if (c) {
            memcpy(c->planes, planes[s].planes, sizeof c->planes);
            memcpy(c->offsets, &offsets[s * OFFSET_WORDS], sizeof c->offsets);
            c->plane_count = planes[s].count;
        }
        for (uint32_t m = 0, j = 0, at = first[s]; m < 1u << planes[s].count; m++) {
            if (!(kept[s] >> m & 1u)) continue;
            lv_slot_region *e = &r[base[s] + j];
            uint64_t mask = present[base[s] + j];
            e->base_slot = base[s];
            e->cut = c ? (uint32_t)(c - cuts) : LV_NO_CUT;
            e->region = m;
            /* Mixed where its own pattern is, or an empty one it stands for. */
            for (uint32_t q = 0; q < 1u << planes[s].count; q++)
                if (planes[s].mixed >> q & 1u && (c ? LV_REGION_OFFSET(c, q) : 0u) == j) e->flags |= LV_REGION_MIXED;
            e->shares = planes[s].count ? at : LV_NO_SHARES;
            e->present[0] = (uint32_t)mask;
            e->present[1] = (uint32_t)(mask >> 32);
            uint32_t count = (uint32_t)__builtin_popcountll(mask);
            e->entries = (uint32_t)entries;
            entries += count;
            at += 1u + count;
            j++;
        }
    }
    lvcl_error e = !r ? lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the cells' regions")
        : entries > UINT32_MAX || share_total > UINT32_MAX
        ? lvcl_fail(st, LVCL_ERR_TOO_LARGE,
                    "the light volume would hold over 2^32 subcell records; use fewer --cells or --subcells")
        : LVCL_OK;
    if (e) {
        free(r);
        free(cuts);
        free(sh);
    } else {
        r[total].shares = LV_NO_SHARES;
        r[total].cut = LV_NO_CUT;
        r[total].entries = (uint32_t)entries;
        *regions =
            (lvcl_regions){.slots = r, .cuts = cuts, .cut_count = cut_count, .shares = sh, .share_count = share_total};
        for (size_t i = 0; i < cells; i++)
            if (slot[i] != LV_EMPTY_CELL) slot[i] = base[slot[i]] | (planes[slot[i]].count ? LV_CUT_CELL : 0u);
        g->slot_count = (lv_u32)total;
    }
    free(base);
    free(offsets);
    free(first);
    free(kept);
    free(present);
    free(tmp);
    free(at);
    free(batch);
    return e;
}
