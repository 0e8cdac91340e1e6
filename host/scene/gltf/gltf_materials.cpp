/* glTF import: extensions, materials and their base-colour textures. */
#include "gltf_importer.h"

#include <stb/stb_image.h>

namespace lvcl_gltf
{

/* ---- materials and textures ---- */

void Importer::check_extensions()
{
    for (const std::string &ext : m.extensionsRequired) {
        if (in_list(kGeometryExtensions, ext))
            fail(LVCL_ERR_UNSUPPORTED, "required extension %s is not supported", ext.c_str());
        if (!in_list(kSupportedExtensions, ext))
            warn_once("ext:" + ext, "required extension %s is not supported (ignored)", ext.c_str());
    }
    for (const std::string &ext : m.extensionsUsed)
        if (!in_list(kSupportedExtensions, ext))
            warn_once("ext:" + ext, "extension %s is not supported (ignored)", ext.c_str());
    if (!m.animations.empty()) warn_once("anim", "animations are not supported (ignored)");
    if (!m.skins.empty()) warn_once("skin", "skins are not supported (meshes use their node transforms)");
}

bool decode_image_bytes(tinygltf::Image *image, int index, const unsigned char *bytes, size_t size)
{
    static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    static const unsigned char jpeg[3] = {0xff, 0xd8, 0xff};
    bool known = (size >= sizeof png && memcmp(bytes, png, sizeof png) == 0) ||
        (size >= sizeof jpeg && memcmp(bytes, jpeg, sizeof jpeg) == 0);
    int width, height, comps;
    if (!known || size > (size_t)std::numeric_limits<int>::max() ||
        !stbi_info_from_memory(bytes, (int)size, &width, &height, &comps) || width < 1 || height < 1 ||
        width > LVCL_MAX_TEXTURE_SIDE || height > LVCL_MAX_TEXTURE_SIDE)
        return false;
    std::string err, warn;
    return tinygltf::LoadImageData(image, index, &err, &warn, 0, 0, bytes, (int)size, nullptr);
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
        if (!decode_image_bytes(&decoded, image_index, bytes.first, bytes.second)) decoded.image.clear();
        img = &decoded;
    }

    int result = -1;
    size_t bytes_per = img->bits == 16 ? 2 : 1;
    size_t expect = 0;
    bool ok = !img->image.empty() && img->width > 0 && img->height > 0 && img->component >= 1 && img->component <= 4 &&
        (img->bits == 8 || img->bits == 16) &&
        !mul_overflows((size_t)img->width * (size_t)img->height, (size_t)img->component * bytes_per, &expect) &&
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
        warn_once(
            "img:" + std::to_string(image_index),
            "image %d could not be decoded as a PNG or JPEG of at most %d pixels a side (material left untextured)",
            image_index, LVCL_MAX_TEXTURE_SIDE);
    }
    texture_of_image[image_index] = result;
    return result;
}

int Importer::base_color_texture(int material, const tinygltf::TextureInfo &info)
{
    if (info.index == -1) return -1;
    if (info.index < 0 || (size_t)info.index >= m.textures.size())
        fail(LVCL_ERR_PARSE, "material %d: texture %d out of range (file has %zu)", material, info.index,
             m.textures.size());
    if (info.texCoord < 0) fail(LVCL_ERR_PARSE, "material %d: texCoord %d is negative", material, info.texCoord);
    int source = m.textures[(size_t)info.index].source;
    if (source == -1) {
        warn_once("nosource", "texture %d has no supported image source (ignored)", info.index);
        return -1;
    }
    if (source < 0 || (size_t)source >= m.images.size())
        fail(LVCL_ERR_PARSE, "texture %d: image %d out of range (file has %zu)", info.index, source, m.images.size());
    return decode_image(source);
}

/* The base colour texture's sampler as lv_material.texture_sampling: its
 * wrap modes, and nearest filtering where magFilter asks for it (lvcl has
 * no mipmaps, so minFilter does not apply); glTF's defaults without one. */
static unsigned wrap_mode(int gl)
{
    return gl == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE  ? LV_WRAP_CLAMP
        : gl == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? LV_WRAP_MIRROR
                                                      : LV_WRAP_REPEAT;
}

void Importer::read_sampler(const tinygltf::TextureInfo &info, lvcl_material_desc &d)
{
    if (d.base_color_texture < 0) return;
    int sampler = m.textures[(size_t)info.index].sampler;
    if (sampler < 0 || (size_t)sampler >= m.samplers.size()) return;
    const tinygltf::Sampler &s = m.samplers[(size_t)sampler];
    d.texture_sampling = wrap_mode(s.wrapS) | wrap_mode(s.wrapT) << LV_WRAP_V_SHIFT |
        (s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST ? LV_TEXTURE_NEAREST : 0u);
}

/* KHR_texture_transform on the base colour texture: the UVs scaled, then
 * turned by `rotation` (the matrix of the extension's ratified text, which
 * its example of the lower left quadrant turned clockwise bears out), then
 * offset. */
void Importer::read_uv_transform(const tinygltf::TextureInfo &info, lvcl_material_desc &d)
{
    const tinygltf::Value *ext = find_ext(info.extensions, "KHR_texture_transform");
    if (!ext || d.base_color_texture < 0) return;
    double offset[2] = {0, 0}, scale[2] = {1, 1}, r = ext_number(*ext, "rotation", 0.0);
    ext_vector(*ext, "offset", 2, offset);
    ext_vector(*ext, "scale", 2, scale);
    double c = std::cos(r), s = std::sin(r);
    const double m[6] = {c * scale[0], s * scale[1], offset[0], -s * scale[0], c * scale[1], offset[1]};
    d.has_uv_transform = 1;
    for (int k = 0; k < 6; k++) d.uv_transform[k] = to_f(m[k]);
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
    read_uv_transform(pbr.baseColorTexture, d);
    read_sampler(pbr.baseColorTexture, d);
    d.metallic = to_f(pbr.metallicFactor);
    d.roughness = to_f(pbr.roughnessFactor);

    if (!mat.emissiveFactor.empty() && mat.emissiveFactor.size() != 3)
        fail(LVCL_ERR_PARSE, "material %d: emissiveFactor must have 3 numbers", index);
    const tinygltf::Value *ext = find_ext(mat.extensions, "KHR_materials_emissive_strength");
    double strength = ext ? ext_number(*ext, "emissiveStrength", 1.0) : 1.0;
    for (int k = 0; k < 3; k++)
        d.emissive[k] = mat.emissiveFactor.empty() ? 0.0f : to_f(mat.emissiveFactor[(size_t)k] * strength);

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
        warn_once("alpha", "alphaMode %s is not supported (treated as OPAQUE)", mat.alphaMode.c_str());
    if (pbr.metallicRoughnessTexture.index != -1)
        warn_once("mrtex", "metallicRoughnessTexture is not supported (ignored)");
    if (mat.normalTexture.index != -1) warn_once("ntex", "normalTexture is not supported (ignored)");
    if (mat.occlusionTexture.index != -1) warn_once("otex", "occlusionTexture is not supported (ignored)");
    if (mat.emissiveTexture.index != -1) warn_once("etex", "emissiveTexture is not supported (ignored)");
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
        fail(LVCL_ERR_PARSE, "mesh %d primitive %d: material %d out of range (file has %zu)", mesh, prim, material,
             materials.size());
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

} // namespace lvcl_gltf
