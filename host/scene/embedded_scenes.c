#include "embedded_scenes.h"

#include <string.h>

/* Generated at build time by host/embed. */
extern const unsigned char lvcl_scene_cornell[];
extern const size_t lvcl_scene_cornell_size;
extern const unsigned char lvcl_scene_furnace[];
extern const size_t lvcl_scene_furnace_size;
extern const unsigned char lvcl_scene_kitchen[];
extern const size_t lvcl_scene_kitchen_size;

const lvcl_embedded_scene *lvcl_embedded_scene_find(const char *name)
{
    static lvcl_embedded_scene scenes[3];
    scenes[0] = (lvcl_embedded_scene){.name = "cornell", .data = lvcl_scene_cornell, .size = lvcl_scene_cornell_size};
    scenes[1] = (lvcl_embedded_scene){.name = "furnace", .data = lvcl_scene_furnace, .size = lvcl_scene_furnace_size};
    scenes[2] = (lvcl_embedded_scene){.name = "kitchen", .data = lvcl_scene_kitchen, .size = lvcl_scene_kitchen_size};
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++)
        if (!strcmp(scenes[i].name, name)) return &scenes[i];
    return NULL;
}

const char *lvcl_embedded_scene_names(void)
{
    return "cornell, furnace, kitchen";
}
