#include "scene_load.h"

#include <sys/stat.h>

#include "embedded_scenes.h"

lvcl_error lvcl_scene_load(const char *name, lvcl_scene *scene, lvcl_status *st)
{
    struct stat sb;
    if (stat(name, &sb) == 0) return lvcl_scene_load_gltf_file(name, scene, st);
    const lvcl_embedded_scene *e = lvcl_embedded_scene_find(name);
    if (e) return lvcl_scene_load_gltf_memory(e->data, e->size, "", scene, st);
    return lvcl_fail(st, LVCL_ERR_IO, "no such file or embedded scene '%s' (embedded: %s)", name,
                     lvcl_embedded_scene_names());
}
