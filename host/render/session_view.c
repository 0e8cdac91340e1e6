/* Light odds learned from the view. Where lamps light spaces the camera
 * does not see (the next room, another storey), the packed odds
 * (host/device/packed_scene.c) still send them particles and light samples
 * by their power and an even share: with a lamp 1000 times brighter behind
 * a wall, the room in view got a quarter of both, and its lv image had 8
 * times the error it had with that lamp off. So the first part of the
 * particle trace also sums, per region the camera sees (found by camera
 * rays on the host) and light group, the light the particles bring to
 * surfaces there, straight from the lights and after scattering; the rest
 * of the trace chooses groups by the scattered light's sums and the
 * gather's light samples by the direct light's (group_weights), every
 * light keeping a share of its packed odds. Each particle's weight is its
 * own odds', and a light sample's pdf the table the gather reads, so the
 * estimators are unbiased whatever the odds; the sums are integers, so
 * every device and every run decides alike (docs/light-volume.md, "Odds
 * learned from the view"). */
#include <math.h>
#include <stdlib.h>

#include "session_internal.h"
#include "../scene/camera.h"

/* Camera rays a side of the probe's image. */
#define VIEW_RAYS 64
/* The share of its packed odds every light keeps: a light the probe found
 * no use for still gets a quarter of them, so its weight grows at most 4x. */
#define VIEW_KEEP 0.25

/* The most light groups, and sums, a probe keeps: beyond, the odds stay
 * packed. */
#define VIEW_GROUPS 64
#define VIEW_SUMS (1u << 22)

/* Whether the lights' odds may follow the view: two lit groups or more
 * (up to VIEW_GROUPS), and one process (a cluster's processes would each
 * sum their own). */
static int view_applies(const lvcl_session *s)
{
    const lvcl_packed_scene *p = &s->packed;
    size_t groups = lvcl_packed_light_groups(p), lit = 0;
    unsigned char *seen = calloc(groups ? groups : 1, 1);
    if (!seen) return 0;
    for (size_t i = 0; i < p->light_count; i++)
        if (p->light_odds[i] > 0 && !seen[p->lights[i].group]) seen[p->lights[i].group] = 1, lit++;
    free(seen);
    return lit >= 2 && groups <= VIEW_GROUPS && !lvcl_cluster_shared(s->cluster);
}

/* Marks the slots (regions of cells) that VIEW_RAYS x VIEW_RAYS camera
 * rays (an image of the render's aspect) reach: the one just in front of
 * each first hit, where the gather reads the volume, and those half a cell
 * and a cell from there along the axes that a straight line from there
 * reaches, where its jittered lookups read. Regions, not cells: a cell a
 * wall cuts holds both rooms, and the other room's slot must stay
 * unmarked. */
static void view_slots(const lvcl_session *s, const lvcl_light_volume *vol, int width, int height, uint8_t *slots)
{
    const lv_grid_info *g = lvcl_volume_grid(vol);
    int w = width >= height ? VIEW_RAYS : (VIEW_RAYS * width + height - 1) / height;
    int h = width >= height ? (VIEW_RAYS * height + width - 1) / width : VIEW_RAYS;
    lv_camera c = lvcl_camera_make(&s->scene.camera, s->packed.bounds_min, s->packed.bounds_max, w, h);
    double reach = 0;
    for (int k = 0; k < 3; k++) reach += (double)g->dims[k] * g->cell_size;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double sx = 2.0 * (x + 0.5) / w - 1.0, sy = 1.0 - 2.0 * (y + 0.5) / h, o[3], d[3], len = 0;
            for (int k = 0; k < 3; k++) {
                o[k] = c.origin[k];
                d[k] = (double)c.forward[k] + sx * c.right[k] + sy * c.up[k];
                len += d[k] * d[k];
            }
            len = sqrt(len);
            /* The camera may stand outside the grid: reach past it. */
            double far = reach;
            for (int k = 0; k < 3; k++) d[k] /= len, far += fabs(o[k] - g->origin[k]);
            double t = lvcl_packed_first_hit(&s->packed, o, d, far);
            if (t <= 0) continue;
            double back = fmin(0.01 * g->cell_size, 0.5 * t), front[3];
            float p[3];
            for (int k = 0; k < 3; k++) front[k] = o[k] + (t - back) * d[k], p[k] = (float)front[k];
            uint32_t slot = lvcl_volume_slot_at(vol, p);
            if (slot != LV_EMPTY_CELL) slots[slot] = 1;
            for (int axis = 0; axis < 6; axis++)
                for (int step = 1; step <= 2; step++) {
                    double dir[3] = {0, 0, 0}, len_step = 0.5 * step * g->cell_size;
                    dir[axis / 2] = axis % 2 ? -1.0 : 1.0;
                    if (lvcl_packed_segment_hits(&s->packed, front, dir, len_step)) break;
                    for (int k = 0; k < 3; k++) p[k] = (float)(front[k] + len_step * dir[k]);
                    slot = lvcl_volume_slot_at(vol, p);
                    if (slot != LV_EMPTY_CELL) slots[slot] = 1;
                }
        }
}

/* Writes the packed light table to every device. */
static lvcl_error upload_lights(lvcl_session *s, lvcl_status *st)
{
    lvcl_error e = LVCL_OK;
    for (int d = 0; d < s->device_count && !e; d++)
        e = lvcl_device_scene_update_lights(&s->devices[d].device, &s->packed, &s->devices[d].device_scene, st);
    return e;
}

uint64_t lvcl_session_first_part(const lvcl_session *s, const lvcl_volume_settings *vs)
{
    uint64_t split_at = lvcl_volume_split_point(vs);
    return split_at || !lvcl_volume_view_probing(s->devices[0].volume) ? split_at : vs->particles / 4;
}

lvcl_error lvcl_session_view_start(lvcl_session *s, int follow, lvcl_status *st)
{
    lvcl_error e = LVCL_OK;
    free(s->gather_odds);
    s->gather_odds = NULL;
    s->view_odds = 0;
    if (lvcl_packed_set_light_odds(&s->packed, NULL, 0) && (e = upload_lights(s, st))) return e;
    if (!follow || !view_applies(s) || !s->devices[0].volume) return LVCL_OK;
    size_t slot_count = (size_t)lvcl_volume_grid(s->devices[0].volume)->slot_count + 1, count = 0;
    uint8_t *marks = calloc(slot_count, 1);
    uint32_t *seen = malloc(slot_count * sizeof *seen);
    if (!marks || !seen) e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the view probe");
    if (!e) {
        int w, h;
        lvcl_image_size(&s->scene.camera, 0, 0, &w, &h);
        view_slots(s, s->devices[0].volume, w, h, marks);
        for (size_t i = 0; i < slot_count; i++) seen[i] = marks[i] ? (uint32_t)count++ : LV_EMPTY_CELL;
    }
    size_t groups = lvcl_packed_light_groups(&s->packed);
    for (int d = 0; d < s->device_count && !e && count * groups * 2 <= VIEW_SUMS; d++)
        e = lvcl_volume_view_probe(s->devices[d].volume, seen, count, groups, st);
    free(marks);
    free(seen);
    return e;
}

/* Each group's weight for one kind of light (0: straight from the lights,
 * 1: scattered): the root of the sum over the regions the camera sees of
 * the squared share of the region's light the group brought. Relative
 * error weighs a dim region as much as a bright one, and with odds p_g a
 * region's relative variance goes as the sum of share^2 / p_g, least where
 * p_g follows that root. */
static void group_weights(const int64_t *units, size_t regions, size_t groups, int kind, double *weight)
{
    for (size_t r = 0; r < regions; r++) {
        double total = 0;
        for (size_t g = 0; g < groups; g++) total += (double)units[2 * (r * groups + g) + kind];
        for (size_t g = 0; total > 0 && g < groups; g++) {
            double share = (double)units[2 * (r * groups + g) + kind] / total;
            weight[g] += share * share;
        }
    }
    for (size_t g = 0; g < groups; g++) weight[g] = sqrt(weight[g]);
}

lvcl_error lvcl_session_view_decide(lvcl_session *s, int store_emitted, lvcl_status *st)
{
    lvcl_light_volume *first = s->devices[0].volume;
    if (!first || !lvcl_volume_view_probing(first)) return LVCL_OK;
    size_t groups = lvcl_packed_light_groups(&s->packed), sums = lvcl_volume_view_sums(first);
    size_t regions = sums / (2 * groups);
    int64_t *units = calloc(sums, sizeof *units), *part = calloc(sums, sizeof *part);
    double *scattered = calloc(groups, sizeof *scattered), *direct = calloc(groups, sizeof *direct);
    lvcl_error e = units && part && scattered && direct
        ? LVCL_OK
        : lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the view probe");
    for (int d = 0; d < s->device_count && !e; d++) {
        lvcl_light_volume *vol = s->devices[d].volume;
        /* Integer sums: the same whichever device traced which particles. */
        if (!(e = lvcl_volume_view_light(vol, part, st)))
            for (size_t i = 0; i < sums; i++) units[i] += part[i];
        if (!e) e = lvcl_volume_view_probe(vol, NULL, 0, 0, st);
    }
    if (!e) {
        /* lv-all reads the lights' own light from the volume too. */
        if (store_emitted)
            for (size_t i = 0; i < sums; i += 2) units[i + 1] += units[i];
        group_weights(units, regions, groups, 1, scattered);
        group_weights(units, regions, groups, 0, direct);
        if (lvcl_packed_set_light_odds(&s->packed, scattered, VIEW_KEEP)) e = upload_lights(s, st);
        s->gather_odds = direct;
        direct = NULL;
    }
    free(units);
    free(part);
    free(scattered);
    free(direct);
    return e;
}

lvcl_error lvcl_session_view_gather(lvcl_session *s, lvcl_status *st)
{
    if (!s->gather_odds) return LVCL_OK;
    int changed = lvcl_packed_set_light_odds(&s->packed, s->gather_odds, VIEW_KEEP);
    free(s->gather_odds);
    s->gather_odds = NULL;
    s->view_odds = 1;
    return changed ? upload_lights(s, st) : LVCL_OK;
}
