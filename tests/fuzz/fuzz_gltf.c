/* libFuzzer harness for the glTF importer: any bytes, as a .gltf (JSON) or
 * .glb (binary), must load or be refused with a one-line message, never crash or
 * read out of bounds; a loaded scene is then flattened as a render would. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "../../host/scene/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lvcl_scene scene = {0};
    lvcl_status st = {0};
    /* No base folder: a relative URI names nothing that exists. */
    if (lvcl_scene_load_gltf_memory(data, size, "/nonexistent-fuzz-dir", &scene, &st) == LVCL_OK)
        (void)lvcl_scene_flatten(&scene, &st);
    else if (!st.message[0] || strchr(st.message, '\n')) {
        fprintf(stderr, "refused without a one-line message: '%s'\n", st.message);
        __builtin_trap();
    }
    lvcl_scene_free(&scene);
    return 0;
}
