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

/* A GLB chunk's type as text, for messages ("JSON", "BIN", or hex). */
std::string chunk_type_name(uint32_t type)
{
    char name[5] = {0};
    memcpy(name, &type, 4);
    bool printable = true;
    for (int i = 0; i < 4; i++) printable = printable && ((name[i] >= 0x20 && name[i] < 0x7f) || name[i] == 0);
    if (printable) return name;
    char hex[16];
    snprintf(hex, sizeof hex, "0x%08x", type);
    return hex;
}

/* The GLB container: version 2, chunks inside the stated length, JSON
 * first. Unknown chunks after it are allowed (the specification says to
 * skip them); tinygltf checks the buffers against the BIN chunk. */
void check_glb_layout(const unsigned char *data, size_t size)
{
    uint32_t version, length;
    memcpy(&version, data + 4, 4);
    memcpy(&length, data + 8, 4);
    if (size < 20 || length > size) fail(LVCL_ERR_PARSE, "truncated GLB (%zu bytes, header says %u)", size, length);
    if (version != 2) fail(LVCL_ERR_UNSUPPORTED, "GLB version %u is not supported (only version 2)", version);
    size_t at = 12;
    for (int index = 0; at < length; index++) {
        uint32_t chunk_length, type;
        if (length - at < 8) fail(LVCL_ERR_PARSE, "GLB: %zu stray bytes after chunk %d", length - at, index - 1);
        memcpy(&chunk_length, data + at, 4);
        memcpy(&type, data + at + 4, 4);
        std::string name = chunk_type_name(type);
        if (chunk_length > length - at - 8)
            fail(LVCL_ERR_PARSE, "GLB chunk %d (%s, %u bytes at offset %zu) runs past the end of the file (%u bytes)",
                 index, name.c_str(), chunk_length, at, length);
        if (index == 0 && name != "JSON") fail(LVCL_ERR_PARSE, "GLB: the first chunk is %s, not JSON", name.c_str());
        at += 8 + (size_t)chunk_length;
    }
}

/* glTF 2.x only: version "1.0" files have another structure altogether. */
void check_asset_version(const tinygltf::Asset &asset)
{
    const std::string &v = asset.version;
    if (v.empty()) fail(LVCL_ERR_PARSE, "asset.version is missing");
    if (v[0] != '2' || (v.size() > 1 && v[1] != '.'))
        fail(LVCL_ERR_UNSUPPORTED, "glTF version %s is not supported (lvcl reads glTF 2.x)", v.c_str());
    if (!asset.minVersion.empty() && asset.minVersion != "2.0")
        fail(LVCL_ERR_UNSUPPORTED, "the file needs glTF %s (asset.minVersion); lvcl reads glTF 2.0",
             asset.minVersion.c_str());
}

/* The URI of tinygltf's "File not found : URI" message, if it is one. */
bool missing_file_uri(const std::string &err, std::string *uri)
{
    static const std::string prefix = "File not found : ";
    size_t at = err.find(prefix);
    if (at == std::string::npos) return false;
    *uri = err.substr(at + prefix.size());
    *uri = uri->substr(0, uri->find("; "));
    return true;
}

/* Whether `uri` starts with a scheme such as http:// (data: URIs never
 * reach the file system). */
bool is_remote(const std::string &uri)
{
    size_t colon = uri.find("://");
    return colon != std::string::npos && colon > 0 &&
        std::all_of(uri.begin(), uri.begin() + (long)colon, [](char c) { return isalpha((unsigned char)c) != 0; });
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
        /* Report a short or odd file plainly before tinygltf looks at chunks. */
        if (size < 12) fail(LVCL_ERR_PARSE, "truncated GLB (%zu bytes)", size);
        check_glb_layout(data, size);
        ok = loader.LoadBinaryFromMemory(model, &err, &warn, data, (unsigned int)size, base_dir);
    } else {
        ok = loader.LoadASCIIFromString(model, &err, &warn, reinterpret_cast<const char *>(data), (unsigned int)size,
                                        base_dir);
    }
    if (!ok) {
        std::string msg = one_line(err), uri;
        if (missing_file_uri(msg, &uri)) {
            if (is_remote(uri))
                fail(LVCL_ERR_UNSUPPORTED, "%s is a remote URI; lvcl reads only local files and data: URIs",
                     uri.c_str());
            fail(LVCL_ERR_IO, "cannot find %s (URIs are relative to the glTF file's folder)", uri.c_str());
        }
        fail(classify_tinygltf_error(msg), "%s", msg.empty() ? "invalid glTF" : msg.c_str());
    }
    check_asset_version(model->asset);
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
