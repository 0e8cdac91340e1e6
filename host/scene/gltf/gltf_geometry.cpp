/* glTF import: triangles of primitives, meshes and their instances. */
#include "gltf_importer.h"

namespace lvcl_gltf
{

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
            fail(LVCL_ERR_PARSE, "%s: NORMAL count %zu differs from POSITION count %zu", what, ns.count, d.count);
    }
    if (uv_acc != -2) {
        d.uv = read_accessor(uv_acc, what, &us);
        bool float_ok = us.comp_type == TINYGLTF_COMPONENT_TYPE_FLOAT && !us.normalized;
        bool unorm_ok = us.normalized &&
            (us.comp_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
             us.comp_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
        if (us.comps != 2 || !(float_ok || unorm_ok))
            fail(LVCL_ERR_PARSE, "%s: TEXCOORD_0 accessor %d must be VEC2 float or normalized unsigned byte/short",
                 what, uv_acc);
        if (us.count != d.count)
            fail(LVCL_ERR_PARSE, "%s: TEXCOORD_0 count %zu differs from POSITION count %zu", what, us.count, d.count);
    }
    return d;
}

/* Triangle corners as vertex indices local to the primitive, each checked. */
std::vector<uint32_t> Importer::read_corners(const tinygltf::Primitive &p, size_t nverts, const char *what)
{
    std::vector<uint32_t> corners;
    if (p.indices == -1) { /* non-indexed: consecutive vertices */
        corners.resize(nverts);
        for (size_t i = 0; i < nverts; i++) corners[i] = (uint32_t)i;
    } else {
        AccessorSpan is;
        std::vector<double> idx = read_accessor(p.indices, what, &is);
        if (is.comps != 1 || !is_unsigned_int_type(is.comp_type))
            fail(LVCL_ERR_PARSE, "%s: indices accessor %d must be scalar unsigned integers", what, p.indices);
        corners.reserve(idx.size());
        for (double v : idx) {
            if (v >= (double)nverts)
                fail(LVCL_ERR_PARSE, "%s: index value %.0f out of range (vertex count %zu)", what, v, nverts);
            corners.push_back((uint32_t)v);
        }
    }
    if (corners.size() % 3 != 0)
        warn_once("partial", "%s: index count %zu is not a multiple of 3 (extra ignored)", what, corners.size());
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
        warn_once("mode:" + std::to_string(p.mode), "primitive mode %d is not supported, only triangles (skipped)",
                  p.mode);
        return;
    }
    if (!p.targets.empty()) warn_once("morph", "morph targets are not supported (ignored)");
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
