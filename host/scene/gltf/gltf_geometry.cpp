/* glTF import: triangles of primitives, meshes and their instances. */
#include "gltf_importer.h"

namespace lvcl_gltf
{

/* ---- geometry ---- */

/* Whether an attribute's storage is one glTF allows: floats, or the
 * integer types of the core specification and, when the file declares it,
 * of KHR_mesh_quantization. */
static bool attribute_type_ok(const char *name, const AccessorSpan &s, bool quantized)
{
    int t = s.comp_type;
    bool is_float = t == TINYGLTF_COMPONENT_TYPE_FLOAT && !s.normalized;
    bool small_int = t == TINYGLTF_COMPONENT_TYPE_BYTE || t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
        t == TINYGLTF_COMPONENT_TYPE_SHORT || t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    bool signed_norm = s.normalized && (t == TINYGLTF_COMPONENT_TYPE_BYTE || t == TINYGLTF_COMPONENT_TYPE_SHORT);
    bool unsigned_norm =
        s.normalized && (t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
    if (strcmp(name, "POSITION") == 0) return s.comps == 3 && (is_float || (quantized && small_int));
    if (strcmp(name, "NORMAL") == 0) return s.comps == 3 && (is_float || (quantized && signed_norm));
    return s.comps == 2 && (is_float || unsigned_norm || (quantized && small_int)); /* TEXCOORD_n */
}

/* The storage glTF allows for `name`, for the error message. */
static const char *attribute_types(const char *name, bool quantized)
{
    if (strcmp(name, "POSITION") == 0)
        return quantized ? "VEC3 float or (normalized) byte or short"
                         : "VEC3 float (integers need extension KHR_mesh_quantization)";
    if (strcmp(name, "NORMAL") == 0)
        return quantized ? "VEC3 float or normalized signed byte or short"
                         : "VEC3 float (integers need extension KHR_mesh_quantization)";
    return quantized ? "VEC2 float or (normalized) byte or short"
                     : "VEC2 float or normalized unsigned byte or short (others need extension KHR_mesh_quantization)";
}

/* The TEXCOORD_n set the primitive's base colour texture reads (0 if none;
 * KHR_texture_transform's texCoord overrides the texture's). */
int Importer::texcoord_set(const tinygltf::Primitive &p)
{
    if (p.material < 0 || (size_t)p.material >= m.materials.size()) return 0;
    const tinygltf::TextureInfo &info = m.materials[(size_t)p.material].pbrMetallicRoughness.baseColorTexture;
    if (info.index == -1) return 0;
    const tinygltf::Value *ext = find_ext(info.extensions, "KHR_texture_transform");
    double set = ext ? ext_number(*ext, "texCoord", info.texCoord) : info.texCoord;
    return set >= 0 && set == std::floor(set) && set < 1 << 16 ? (int)set : info.texCoord;
}

VertexData Importer::read_vertices(const tinygltf::Primitive &p, const char *what)
{
    bool quantized =
        std::find(m.extensionsUsed.begin(), m.extensionsUsed.end(), "KHR_mesh_quantization") != m.extensionsUsed.end();
    std::string uv_name = "TEXCOORD_" + std::to_string(texcoord_set(p));
    VertexData d;
    /* Reads attribute `name` into `out` (left empty when absent); checks
     * its storage and that it has one element per vertex. */
    auto read = [&](const char *name, std::vector<double> &out) {
        auto it = p.attributes.find(name);
        if (it == p.attributes.end()) return false;
        AccessorSpan s;
        out = read_accessor(it->second, what, &s);
        if (!attribute_type_ok(name, s, quantized))
            fail(LVCL_ERR_PARSE, "%s: %s accessor %d must be %s", what, name, it->second,
                 attribute_types(name, quantized));
        if (strcmp(name, "POSITION") == 0) d.count = s.count;
        else if (s.count != d.count)
            fail(LVCL_ERR_PARSE, "%s: %s count %zu differs from POSITION count %zu", what, name, s.count, d.count);
        return true;
    };
    if (!read("POSITION", d.pos)) fail(LVCL_ERR_PARSE, "%s has no POSITION attribute", what);
    read("NORMAL", d.nrm);
    if (!read(uv_name.c_str(), d.uv) && uv_name != "TEXCOORD_0")
        warn_once("uv:" + uv_name, "%s: the base colour texture reads %s, which it lacks (texture not mapped)", what,
                  uv_name.c_str());
    return d;
}

/* Triangle corners as vertex indices local to the primitive, each checked;
 * strips and fans become lists, keeping the winding glTF gives them. */
std::vector<uint32_t> Importer::read_corners(const tinygltf::Primitive &p, size_t nverts, const char *what)
{
    std::vector<uint32_t> v;
    if (p.indices == -1) { /* non-indexed: consecutive vertices */
        v.resize(nverts);
        for (size_t i = 0; i < nverts; i++) v[i] = (uint32_t)i;
    } else {
        AccessorSpan is;
        std::vector<double> idx = read_accessor(p.indices, what, &is);
        if (is.comps != 1 || !is_unsigned_int_type(is.comp_type) || is.normalized)
            fail(LVCL_ERR_PARSE, "%s: indices accessor %d must be scalar unsigned integers", what, p.indices);
        v.reserve(idx.size());
        for (double x : idx) {
            if (x >= (double)nverts)
                fail(LVCL_ERR_PARSE, "%s: index value %.0f out of range (vertex count %zu)", what, x, nverts);
            v.push_back((uint32_t)x);
        }
    }
    if (p.mode == TINYGLTF_MODE_TRIANGLES) {
        if (v.size() % 3 != 0)
            warn_once("partial", "%s: index count %zu is not a multiple of 3 (extra ignored)", what, v.size());
        return v;
    }
    std::vector<uint32_t> corners;
    for (size_t i = 0; i + 2 < v.size(); i++) {
        if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP) /* every other triangle swaps two corners */
            corners.insert(corners.end(), {v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]});
        else /* fan */ corners.insert(corners.end(), {v[i + 1], v[i + 2], v[0]});
    }
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

    if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        p.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        warn_once("mode:" + std::to_string(p.mode),
                  "%s: primitive mode %d is points or lines, which have no surface (skipped)", what, p.mode);
        return;
    }
    if (!p.targets.empty()) warn_once("morph", "morph targets are not supported (ignored)");
    if (p.attributes.count("COLOR_0"))
        warn_once("color0", "%s: vertex colours (COLOR_0) are not supported (base colour used alone)", what);
    if (find_ext(p.extensions, "KHR_draco_mesh_compression"))
        warn_once("ext:KHR_draco_mesh_compression", "extension KHR_draco_mesh_compression is not supported (ignored)");

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
        if (id >= (size_t)UINT32_MAX) fail(LVCL_ERR_UNSUPPORTED, "scene has more than 2^32 - 1 vertices");
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
        fail(LVCL_ERR_PARSE, "node %d: mesh %d out of range (file has %zu)", node, mesh, m.meshes.size());
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
    for (size_t p = 0; p < m.meshes[(size_t)mesh].primitives.size(); p++) add_primitive(mesh, (int)p, world);
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

} // namespace lvcl_gltf
