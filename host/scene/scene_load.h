/* A scene by name: a .gltf/.glb path, or one of the embedded scenes. */
#ifndef LVCL_SCENE_LOAD_H
#define LVCL_SCENE_LOAD_H

#include "scene.h"

/* Loads a scene from a .gltf/.glb path or an embedded scene name. */
lvcl_error lvcl_scene_load(const char *name, lvcl_scene *scene, lvcl_status *st);

#endif
