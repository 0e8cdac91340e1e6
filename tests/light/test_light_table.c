/* The light table (host/device/packed_scene.c): the odds with which a
 * particle leaves a light and a light sample aims at it. Lights of one
 * emissive material together, and each punctual light, form a group; the
 * odds mix each light's share of the power with an even share per group
 * (LVCL_EVEN_LIGHT_SHARE). Checked on scenes of two or three lamps of
 * radiance ratios 1 to 1000 and sizes 1 to 25 (by area), with and without
 * a point light:
 *   sums        the odds sum to 1 and the cumulative table climbs to 1;
 *   power       no light gets less than (1 - e) of its power's share, so a
 *               particle's weight (its light's power over odds x total
 *               power) stays within 1 / (1 - e);
 *   groups      every group gets at least e / (number of groups);
 *   one group   lamps of one material are picked by power alone, exactly.
 * That the renders stay unbiased with these odds is checked against closed
 * forms in test_area_lights.c and test_point_lights.c, and on two lit
 * rooms in tests/volume/test_two_rooms.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "../../host/accel/accel.h"
#include "../../host/device/packed_scene.h"
#include "../check.h"
#include "closed_forms.h"

/* The emitted power (luminance watts) of light i of the packed table. */
static double light_power(const lvcl_packed_scene *p, const lvcl_scene *s, size_t i)
{
    const lv_light *l = &p->lights[i];
    if (l->kind == LV_LIGHT_PUNCTUAL) {
        const lv_punctual_light *pl = &s->punctuals[l->index];
        return 4.0 * PI * LV_LUMINANCE(pl->intensity[0], pl->intensity[1], pl->intensity[2]);
    }
    float v[9];
    lvcl_packed_triangle_world(p, l->instance, l->index, v);
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = v[3 + k] - v[k];
        e2[k] = v[6 + k] - v[k];
    }
    cross3(e1, e2, n);
    const float *le = p->materials[p->triangles[l->index].material].emission;
    return PI * LV_LUMINANCE(le[0], le[1], le[2]) * 0.5 * sqrt(dot3(n, n));
}

/* The light's group: its material, or for a punctual light one past the
 * materials per light. */
static size_t light_group(const lvcl_packed_scene *p, size_t i)
{
    const lv_light *l = &p->lights[i];
    return l->kind == LV_LIGHT_PUNCTUAL ? p->material_count + l->index : p->triangles[l->index].material;
}

/* Lamps: `count` squares facing down over the ground, lamp k of half-size
 * half[k] and radiance le[k], of material 1 + group[k]; `point` adds a point
 * light of that intensity (0: none). */
static void check_table(const char *what, int count, const double *half, const double *le, const int *group,
                        double point)
{
    quad quads[4];
    lvcl_material_desc m[4];
    int materials = 1;
    quads[0] = ground();
    m[0] = lambertian(0.5f);
    for (int k = 0; k < count; k++) {
        quads[1 + k] = horizontal_quad(2.0 * k, 0, 1.0, half[k], 0, (uint32_t)(1 + group[k]));
        m[1 + group[k]] = emitter((float)le[k]);
        if (1 + group[k] >= materials) materials = 2 + group[k];
    }
    const double intensity[3] = {point, point, point};
    lv_punctual_light light = point_light(0, 0, 2.0, intensity);
    lvcl_scene scene;
    quad_scene(quads, (size_t)(1 + count), m, (size_t)materials, point > 0 ? &light : NULL, point > 0, &scene);
    lvcl_accel accel = {0};
    lvcl_packed_scene p = {0};
    lvcl_status st = {0};
    int ok = !lvcl_accel_build(&scene, &accel, &st) && !lvcl_pack_scene(&scene, &accel, 0, 8, &p, &st);
    CHECK("light table: the scene packs", ok, "%s: %s", what, st.message);
    if (!ok) {
        lvcl_accel_free(&accel);
        lvcl_scene_free(&scene);
        return;
    }
    double total = 0, group_odds[8] = {0}, group_power[8] = {0}, sum = 0, worst_weight = 0, previous = 0;
    int climbs = 1;
    for (size_t i = 0; i < p.light_count; i++) total += light_power(&p, &scene, i);
    for (size_t i = 0; i < p.light_count; i++) {
        double power = light_power(&p, &scene, i), odds = p.lights[i].pdf_select;
        sum += odds;
        climbs &= p.lights[i].cdf >= previous && fabs(p.lights[i].cdf - sum) < 1e-5;
        previous = p.lights[i].cdf;
        group_odds[light_group(&p, i)] += odds;
        group_power[light_group(&p, i)] += power;
        worst_weight = fmax(worst_weight, power / (odds * total));
    }
    int groups = 0;
    double least_group = 1;
    for (int g = 0; g < 8; g++)
        if (group_power[g] > 0) {
            groups++;
            least_group = fmin(least_group, group_odds[g]);
        }
    printf("  %s: %zu lights in %d groups, odds sum %.7f, least group's odds %.4f, largest weight %.4f\n", what,
           p.light_count, groups, sum, least_group, worst_weight);
    CHECK("light table: the odds sum to 1 and the cumulative table climbs to exactly 1",
          fabs(sum - 1) < 1e-5 && climbs && p.lights[p.light_count - 1].cdf == 1.0f, "%s: sum %.7f", what, sum);
    CHECK("light table: no light gets less than (1 - e) of its power's share (weights within 1 / (1 - e))",
          worst_weight <= (1 + 1e-5) / (1 - LVCL_EVEN_LIGHT_SHARE), "%s: a weight of %.5f", what, worst_weight);
    CHECK("light table: every group gets at least e / groups of the choices",
          least_group >= (1 - 1e-5) * LVCL_EVEN_LIGHT_SHARE / groups, "%s: least %.5f of %d groups", what, least_group,
          groups);
    if (groups == 1) {
        int exact = 1;
        for (size_t i = 0; i < p.light_count; i++)
            exact &= fabs(p.lights[i].pdf_select - light_power(&p, &scene, i) / total) <= 1e-6;
        CHECK("light table: lamps of one material are picked by power alone", exact, "%s", what);
    }
    lvcl_packed_scene_free(&p);
    lvcl_accel_free(&accel);
    lvcl_scene_free(&scene);
}

int main(void)
{
    const double ratios[] = {1, 25, 1000};
    const double sizes[][3] = {{0.5, 0.5, 0.2}, {0.1, 0.5, 0.5}, {0.5, 0.1, 0.3}};
    const int two_groups[] = {0, 1, 1}, three_groups[] = {0, 1, 2}, one_group[] = {0, 0, 0};
    char what[160];
    for (int r = 0; r < 3; r++)
        for (int s = 0; s < 3; s++) {
            const double le[3] = {4.0 * ratios[r], 4.0, 4.0 * sqrt(ratios[r])};
            snprintf(what, sizeof what, "two lamps %gx, half-sizes %g and %g", ratios[r], sizes[s][0], sizes[s][1]);
            check_table(what, 2, sizes[s], le, two_groups, 0);
            snprintf(what, sizeof what, "three lamps of three materials %gx, sizes set %d, a point light", ratios[r],
                     s);
            check_table(what, 3, sizes[s], le, three_groups, 100.0);
            snprintf(what, sizeof what, "lamps of two materials, one twice, %gx, sizes set %d", ratios[r], s);
            check_table(what, 3, sizes[s], le, two_groups, 0);
        }
    const double le[3] = {4, 4, 4};
    check_table("three lamps of one material, half-sizes 0.5, 0.1, 0.3", 3, sizes[2], le, one_group, 0);
    check_table("two lamps of one material and a faint point light", 2, sizes[1], le, one_group, 0.01);
    CHECK_EXIT();
}
