// The C API (core/include/penumbra/penumbra.h) as a thin layer over the C++
// API: handles own C++ objects, and every entry point catches everything, so
// no exception crosses into C.
#include <penumbra/penumbra.h>

#include <atomic>
#include <cstring>
#include <new>
#include <penumbra/penumbra.hpp>
#include <string>
#include <utility>

struct pnb_renderer {
    pnb::Renderer renderer;
    std::string error;
};

struct pnb_scene {
    pnb::Scene scene;
    std::string error;
};

struct pnb_prepared_scene {
    pnb::PreparedScene prepared;
};

struct pnb_framebuffer {
    pnb::Framebuffer owned;
    const pnb::Framebuffer* borrowed = nullptr;  // a job's or a callback's image: read-only
    mutable std::string error;
    const pnb::Framebuffer& get() const { return borrowed ? *borrowed : owned; }
};

struct pnb_render_job {
    pnb::RenderJob job;
    pnb_framebuffer image;  // borrows the job's image once it finished
    std::string error;
};

namespace {

// The per-thread fallback for failures without a handle to keep them.
thread_local std::string tLastError;

// A C caller may store any int in an enum field; in C++ reading an enum object
// outside its value range is undefined, so the raw bits are read instead.
template <class E>
int rawEnum(const E& e) {
    static_assert(sizeof(E) == sizeof(int), "C enums are int-sized");
    int v;
    std::memcpy(&v, &e, sizeof v);
    return v;
}

pnb_status toStatus(pnb::ErrorCode code) { return static_cast<pnb_status>(static_cast<int>(code)); }

pnb_status record(std::string* sink, pnb_status status, const char* function, const char* message) noexcept {
    try {
        std::string text(function);
        text += ": ";
        text += message;
        if (sink) *sink = text;
        tLastError = std::move(text);
    } catch (...) {
        // Out of memory while reporting: the status code still tells what happened.
    }
    return status;
}

// Runs f, turning every exception into a status and a recorded message.
template <class F>
pnb_status guard(std::string* sink, const char* function, F&& f) noexcept {
    try {
        f();
        return PNB_OK;
    } catch (const pnb::Error& e) {
        return record(sink, toStatus(e.code()), function, e.what());
    } catch (const std::bad_alloc&) {
        return record(sink, PNB_ERROR_OUT_OF_MEMORY, function, "out of memory");
    } catch (const std::exception& e) {
        return record(sink, PNB_ERROR_INTERNAL, function, e.what());
    } catch (...) {
        return record(sink, PNB_ERROR_INTERNAL, function, "unknown exception");
    }
}

// Throws the InvalidArgument error guard() reports for a NULL argument.
void need(const void* p, const char* what) {
    if (!p) throw pnb::Error(pnb::ErrorCode::InvalidArgument, std::string(what) + " is NULL");
}

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
    if (selection != PNB_LIGHTS_ALL && selection != PNB_LIGHTS_POWER)
        throw pnb::Error(pnb::ErrorCode::InvalidArgument,
                         "light_selection " + std::to_string(selection) + " is not a pnb_light_selection");
    r.lightSelection = selection == PNB_LIGHTS_POWER ? pnb::LightSelection::Power : pnb::LightSelection::All;
    r.aovs = s.aovs != 0;
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
    r.light_selection = s.lightSelection == pnb::LightSelection::Power ? PNB_LIGHTS_POWER : PNB_LIGHTS_ALL;
    r.aovs = s.aovs ? 1 : 0;
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
    return r;
}

// A synchronous render's hooks: the C progress callback cancels by returning nonzero.
struct SyncControl {
    std::atomic<bool> cancel{false};
    pnb::RenderControl control;
    explicit SyncControl(const pnb_render_callbacks* cb) {
        if (!cb || !cb->progress) return;
        control.cancel = &cancel;
        control.progress = [this, fn = cb->progress, user = cb->user](double f) {
            if (fn(f, user) != 0) cancel.store(true);
        };
    }
};

template <class T>
void destroy(T* p) noexcept {
    delete p;
}

}  // namespace

extern "C" {

const char* pnb_status_name(pnb_status status) {
    if (status == PNB_OK) return "ok";
    if (status < PNB_ERROR_INVALID_ARGUMENT || status > PNB_ERROR_INTERNAL) return "unknown status";
    return pnb::errorCodeName(static_cast<pnb::ErrorCode>(static_cast<int>(status)));
}

const char* pnb_last_error(void) { return tLastError.c_str(); }
const char* pnb_version(void) { return pnb::version(); }

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
    if (o) *o = pnb_load_options{0, 1, nullptr, 0};
}

void pnb_prepare_options_init(pnb_prepare_options* o) {
    if (o) *o = pnb_prepare_options{"embree", PNB_BUILD_HIGH};
}

void pnb_image_options_init(pnb_image_options* o) {
    if (o) *o = pnb_image_options{0.f, 0};
}

void pnb_render_callbacks_init(pnb_render_callbacks* cb) {
    if (cb) *cb = pnb_render_callbacks{nullptr, nullptr};
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

pnb_status pnb_scene_add_material(pnb_scene* scene, const pnb_material* material, uint32_t* out_id) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_material", [&] {
        need(scene, "scene");
        need(material, "material");
        pnb::Material m;
        if (material->name) m.name = material->name;
        m.ka = in(material->ka);
        m.kd = in(material->kd);
        m.ks = in(material->ks);
        m.exponent = material->exponent;
        m.kr = in(material->kr);
        m.ke = in(material->ke);
        m.twoSidedEmission = material->two_sided_emission != 0;
        const int model = rawEnum(material->model);
        if (model != PNB_PHONG_NORMALIZED && model != PNB_PHONG_CLASSIC)
            throw pnb::Error(pnb::ErrorCode::InvalidArgument,
                             "material model " + std::to_string(model) + " is not a pnb_phong_model");
        m.model = model == PNB_PHONG_CLASSIC ? pnb::PhongModel::Classic : pnb::PhongModel::Normalized;
        if (material->diffuse_texture) m.diffuseTexture = material->diffuse_texture;
        const pnb::MaterialId id = scene->scene.addMaterial(m);
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

pnb_status pnb_scene_add_mesh(pnb_scene* scene, const pnb_mesh_desc* mesh) {
    return guard(scene ? &scene->error : nullptr, "pnb_scene_add_mesh", [&] {
        need(scene, "scene");
        need(mesh, "mesh");
        pnb::MeshDesc d;
        if (mesh->name) d.name = mesh->name;
        d.positions = mesh->positions;
        d.vertexCount = mesh->vertex_count;
        d.indices = mesh->indices;
        d.triangleCount = mesh->triangle_count;
        d.normals = mesh->normals;
        d.uvs = mesh->uvs;
        d.faceMaterials = mesh->face_materials;
        d.material = mesh->material;
        scene->scene.addMesh(d);
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
            if (options->accelerator) po.accelerator = options->accelerator;
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

void pnb_prepared_scene_destroy(pnb_prepared_scene* prepared) { destroy(prepared); }

pnb_status pnb_prepared_scene_get_info(const pnb_prepared_scene* prepared, pnb_prepared_info* out) {
    return guard(nullptr, "pnb_prepared_scene_get_info", [&] {
        need(prepared, "prepared scene");
        need(out, "out");
        const pnb::PreparedScene& p = prepared->prepared;
        *out = pnb_prepared_info{p.primitiveCount(),   p.triangleCount(), p.lightCount(),
                                 p.droppedTriangles(), p.droppedShapes(), p.buildSeconds()};
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

// ---------------------------------------------------------------- framebuffer

pnb_status pnb_framebuffer_create(const pnb_render_settings* settings, pnb_framebuffer** out) {
    if (out) *out = nullptr;
    return guard(nullptr, "pnb_framebuffer_create", [&] {
        need(settings, "settings");
        need(out, "out");
        auto image = std::make_unique<pnb_framebuffer>();
        image->owned = pnb::Framebuffer(in(*settings));
        *out = image.release();
    });
}

void pnb_framebuffer_destroy(pnb_framebuffer* image) {
    if (image && !image->borrowed) delete image;  // borrowed images belong to their job
}

const char* pnb_framebuffer_last_error(const pnb_framebuffer* image) { return image ? image->error.c_str() : ""; }
int pnb_framebuffer_width(const pnb_framebuffer* image) { return image ? image->get().width() : 0; }
int pnb_framebuffer_height(const pnb_framebuffer* image) { return image ? image->get().height() : 0; }
uint32_t pnb_framebuffer_sample_count(const pnb_framebuffer* image) { return image ? image->get().sampleCount() : 0; }

pnb_status pnb_framebuffer_read_rgba(const pnb_framebuffer* image, float* dst, size_t count) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_read_rgba", [&] {
        need(image, "framebuffer");
        need(dst, "dst");
        image->get().readRgba(dst, count);
    });
}

pnb_status pnb_framebuffer_read_albedo(const pnb_framebuffer* image, float* dst, size_t count) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_read_albedo", [&] {
        need(image, "framebuffer");
        need(dst, "dst");
        image->get().readAlbedo(dst, count);
    });
}

pnb_status pnb_framebuffer_read_normals(const pnb_framebuffer* image, float* dst, size_t count) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_read_normals", [&] {
        need(image, "framebuffer");
        need(dst, "dst");
        image->get().readNormals(dst, count);
    });
}

pnb_status pnb_framebuffer_read_depth(const pnb_framebuffer* image, float* dst, size_t count) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_read_depth", [&] {
        need(image, "framebuffer");
        need(dst, "dst");
        image->get().readDepth(dst, count);
    });
}

pnb_status pnb_framebuffer_pixel(const pnb_framebuffer* image, int x, int y, pnb_color* out) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_pixel", [&] {
        need(image, "framebuffer");
        need(out, "out");
        *out = ::out(image->get().pixel(x, y));
    });
}

pnb_status pnb_framebuffer_clear(pnb_framebuffer* image) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_clear", [&] {
        need(image, "framebuffer");
        if (image->borrowed)
            throw pnb::Error(pnb::ErrorCode::InvalidArgument, "a render job's framebuffer is read-only");
        image->owned.clear();
    });
}

pnb_status pnb_framebuffer_write_image(const pnb_framebuffer* image, const char* path,
                                       const pnb_image_options* options) {
    return guard(image ? &image->error : nullptr, "pnb_framebuffer_write_image", [&] {
        need(image, "framebuffer");
        need(path, "path");
        pnb::ImageOptions o;
        if (options) {
            o.exposure = options->exposure;
            o.aovs = options->aovs != 0;
        }
        image->get().writeImage(path, o);
    });
}

// ---------------------------------------------------------------- rendering

pnb_status pnb_render(pnb_renderer* renderer, const pnb_prepared_scene* prepared, const pnb_camera* camera,
                      const pnb_render_settings* settings, pnb_framebuffer* image,
                      const pnb_render_callbacks* callbacks, pnb_render_stats* stats) {
    return guard(renderer ? &renderer->error : nullptr, "pnb_render", [&] {
        need(renderer, "renderer");
        need(prepared, "prepared scene");
        need(camera, "camera");
        need(settings, "settings");
        need(image, "framebuffer");
        if (image->borrowed)
            throw pnb::Error(pnb::ErrorCode::InvalidArgument, "a render job's framebuffer is read-only");
        SyncControl control(callbacks);
        const pnb::RenderStats st =
            renderer->renderer.render(prepared->prepared, in(*camera), in(*settings), image->owned, control.control);
        if (stats) *stats = out(st);
    });
}

pnb_status pnb_render_rgba(pnb_renderer* renderer, const pnb_prepared_scene* prepared, const pnb_camera* camera,
                           const pnb_render_settings* settings, float* rgba, size_t count,
                           const pnb_render_callbacks* callbacks, pnb_render_stats* stats) {
    return guard(renderer ? &renderer->error : nullptr, "pnb_render_rgba", [&] {
        need(renderer, "renderer");
        need(prepared, "prepared scene");
        need(camera, "camera");
        need(settings, "settings");
        need(rgba, "rgba");
        SyncControl control(callbacks);
        const pnb::RenderStats st =
            renderer->renderer.render(prepared->prepared, in(*camera), in(*settings), rgba, count, control.control);
        if (stats) *stats = out(st);
    });
}

pnb_status pnb_render_pass(pnb_renderer* renderer, const pnb_prepared_scene* prepared, const pnb_camera* camera,
                           const pnb_render_settings* settings, pnb_framebuffer* image, uint32_t first_sample,
                           uint32_t sample_count, const pnb_render_callbacks* callbacks, pnb_render_stats* stats) {
    return guard(renderer ? &renderer->error : nullptr, "pnb_render_pass", [&] {
        need(renderer, "renderer");
        need(prepared, "prepared scene");
        need(camera, "camera");
        need(settings, "settings");
        need(image, "framebuffer");
        if (image->borrowed)
            throw pnb::Error(pnb::ErrorCode::InvalidArgument, "a render job's framebuffer is read-only");
        SyncControl control(callbacks);
        const pnb::RenderStats st = renderer->renderer.renderPass(prepared->prepared, in(*camera), in(*settings),
                                                                  image->owned, first_sample, sample_count,
                                                                  control.control);
        if (stats) *stats = out(st);
    });
}

pnb_status pnb_render_async(pnb_renderer* renderer, const pnb_prepared_scene* prepared, const pnb_camera* camera,
                            const pnb_render_settings* settings, const pnb_async_options* options,
                            pnb_render_job** out) {
    if (out) *out = nullptr;
    return guard(renderer ? &renderer->error : nullptr, "pnb_render_async", [&] {
        need(renderer, "renderer");
        need(prepared, "prepared scene");
        need(camera, "camera");
        need(settings, "settings");
        need(out, "out");
        pnb::AsyncOptions ao;
        if (options) {
            const pnb_async_options o = *options;
            ao.passSamples = o.pass_samples;
            if (o.progress) ao.progress = [o](double f) { o.progress(f, o.user); };
            if (o.on_pass)
                ao.onPass = [o](const pnb::Framebuffer& image, uint32_t done) {
                    pnb_framebuffer view;
                    view.borrowed = &image;
                    o.on_pass(&view, done, o.user);
                };
            if (o.on_complete)
                ao.onComplete = [o](const pnb::JobResult& r) {
                    pnb_framebuffer view;
                    view.borrowed = r.framebuffer;
                    const pnb_status status = r.error ? toStatus(r.error->code()) : PNB_OK;
                    o.on_complete(status, r.error ? r.error->what() : "", r.framebuffer ? &view : nullptr, o.user);
                };
        }
        auto job = std::make_unique<pnb_render_job>();
        job->job = renderer->renderer.renderAsync(prepared->prepared, in(*camera), in(*settings), std::move(ao));
        *out = job.release();
    });
}

double pnb_render_job_progress(const pnb_render_job* job) { return job ? job->job.progress() : 0.0; }

pnb_status pnb_render_job_cancel(pnb_render_job* job) {
    return guard(nullptr, "pnb_render_job_cancel", [&] {
        need(job, "job");
        job->job.cancel();
    });
}

int pnb_render_job_done(const pnb_render_job* job) { return job && job->job.done() ? 1 : 0; }

pnb_status pnb_render_job_wait(pnb_render_job* job) {
    if (!job) return record(nullptr, PNB_ERROR_INVALID_ARGUMENT, "pnb_render_job_wait", "job is NULL");
    pnb_status status = PNB_OK;
    const pnb_status called = guard(&job->error, "pnb_render_job_wait", [&] {
        const std::optional<pnb::Error> e = job->job.error();  // waits
        if (e) status = record(&job->error, toStatus(e->code()), "pnb_render_job_wait", e->what());
    });
    return called != PNB_OK ? called : status;
}

pnb_status pnb_render_job_wait_for(pnb_render_job* job, uint32_t timeout_ms, int* done) {
    return guard(job ? &job->error : nullptr, "pnb_render_job_wait_for", [&] {
        need(job, "job");
        const bool finished = job->job.waitFor(std::chrono::milliseconds(timeout_ms));
        if (done) *done = finished ? 1 : 0;
    });
}

pnb_status pnb_render_job_framebuffer(pnb_render_job* job, const pnb_framebuffer** out) {
    if (out) *out = nullptr;
    return guard(job ? &job->error : nullptr, "pnb_render_job_framebuffer", [&] {
        need(job, "job");
        need(out, "out");
        job->image.borrowed = &job->job.framebuffer();  // waits; throws the job's error
        *out = &job->image;
    });
}

pnb_status pnb_render_job_stats(pnb_render_job* job, pnb_render_stats* out) {
    return guard(job ? &job->error : nullptr, "pnb_render_job_stats", [&] {
        need(job, "job");
        need(out, "out");
        *out = ::out(job->job.stats());
    });
}

void pnb_render_job_destroy(pnb_render_job* job) { destroy(job); }
const char* pnb_render_job_last_error(const pnb_render_job* job) { return job ? job->error.c_str() : ""; }

}  // extern "C"
