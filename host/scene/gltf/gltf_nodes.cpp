/* glTF import: cameras, punctual lights, the node hierarchy, and the scene filled at the end. */
#include "gltf_importer.h"

namespace lvcl_gltf
{

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
        fail(LVCL_ERR_PARSE, "node %d: camera %d out of range (file has %zu)", node, index, m.cameras.size());
    const tinygltf::Camera &cam = m.cameras[(size_t)index];
    if (cam.type != "perspective") {
        warn_once("ortho", "camera %d: %s cameras are not supported (ignored)", index, cam.type.c_str());
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
        fail(LVCL_ERR_PARSE, "node %d: KHR_lights_punctual light %g out of range (file has %zu)", node, light,
             m.lights.size());
    int index = (int)light;
    const tinygltf::Light &l = m.lights[(size_t)index];
    if (l.type != "point" && l.type != "spot" && l.type != "directional") {
        warn_once("light:" + l.type, "light %d ('%s'): %s lights are not supported (skipped)", index, l.name.c_str(),
                  l.type.c_str());
        return;
    }
    if (!l.color.empty() && l.color.size() != 3) fail(LVCL_ERR_PARSE, "light %d: color must have 3 numbers", index);

    lv_punctual_light pl{};
    store3(pl.position, glm::dvec3(world[3]));
    store3(pl.direction, transform_dir(world, {0, 0, -1}));
    for (int k = 0; k < 3; k++) pl.intensity[k] = to_f((l.color.empty() ? 1.0 : l.color[(size_t)k]) * l.intensity);
    if (l.type == "spot") {
        pl.type = LV_PUNCTUAL_SPOT;
        pl.cos_outer = to_f(std::cos(l.spot.outerConeAngle));
        pl.cos_inner = to_f(std::cos(l.spot.innerConeAngle));
    } else if (l.type == "directional") {
        pl.type = LV_PUNCTUAL_DIRECTIONAL; /* intensity: irradiance (glTF's lux, as W/m^2) */
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
        if (n.matrix.size() != 16) fail(LVCL_ERR_PARSE, "node %d: matrix must have 16 numbers", node);
        return glm::make_mat4(n.matrix.data()); /* glTF and GLM are both column-major */
    }
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (!n.translation.empty()) {
        if (n.translation.size() != 3) fail(LVCL_ERR_PARSE, "node %d: translation must have 3 numbers", node);
        t = glm::translate(glm::dmat4(1.0), glm::make_vec3(n.translation.data()));
    }
    if (!n.rotation.empty()) {
        if (n.rotation.size() != 4) fail(LVCL_ERR_PARSE, "node %d: rotation must have 4 numbers", node);
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
    if (visited[(size_t)node]) fail(LVCL_ERR_PARSE, "node %d is reached twice (child cycle or shared child)", node);
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
            fail(LVCL_ERR_PARSE, "default scene %d out of range (file has %zu)", m.defaultScene, m.scenes.size());
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
        lvcl_warn("%s: skipped %zu triangles with non-finite vertex positions", src, nonfinite_triangles);
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
        scene->textures = static_cast<lvcl_texture_data *>(calloc(textures.size(), sizeof(lvcl_texture_data)));
        if (!scene->textures) throw std::bad_alloc();
        scene->texture_count = textures.size();
        for (size_t i = 0; i < textures.size(); i++) {
            scene->textures[i].width = textures[i].width;
            scene->textures[i].height = textures[i].height;
            scene->textures[i].rgba = c_array(textures[i].rgba);
        }
    }
}

} // namespace lvcl_gltf
