/* The glTF importer's private declarations, shared by the files of
 * host/scene/gltf/: the error it throws, small readers of tinygltf values
 * and accessor bytes, and the Importer class whose members those files
 * define (accessors, materials, geometry, nodes). */
#ifndef LVCL_GLTF_IMPORTER_H
#define LVCL_GLTF_IMPORTER_H

#include "../scene.h"
#include <tiny_gltf.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <cfloat>
#include <limits>
#include <map>
#include <new>
#include <set>
#include <string>
#include <vector>

namespace lvcl_gltf
{

struct ImportError {
    lvcl_error code;
    std::string message;
};

inline std::string vformat(const char *fmt, va_list ap)
{
    char buf[400];
    vsnprintf(buf, sizeof buf, fmt, ap);
    return buf;
}

[[noreturn]] inline void fail(lvcl_error code, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

inline void fail(lvcl_error code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    std::string msg = vformat(fmt, ap);
    va_end(ap);
    throw ImportError{code, msg};
}

/* tinygltf reports several lines; lvcl messages are one line. */
inline std::string one_line(const std::string &text)
{
    std::string out;
    for (char c : text) {
        if (c == '\n' || c == '\r') {
            bool ends_sep = out.size() >= 2 && out.compare(out.size() - 2, 2, "; ") == 0;
            if (!out.empty() && !ends_sep) out += "; ";
        } else {
            out += c;
        }
    }
    while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
    return out;
}

inline bool add_overflows(size_t a, size_t b, size_t *out)
{
    return __builtin_add_overflow(a, b, out);
}
inline bool mul_overflows(size_t a, size_t b, size_t *out)
{
    return __builtin_mul_overflow(a, b, out);
}

/* Sizes for the six component types glTF allows; 0 for anything else. */
inline size_t component_size(int type)
{
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return 4;
    default:
        return 0;
    }
}

inline int component_count(int type)
{
    switch (type) {
    case TINYGLTF_TYPE_SCALAR:
        return 1;
    case TINYGLTF_TYPE_VEC2:
        return 2;
    case TINYGLTF_TYPE_VEC3:
        return 3;
    case TINYGLTF_TYPE_VEC4:
        return 4;
    case TINYGLTF_TYPE_MAT2:
        return 4;
    case TINYGLTF_TYPE_MAT3:
        return 9;
    case TINYGLTF_TYPE_MAT4:
        return 16;
    default:
        return 0;
    }
}

/* One component as a double; `normalized` maps integers to [0,1] / [-1,1]
 * as the glTF spec defines. memcpy because buffers need not be aligned. */
inline double read_component(const uint8_t *p, int type, bool normalized)
{
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
        int8_t v;
        memcpy(&v, p, 1);
        return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t v;
        memcpy(&v, p, 2);
        return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        memcpy(&v, p, 2);
        return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t v;
        memcpy(&v, p, 4);
        return normalized ? v / 4294967295.0 : v;
    }
    default: {
        float v;
        memcpy(&v, p, 4);
        return v;
    }
    }
}

inline bool is_unsigned_int_type(int type)
{
    return type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
        type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

/* double -> float without undefined behaviour: out-of-range becomes +-inf. */
inline float to_f(double d)
{
    if (d > FLT_MAX) return INFINITY;
    if (d < -FLT_MAX) return -INFINITY;
    return (float)d;
}

/* A finite number, or `def` if `v` is not one. */
inline double number_or(const tinygltf::Value &v, double def)
{
    if (!v.IsNumber()) return def;
    double d = v.GetNumberAsDouble();
    return std::isfinite(d) ? d : def;
}

/* A number from an extension object, or `def` if absent or not a number. */
inline double ext_number(const tinygltf::Value &obj, const char *key, double def)
{
    if (!obj.IsObject() || !obj.Has(key)) return def;
    return number_or(obj.Get(key), def);
}

/* An n-vector from an extension object into `out`, left alone if absent. */
inline void ext_vector(const tinygltf::Value &obj, const char *key, int n, double *out)
{
    if (!obj.IsObject() || !obj.Has(key)) return;
    const tinygltf::Value &v = obj.Get(key);
    if (!v.IsArray() || v.ArrayLen() != (size_t)n) return;
    for (int k = 0; k < n; k++) out[k] = number_or(v.Get(k), out[k]);
}

inline void ext_vec3(const tinygltf::Value &obj, const char *key, float out[3])
{
    double v[3] = {out[0], out[1], out[2]};
    ext_vector(obj, key, 3, v);
    for (int k = 0; k < 3; k++) out[k] = to_f(v[k]);
}

inline const tinygltf::Value *find_ext(const tinygltf::ExtensionMap &exts, const char *name)
{
    auto it = exts.find(name);
    return it == exts.end() ? nullptr : &it->second;
}

/* Extensions this importer honours (fully or in the parts lvcl uses). */
inline const char *const kSupportedExtensions[] = {
    "KHR_lights_punctual",   "KHR_materials_emissive_strength", "KHR_materials_transmission",
    "KHR_materials_ior",     "KHR_materials_specular",          "KHR_materials_volume",
    "KHR_mesh_quantization", "KHR_texture_transform",
};

/* Required extensions that change how geometry is stored: without them the
 * triangles cannot be read, so the file is refused. */
inline const char *const kGeometryExtensions[] = {
    "KHR_draco_mesh_compression",
    "EXT_meshopt_compression",
    "EXT_mesh_gpu_instancing",
};

template <size_t N> bool in_list(const char *const (&list)[N], const std::string &name)
{
    for (const char *s : list)
        if (name == s) return true;
    return false;
}

struct Texture {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba;
};

/* The largest texture side decoded (16384, the common GPU image limit;
 * an RGBA8 texture of it is 1 GiB). */
#define LVCL_MAX_TEXTURE_SIDE 16384

/* Decodes one image's bytes into `image` (tinygltf's layout), or returns
 * false. Only PNG and JPEG, the two formats glTF 2.0 allows, and at most
 * LVCL_MAX_TEXTURE_SIDE pixels a side: stb_image, which tinygltf decodes
 * with, also reads GIF, PSD, PNM and more, whose decoders fuzzing has
 * found allocating from untrusted headers. */
bool decode_image_bytes(tinygltf::Image *image, int index, const unsigned char *bytes, size_t size);

/* Image loader hook for tinygltf: images inside buffer views are decoded
 * later, after their byte range has been checked (tinygltf does not check
 * it); images from URIs arrive as validated bytes and are decoded now. A
 * failed decode is a warning, not an error: the material goes untextured. */
inline bool load_image_hook(tinygltf::Image *image, int index, std::string *, std::string *, int, int,
                            const unsigned char *bytes, int size, void *)
{
    if (image->bufferView != -1) return true;
    if (size < 0 || !decode_image_bytes(image, index, bytes, (size_t)size))
        image->image.clear(); /* reported by decode_image() if a material uses it */
    return true;
}

/* Raw, validated location of an accessor's elements. */
struct AccessorSpan {
    const uint8_t *base = nullptr; /* null: no bufferView, all zeros */
    size_t stride = 0;
    size_t count = 0;
    size_t elem_size = 0;
    int comp_type = 0;
    int comps = 0;
    bool normalized = false;
};

/* Validated attribute data of one primitive. */
struct VertexData {
    size_t count = 0;
    std::vector<double> pos, nrm, uv; /* nrm, uv empty when absent */
};

class Importer
{
  public:
    Importer(const tinygltf::Model &model, const char *source) : m(model), src(source)
    {
    }

    void run();
    void fill(lvcl_scene *scene) const;

  private:
    const tinygltf::Model &m;
    const char *src; /* file name for warnings */

    std::vector<float> positions, normals, uvs;
    std::vector<uint32_t> indices, tri_material, tri_flags;
    std::vector<lvcl_material_desc> materials;
    std::vector<Texture> textures;
    std::map<int, int> texture_of_image;
    std::vector<lv_punctual_light> lights;
    lvcl_camera_desc camera{};
    int default_material = -1;
    size_t nonfinite_triangles = 0;
    std::vector<char> visited;
    /* Instancing: a glTF mesh that several nodes use is stored once, in
     * its own space, and placed by one instance per node; the rest is
     * baked into world space as mesh 0. */
    struct Placement {
        int mesh;
        glm::dmat4 world;
    };
    std::vector<int> mesh_uses;
    std::vector<Placement> placements;
    std::vector<lvcl_mesh> meshes;
    std::vector<lvcl_instance> instances;
    std::set<std::string> warned;

    void warn_once(const std::string &key, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

    void check_extensions();
    void convert_materials();
    lvcl_material_desc convert_material(int index);
    int base_color_texture(int material, const tinygltf::TextureInfo &info);
    void read_uv_transform(const tinygltf::TextureInfo &info, lvcl_material_desc &d);
    void read_sampler(const tinygltf::TextureInfo &info, lvcl_material_desc &d);
    int decode_image(int image_index);
    std::vector<int> scene_roots();
    void visit(int node, const glm::dmat4 &parent, int depth);
    glm::dmat4 local_transform(int node);
    void add_camera(int node, const glm::dmat4 &world);
    void add_light(int node, const glm::dmat4 &world);
    void add_mesh(int node, const glm::dmat4 &world);
    void add_primitive(int mesh, int prim, const glm::dmat4 &world);
    void count_mesh_uses();
    void build_instances();
    int texcoord_set(const tinygltf::Primitive &p);
    VertexData read_vertices(const tinygltf::Primitive &p, const char *what);
    std::vector<uint32_t> read_corners(const tinygltf::Primitive &p, size_t nverts, const char *what);
    int material_index(int mesh, int prim, int material);

    AccessorSpan span(int accessor, const char *what);
    std::pair<const uint8_t *, size_t> view_bytes(int view, const char *what);
    std::vector<double> read_accessor(int accessor, const char *what, AccessorSpan *info);
    void apply_sparse(int accessor, const AccessorSpan &s, std::vector<double> &out);
};

} // namespace lvcl_gltf

#endif
