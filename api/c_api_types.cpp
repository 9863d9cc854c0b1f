// The C API's plain structs and their C++ counterparts: compile-time checks
// that they agree (enum values, layouts, field types), the conversions, and
// the pnb_*_init defaults, which come from the C++ types' defaults.
#include <cstddef>
#include <type_traits>

#include "api/c_api_internal.h"
#include "core/instance.h"

// Enumerations: one set of values, spelled twice (C cannot include C++).
#define PNB_SAME_VALUE(c, cpp) static_assert(static_cast<int>(c) == static_cast<int>(cpp), #c " != " #cpp)
PNB_SAME_VALUE(PNB_ERROR_INVALID_ARGUMENT, pnb::ErrorCode::InvalidArgument);
PNB_SAME_VALUE(PNB_ERROR_FILE_NOT_FOUND, pnb::ErrorCode::FileNotFound);
PNB_SAME_VALUE(PNB_ERROR_PARSE, pnb::ErrorCode::ParseError);
PNB_SAME_VALUE(PNB_ERROR_INVALID_SCENE, pnb::ErrorCode::InvalidScene);
PNB_SAME_VALUE(PNB_ERROR_IO, pnb::ErrorCode::IoError);
PNB_SAME_VALUE(PNB_ERROR_OUT_OF_MEMORY, pnb::ErrorCode::OutOfMemory);
PNB_SAME_VALUE(PNB_ERROR_CANCELLED, pnb::ErrorCode::Cancelled);
PNB_SAME_VALUE(PNB_ERROR_EMBREE, pnb::ErrorCode::Embree);
PNB_SAME_VALUE(PNB_ERROR_INTERNAL, pnb::ErrorCode::Internal);
PNB_SAME_VALUE(PNB_LOG_DEBUG, pnb::LogLevel::Debug);
PNB_SAME_VALUE(PNB_LOG_INFO, pnb::LogLevel::Info);
PNB_SAME_VALUE(PNB_LOG_WARNING, pnb::LogLevel::Warning);
PNB_SAME_VALUE(PNB_LOG_ERROR, pnb::LogLevel::Error);
PNB_SAME_VALUE(PNB_PHONG_NORMALIZED, pnb::PhongModel::Normalized);
PNB_SAME_VALUE(PNB_PHONG_CLASSIC, pnb::PhongModel::Classic);
PNB_SAME_VALUE(PNB_MATERIAL_PHONG, pnb::MaterialKind::Phong);
PNB_SAME_VALUE(PNB_MATERIAL_METAL_ROUGHNESS, pnb::MaterialKind::MetalRoughness);
PNB_SAME_VALUE(PNB_LIGHTS_ALL, pnb::LightSelection::All);
PNB_SAME_VALUE(PNB_LIGHTS_POWER, pnb::LightSelection::Power);
PNB_SAME_VALUE(PNB_LIGHTS_TREE, pnb::LightSelection::Tree);
PNB_SAME_VALUE(PNB_LIGHTS_AUTO, pnb::LightSelection::Auto);
PNB_SAME_VALUE(PNB_INTEGRATOR_WHITTED, pnb::IntegratorKind::Whitted);
PNB_SAME_VALUE(PNB_INTEGRATOR_PATH, pnb::IntegratorKind::Path);
PNB_SAME_VALUE(PNB_DIRECT_LIGHT_MIS, pnb::DirectLightSampling::Mis);
PNB_SAME_VALUE(PNB_DIRECT_LIGHT_LIGHT, pnb::DirectLightSampling::Light);
PNB_SAME_VALUE(PNB_BUILD_LOW, pnb::BuildQuality::Low);
PNB_SAME_VALUE(PNB_BUILD_MEDIUM, pnb::BuildQuality::Medium);
PNB_SAME_VALUE(PNB_BUILD_HIGH, pnb::BuildQuality::High);
PNB_SAME_VALUE(PNB_ACCEL_EMBREE, pnb::AcceleratorKind::Embree);
PNB_SAME_VALUE(PNB_ACCEL_NAIVE, pnb::AcceleratorKind::Naive);
#undef PNB_SAME_VALUE

// Structs of the same layout: the conversions are member-wise copies.
#define PNB_SAME_FIELD(c, cf, cpp, cppf)                                                             \
    static_assert(offsetof(c, cf) == offsetof(cpp, cppf) &&                                         \
                      std::is_same_v<decltype(c::cf), decltype(cpp::cppf)>,                         \
                  #c "::" #cf " does not match " #cpp "::" #cppf)
static_assert(sizeof(pnb_vec3) == sizeof(pnb::Vec3));
PNB_SAME_FIELD(pnb_vec3, x, pnb::Vec3, x);
PNB_SAME_FIELD(pnb_vec3, y, pnb::Vec3, y);
PNB_SAME_FIELD(pnb_vec3, z, pnb::Vec3, z);
static_assert(sizeof(pnb_color) == sizeof(pnb::Color));
PNB_SAME_FIELD(pnb_color, r, pnb::Color, r);
PNB_SAME_FIELD(pnb_color, g, pnb::Color, g);
PNB_SAME_FIELD(pnb_color, b, pnb::Color, b);
static_assert(sizeof(pnb_camera) == sizeof(pnb::Camera));
static_assert(offsetof(pnb_camera, eye) == offsetof(pnb::Camera, eye));
static_assert(offsetof(pnb_camera, look_at) == offsetof(pnb::Camera, lookAt));
static_assert(offsetof(pnb_camera, up) == offsetof(pnb::Camera, up));
PNB_SAME_FIELD(pnb_camera, vfov_degrees, pnb::Camera, vfovDegrees);
PNB_SAME_FIELD(pnb_camera, aperture, pnb::Camera, aperture);
PNB_SAME_FIELD(pnb_camera, focus_distance, pnb::Camera, focusDistance);
#undef PNB_SAME_FIELD

// Render settings differ in form (C has no optional: use_crop + four ints;
// bools are ints), so each scalar's type is checked, and both sizes are
// pinned: a field added on either side fails here until in()/out() and the
// other side have it too.
#define PNB_SAME_TYPE(cf, cppf)                                                                      \
    static_assert(std::is_same_v<decltype(pnb_render_settings::cf), decltype(pnb::RenderSettings::cppf)>, \
                  "pnb_render_settings::" #cf " does not match RenderSettings::" #cppf)
PNB_SAME_TYPE(width, width);
PNB_SAME_TYPE(height, height);
PNB_SAME_TYPE(spp, spp);
PNB_SAME_TYPE(light_samples, lightSamples);
PNB_SAME_TYPE(max_depth, maxDepth);
PNB_SAME_TYPE(seed, seed);
PNB_SAME_TYPE(threads, threads);
PNB_SAME_TYPE(tile_size, tileSize);
PNB_SAME_TYPE(crop_x0, crop->x0);
#undef PNB_SAME_TYPE
static_assert(sizeof(pnb_render_settings) == 80, "pnb_render_settings changed: update in()/out() and RenderSettings");
static_assert(sizeof(pnb::RenderSettings) == 80, "RenderSettings changed: update pnb_render_settings and in()/out()");
// pnb_prepared_info grows at its end only, so the existing fields keep their offsets.
static_assert(offsetof(pnb_prepared_info, default_light_added) > offsetof(pnb_prepared_info, build_seconds) &&
                  std::is_same_v<decltype(pnb_prepared_info::default_light_added), int>,
              "pnb_prepared_info: new fields go at the end");

namespace pnb::c_api {

pnb::Vec3 in(pnb_vec3 v) { return {v.x, v.y, v.z}; }
pnb_vec3 out(const pnb::Vec3& v) { return {v.x, v.y, v.z}; }
pnb::Color in(pnb_color c) { return {c.r, c.g, c.b}; }
pnb_color out(const pnb::Color& c) { return {c.r, c.g, c.b}; }

pnb::Camera in(const pnb_camera& c) {
    pnb::Camera r;
    r.eye = in(c.eye);
    r.lookAt = in(c.look_at);
    r.up = in(c.up);
    r.vfovDegrees = c.vfov_degrees;
    r.aperture = c.aperture;
    r.focusDistance = c.focus_distance;
    return r;
}
pnb_camera out(const pnb::Camera& c) {
    pnb_camera r;
    r.eye = out(c.eye);
    r.look_at = out(c.lookAt);
    r.up = out(c.up);
    r.vfov_degrees = c.vfovDegrees;
    r.aperture = c.aperture;
    r.focus_distance = c.focusDistance;
    return r;
}

pnb::RenderSettings in(const pnb_render_settings& s) {
    pnb::RenderSettings r;
    r.width = s.width;
    r.height = s.height;
    r.spp = s.spp;
    r.lightSamples = s.light_samples;
    r.maxDepth = s.max_depth;
    r.seed = s.seed;
    r.threads = s.threads;
    r.tileSize = s.tile_size;
    if (s.use_crop) r.crop = pnb::CropWindow{s.crop_x0, s.crop_y0, s.crop_x1, s.crop_y1};
    const int selection = rawEnum(s.light_selection);
    if (selection < PNB_LIGHTS_ALL || selection > PNB_LIGHTS_AUTO)
        throw pnb::Error(pnb::ErrorCode::InvalidArgument,
                         "light_selection " + std::to_string(selection) + " is not a pnb_light_selection");
    r.lightSelection = static_cast<pnb::LightSelection>(selection);
    r.aovs = s.aovs != 0;
    const int integrator = rawEnum(s.integrator);
    if (integrator != PNB_INTEGRATOR_WHITTED && integrator != PNB_INTEGRATOR_PATH)
        throw pnb::Error(pnb::ErrorCode::InvalidArgument,
                         "integrator " + std::to_string(integrator) + " is not a pnb_integrator");
    r.integrator = integrator == PNB_INTEGRATOR_PATH ? pnb::IntegratorKind::Path : pnb::IntegratorKind::Whitted;
    const int direct = rawEnum(s.direct_light);
    if (direct != PNB_DIRECT_LIGHT_MIS && direct != PNB_DIRECT_LIGHT_LIGHT)
        throw pnb::Error(pnb::ErrorCode::InvalidArgument,
                         "direct_light " + std::to_string(direct) + " is not a pnb_direct_light");
    r.directLight = static_cast<pnb::DirectLightSampling>(direct);
    return r;
}
pnb_render_settings out(const pnb::RenderSettings& s) {
    pnb_render_settings r;
    r.width = s.width;
    r.height = s.height;
    r.spp = s.spp;
    r.light_samples = s.lightSamples;
    r.max_depth = s.maxDepth;
    r.seed = s.seed;
    r.threads = s.threads;
    r.tile_size = s.tileSize;
    r.use_crop = s.crop ? 1 : 0;
    r.crop_x0 = s.crop ? s.crop->x0 : 0;
    r.crop_y0 = s.crop ? s.crop->y0 : 0;
    r.crop_x1 = s.crop ? s.crop->x1 : 0;
    r.crop_y1 = s.crop ? s.crop->y1 : 0;
    r.light_selection = static_cast<pnb_light_selection>(s.lightSelection);
    r.aovs = s.aovs ? 1 : 0;
    r.integrator = s.integrator == pnb::IntegratorKind::Path ? PNB_INTEGRATOR_PATH : PNB_INTEGRATOR_WHITTED;
    r.direct_light = static_cast<pnb_direct_light>(s.directLight);
    return r;
}

pnb_render_stats out(const pnb::RenderStats& s) {
    pnb_render_stats r;
    r.camera_rays = s.cameraRays;
    r.shadow_rays = s.shadowRays;
    r.reflection_rays = s.reflectionRays;
    r.invalid_rays = s.invalidRays;
    r.non_finite_samples = s.nonFiniteSamples;
    r.render_seconds = s.renderSeconds;
    r.mrays_per_second = s.mraysPerSecond;
    r.samples_per_pixel = s.samplesPerPixel;
    r.threads = s.threads;
    r.transmission_rays = s.transmissionRays;
    r.brdf_rays = s.brdfRays;
    r.pixels_hit = s.pixelsHit;
    r.indirect_rays = s.indirectRays;
    r.path_length_sum = s.pathLengthSum;
    r.path_length_max = s.pathLengthMax;
    return r;
}

}  // namespace pnb::c_api

using namespace pnb::c_api;

extern "C" {

// ---------------------------------------------------------------- defaults

void pnb_material_init(pnb_material* m) {
    if (!m) return;
    const pnb::Material d;
    m->name = nullptr;
    m->ka = out(d.ka);
    m->kd = out(d.kd);
    m->ks = out(d.ks);
    m->exponent = d.exponent;
    m->kr = out(d.kr);
    m->ke = out(d.ke);
    m->two_sided_emission = 0;
    m->model = PNB_PHONG_NORMALIZED;
    m->diffuse_texture = nullptr;
    m->kt = out(d.kt);
    m->ior = d.ior;
    m->kind = PNB_MATERIAL_PHONG;
    m->base_color = out(d.baseColor);
    m->metallic = d.metallic;
    m->roughness = d.roughness;
    m->transmission = d.transmission;
    m->base_color_texture = m->metallic_roughness_texture = m->normal_texture = m->emissive_texture = nullptr;
    m->normal_scale = d.normalScale;
}

void pnb_mesh_desc_init(pnb_mesh_desc* mesh) {
    if (mesh) *mesh = pnb_mesh_desc{nullptr, nullptr, 0, nullptr, 0, nullptr, nullptr, nullptr, 0};
}

void pnb_camera_init(pnb_camera* camera) {
    if (camera) *camera = out(pnb::Camera{});
}

void pnb_render_settings_init(pnb_render_settings* settings) {
    if (settings) *settings = out(pnb::RenderSettings{});
}

void pnb_load_options_init(pnb_load_options* o) {
    if (o) *o = pnb_load_options{0, 1, nullptr, 0, 0, PNB_PHONG_NORMALIZED, 30.f};
}

void pnb_prepare_options_init(pnb_prepare_options* o) {
    if (o) *o = pnb_prepare_options{PNB_ACCEL_EMBREE, PNB_BUILD_HIGH};
}

void pnb_image_options_init(pnb_image_options* o) {
    if (o) *o = pnb_image_options{0.f, 0};
}

void pnb_render_callbacks_init(pnb_render_callbacks* cb) {
    if (cb) *cb = pnb_render_callbacks{nullptr, nullptr};
}

void pnb_scene_edits_init(pnb_scene_edits* e) {
    if (e) *e = pnb_scene_edits{nullptr, 0, nullptr, 0, nullptr, 0, nullptr, 0, 0, 0.f, 0, 1.f};
}

void pnb_async_options_init(pnb_async_options* o) {
    if (o) *o = pnb_async_options{nullptr, 0, nullptr, nullptr, nullptr};
}

pnb_status pnb_render_settings_validate(const pnb_render_settings* settings) {
    return guard(nullptr, "pnb_render_settings_validate", [&] {
        need(settings, "settings");
        pnb::validate(in(*settings));
    });
}

pnb_status pnb_camera_validate(const pnb_camera* camera) {
    return guard(nullptr, "pnb_camera_validate", [&] {
        need(camera, "camera");
        pnb::validate(in(*camera));
    });
}

}  // extern "C"

// pnb_scene_add_instance's "keep the prototype's materials" is the library's "no override".
static_assert(PNB_KEEP_MATERIALS == penumbra::kNoMaterialOverride);
