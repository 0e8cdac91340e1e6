/* glTF 2.0 import: a thin layer over tinygltf (parsing, data URIs, image
 * decoding) that flattens the node hierarchy into world-space triangles,
 * materials, punctual lights and a camera (host/scene.h).
 *
 * tinygltf checks the JSON and the GLB container but not most indices and
 * byte ranges, so everything that points into an array or a buffer is
 * validated here before it is read. Errors are thrown as ImportError inside
 * this file and turned into an lvcl_status at the two entry points; the
 * scene is only filled once the whole import has succeeded. */
#include "scene.h"

#include <tiny_gltf.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

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

namespace {

struct ImportError {
    lvcl_error code;
    std::string message;
};

std::string vformat(const char *fmt, va_list ap)
{
    char buf[400];
    vsnprintf(buf, sizeof buf, fmt, ap);
    return buf;
}

[[noreturn]] void fail(lvcl_error code, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

void fail(lvcl_error code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    std::string msg = vformat(fmt, ap);
    va_end(ap);
    throw ImportError{code, msg};
}

/* tinygltf reports several lines; lvcl messages are one line. */
std::string one_line(const std::string &text)
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

bool add_overflows(size_t a, size_t b, size_t *out) { return __builtin_add_overflow(a, b, out); }
bool mul_overflows(size_t a, size_t b, size_t *out) { return __builtin_mul_overflow(a, b, out); }

/* Sizes for the six component types glTF allows; 0 for anything else. */
size_t component_size(int type)
{
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
    }
}

int component_count(int type)
{
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
    }
}

/* One component as a double; `normalized` maps integers to [0,1] / [-1,1]
 * as the glTF spec defines. memcpy because buffers need not be aligned. */
double read_component(const uint8_t *p, int type, bool normalized)
{
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
        int8_t v;
        memcpy(&v, p, 1);
        return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
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

bool is_unsigned_int_type(int type)
{
    return type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
           type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
           type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

/* double -> float without undefined behaviour: out-of-range becomes +-inf. */
float to_f(double d)
{
    if (d > FLT_MAX) return INFINITY;
    if (d < -FLT_MAX) return -INFINITY;
    return (float)d;
}

/* A finite number, or `def` if `v` is not one. */
double number_or(const tinygltf::Value &v, double def)
{
    if (!v.IsNumber()) return def;
    double d = v.GetNumberAsDouble();
    return std::isfinite(d) ? d : def;
}

/* A number from an extension object, or `def` if absent or not a number. */
double ext_number(const tinygltf::Value &obj, const char *key, double def)
{
    if (!obj.IsObject() || !obj.Has(key)) return def;
    return number_or(obj.Get(key), def);
}

/* A 3-vector from an extension object into `out`, left alone if absent. */
void ext_vec3(const tinygltf::Value &obj, const char *key, float out[3])
{
    if (!obj.IsObject() || !obj.Has(key)) return;
    const tinygltf::Value &v = obj.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 3) return;
    for (int k = 0; k < 3; k++) out[k] = to_f(number_or(v.Get(k), out[k]));
}

const tinygltf::Value *find_ext(const tinygltf::ExtensionMap &exts, const char *name)
{
    auto it = exts.find(name);
    return it == exts.end() ? nullptr : &it->second;
}

/* Extensions this importer honours (fully or in the parts lvcl uses). */
const char *const kSupportedExtensions[] = {
    "KHR_lights_punctual",    "KHR_materials_emissive_strength",
    "KHR_materials_transmission", "KHR_materials_ior",
    "KHR_materials_specular", "KHR_materials_volume",
};

/* Required extensions that change how geometry is stored: without them the
 * triangles cannot be read, so the file is refused. */
const char *const kGeometryExtensions[] = {
    "KHR_draco_mesh_compression", "KHR_mesh_quantization",
    "EXT_meshopt_compression",    "EXT_mesh_gpu_instancing",
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

/* Image loader hook for tinygltf: images inside buffer views are decoded
 * later, after their byte range has been checked (tinygltf does not check
 * it); images from URIs arrive as validated bytes and are decoded now. A
 * failed decode is a warning, not an error: the material goes untextured. */
bool load_image_hook(tinygltf::Image *image, int index, std::string *, std::string *warn,
                     int req_width, int req_height, const unsigned char *bytes, int size, void *)
{
    if (image->bufferView != -1) return true;
    std::string decode_err;
    if (!tinygltf::LoadImageData(image, index, &decode_err, warn, req_width, req_height, bytes,
                                 size, nullptr))
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

class Importer {
public:
    Importer(const tinygltf::Model &model, const char *source) : m(model), src(source) {}

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

    void warn_once(const std::string &key, const char *fmt, ...)
        __attribute__((format(printf, 3, 4)));

    void check_extensions();
    void convert_materials();
    lvcl_material_desc convert_material(int index);
    int base_color_texture(int material, const tinygltf::TextureInfo &info);
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
    VertexData read_vertices(const tinygltf::Primitive &p, const char *what);
    std::vector<uint32_t> read_corners(const tinygltf::Primitive &p, size_t nverts,
                                       const char *what);
    int material_index(int mesh, int prim, int material);

    AccessorSpan span(int accessor, const char *what);
    std::pair<const uint8_t *, size_t> view_bytes(int view, const char *what);
    std::vector<double> read_accessor(int accessor, const char *what, AccessorSpan *info);
    void apply_sparse(int accessor, const AccessorSpan &s, std::vector<double> &out);
};

void Importer::warn_once(const std::string &key, const char *fmt, ...)
{
    if (!warned.insert(key).second) return;
    va_list ap;
    va_start(ap, fmt);
    std::string msg = vformat(fmt, ap);
    va_end(ap);
    lvcl_warn("%s: %s", src, msg.c_str());
}

/* ---- accessors ---- */

/* The bytes of buffer view `view`, checked to lie inside its buffer. */
std::pair<const uint8_t *, size_t> Importer::view_bytes(int view, const char *what)
{
    if (view < 0 || (size_t)view >= m.bufferViews.size())
        fail(LVCL_ERR_PARSE, "%s: bufferView %d out of range (file has %zu)", what, view,
             m.bufferViews.size());
    const tinygltf::BufferView &bv = m.bufferViews[(size_t)view];
    if (bv.buffer < 0 || (size_t)bv.buffer >= m.buffers.size())
        fail(LVCL_ERR_PARSE, "bufferView %d: buffer %d out of range (file has %zu)", view,
             bv.buffer, m.buffers.size());
    const std::vector<unsigned char> &data = m.buffers[(size_t)bv.buffer].data;
    size_t end;
    if (add_overflows(bv.byteOffset, bv.byteLength, &end) || end > data.size())
        fail(LVCL_ERR_PARSE,
             "bufferView %d (offset %zu, length %zu) extends past the end of buffer %d (%zu bytes)",
             view, bv.byteOffset, bv.byteLength, bv.buffer, data.size());
    return {data.data() + bv.byteOffset, bv.byteLength};
}

AccessorSpan Importer::span(int accessor, const char *what)
{
    if (accessor < 0 || (size_t)accessor >= m.accessors.size())
        fail(LVCL_ERR_PARSE, "%s: accessor %d out of range (file has %zu)", what, accessor,
             m.accessors.size());
    const tinygltf::Accessor &a = m.accessors[(size_t)accessor];
    AccessorSpan s;
    s.comp_type = a.componentType;
    s.comps = component_count(a.type);
    s.count = a.count;
    s.normalized = a.normalized;
    size_t csize = component_size(a.componentType);
    if (csize == 0 || s.comps == 0)
        fail(LVCL_ERR_PARSE, "accessor %d: invalid componentType %d or type", accessor,
             a.componentType);
    s.elem_size = csize * (size_t)s.comps;
    if (a.count > (size_t)UINT32_MAX)
        fail(LVCL_ERR_PARSE, "accessor %d: count %zu is too large", accessor, a.count);
    if (a.bufferView == -1) return s; /* glTF: no bufferView means zeros (or sparse only) */

    auto bytes = view_bytes(a.bufferView, what);
    const tinygltf::BufferView &bv = m.bufferViews[(size_t)a.bufferView];
    s.stride = bv.byteStride ? bv.byteStride : s.elem_size;
    if (s.stride < s.elem_size)
        fail(LVCL_ERR_PARSE, "bufferView %d: byteStride %zu is smaller than accessor %d's element",
             a.bufferView, bv.byteStride, accessor);
    size_t need = 0;
    if (a.count > 0 &&
        (mul_overflows(a.count - 1, s.stride, &need) || add_overflows(need, s.elem_size, &need) ||
         add_overflows(need, a.byteOffset, &need) || need > bytes.second))
        fail(LVCL_ERR_PARSE,
             "accessor %d (offset %zu, count %zu, stride %zu) reads past the end of bufferView %d "
             "(%zu bytes)",
             accessor, a.byteOffset, a.count, s.stride, a.bufferView, bytes.second);
    s.base = bytes.first + a.byteOffset;
    return s;
}

/* Overwrites the elements a sparse accessor substitutes. */
void Importer::apply_sparse(int accessor, const AccessorSpan &s, std::vector<double> &out)
{
    const auto &sp = m.accessors[(size_t)accessor].sparse;
    if (sp.count < 0 || (size_t)sp.count > s.count)
        fail(LVCL_ERR_PARSE, "accessor %d: sparse count %d out of range", accessor, sp.count);
    if (!is_unsigned_int_type(sp.indices.componentType))
        fail(LVCL_ERR_PARSE, "accessor %d: sparse indices must be unsigned integers", accessor);
    if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0)
        fail(LVCL_ERR_PARSE, "accessor %d: negative sparse byteOffset", accessor);

    size_t n = (size_t)sp.count, isize = component_size(sp.indices.componentType);
    auto ib = view_bytes(sp.indices.bufferView, "sparse indices");
    auto vb = view_bytes(sp.values.bufferView, "sparse values");
    if ((size_t)sp.indices.byteOffset + n * isize > ib.second ||
        (size_t)sp.values.byteOffset + n * s.elem_size > vb.second)
        fail(LVCL_ERR_PARSE, "accessor %d: sparse data reads past the end of its bufferView",
             accessor);

    size_t csize = component_size(s.comp_type);
    for (size_t i = 0; i < n; i++) {
        double target = read_component(ib.first + sp.indices.byteOffset + i * isize,
                                       sp.indices.componentType, false);
        if (target >= (double)s.count)
            fail(LVCL_ERR_PARSE, "accessor %d: sparse index %.0f out of range (count %zu)",
                 accessor, target, s.count);
        const uint8_t *src = vb.first + sp.values.byteOffset + i * s.elem_size;
        for (int c = 0; c < s.comps; c++)
            out[(size_t)target * (size_t)s.comps + (size_t)c] =
                read_component(src + (size_t)c * csize, s.comp_type, s.normalized);
    }
}

/* All components of an accessor, converted to doubles (sparse resolved). */
std::vector<double> Importer::read_accessor(int accessor, const char *what, AccessorSpan *info)
{
    AccessorSpan s = span(accessor, what);
    *info = s;
    std::vector<double> out(s.count * (size_t)s.comps, 0.0);
    size_t csize = component_size(s.comp_type);
    if (s.base)
        for (size_t i = 0; i < s.count; i++)
            for (int c = 0; c < s.comps; c++)
                out[i * (size_t)s.comps + (size_t)c] = read_component(
                    s.base + i * s.stride + (size_t)c * csize, s.comp_type, s.normalized);
    if (m.accessors[(size_t)accessor].sparse.isSparse) apply_sparse(accessor, s, out);
    return out;
}

/* ---- materials and textures ---- */

void Importer::check_extensions()
{
    for (const std::string &ext : m.extensionsRequired) {
        if (in_list(kGeometryExtensions, ext))
            fail(LVCL_ERR_UNSUPPORTED, "required extension %s is not supported", ext.c_str());
        if (!in_list(kSupportedExtensions, ext))
            warn_once("ext:" + ext, "required extension %s is not supported (ignored)",
                      ext.c_str());
    }
    for (const std::string &ext : m.extensionsUsed)
        if (!in_list(kSupportedExtensions, ext))
            warn_once("ext:" + ext, "extension %s is not supported (ignored)", ext.c_str());
    if (!m.animations.empty()) warn_once("anim", "animations are not supported (ignored)");
    if (!m.skins.empty()) warn_once("skin", "skins are not supported (meshes use their node transforms)");
}

/* Decodes image `image_index` once into an RGBA8 texture; -1 if it cannot
 * be decoded (a warning, since the geometry is still usable). */
int Importer::decode_image(int image_index)
{
    auto known = texture_of_image.find(image_index);
    if (known != texture_of_image.end()) return known->second;

    const tinygltf::Image &src = m.images[(size_t)image_index];
    tinygltf::Image decoded;
    const tinygltf::Image *img = &src;
    if (src.bufferView != -1) {
        auto bytes = view_bytes(src.bufferView, "image");
        std::string err, warn;
        if (bytes.second > (size_t)std::numeric_limits<int>::max() ||
            !tinygltf::LoadImageData(&decoded, image_index, &err, &warn, 0, 0, bytes.first,
                                     (int)bytes.second, nullptr))
            decoded.image.clear();
        img = &decoded;
    }

    int result = -1;
    size_t bytes_per = img->bits == 16 ? 2 : 1;
    size_t expect = 0;
    bool ok = !img->image.empty() && img->width > 0 && img->height > 0 && img->component >= 1 &&
              img->component <= 4 && (img->bits == 8 || img->bits == 16) &&
              !mul_overflows((size_t)img->width * (size_t)img->height,
                             (size_t)img->component * bytes_per, &expect) &&
              expect == img->image.size();
    if (ok) {
        Texture t;
        t.width = (uint32_t)img->width;
        t.height = (uint32_t)img->height;
        size_t pixels = (size_t)img->width * (size_t)img->height;
        t.rgba.resize(pixels * 4);
        int comps = img->component;
        for (size_t p = 0; p < pixels; p++) {
            uint8_t c[4] = {0, 0, 0, 0};
            for (int k = 0; k < comps; k++) {
                size_t at = (p * (size_t)comps + (size_t)k) * bytes_per;
                /* 16-bit images (native little-endian ushorts): keep the high byte. */
                c[k] = bytes_per == 2 ? img->image[at + 1] : img->image[at];
            }
            /* Expand grey, grey+alpha and RGB to RGBA. */
            uint8_t r = c[0], g = comps >= 3 ? c[1] : c[0], b = comps >= 3 ? c[2] : c[0];
            uint8_t a = comps == 2 ? c[1] : comps == 4 ? c[3] : 255;
            uint8_t *dst = &t.rgba[p * 4];
            dst[0] = r, dst[1] = g, dst[2] = b, dst[3] = a;
        }
        textures.push_back(std::move(t));
        result = (int)textures.size() - 1;
    } else {
        warn_once("img:" + std::to_string(image_index),
                  "image %d could not be decoded (material left untextured)", image_index);
    }
    texture_of_image[image_index] = result;
    return result;
}

int Importer::base_color_texture(int material, const tinygltf::TextureInfo &info)
{
    if (info.index == -1) return -1;
    if (info.index < 0 || (size_t)info.index >= m.textures.size())
        fail(LVCL_ERR_PARSE, "material %d: texture %d out of range (file has %zu)", material,
             info.index, m.textures.size());
    if (info.texCoord != 0)
        warn_once("texcoord", "material %d: texCoord %d is not supported (TEXCOORD_0 used)",
                  material, info.texCoord);
    if (find_ext(info.extensions, "KHR_texture_transform"))
        warn_once("ext:KHR_texture_transform",
                  "extension KHR_texture_transform is not supported (ignored)");
    int source = m.textures[(size_t)info.index].source;
    if (source == -1) {
        warn_once("nosource", "texture %d has no supported image source (ignored)", info.index);
        return -1;
    }
    if (source < 0 || (size_t)source >= m.images.size())
        fail(LVCL_ERR_PARSE, "texture %d: image %d out of range (file has %zu)", info.index,
             source, m.images.size());
    return decode_image(source);
}

lvcl_material_desc Importer::convert_material(int index)
{
    const tinygltf::Material &mat = m.materials[(size_t)index];
    const tinygltf::PbrMetallicRoughness &pbr = mat.pbrMetallicRoughness;
    lvcl_material_desc d{};

    if (pbr.baseColorFactor.size() != 4)
        fail(LVCL_ERR_PARSE, "material %d: baseColorFactor must have 4 numbers", index);
    for (int k = 0; k < 4; k++) d.base_color[k] = to_f(pbr.baseColorFactor[(size_t)k]);
    d.base_color_texture = base_color_texture(index, pbr.baseColorTexture);
    d.metallic = to_f(pbr.metallicFactor);
    d.roughness = to_f(pbr.roughnessFactor);

    if (!mat.emissiveFactor.empty() && mat.emissiveFactor.size() != 3)
        fail(LVCL_ERR_PARSE, "material %d: emissiveFactor must have 3 numbers", index);
    const tinygltf::Value *ext = find_ext(mat.extensions, "KHR_materials_emissive_strength");
    double strength = ext ? ext_number(*ext, "emissiveStrength", 1.0) : 1.0;
    for (int k = 0; k < 3; k++)
        d.emissive[k] = mat.emissiveFactor.empty()
                            ? 0.0f
                            : to_f(mat.emissiveFactor[(size_t)k] * strength);

    ext = find_ext(mat.extensions, "KHR_materials_transmission");
    d.transmission = ext ? to_f(ext_number(*ext, "transmissionFactor", 0.0)) : 0.0f;
    ext = find_ext(mat.extensions, "KHR_materials_ior");
    d.ior = ext ? to_f(ext_number(*ext, "ior", 1.5)) : 1.5f;
    ext = find_ext(mat.extensions, "KHR_materials_specular");
    d.specular = ext ? to_f(ext_number(*ext, "specularFactor", 1.0)) : 1.0f;

    d.attenuation_color[0] = d.attenuation_color[1] = d.attenuation_color[2] = 1.0f;
    d.attenuation_distance = INFINITY;
    ext = find_ext(mat.extensions, "KHR_materials_volume");
    if (ext) {
        d.has_volume = ext_number(*ext, "thicknessFactor", 0.0) > 0.0;
        ext_vec3(*ext, "attenuationColor", d.attenuation_color);
        double dist = ext_number(*ext, "attenuationDistance", INFINITY);
        if (dist > 0.0) d.attenuation_distance = to_f(dist);
    }
    d.double_sided = mat.doubleSided ? 1 : 0;

    /* What lvcl ignores, once per kind. */
    if (mat.alphaMode != "OPAQUE")
        warn_once("alpha", "alphaMode %s is not supported (treated as OPAQUE)",
                  mat.alphaMode.c_str());
    if (pbr.metallicRoughnessTexture.index != -1)
        warn_once("mrtex", "metallicRoughnessTexture is not supported (ignored)");
    if (mat.normalTexture.index != -1)
        warn_once("ntex", "normalTexture is not supported (ignored)");
    if (mat.occlusionTexture.index != -1)
        warn_once("otex", "occlusionTexture is not supported (ignored)");
    if (mat.emissiveTexture.index != -1)
        warn_once("etex", "emissiveTexture is not supported (ignored)");
    return d;
}

void Importer::convert_materials()
{
    for (size_t i = 0; i < m.materials.size(); i++) materials.push_back(convert_material((int)i));
}

/* The glTF default material, appended on first use. */
int Importer::material_index(int mesh, int prim, int material)
{
    if (material >= 0 && (size_t)material < materials.size()) return material;
    if (material != -1)
        fail(LVCL_ERR_PARSE, "mesh %d primitive %d: material %d out of range (file has %zu)", mesh,
             prim, material, materials.size());
    if (default_material < 0) {
        lvcl_material_desc d{};
        d.base_color[0] = d.base_color[1] = d.base_color[2] = d.base_color[3] = 1.0f;
        d.base_color_texture = -1;
        d.metallic = 1.0f;
        d.roughness = 1.0f;
        d.ior = 1.5f;
        d.specular = 1.0f;
        d.attenuation_color[0] = d.attenuation_color[1] = d.attenuation_color[2] = 1.0f;
        d.attenuation_distance = INFINITY;
        materials.push_back(d);
        default_material = (int)materials.size() - 1;
    }
    return default_material;
}

/* ---- geometry ---- */

VertexData Importer::read_vertices(const tinygltf::Primitive &p, const char *what)
{
    auto attr = [&](const char *name) {
        auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -2 : it->second;
    };
    int pos_acc = attr("POSITION"), nrm_acc = attr("NORMAL"), uv_acc = attr("TEXCOORD_0");
    if (pos_acc == -2) fail(LVCL_ERR_PARSE, "%s has no POSITION attribute", what);

    VertexData d;
    AccessorSpan ps, ns, us;
    d.pos = read_accessor(pos_acc, what, &ps);
    if (ps.comps != 3 || ps.comp_type != TINYGLTF_COMPONENT_TYPE_FLOAT || ps.normalized)
        fail(LVCL_ERR_PARSE, "%s: POSITION accessor %d must be VEC3 float", what, pos_acc);
    d.count = ps.count;

    if (nrm_acc != -2) {
        d.nrm = read_accessor(nrm_acc, what, &ns);
        if (ns.comps != 3 || ns.comp_type != TINYGLTF_COMPONENT_TYPE_FLOAT || ns.normalized)
            fail(LVCL_ERR_PARSE, "%s: NORMAL accessor %d must be VEC3 float", what, nrm_acc);
        if (ns.count != d.count)
            fail(LVCL_ERR_PARSE, "%s: NORMAL count %zu differs from POSITION count %zu", what,
                 ns.count, d.count);
    }
    if (uv_acc != -2) {
        d.uv = read_accessor(uv_acc, what, &us);
        bool float_ok = us.comp_type == TINYGLTF_COMPONENT_TYPE_FLOAT && !us.normalized;
        bool unorm_ok = us.normalized && (us.comp_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                          us.comp_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
        if (us.comps != 2 || !(float_ok || unorm_ok))
            fail(LVCL_ERR_PARSE,
                 "%s: TEXCOORD_0 accessor %d must be VEC2 float or normalized unsigned byte/short",
                 what, uv_acc);
        if (us.count != d.count)
            fail(LVCL_ERR_PARSE, "%s: TEXCOORD_0 count %zu differs from POSITION count %zu", what,
                 us.count, d.count);
    }
    return d;
}

/* Triangle corners as vertex indices local to the primitive, each checked. */
std::vector<uint32_t> Importer::read_corners(const tinygltf::Primitive &p, size_t nverts,
                                             const char *what)
{
    std::vector<uint32_t> corners;
    if (p.indices == -1) { /* non-indexed: consecutive vertices */
        corners.resize(nverts);
        for (size_t i = 0; i < nverts; i++) corners[i] = (uint32_t)i;
    } else {
        AccessorSpan is;
        std::vector<double> idx = read_accessor(p.indices, what, &is);
        if (is.comps != 1 || !is_unsigned_int_type(is.comp_type))
            fail(LVCL_ERR_PARSE, "%s: indices accessor %d must be scalar unsigned integers", what,
                 p.indices);
        corners.reserve(idx.size());
        for (double v : idx) {
            if (v >= (double)nverts)
                fail(LVCL_ERR_PARSE, "%s: index value %.0f out of range (vertex count %zu)", what,
                     v, nverts);
            corners.push_back((uint32_t)v);
        }
    }
    if (corners.size() % 3 != 0)
        warn_once("partial", "%s: index count %zu is not a multiple of 3 (extra ignored)", what,
                  corners.size());
    return corners;
}

/* Positions and normals in world space, with per-vertex validity. Normals
 * use the inverse transpose so they stay perpendicular under non-uniform
 * scale; a normal that degenerates is zeroed and marked invalid. */
struct WorldVertices {
    std::vector<float> pos, nrm;
    std::vector<char> pos_ok, nrm_ok;
};

WorldVertices to_world(const VertexData &d, const glm::dmat4 &world)
{
    glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(world)));
    bool has_nrm = !d.nrm.empty();
    WorldVertices w;
    w.pos.resize(d.count * 3);
    w.pos_ok.resize(d.count);
    w.nrm.resize(has_nrm ? d.count * 3 : 0);
    w.nrm_ok.resize(has_nrm ? d.count : 0);
    for (size_t v = 0; v < d.count; v++) {
        glm::dvec4 p = world * glm::dvec4(d.pos[3 * v], d.pos[3 * v + 1], d.pos[3 * v + 2], 1.0);
        bool ok = true;
        for (size_t k = 0; k < 3; k++) {
            w.pos[3 * v + k] = to_f(p[(int)k]);
            ok = ok && std::isfinite(w.pos[3 * v + k]);
        }
        w.pos_ok[v] = ok;
        if (!has_nrm) continue;
        glm::dvec3 n = normal_matrix * glm::dvec3(d.nrm[3 * v], d.nrm[3 * v + 1], d.nrm[3 * v + 2]);
        double len = glm::length(n);
        bool nok = std::isfinite(len) && len > 0.0;
        for (size_t k = 0; k < 3; k++) w.nrm[3 * v + k] = nok ? (float)(n[(int)k] / len) : 0.0f;
        w.nrm_ok[v] = nok;
    }
    return w;
}

void Importer::add_primitive(int mesh, int prim, const glm::dmat4 &world)
{
    const tinygltf::Primitive &p = m.meshes[(size_t)mesh].primitives[(size_t)prim];
    char what[64];
    snprintf(what, sizeof what, "mesh %d primitive %d", mesh, prim);

    if (p.mode != TINYGLTF_MODE_TRIANGLES) {
        warn_once("mode:" + std::to_string(p.mode),
                  "primitive mode %d is not supported, only triangles (skipped)", p.mode);
        return;
    }
    if (!p.targets.empty()) warn_once("morph", "morph targets are not supported (ignored)");
    if (find_ext(p.extensions, "KHR_draco_mesh_compression"))
        warn_once("ext:KHR_draco_mesh_compression",
                  "extension KHR_draco_mesh_compression is not supported (ignored)");

    uint32_t material = (uint32_t)material_index(mesh, prim, p.material);
    VertexData d = read_vertices(p, what);
    std::vector<uint32_t> corners = read_corners(p, d.count, what);
    WorldVertices w = to_world(d, world);
    bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;

    /* Keep triangles with finite corners. */
    std::vector<uint32_t> kept;
    for (size_t t = 0; t + 2 < corners.size(); t += 3) {
        uint32_t a = corners[t], b = corners[t + 1], c = corners[t + 2];
        if (!w.pos_ok[a] || !w.pos_ok[b] || !w.pos_ok[c]) {
            nonfinite_triangles++;
            continue;
        }
        if (mirrored) std::swap(b, c); /* keep the world-space winding (front faces) */
        kept.insert(kept.end(), {a, b, c});
        uint32_t flags = 0;
        if (!d.nrm.empty() && w.nrm_ok[a] && w.nrm_ok[b] && w.nrm_ok[c]) flags |= LV_TRI_HAS_NORMALS;
        if (!d.uv.empty()) flags |= LV_TRI_HAS_UVS;
        tri_flags.push_back(flags);
        tri_material.push_back(material);
    }

    /* Append only the vertices those triangles use (in vertex order), so a
     * shared vertex buffer or a skipped NaN vertex adds nothing. */
    std::vector<uint32_t> remap(d.count, UINT32_MAX);
    for (uint32_t v : kept) remap[v] = 0;
    for (size_t v = 0; v < d.count; v++) {
        if (remap[v] == UINT32_MAX) continue;
        size_t id = positions.size() / 3;
        if (id >= (size_t)UINT32_MAX)
            fail(LVCL_ERR_UNSUPPORTED, "scene has more than 2^32 - 1 vertices");
        remap[v] = (uint32_t)id;
        positions.insert(positions.end(), &w.pos[3 * v], &w.pos[3 * v] + 3);
        for (size_t k = 0; k < 3; k++) normals.push_back(d.nrm.empty() ? 0.0f : w.nrm[3 * v + k]);
        for (size_t k = 0; k < 2; k++) uvs.push_back(d.uv.empty() ? 0.0f : to_f(d.uv[2 * v + k]));
    }
    for (uint32_t v : kept) indices.push_back(remap[v]);
}

void Importer::add_mesh(int node, const glm::dmat4 &world)
{
    int mesh = m.nodes[(size_t)node].mesh;
    if (mesh < 0 || (size_t)mesh >= m.meshes.size())
        fail(LVCL_ERR_PARSE, "node %d: mesh %d out of range (file has %zu)", node, mesh,
             m.meshes.size());
    if (mesh_uses[(size_t)mesh] > 1) {
        double det = glm::determinant(glm::dmat3(world));
        bool finite = std::isfinite(det);
        for (int c = 0; c < 4; c++)
            for (int r = 0; r < 3; r++) finite = finite && std::isfinite(world[c][r]);
        if (!finite || det == 0.0)
            fail(LVCL_ERR_PARSE, "node %d: its transform is %s", node, finite ? "singular" : "not finite");
        placements.push_back({mesh, world});
        return;
    }
    for (size_t p = 0; p < m.meshes[(size_t)mesh].primitives.size(); p++)
        add_primitive(mesh, (int)p, world);
}

void Importer::count_mesh_uses()
{
    mesh_uses.assign(m.meshes.size(), 0);
    for (const tinygltf::Node &n : m.nodes)
        if (n.mesh >= 0 && (size_t)n.mesh < m.meshes.size()) mesh_uses[(size_t)n.mesh]++;
}

/* After the node walk: mesh 0 holds the baked triangles (if any), then each
 * shared mesh follows once, in object space, in order of first placement. */
void Importer::build_instances()
{
    if (placements.empty()) return;
    size_t baked = indices.size() / 3;
    if (baked) {
        meshes.push_back({0, baked});
        lvcl_instance in{};
        memcpy(in.world_from_object, lvcl_identity_transform, sizeof in.world_from_object);
        instances.push_back(in);
    }
    std::map<int, uint32_t> stored;
    for (const Placement &pl : placements) {
        if (!stored.count(pl.mesh)) {
            size_t first = indices.size() / 3;
            for (size_t p = 0; p < m.meshes[(size_t)pl.mesh].primitives.size(); p++)
                add_primitive(pl.mesh, (int)p, glm::dmat4(1.0));
            stored[pl.mesh] = (uint32_t)meshes.size();
            meshes.push_back({first, indices.size() / 3 - first});
        }
        lvcl_instance in{};
        in.mesh = stored[pl.mesh];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 4; c++) in.world_from_object[4 * r + c] = to_f(pl.world[c][r]);
        instances.push_back(in);
    }
}

/* ---- cameras and lights ---- */

glm::dvec3 transform_dir(const glm::dmat4 &world, glm::dvec3 local)
{
    glm::dvec3 d = glm::dmat3(world) * local;
    double len = glm::length(d);
    return std::isfinite(len) && len > 0.0 ? d / len : glm::dvec3(0.0);
}

void store3(float out[3], glm::dvec3 v)
{
    for (int k = 0; k < 3; k++) out[k] = to_f(v[k]);
}

void Importer::add_camera(int node, const glm::dmat4 &world)
{
    int index = m.nodes[(size_t)node].camera;
    if (index < 0 || (size_t)index >= m.cameras.size())
        fail(LVCL_ERR_PARSE, "node %d: camera %d out of range (file has %zu)", node, index,
             m.cameras.size());
    const tinygltf::Camera &cam = m.cameras[(size_t)index];
    if (cam.type != "perspective") {
        warn_once("ortho", "camera %d: %s cameras are not supported (ignored)", index,
                  cam.type.c_str());
        return;
    }
    if (camera.present) return; /* the first perspective camera wins */
    double yfov = cam.perspective.yfov, aspect = cam.perspective.aspectRatio;
    if (!(yfov > 0.0 && yfov < 3.14159265358979)) {
        warn_once("yfov", "camera %d: invalid yfov %g (ignored)", index, yfov);
        return;
    }
    camera.present = 1;
    store3(camera.position, glm::dvec3(world[3]));
    store3(camera.right, transform_dir(world, {1, 0, 0}));
    store3(camera.up, transform_dir(world, {0, 1, 0}));
    store3(camera.back, transform_dir(world, {0, 0, 1}));
    camera.yfov = (float)yfov;
    camera.aspect = std::isfinite(aspect) && aspect > 0.0 ? to_f(aspect) : 0.0f;
}

void Importer::add_light(int node, const glm::dmat4 &world)
{
    const tinygltf::Value *ext = find_ext(m.nodes[(size_t)node].extensions, "KHR_lights_punctual");
    double light = ext && ext->IsObject() && ext->Has("light") ? number_or(ext->Get("light"), -1) : -1;
    if (light < 0 || light >= (double)m.lights.size() || light != std::floor(light))
        fail(LVCL_ERR_PARSE, "node %d: KHR_lights_punctual light %g out of range (file has %zu)",
             node, light, m.lights.size());
    int index = (int)light;
    const tinygltf::Light &l = m.lights[(size_t)index];
    if (l.type != "point" && l.type != "spot") {
        warn_once("light:" + l.type, "light %d ('%s'): %s lights are not supported (skipped)",
                  index, l.name.c_str(), l.type.c_str());
        return;
    }
    if (!l.color.empty() && l.color.size() != 3)
        fail(LVCL_ERR_PARSE, "light %d: color must have 3 numbers", index);

    lv_punctual_light pl{};
    store3(pl.position, glm::dvec3(world[3]));
    store3(pl.direction, transform_dir(world, {0, 0, -1}));
    for (int k = 0; k < 3; k++)
        pl.intensity[k] = to_f((l.color.empty() ? 1.0 : l.color[(size_t)k]) * l.intensity);
    if (l.type == "spot") {
        pl.type = LV_PUNCTUAL_SPOT;
        pl.cos_outer = to_f(std::cos(l.spot.outerConeAngle));
        pl.cos_inner = to_f(std::cos(l.spot.innerConeAngle));
    } else {
        /* Points shine everywhere: a cone covering the whole sphere. */
        pl.type = LV_PUNCTUAL_POINT;
        pl.cos_outer = -1.0f;
        pl.cos_inner = -1.0f;
    }
    lights.push_back(pl);
}

/* ---- node hierarchy ---- */

glm::dmat4 Importer::local_transform(int node)
{
    const tinygltf::Node &n = m.nodes[(size_t)node];
    if (!n.matrix.empty()) {
        if (n.matrix.size() != 16)
            fail(LVCL_ERR_PARSE, "node %d: matrix must have 16 numbers", node);
        return glm::make_mat4(n.matrix.data()); /* glTF and GLM are both column-major */
    }
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (!n.translation.empty()) {
        if (n.translation.size() != 3)
            fail(LVCL_ERR_PARSE, "node %d: translation must have 3 numbers", node);
        t = glm::translate(glm::dmat4(1.0), glm::make_vec3(n.translation.data()));
    }
    if (!n.rotation.empty()) {
        if (n.rotation.size() != 4)
            fail(LVCL_ERR_PARSE, "node %d: rotation must have 4 numbers", node);
        /* glTF stores x, y, z, w; glm::dquat's constructor takes w first. */
        glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
        double len = glm::length(q);
        if (std::isfinite(len) && len > 0.0) r = glm::mat4_cast(q / len);
    }
    if (!n.scale.empty()) {
        if (n.scale.size() != 3) fail(LVCL_ERR_PARSE, "node %d: scale must have 3 numbers", node);
        s = glm::scale(glm::dmat4(1.0), glm::make_vec3(n.scale.data()));
    }
    return t * r * s;
}

void Importer::visit(int node, const glm::dmat4 &parent, int depth)
{
    if (node < 0 || (size_t)node >= m.nodes.size())
        fail(LVCL_ERR_PARSE, "node %d out of range (file has %zu)", node, m.nodes.size());
    if (depth > 1000) fail(LVCL_ERR_PARSE, "node hierarchy deeper than 1000 levels");
    if (visited[(size_t)node])
        fail(LVCL_ERR_PARSE, "node %d is reached twice (child cycle or shared child)", node);
    visited[(size_t)node] = 1;

    const tinygltf::Node &n = m.nodes[(size_t)node];
    glm::dmat4 world = parent * local_transform(node);
    if (n.skin != -1) warn_once("skin", "skins are not supported (meshes use their node transforms)");
    if (!n.weights.empty()) warn_once("morph", "morph targets are not supported (ignored)");
    if (n.camera != -1) add_camera(node, world);
    if (n.extensions.count("KHR_lights_punctual")) add_light(node, world);
    if (n.mesh != -1) add_mesh(node, world);
    for (int child : n.children) visit(child, world, depth + 1);
}

/* The default scene, else scene 0, else every node that is nobody's child. */
std::vector<int> Importer::scene_roots()
{
    if (m.defaultScene != -1) {
        if (m.defaultScene < 0 || (size_t)m.defaultScene >= m.scenes.size())
            fail(LVCL_ERR_PARSE, "default scene %d out of range (file has %zu)", m.defaultScene,
                 m.scenes.size());
        return m.scenes[(size_t)m.defaultScene].nodes;
    }
    if (!m.scenes.empty()) return m.scenes[0].nodes;
    std::vector<char> is_child(m.nodes.size(), 0);
    for (const tinygltf::Node &n : m.nodes)
        for (int c : n.children)
            if (c >= 0 && (size_t)c < m.nodes.size()) is_child[(size_t)c] = 1;
    std::vector<int> roots;
    for (size_t i = 0; i < m.nodes.size(); i++)
        if (!is_child[i]) roots.push_back((int)i);
    return roots;
}

void Importer::run()
{
    check_extensions();
    convert_materials();
    visited.assign(m.nodes.size(), 0);
    count_mesh_uses();
    for (int root : scene_roots()) visit(root, glm::dmat4(1.0), 0);
    build_instances();
    if (nonfinite_triangles)
        lvcl_warn("%s: skipped %zu triangles with non-finite vertex positions", src,
                  nonfinite_triangles);
    if (indices.empty()) fail(LVCL_ERR_UNSUPPORTED, "scene has no triangles");
}

/* malloc'd copy of a vector (NULL when empty), as C code frees with free(). */
template <typename T> T *c_array(const std::vector<T> &v)
{
    if (v.empty()) return nullptr;
    T *p = static_cast<T *>(malloc(v.size() * sizeof(T)));
    if (!p) throw std::bad_alloc();
    memcpy(p, v.data(), v.size() * sizeof(T));
    return p;
}

/* Fills `scene` (zeroed); on an allocation failure the caller frees it. */
void Importer::fill(lvcl_scene *scene) const
{
    scene->vertex_count = positions.size() / 3;
    scene->positions = c_array(positions);
    scene->normals = c_array(normals);
    scene->uvs = c_array(uvs);
    scene->triangle_count = indices.size() / 3;
    scene->indices = c_array(indices);
    scene->tri_material = c_array(tri_material);
    scene->tri_flags = c_array(tri_flags);
    scene->mesh_count = meshes.size();
    scene->meshes = c_array(meshes);
    scene->instance_count = instances.size();
    scene->instances = c_array(instances);
    scene->material_count = materials.size();
    scene->materials = c_array(materials);
    scene->punctual_count = lights.size();
    scene->punctuals = c_array(lights);
    scene->camera = camera;
    if (!textures.empty()) {
        scene->textures =
            static_cast<lvcl_texture_data *>(calloc(textures.size(), sizeof(lvcl_texture_data)));
        if (!scene->textures) throw std::bad_alloc();
        scene->texture_count = textures.size();
        for (size_t i = 0; i < textures.size(); i++) {
            scene->textures[i].width = textures[i].width;
            scene->textures[i].height = textures[i].height;
            scene->textures[i].rgba = c_array(textures[i].rgba);
        }
    }
}

/* tinygltf errors about files it could not read are I/O errors, not parse errors. */
lvcl_error classify_tinygltf_error(const std::string &err)
{
    if (err.find("File not found") != std::string::npos ||
        err.find("File open error") != std::string::npos ||
        err.find("File read error") != std::string::npos)
        return LVCL_ERR_IO;
    return LVCL_ERR_PARSE;
}

void parse_model(const char *source, const unsigned char *data, size_t size,
                 const std::string &base_dir, tinygltf::Model *model)
{
    if (size == 0) fail(LVCL_ERR_PARSE, "empty input");
    if (size > std::numeric_limits<unsigned int>::max())
        fail(LVCL_ERR_UNSUPPORTED, "file is larger than 4 GiB");
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(load_image_hook, nullptr);
    std::string err, warn;
    bool ok;
    if (size >= 4 && memcmp(data, "glTF", 4) == 0) {
        /* Report a short file plainly before tinygltf looks at chunks. */
        uint32_t length = 0;
        if (size >= 12) memcpy(&length, data + 8, 4);
        if (size < 20 || length > size)
            fail(LVCL_ERR_PARSE, "truncated GLB (%zu bytes, header says %u)", size, length);
        ok = loader.LoadBinaryFromMemory(model, &err, &warn, data, (unsigned int)size, base_dir);
    } else {
        ok = loader.LoadASCIIFromString(model, &err, &warn, reinterpret_cast<const char *>(data),
                                        (unsigned int)size, base_dir);
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
lvcl_error import(const char *source, const unsigned char *data, size_t size,
                  const std::string &base_dir, lvcl_scene *scene, lvcl_status *st)
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

extern "C" lvcl_error lvcl_scene_load_gltf_file(const char *path, lvcl_scene *scene,
                                                lvcl_status *st)
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

extern "C" lvcl_error lvcl_scene_load_gltf_memory(const void *data, size_t size,
                                                  const char *base_dir, lvcl_scene *scene,
                                                  lvcl_status *st)
{
    memset(scene, 0, sizeof *scene);
    if (!data && size > 0)
        return lvcl_fail(st, LVCL_ERR_USAGE, "<memory>: null data pointer");
    try {
        return import("<memory>", static_cast<const unsigned char *>(data), size,
                      base_dir ? base_dir : "", scene, st);
    } catch (...) {
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "<memory>: out of memory");
    }
}
