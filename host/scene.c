#include "scene.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void lvcl_scene_free(lvcl_scene *scene)
{
    free(scene->positions);
    free(scene->normals);
    free(scene->uvs);
    free(scene->indices);
    free(scene->tri_material);
    free(scene->tri_flags);
    free(scene->materials);
    for (size_t i = 0; i < scene->texture_count; i++)
        free(scene->textures[i].rgba);
    free(scene->textures);
    free(scene->punctuals);
    memset(scene, 0, sizeof *scene);
}

void lvcl_scene_bounds(const lvcl_scene *scene, float bmin[3], float bmax[3])
{
    for (int k = 0; k < 3; k++) {
        bmin[k] = FLT_MAX;
        bmax[k] = -FLT_MAX;
    }
    /* Non-finite coordinates (whose triangles the BVH leaves out) would
     * make the bounds, and every size derived from them, infinite. */
    for (size_t i = 0; i < scene->vertex_count; i++)
        for (int k = 0; k < 3; k++) {
            float p = scene->positions[3 * i + k];
            if (!isfinite(p)) continue;
            if (p < bmin[k]) bmin[k] = p;
            if (p > bmax[k]) bmax[k] = p;
        }
}
