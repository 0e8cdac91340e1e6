#include "harness.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../host/accel/accel.h"
#include "../host/render/light_volume_internal.h"
#include "../host/scene/materials.h"

extern const unsigned char lvcl_test_kernel_source[];
extern const size_t lvcl_test_kernel_source_size;

static void die(const char *what, const char *why)
{
    printf("FAIL harness: %s: %s\n", what, why);
    exit(1);
}

void harness_cl(cl_int err, const char *what)
{
    if (err != CL_SUCCESS) die(what, lvcl_cl_error_name(err));
}

void harness_ok(lvcl_error e, const lvcl_status *st, const char *what)
{
    if (e) die(what, st->message);
}

lvcl_session *harness_session(const char *name, unsigned seed)
{
    lvcl_scene scene;
    lvcl_status st = {0};
    lvcl_session *s = NULL;
    lvcl_session_config cfg = {.seed = seed, .max_depth = 64, .fast_math = 1};
    if (lvcl_scene_load(name, &scene, &st) || lvcl_session_open(&scene, &cfg, &s, &st))
        die("opening a session", st.message);
    return s;
}

void harness_open(const char *spec, lvcl_device *dev, lvcl_program *prog)
{
    lvcl_status st = {0};
    lvcl_device_prepare_environment();
    if (!spec) spec = getenv("LVCL_TEST_DEVICE");
    if (lvcl_device_open(spec, dev, &st)) die("opening the device", st.message);
    harness_build(dev, prog);
}

void harness_build(const lvcl_device *dev, lvcl_program *prog)
{
    lvcl_status st = {0};
    if (lvcl_program_build_source(dev, lvcl_test_kernel_source, lvcl_test_kernel_source_size,
                                  " -DLV_FEATURE_GLASS -DLV_FEATURE_TEXTURES -DLV_FEATURE_PUNCTUAL", 1, prog, &st))
        die("building the test kernels", st.message);
}

void harness_close(lvcl_device *dev, lvcl_program *prog)
{
    lvcl_program_release(prog);
    lvcl_device_close(dev);
}

void harness_triangle_scene(const float *tris, size_t count, lvcl_scene *s)
{
    memset(s, 0, sizeof *s);
    s->vertex_count = 3 * count;
    s->triangle_count = count;
    s->positions = malloc(9 * count * sizeof(float));
    s->normals = calloc(9 * count, sizeof(float));
    s->uvs = calloc(6 * count, sizeof(float));
    s->indices = malloc(3 * count * sizeof(uint32_t));
    s->tri_material = calloc(count, sizeof(uint32_t));
    s->tri_flags = calloc(count, sizeof(uint32_t));
    s->materials = calloc(1, sizeof *s->materials);
    if (!s->positions || !s->normals || !s->uvs || !s->indices || !s->tri_material || !s->tri_flags || !s->materials)
        die("making a scene", "out of memory");
    memcpy(s->positions, tris, 9 * count * sizeof(float));
    for (size_t i = 0; i < 3 * count; i++) s->indices[i] = (uint32_t)i;
    s->material_count = 1;
    lvcl_material_desc *m = &s->materials[0];
    m->base_color[0] = m->base_color[1] = m->base_color[2] = m->base_color[3] = 0.5f;
    m->base_color_texture = -1;
    m->ior = 1.5f;
    m->double_sided = 1;
}

lvcl_material_desc *harness_materials(lvcl_scene *s, size_t count)
{
    lvcl_material_desc *m = realloc(s->materials, count * sizeof *m);
    if (!m) die("making a scene", "out of memory");
    for (size_t k = 1; k < count; k++) m[k] = m[0];
    s->materials = m;
    s->material_count = count;
    return m;
}

void harness_make_lamp(lvcl_material_desc *m, float radiance)
{
    for (int c = 0; c < 3; c++) m->base_color[c] = 0.0f, m->emissive[c] = radiance;
}

void harness_make_glass(lvcl_material_desc *m, float ior)
{
    for (int c = 0; c < 3; c++) m->base_color[c] = m->attenuation_color[c] = 1.0f;
    m->transmission = 1.0f;
    m->ior = ior;
    m->has_volume = 1;
    m->attenuation_distance = INFINITY;
}

size_t harness_add_quad(float *t, size_t n, const float a[3], const float u[3], const float v[3])
{
    float p[4][3];
    for (int k = 0; k < 3; k++) {
        p[0][k] = a[k];
        p[1][k] = a[k] + u[k];
        p[2][k] = a[k] + u[k] + v[k];
        p[3][k] = a[k] + v[k];
    }
    const int order[6] = {0, 1, 2, 0, 2, 3};
    for (int i = 0; i < 6; i++) memcpy(t + 9 * n + 3 * (i % 3) + (i / 3) * 9, p[order[i]], sizeof p[0]);
    return n + 2;
}

size_t harness_add_box(float *t, size_t n, const float lo[3], const float hi[3])
{
    for (int axis = 0; axis < 3; axis++) {
        int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        for (int side = 0; side < 2; side++) {
            float corner[3] = {lo[0], lo[1], lo[2]}, u[3] = {0, 0, 0}, v[3] = {0, 0, 0};
            corner[axis] = side ? hi[axis] : lo[axis];
            /* e1 x e2 = e0 faces +axis; swapped, -axis. */
            int first = side ? a1 : a2, second = side ? a2 : a1;
            u[first] = hi[first] - lo[first];
            v[second] = hi[second] - lo[second];
            n = harness_add_quad(t, n, corner, u, v);
        }
    }
    return n;
}

size_t harness_add_room(float *t, size_t n, const float lo[3], const float hi[3])
{
    size_t end = harness_add_box(t, n, lo, hi);
    for (size_t i = n; i < end; i++) /* turned inward: swap each triangle's last two corners */
        for (int k = 0; k < 3; k++) {
            float c = t[9 * i + 3 + k];
            t[9 * i + 3 + k] = t[9 * i + 6 + k];
            t[9 * i + 6 + k] = c;
        }
    return end;
}

void harness_turn(float v[3], float yaw_deg, float pitch_deg)
{
    const float yaw = yaw_deg * 3.14159265f / 180.0f, pitch = pitch_deg * 3.14159265f / 180.0f;
    float x = cosf(yaw) * v[0] + sinf(yaw) * v[2], z = -sinf(yaw) * v[0] + cosf(yaw) * v[2];
    float y = cosf(pitch) * v[1] - sinf(pitch) * z;
    v[2] = sinf(pitch) * v[1] + cosf(pitch) * z;
    v[0] = x, v[1] = y;
}

size_t harness_two_rooms(float *tris, float wall, float shell, float panel, float door, float yaw, float pitch,
                         size_t *walls)
{
    const float X = HARNESS_ROOMS_X, Y = HARNESS_ROOMS_Y, Z = HARNESS_ROOMS_Z, W = HARNESS_WALL_X;
    const float lo[3] = {-X, 0, -Z}, hi[3] = {X, Y, Z};
    size_t n = 0;
    if (shell > 0) {
        /* Six slabs round the rooms, overlapping at the edges. */
        for (int axis = 0; axis < 3; axis++)
            for (int side = 0; side < 2; side++) {
                float slo[3], shi[3];
                for (int k = 0; k < 3; k++) slo[k] = lo[k] - shell, shi[k] = hi[k] + shell;
                if (side) slo[axis] = hi[axis];
                else shi[axis] = lo[axis];
                n = harness_add_box(tris, n, slo, shi);
            }
    } else {
        n = harness_add_room(tris, n, lo, hi);
    }
    /* The wall in pieces round the doorway (one piece without one): their
     * z spans, full height from their foot. */
    const float dz = HARNESS_DOOR_Z,
                pieces[3][3] = {{-Z, door > 0 ? dz : Z, 0}, {dz + door, Z, 0}, {dz, dz + door, HARNESS_DOOR_TOP}};
    for (int k = 0; k < (door > 0 ? 3 : 1); k++) {
        const float z0 = pieces[k][0], z1 = pieces[k][1], y0 = pieces[k][2];
        if (wall > 0) {
            const float wlo[3] = {W - wall / 2, y0, z0}, whi[3] = {W + wall / 2, Y, z1};
            n = harness_add_box(tris, n, wlo, whi);
        } else {
            const float corner[3] = {W, y0, z0}, up[3] = {0, Y - y0, 0}, across[3] = {0, 0, z1 - z0};
            n = harness_add_quad(tris, n, corner, up, across); /* facing +x */
        }
    }
    if (panel > 0) {
        const float plo[3] = {W + wall / 2, 0, -0.5f}, phi[3] = {W + wall / 2 + panel, 0.9f, 0.5f};
        n = harness_add_box(tris, n, plo, phi);
    }
    *walls = n;
    const float ly = Y - 0.001f, x[2][2] = {{1.0f, 1.6f}, {-1.4f, -0.8f}};
    for (int l = 0; l < 2; l++) {
        const float corner[3] = {x[l][0], ly, -0.3f}, along[3] = {x[l][1] - x[l][0], 0, 0}, across[3] = {0, 0, 0.6f};
        n = harness_add_quad(tris, n, corner, along, across); /* facing down */
    }
    for (size_t v = 0; v < 3 * n; v++) harness_turn(tris + 3 * v, yaw, pitch);
    return n;
}

void harness_look_at(lvcl_scene *s, const float eye[3], const float target[3], float yfov_deg)
{
    lvcl_camera_desc *cam = &s->camera;
    cam->present = 1;
    memcpy(cam->position, eye, 3 * sizeof(float));
    float l = 0;
    for (int k = 0; k < 3; k++) {
        cam->back[k] = eye[k] - target[k];
        l += cam->back[k] * cam->back[k];
    }
    for (int k = 0; k < 3; k++) cam->back[k] /= sqrtf(l);
    /* right = up_world x back, up = back x right */
    float rl = sqrtf(cam->back[2] * cam->back[2] + cam->back[0] * cam->back[0]);
    cam->right[0] = cam->back[2] / rl, cam->right[1] = 0, cam->right[2] = -cam->back[0] / rl;
    cam->up[0] = cam->back[1] * cam->right[2] - cam->back[2] * cam->right[1];
    cam->up[1] = cam->back[2] * cam->right[0] - cam->back[0] * cam->right[2];
    cam->up[2] = cam->back[0] * cam->right[1] - cam->back[1] * cam->right[0];
    cam->yfov = yfov_deg * 3.14159265f / 180.0f;
    cam->aspect = 1.0f;
}

void harness_run(const lvcl_device *dev, cl_kernel k, size_t global)
{
    lvcl_status st = {0};
    if (lvcl_kernel_enqueue(dev, k, global, "launching", &st)) die("launching", st.message);
    harness_cl(clFinish(dev->queue), "running");
}

LVCL_DEFINE_BINDER(t_trace, T_TRACE_ARGS, t_trace_args)
LVCL_DEFINE_BINDER(t_offset_rays, T_OFFSET_RAYS_ARGS, t_offset_rays_args)

cl_kernel harness_kernel(const lvcl_program *prog, const char *name)
{
    cl_kernel k;
    lvcl_status st = {0};
    if (lvcl_kernel_create(prog, name, &k, &st)) die(name, st.message);
    return k;
}

cl_mem harness_buffer(const lvcl_device *dev, const void *data, size_t bytes)
{
    cl_int err;
    cl_mem m =
        clCreateBuffer(dev->context, CL_MEM_READ_WRITE | (data ? CL_MEM_COPY_HOST_PTR : 0), bytes, (void *)data, &err);
    harness_cl(err, "allocating");
    return m;
}

void harness_read(const lvcl_device *dev, cl_mem m, size_t bytes, void *out)
{
    harness_cl(clEnqueueReadBuffer(dev->queue, m, CL_TRUE, 0, bytes, out, 0, NULL, NULL), "reading results");
}

void harness_trace(const lvcl_device *dev, const lvcl_program *prog, const lvcl_scene *scene, const char *kernel_name,
                   const float *rays, size_t count, float *results)
{
    lvcl_status st = {0};
    lvcl_accel accel;
    lvcl_packed_scene packed;
    lvcl_device_scene ds;
    if (lvcl_accel_build(scene, &accel, &st) || lvcl_pack_scene(scene, &accel, 0, 8, &packed, &st) ||
        lvcl_device_scene_upload(dev, scene, &packed, &ds, &st))
        die("preparing the scene", st.message);
    cl_kernel k = harness_kernel(prog, kernel_name);
    t_trace_args a = {
        .scene = &ds.buffers,
        .rays = harness_buffer(dev, rays, count * 8 * sizeof(float)),
        .count = (cl_uint)count,
        .results = harness_buffer(dev, NULL, count * 4 * sizeof(float)),
    };
    harness_ok(lvcl_bind_t_trace(k, &a, &st), &st, "setting arguments");
    harness_run(dev, k, count);
    harness_read(dev, a.results, count * 4 * sizeof(float), results);
    clReleaseMemObject(a.rays);
    clReleaseMemObject(a.results);
    clReleaseKernel(k);
    lvcl_device_scene_release(&ds);
    lvcl_packed_scene_free(&packed);
    lvcl_accel_free(&accel);
}

double harness_uniform(harness_rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}

lvcl_error harness_render(lvcl_scene *scene, const char *device, unsigned seed, const lvcl_render_request *req,
                          lvcl_render_result *out, lvcl_status *st)
{
    lvcl_session_config cfg = {.device = device, .seed = seed, .max_depth = 64, .fast_math = 1};
    return harness_render_with(scene, &cfg, req, out, st);
}

lvcl_error harness_render_with(lvcl_scene *scene, const lvcl_session_config *cfg, const lvcl_render_request *req,
                               lvcl_render_result *out, lvcl_status *st)
{
    lvcl_session *s = NULL;
    memset(out, 0, sizeof *out);
    lvcl_error e = lvcl_session_open(scene, cfg, &s, st);
    if (!e) e = lvcl_session_render(s, req, out, st);
    lvcl_session_close(s);
    return e;
}

lvcl_error harness_trace_volume(lvcl_scene *scene, const lvcl_session_config *cfg, const lvcl_volume_settings *vs,
                                harness_volume *out, lvcl_status *st)
{
    memset(out, 0, sizeof *out);
    lvcl_error e = lvcl_session_open(scene, cfg, &out->session, st);
    if (!e) e = lvcl_session_trace_volume(out->session, vs, st);
    if (!e) {
        out->volume = lvcl_session_volume(out->session, 0);
        e = lvcl_volume_read(out->volume, &out->tallies, &out->masks, st);
    }
    if (!e) e = lvcl_volume_read_lit(out->volume, &out->lit, st);
    if (e) harness_volume_release(out);
    return e;
}

void harness_volume_release(harness_volume *v)
{
    free(v->tallies);
    free(v->masks);
    free(v->lit);
    lvcl_session_close(v->session);
    memset(v, 0, sizeof *v);
}

lvcl_error harness_render_mean(lvcl_scene *scene, unsigned seed, const lvcl_render_request *req, double *mean,
                               lvcl_status *st)
{
    lvcl_render_result r;
    *mean = -1;
    lvcl_error e = harness_render(scene, NULL, seed, req, &r, st);
    if (e) return e;
    double sum = 0;
    for (int i = 0; i < 3 * r.width * r.height; i++) sum += r.rgb[i];
    free(r.rgb);
    *mean = sum / (3.0 * r.width * r.height);
    return LVCL_OK;
}

lvcl_render_request harness_request(lvcl_mode mode, int size, int spp, int cells, uint64_t particles)
{
    return (lvcl_render_request){
        .mode = mode,
        .width = size,
        .height = size,
        .pass = {.spp = spp},
        .volume = {.cells = cells, .dirs = 8, .subcells = 4, .particles = particles},
        .integrate = 1,
        .see_through = 1,
    };
}

int harness_build_regions(const char *who, const float *tris, size_t n, int cells, double offset, int subcells,
                          harness_regions *out)
{
    lvcl_scene scene;
    harness_triangle_scene(tris, n, &scene);
    lvcl_material_desc *m = harness_materials(&scene, 2);
    harness_make_lamp(&m[1], 1.0f);
    scene.tri_material[0] = 1; /* a lamp, as the grid expects one */
    lvcl_accel accel = {0};
    lvcl_packed_scene packed = {0};
    lvcl_status st = {0};
    lvcl_volume_settings vs = {.cells = cells, .offset = offset, .dirs = 4, .subcells = subcells, .particles = 1};
    size_t count = 0;
    lvcl_solid_slabs solids = {0};
    memset(out, 0, sizeof *out);
    int ok = !lvcl_accel_build(&scene, &accel, &st);
    if (ok) ok = !lvcl_pack_scene(&scene, &accel, 0, 8, &packed, &st);
    if (ok) ok = !lvcl_volume_grid_choose(&packed, &vs, &out->g, &count, &st);
    if (ok) ok = (out->slot = malloc(count * sizeof *out->slot)) != NULL;
    if (ok) ok = !lvcl_volume_assign_slots(&packed, &out->g, count, out->slot, &st);
    if (ok) ok = !lvcl_volume_build_regions(&packed, &out->g, count, out->slot, &out->regions, &solids, &st);
    lvcl_solid_slabs_free(&solids); /* already in the shares */
    if (!ok) fprintf(stderr, "%s: making the regions failed: %s\n", who, st.message);
    lvcl_packed_scene_free(&packed);
    lvcl_accel_free(&accel);
    lvcl_scene_free(&scene);
    return ok;
}

void harness_free_regions(harness_regions *r)
{
    free(r->slot);
    lvcl_regions_free(&r->regions);
}
