/* glTF 2.0 import: a thin layer over tinygltf (parsing, data URIs, image
 * decoding) that flattens the node hierarchy into world-space triangles,
 * materials, punctual lights and a camera (host/scene/scene.h).
 *
 * tinygltf checks the JSON and the GLB container but not most indices and
 * byte ranges, so everything that points into an array or a buffer is
 * validated here before it is read. Errors are thrown as ImportError inside
 * host/scene/gltf/ and turned into an lvcl_status at the two entry points; the
 * scene is only filled once the whole import has succeeded. */
#include "gltf_importer.h"

#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

namespace
{

using namespace lvcl_gltf;

/* tinygltf errors about files it could not read are I/O errors, not parse errors. */
lvcl_error classify_tinygltf_error(const std::string &err)
{
    if (err.find("File not found") != std::string::npos || err.find("File open error") != std::string::npos ||
        err.find("File read error") != std::string::npos)
        return LVCL_ERR_IO;
    return LVCL_ERR_PARSE;
}

void parse_model(const char *source, const unsigned char *data, size_t size, const std::string &base_dir,
                 tinygltf::Model *model)
{
    if (size == 0) fail(LVCL_ERR_PARSE, "empty input");
    if (size > std::numeric_limits<unsigned int>::max()) fail(LVCL_ERR_UNSUPPORTED, "file is larger than 4 GiB");
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(load_image_hook, nullptr);
    std::string err, warn;
    bool ok;
    if (size >= 4 && memcmp(data, "glTF", 4) == 0) {
        /* Report a short file plainly before tinygltf looks at chunks. */
        uint32_t length = 0;
        if (size >= 12) memcpy(&length, data + 8, 4);
        if (size < 20 || length > size) fail(LVCL_ERR_PARSE, "truncated GLB (%zu bytes, header says %u)", size, length);
        ok = loader.LoadBinaryFromMemory(model, &err, &warn, data, (unsigned int)size, base_dir);
    } else {
        ok = loader.LoadASCIIFromString(model, &err, &warn, reinterpret_cast<const char *>(data), (unsigned int)size,
                                        base_dir);
    }
    if (!ok) {
        std::string msg = one_line(err);
        fail(classify_tinygltf_error(msg), "%s", msg.empty() ? "invalid glTF" : msg.c_str());
    }
    /* tinygltf's warnings, one line each. */
    size_t start = 0;
    while (start < warn.size()) {
        size_t end = warn.find('\n', start);
        if (end == std::string::npos) end = warn.size();
        if (end > start) lvcl_warn("%s: %s", source, warn.substr(start, end - start).c_str());
        start = end + 1;
    }
}

/* The shared body of both entry points: all failures become `st`. */
lvcl_error import(const char *source, const unsigned char *data, size_t size, const std::string &base_dir,
                  lvcl_scene *scene, lvcl_status *st)
{
    lvcl_scene result;
    memset(&result, 0, sizeof result);
    try {
        tinygltf::Model model;
        parse_model(source, data, size, base_dir, &model);
        Importer importer(model, source);
        importer.run();
        importer.fill(&result);
        *scene = result;
        return LVCL_OK;
    } catch (const ImportError &e) {
        lvcl_scene_free(&result);
        return lvcl_fail(st, e.code, "%s: %s", source, e.message.c_str());
    } catch (const std::bad_alloc &) {
        lvcl_scene_free(&result);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "%s: out of memory", source);
    } catch (...) {
        lvcl_scene_free(&result);
        return lvcl_fail(st, LVCL_ERR_PARSE, "%s: unexpected error while reading glTF", source);
    }
}

/* Reads a whole file; false with errno-based message on failure. */
bool read_file(const char *path, std::vector<unsigned char> *out, std::string *why)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        *why = strerror(errno);
        return false;
    }
    unsigned char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) out->insert(out->end(), buf, buf + n);
    bool ok = !ferror(f);
    if (!ok) *why = strerror(errno);
    fclose(f);
    return ok;
}

} // namespace

extern "C" lvcl_error lvcl_scene_load_gltf_file(const char *path, lvcl_scene *scene, lvcl_status *st)
{
    memset(scene, 0, sizeof *scene);
    try {
        std::vector<unsigned char> bytes;
        std::string why;
        if (!read_file(path, &bytes, &why))
            return lvcl_fail(st, LVCL_ERR_IO, "%s: cannot read file: %s", path, why.c_str());
        std::string p(path);
        size_t slash = p.find_last_of('/');
        std::string base_dir = slash == std::string::npos ? "" : p.substr(0, slash);
        return import(path, bytes.data(), bytes.size(), base_dir, scene, st);
    } catch (...) {
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
}

extern "C" lvcl_error lvcl_scene_load_gltf_memory(const void *data, size_t size, const char *base_dir,
                                                  lvcl_scene *scene, lvcl_status *st)
{
    memset(scene, 0, sizeof *scene);
    if (!data && size > 0) return lvcl_fail(st, LVCL_ERR_USAGE, "<memory>: null data pointer");
    try {
        return import("<memory>", static_cast<const unsigned char *>(data), size, base_dir ? base_dir : "", scene, st);
    } catch (...) {
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "<memory>: out of memory");
    }
}
