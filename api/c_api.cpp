// The C API (api/include/penumbra/penumbra.h) as a thin layer over the C++
// API: handles own C++ objects, and every entry point catches everything, so
// no exception crosses into C. Value conversions: api/c_api_types.cpp.
#include "api/c_api_internal.h"

using namespace pnb::c_api;

extern "C" {

const char* pnb_status_name(pnb_status status) {
    if (status == PNB_OK) return "ok";
    if (status < PNB_ERROR_INVALID_ARGUMENT || status > PNB_ERROR_INTERNAL) return "unknown status";
    return pnb::errorCodeName(static_cast<pnb::ErrorCode>(static_cast<int>(status)));
}

const char* pnb_last_error(void) { return lastErrorSlot().c_str(); }
const char* pnb_version(void) { return pnb::version(); }

// ---------------------------------------------------------------- renderer

pnb_status pnb_renderer_create(pnb_renderer** out) {
    if (out) *out = nullptr;
    return guard(nullptr, "pnb_renderer_create", [&] {
        need(out, "out");
        *out = new pnb_renderer();
    });
}

void pnb_renderer_destroy(pnb_renderer* renderer) { destroy(renderer); }

pnb_status pnb_renderer_set_log(pnb_renderer* renderer, pnb_log_fn fn, void* user, pnb_log_level min_level) {
    return guard(renderer ? &renderer->error : nullptr, "pnb_renderer_set_log", [&] {
        need(renderer, "renderer");
        const int raw = rawEnum(min_level);
        if (raw < PNB_LOG_DEBUG || raw > PNB_LOG_ERROR)
            throw pnb::Error(pnb::ErrorCode::InvalidArgument,
                             "min_level " + std::to_string(raw) + " is not a pnb_log_level");
        const auto level = static_cast<pnb::LogLevel>(raw);
        if (!fn) {
            renderer->renderer.setLog({}, level);
            return;
        }
        renderer->renderer.setLog(
            [fn, user](pnb::LogLevel l, std::string_view m) {
                const std::string text(m);
                fn(static_cast<pnb_log_level>(static_cast<int>(l)), text.c_str(), user);
            },
            level);
    });
}

const char* pnb_renderer_last_error(const pnb_renderer* renderer) { return renderer ? renderer->error.c_str() : ""; }

// ---------------------------------------------------------------- scene

pnb_status pnb_scene_create(pnb_scene** out) {
    if (out) *out = nullptr;
    return guard(nullptr, "pnb_scene_create", [&] {
        need(out, "out");
        *out = new pnb_scene();
    });
}

pnb_status pnb_scene_load(pnb_renderer* renderer, const char* path, const pnb_load_options* options, pnb_scene** out) {
    if (out) *out = nullptr;
    return guard(renderer ? &renderer->error : nullptr, "pnb_scene_load", [&] {
        need(renderer, "renderer");
        need(path, "path");
        need(out, "out");
        pnb::LoadOptions lo;
        if (options) {
            lo.strict = options->strict != 0;
            lo.restrictPaths = options->restrict_paths != 0;
            if (options->allowed_root_count > 0) need(options->allowed_roots, "options->allowed_roots");
            for (size_t i = 0; i < options->allowed_root_count; ++i) {
                need(options->allowed_roots[i], "an allowed root");
                lo.allowedRoots.emplace_back(options->allowed_roots[i]);
            }
            if (options->use_mesh_model) {
                const int model = rawEnum(options->mesh_model);
                if (model != PNB_PHONG_NORMALIZED && model != PNB_PHONG_CLASSIC)
                    throw pnb::Error(pnb::ErrorCode::InvalidArgument,
                                     "options->mesh_model " + std::to_string(model) + " is not a pnb_phong_model");
                lo.meshModel = static_cast<pnb::PhongModel>(model);
            }
            lo.smoothAngleDegrees = options->smooth_angle_degrees;  // checked by loadScene
        }
        auto scene = std::make_unique<pnb_scene>();
        scene->scene = renderer->renderer.loadScene(path, lo);
        *out = scene.release();
    });
}

pnb_status pnb_scene_clone(const pnb_scene* scene, pnb_scene** out) {
    if (out) *out = nullptr;
    return guard(nullptr, "pnb_scene_clone", [&] {
        need(scene, "scene");
        need(out, "out");
        auto copy = std::make_unique<pnb_scene>();
        copy->scene = scene->scene;
        *out = copy.release();
    });
}

void pnb_scene_destroy(pnb_scene* scene) { destroy(scene); }
const char* pnb_scene_last_error(const pnb_scene* scene) { return scene ? scene->error.c_str() : ""; }

namespace {

// The metal-roughness fields and the texture slots of a C material.
void readMetalRoughness(const pnb_material& c, pnb::Material& m) {
    const int kind = rawEnum(c.kind);
    if (kind != PNB_MATERIAL_PHONG && kind != PNB_MATERIAL_METAL_ROUGHNESS)
        throw pnb::Error(pnb::ErrorCode::InvalidArgument, "material kind " + std::to_string(kind) + " is not a pnb_material_kind");
    m.kind = kind == PNB_MATERIAL_METAL_ROUGHNESS ? pnb::MaterialKind::MetalRoughness : pnb::MaterialKind::Phong;
    m.baseColor = in(c.base_color);
    m.metallic = c.metallic;
    m.roughness = c.roughness;
    m.transmission = c.transmission;
    m.normalScale = c.normal_scale;
    if (c.base_color_texture) m.baseColorTexture.path = c.base_color_texture;
    if (c.metallic_roughness_texture) {
        m.metallicTexture.path = m.roughnessTexture.path = c.metallic_roughness_texture;
        m.metallicTexture.channel = 2;
        m.roughnessTexture.channel = 1;
    }
    if (c.normal_texture) m.normalTexture.path = c.normal_texture;
    if (c.emissive_texture) m.emissiveTexture.path = c.emissive_texture;
}

// The C material as the C++ one (values are checked where it is used).
pnb::Material materialIn(const pnb_material& material) {
    pnb::Material m;
    if (material.name) m.name = material.name;
    m.ka = in(material.ka);
    m.kd = in(material.kd);
    m.ks = in(material.ks);
    m.exponent = material.exponent;
    m.kr = in(material.kr);
    m.ke = in(material.ke);
    m.twoSidedEmission = material.two_sided_emission != 0;
    const int model = rawEnum(material.model);
    if (model != PNB_PHONG_NORMALIZED && model != PNB_PHONG_CLASSIC)
        throw pnb::Error(pnb::ErrorCode::InvalidArgument,
                         "material model " + std::to_string(model) + " is not a pnb_phong_model");
    m.model = model == PNB_PHONG_CLASSIC ? pnb::PhongModel::Classic : pnb::PhongModel::Normalized;
    if (material.diffuse_texture) m.diffuseTexture = material.diffuse_texture;
    m.kt = in(material.kt);
    m.ior = material.ior;
    readMetalRoughness(material, m);
    return m;
}

// 12 floats, a row-major 3x4 matrix; NULL: the identity.
pnb::Matrix3x4 matrixIn(const float* rowMajor) {
    pnb::Matrix3x4 m;
    if (rowMajor)
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) m.m[r][c] = rowMajor[4 * r + c];
    return m;
}

}  // namespace

pnb_status pnb_scene_add_material(pnb_scene* scene, const pnb_material* material, uint32_t* out_id) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_material", [&] {
        need(scene, "scene");
        need(material, "material");
        const pnb::MaterialId id = scene->scene.addMaterial(materialIn(*material));
        if (out_id) *out_id = id;
    });
}

pnb_status pnb_scene_add_sphere(pnb_scene* scene, pnb_vec3 center, float radius, uint32_t material) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_sphere", [&] {
        need(scene, "scene");
        scene->scene.addSphere(in(center), radius, material);
    });
}

pnb_status pnb_scene_add_plane(pnb_scene* scene, pnb_vec3 point, pnb_vec3 normal, int two_sided, uint32_t material) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_plane", [&] {
        need(scene, "scene");
        scene->scene.addPlane(in(point), in(normal), material, two_sided != 0);
    });
}

pnb_status pnb_scene_add_box(pnb_scene* scene, pnb_vec3 lo, pnb_vec3 hi, const float* world_from_object,
                             uint32_t material) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_box", [&] {
        need(scene, "scene");
        pnb::Matrix3x4 m;
        if (world_from_object)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 4; ++c) m.m[r][c] = world_from_object[4 * r + c];
        scene->scene.addBox(in(lo), in(hi), m, material);
    });
}

pnb_status pnb_scene_add_rectangle(pnb_scene* scene, pnb_vec3 corner, pnb_vec3 edge_a, pnb_vec3 edge_b,
                                   uint32_t material) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_rectangle", [&] {
        need(scene, "scene");
        scene->scene.addRectangle(in(corner), in(edge_a), in(edge_b), material);
    });
}

pnb_status pnb_scene_add_disk(pnb_scene* scene, pnb_vec3 center, pnb_vec3 normal, float radius, uint32_t material) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_disk", [&] {
        need(scene, "scene");
        scene->scene.addDisk(in(center), in(normal), radius, material);
    });
}

namespace {
pnb::MeshDesc meshDesc(const pnb_mesh_desc& mesh) {
    pnb::MeshDesc d;
    if (mesh.name) d.name = mesh.name;
    d.positions = mesh.positions;
    d.vertexCount = mesh.vertex_count;
    d.indices = mesh.indices;
    d.triangleCount = mesh.triangle_count;
    d.normals = mesh.normals;
    d.uvs = mesh.uvs;
    d.faceMaterials = mesh.face_materials;
    d.material = mesh.material;
    return d;
}
}  // namespace

pnb_status pnb_scene_add_mesh(pnb_scene* scene, const pnb_mesh_desc* mesh) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_mesh", [&] {
        need(scene, "scene");
        need(mesh, "mesh");
        scene->scene.addMesh(meshDesc(*mesh));
    });
}

pnb_status pnb_scene_add_point_light(pnb_scene* scene, pnb_vec3 position, pnb_color intensity) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_point_light", [&] {
        need(scene, "scene");
        scene->scene.addPointLight(in(position), in(intensity));
    });
}

pnb_status pnb_scene_add_directional_light(pnb_scene* scene, pnb_vec3 direction, pnb_color irradiance) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_directional_light", [&] {
        need(scene, "scene");
        scene->scene.addDirectionalLight(in(direction), in(irradiance));
    });
}

pnb_status pnb_scene_set_ambient(pnb_scene* scene, pnb_color ambient) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_set_ambient", [&] {
        need(scene, "scene");
        scene->scene.setAmbient(in(ambient));
    });
}

pnb_status pnb_scene_set_background(pnb_scene* scene, pnb_color background) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_set_background", [&] {
        need(scene, "scene");
        scene->scene.setBackground(in(background));
    });
}

pnb_status pnb_scene_set_environment(pnb_scene* scene, pnb_color radiance, float scale) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_set_environment", [&] {
        need(scene, "scene");
        scene->scene.setEnvironment(in(radiance), scale);
    });
}

pnb_status pnb_scene_set_environment_image(pnb_scene* scene, const char* path, float rotate_degrees, float scale) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_set_environment_image", [&] {
        need(scene, "scene");
        need(path, "path");
        scene->scene.setEnvironmentImage(path, rotate_degrees, scale);
    });
}

pnb_status pnb_scene_clear_environment(pnb_scene* scene) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_clear_environment", [&] {
        need(scene, "scene");
        scene->scene.clearEnvironment();
    });
}

pnb_status pnb_scene_set_default_light(pnb_scene* scene, int enabled) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_set_default_light", [&] {
        need(scene, "scene");
        scene->scene.setDefaultLight(enabled != 0);
    });
}

pnb_status pnb_scene_set_camera(pnb_scene* scene, const pnb_camera* camera) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_set_camera", [&] {
        need(scene, "scene");
        need(camera, "camera");
        scene->scene.setCamera(in(*camera));
    });
}

pnb_status pnb_scene_get_camera(const pnb_scene* scene, pnb_camera* out, int* has_camera) {
    return guard(nullptr, "pnb_scene_get_camera", [&] {
        need(scene, "scene");
        need(out, "out");
        const std::optional<pnb::Camera> c = scene->scene.camera();
        if (c) *out = ::out(*c);
        if (has_camera) *has_camera = c ? 1 : 0;
    });
}

pnb_status pnb_scene_default_camera(const pnb_scene* scene, float aspect, float vfov_degrees, pnb_camera* out) {
    return guard(nullptr, "pnb_scene_default_camera", [&] {
        need(scene, "scene");
        need(out, "out");
        *out = ::out(scene->scene.defaultCamera(aspect, vfov_degrees));
    });
}

pnb_status pnb_scene_get_settings(const pnb_scene* scene, pnb_render_settings* out) {
    return guard(nullptr, "pnb_scene_get_settings", [&] {
        need(scene, "scene");
        need(out, "out");
        *out = ::out(scene->scene.settings());
    });
}

size_t pnb_scene_primitive_count(const pnb_scene* scene) { return scene ? scene->scene.primitiveCount() : 0; }

pnb_status pnb_scene_add_prototype(pnb_scene* scene, const char* name, uint32_t* out_id) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_prototype", [&] {
        need(scene, "scene");
        need(out_id, "out_id");
        *out_id = scene->scene.addPrototype(name ? name : "");
    });
}

pnb_status pnb_scene_add_prototype_mesh(pnb_scene* scene, uint32_t prototype, const pnb_mesh_desc* mesh) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_prototype_mesh", [&] {
        need(scene, "scene");
        need(mesh, "mesh");
        scene->scene.addPrototypeMesh(prototype, meshDesc(*mesh));
    });
}

pnb_status pnb_scene_add_instance(pnb_scene* scene, uint32_t prototype, const float* world_from_object,
                                  uint32_t material) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_instance", [&] {
        need(scene, "scene");
        std::optional<pnb::MaterialId> mat;
        if (material != PNB_KEEP_MATERIALS) mat = material;
        scene->scene.addInstance(prototype, matrixIn(world_from_object), mat);
    });
}

// ---------------------------------------------------------------- prepared scene

pnb_status pnb_prepare(pnb_renderer* renderer, const pnb_scene* scene, const pnb_prepare_options* options,
                       pnb_prepared_scene** out) {
    if (out) *out = nullptr;
    return guard(renderer ? &renderer->error : nullptr, "pnb_prepare", [&] {
        need(renderer, "renderer");
        need(scene, "scene");
        need(out, "out");
        pnb::PrepareOptions po;
        if (options) {
            po.accelerator = static_cast<pnb::AcceleratorKind>(rawEnum(options->accelerator));  // checked by prepare
            const int quality = rawEnum(options->quality);
            if (quality < PNB_BUILD_LOW || quality > PNB_BUILD_HIGH)
                throw pnb::Error(pnb::ErrorCode::InvalidArgument,
                                 "build quality " + std::to_string(quality) + " is not a pnb_build_quality");
            po.quality = static_cast<pnb::BuildQuality>(quality);
        }
        auto prepared = std::make_unique<pnb_prepared_scene>();
        prepared->prepared = renderer->renderer.prepare(scene->scene, po);
        *out = prepared.release();
    });
}

pnb_status pnb_update(pnb_renderer* renderer, const pnb_prepared_scene* base, const pnb_scene_edits* edits,
                      pnb_prepared_scene** out) {
    if (out) *out = nullptr;
    return guard(renderer ? &renderer->error : nullptr, "pnb_update", [&] {
        need(renderer, "renderer");
        need(base, "base");
        need(edits, "edits");
        need(out, "out");
        auto array = [](const void* p, size_t count, const char* what) {
            if (count && !p) throw pnb::Error(pnb::ErrorCode::InvalidArgument, std::string(what) + " is NULL");
        };
        array(edits->transforms, edits->transform_count, "edits->transforms");
        array(edits->materials, edits->material_count, "edits->materials");
        array(edits->point_lights, edits->point_light_count, "edits->point_lights");
        array(edits->directional_lights, edits->directional_light_count, "edits->directional_lights");
        pnb::SceneEdits e;
        for (size_t i = 0; i < edits->transform_count; ++i)
            e.transforms.emplace_back(edits->transforms[i].instance, matrixIn(edits->transforms[i].world_from_object));
        for (size_t i = 0; i < edits->material_count; ++i)
            e.materials.emplace_back(edits->materials[i].material, materialIn(edits->materials[i].value));
        for (size_t i = 0; i < edits->point_light_count; ++i)
            e.pointLights.emplace_back(edits->point_lights[i].light, in(edits->point_lights[i].value));
        for (size_t i = 0; i < edits->directional_light_count; ++i)
            e.directionalLights.emplace_back(edits->directional_lights[i].light, in(edits->directional_lights[i].value));
        if (edits->set_environment_rotation) e.environmentRotateDegrees = edits->environment_rotate_degrees;
        if (edits->set_environment_scale) e.environmentScale = edits->environment_scale;
        auto prepared = std::make_unique<pnb_prepared_scene>();
        prepared->prepared = renderer->renderer.update(base->prepared, e);
        *out = prepared.release();
    });
}

void pnb_prepared_scene_destroy(pnb_prepared_scene* prepared) { destroy(prepared); }

pnb_status pnb_prepared_scene_get_info(const pnb_prepared_scene* prepared, pnb_prepared_info* out) {
    return guard(nullptr, "pnb_prepared_scene_get_info", [&] {
        need(prepared, "prepared scene");
        need(out, "out");
        const pnb::PreparedScene& p = prepared->prepared;
        *out = pnb_prepared_info{p.primitiveCount(),   p.triangleCount(), p.lightCount(),
                                 p.droppedTriangles(), p.droppedShapes(), p.buildSeconds(),
                                 p.defaultLightAdded() ? 1 : 0};
    });
}

pnb_status pnb_prepared_scene_default_camera(const pnb_prepared_scene* prepared, float aspect, float vfov_degrees,
                                             pnb_camera* out) {
    return guard(nullptr, "pnb_prepared_scene_default_camera", [&] {
        need(prepared, "prepared scene");
        need(out, "out");
        *out = ::out(prepared->prepared.defaultCamera(aspect, vfov_degrees));
    });
}

pnb_status pnb_prepared_scene_get_settings(const pnb_prepared_scene* prepared, pnb_render_settings* out) {
    return guard(nullptr, "pnb_prepared_scene_get_settings", [&] {
        need(prepared, "prepared scene");
        need(out, "out");
        *out = ::out(prepared->prepared.settings());
    });
}

}  // extern "C"
