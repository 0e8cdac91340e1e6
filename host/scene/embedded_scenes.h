/* Scenes compiled into the executable (the glTF files in scenes/), so that lvcl
 * renders something with no files around it. */
#ifndef LVCL_EMBEDDED_SCENES_H
#define LVCL_EMBEDDED_SCENES_H

#include <stddef.h>

typedef struct {
    const char *name;
    const unsigned char *data;
    size_t size;
} lvcl_embedded_scene;

/* The scene called `name`, or NULL. */
const lvcl_embedded_scene *lvcl_embedded_scene_find(const char *name);

/* Comma-separated names, for messages. */
const char *lvcl_embedded_scene_names(void);

#endif
