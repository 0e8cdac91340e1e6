#include "scene.h"

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
    free(scene->meshes);
    free(scene->instances);
    free(scene->materials);
    for (size_t i = 0; i < scene->texture_count; i++)
        free(scene->textures[i].rgba);
    free(scene->textures);
    free(scene->punctuals);
    memset(scene, 0, sizeof *scene);
}
