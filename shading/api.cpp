// The C++ embedding API (core/include/penumbra/penumbra.hpp) on top of the
// renderer. Every entry point translates internal failures into pnb::Error, so
// neither penumbra::Error nor std::bad_alloc reaches a host.
#include <penumbra/penumbra.hpp>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <limits>
#include <mutex>
#include <new>
#include <thread>

#include "core/error.h"
#include "core/image_io.h"
#include "core/scene_loader.h"
#include "shading/renderer.h"

namespace pnb {

namespace fs = std::filesystem;
namespace pn = penumbra;

// ---------------------------------------------------------------- internals

struct Scene::Impl {
    pn::Scene scene;
    std::optional<pn::CameraDesc> camera;
    pn::SettingsPatch settings;
};

struct PreparedScene::Impl {
    Impl(pn::Scene scene, const pn::PrepareOptions& options, const pn::Logger& log,
         std::optional<pn::CameraDesc> cam, pn::SettingsPatch patch)
        : prepared(std::move(scene), options, log), camera(cam), settings(patch) {}
    pn::PreparedScene prepared;
    std::optional<pn::CameraDesc> camera;
    pn::SettingsPatch settings;
};

struct Framebuffer::Impl {
    pn::Film film;
    bool incomplete = false;  // a pass was cut short: the sums are partial
    std::uint64_t seed = 0;
    double renderSeconds = 0.0;
};

struct Renderer::Impl {
    pn::Logger log;
};

namespace {

// What an asynchronous job shares with its thread.
struct JobState {
    std::atomic<double> progress{0.0};
    std::atomic<bool> cancel{false};
    std::atomic<JobStatus> status{JobStatus::Running};
    std::atomic<bool> done{false};
    std::mutex mutex;
    std::condition_variable finished;
    std::optional<Error> error;
    RenderStats stats;
    Framebuffer image;
};

}  // namespace

struct RenderJob::Impl {
    std::shared_ptr<JobState> state;
    std::thread thread;
    ~Impl() {
        state->cancel.store(true);
        if (thread.joinable()) thread.join();
    }
};

namespace detail {
struct Access {
    using SceneImpl = Scene::Impl;
    using PreparedImpl = PreparedScene::Impl;
    using FramebufferImpl = Framebuffer::Impl;
    using JobImpl = RenderJob::Impl;
    static Scene::Impl& of(Scene& s) { return *s.impl_; }
    static const Scene::Impl& of(const Scene& s) { return *s.impl_; }
    static const PreparedScene::Impl* of(const PreparedScene& p) { return p.impl_.get(); }
    static void set(PreparedScene& p, std::shared_ptr<const PreparedScene::Impl> impl) { p.impl_ = std::move(impl); }
    static Framebuffer::Impl& of(Framebuffer& f) { return *f.impl_; }
    static const Framebuffer::Impl& of(const Framebuffer& f) { return *f.impl_; }
    static const pn::Logger& log(const Renderer& r) { return r.impl_->log; }
    static void set(RenderJob& j, std::unique_ptr<RenderJob::Impl> impl) { j.impl_ = std::move(impl); }
};
}  // namespace detail

using SceneImpl = detail::Access::SceneImpl;
using PreparedImpl = detail::Access::PreparedImpl;
using FramebufferImpl = detail::Access::FramebufferImpl;
using JobImpl = detail::Access::JobImpl;

namespace {

using detail::Access;

[[noreturn]] void fail(ErrorCode code, const std::string& message) { throw Error(code, message); }

void require(bool ok, const std::string& message) {
    if (!ok) fail(ErrorCode::InvalidArgument, message);
}

// Runs f, turning every internal failure into pnb::Error. Host callbacks may
// throw pnb::Error themselves; that passes through unchanged.
template <class F>
auto guarded(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const Error&) {
        throw;
    } catch (const pn::Error& e) {
        throw Error(static_cast<ErrorCode>(static_cast<int>(e.code())), e.what());
    } catch (const std::bad_alloc&) {
        throw Error(ErrorCode::OutOfMemory, "out of memory");
    } catch (const fs::filesystem_error& e) {
        throw Error(ErrorCode::IoError, e.what());
    } catch (const std::exception& e) {
        throw Error(ErrorCode::Internal, e.what());
    } catch (...) {
        throw Error(ErrorCode::Internal, "unknown exception");
    }
}

// ---- conversions

pn::Vec3f in(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 out(const pn::Vec3f& v) { return {v.x, v.y, v.z}; }
pn::Rgb in(const Color& c) { return {c.r, c.g, c.b}; }
Color out(const pn::Rgb& c) { return {c.r, c.g, c.b}; }

pn::Transform in(const Matrix3x4& m) { return pn::Transform(m.m); }
Matrix3x4 out(const pn::Transform& t) {
    Matrix3x4 m;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) m.m[r][c] = t(r, c);
    return m;
}

pn::CameraDesc in(const Camera& c) {
    pn::CameraDesc d;
    d.eye = in(c.eye);
    d.lookAt = in(c.lookAt);
    d.up = in(c.up);
    d.vfovDegrees = c.vfovDegrees;
    d.aperture = c.aperture;
    d.focusDistance = c.focusDistance;
    return d;
}
Camera out(const pn::CameraDesc& d) {
    Camera c;
    c.eye = out(d.eye);
    c.lookAt = out(d.lookAt);
    c.up = out(d.up);
    c.vfovDegrees = d.vfovDegrees;
    c.aperture = d.aperture;
    c.focusDistance = d.focusDistance;
    return c;
}

pn::RenderSettings in(const RenderSettings& s) {
    pn::RenderSettings r;
    r.width = s.width;
    r.height = s.height;
    r.spp = s.spp;
    r.lightSamples = s.lightSamples;
    r.maxDepth = s.maxDepth;
    r.seed = s.seed;
    r.threads = s.threads;
    r.tileSize = s.tileSize;
    if (s.crop) r.crop = pn::CropWindow{s.crop->x0, s.crop->y0, s.crop->x1, s.crop->y1};
    r.lightSelection = s.lightSelection == LightSelection::Power ? pn::LightSelection::Power : pn::LightSelection::All;
    r.aovs = s.aovs;
    return r;
}
RenderSettings out(const pn::RenderSettings& r) {
    RenderSettings s;
    s.width = r.width;
    s.height = r.height;
    s.spp = r.spp;
    s.lightSamples = r.lightSamples;
    s.maxDepth = r.maxDepth;
    s.seed = r.seed;
    s.threads = r.threads;
    s.tileSize = r.tileSize;
    if (r.crop) s.crop = CropWindow{r.crop->x0, r.crop->y0, r.crop->x1, r.crop->y1};
    s.lightSelection = r.lightSelection == pn::LightSelection::Power ? LightSelection::Power : LightSelection::All;
    return s;  // aovs stay off: they are the host's choice, not the file's
}

RenderSettings settingsFrom(const pn::SettingsPatch& patch) {
    pn::RenderSettings r;
    patch.applyTo(r);
    return out(r);
}

Camera defaultCameraFor(const std::optional<pn::CameraDesc>& cam, const pn::Bounds3f& bounds, float aspect,
                        float vfov) {
    if (cam) return out(*cam);
    return out(pn::frameBounds(bounds, vfov, aspect));
}

RenderStats out(const pn::RenderStats& s) {
    RenderStats r;
    r.cameraRays = s.rays.camera;
    r.shadowRays = s.rays.shadow;
    r.reflectionRays = s.rays.reflection;
    r.invalidRays = s.invalidRays;
    r.nonFiniteSamples = s.rays.nonFinite;
    r.renderSeconds = s.renderSeconds;
    r.mraysPerSecond = s.mraysPerSecond;
    r.samplesPerPixel = s.samplesPerPixel;
    r.threads = s.threads;
    return r;
}

void accumulate(RenderStats& total, const RenderStats& pass) {
    total.cameraRays += pass.cameraRays;
    total.shadowRays += pass.shadowRays;
    total.reflectionRays += pass.reflectionRays;
    total.invalidRays += pass.invalidRays;
    total.nonFiniteSamples += pass.nonFiniteSamples;
    total.renderSeconds += pass.renderSeconds;
    const double rays = double(total.cameraRays + total.shadowRays + total.reflectionRays);
    total.mraysPerSecond = total.renderSeconds > 0 ? rays / total.renderSeconds * 1e-6 : 0.0;
    total.samplesPerPixel = pass.samplesPerPixel;
    total.threads = pass.threads;
}

// ---- validation

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool nonNegative(const Color& c) {
    return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && c.r >= 0.f && c.g >= 0.f && c.b >= 0.f;
}
std::string str(const Vec3& v) {
    // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "(" + std::to_string(...).
    std::string s(1, '(');
    s += std::to_string(v.x);
    s += ", ";
    s += std::to_string(v.y);
    s += ", ";
    s += std::to_string(v.z);
    s += ')';
    return s;
}

void requireFinite(const Vec3& v, const char* what) {
    require(finite(v), std::string(what) + " must be finite, got " + str(v));
}
void requireDirection(const Vec3& v, const char* what) {
    requireFinite(v, what);
    require(v.x != 0.f || v.y != 0.f || v.z != 0.f, std::string(what) + " must not be the zero vector");
}
void requireColor(const Color& c, const std::string& what) {
    require(nonNegative(c), what + " must be finite and >= 0");
}

void requireMaterial(const pn::Scene& s, MaterialId id, const std::string& what) {
    const size_t count = std::max<size_t>(s.materials.size(), 1);  // id 0: the default material
    require(id < count, what + ": material id " + std::to_string(id) + " does not exist (the scene has " +
                            std::to_string(s.materials.size()) + " materials)");
}

const PreparedImpl& requirePrepared(const PreparedScene& p) {
    const PreparedImpl* impl = Access::of(p);
    require(impl != nullptr, "the prepared scene is empty (use Renderer::prepare)");
    return *impl;
}

uint64_t physicalMemoryBytes() {
    long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? uint64_t(pages) * uint64_t(size) : 0;
}

pn::CropWindow windowOf(const pn::RenderSettings& s) {
    return s.crop ? *s.crop : pn::CropWindow{0, 0, s.width, s.height};
}

// Checks a pass against its framebuffer before anything is written, so a
// rejected call leaves the framebuffer untouched.
void checkPass(const pn::RenderSettings& s, const FramebufferImpl& fb, uint32_t first, uint32_t count) {
    const pn::Film& f = fb.film;
    require(f.fullWidth() > 0, "the framebuffer is empty (create it from the render settings)");
    require(!fb.incomplete, "the framebuffer holds a cancelled or failed pass; clear() it first");
    const pn::CropWindow w = windowOf(s);
    require(f.fullWidth() == s.width && f.fullHeight() == s.height && f.window() == w,
            "the framebuffer (" + std::to_string(f.fullWidth()) + "x" + std::to_string(f.fullHeight()) + ", window " +
                std::to_string(f.window().x0) + "," + std::to_string(f.window().y0) + "," +
                std::to_string(f.window().x1) + "," + std::to_string(f.window().y1) +
                ") does not match the render settings (" + std::to_string(s.width) + "x" + std::to_string(s.height) +
                ", window " + std::to_string(w.x0) + "," + std::to_string(w.y0) + "," + std::to_string(w.x1) + "," +
                std::to_string(w.y1) + ")");
    require(uint64_t(first) + count <= uint64_t(s.spp), "samples [" + std::to_string(first) + ", " +
                                                            std::to_string(uint64_t(first) + count) +
                                                            ") exceed spp = " + std::to_string(s.spp));
    require(f.sampleCount() == first, "the framebuffer holds " + std::to_string(f.sampleCount()) +
                                          " samples per pixel; the pass must start there, not at " +
                                          std::to_string(first));
}

// One checked pass; `progress` receives the fraction of this pass.
RenderStats runPass(const PreparedImpl& p, const pn::CameraDesc& camera, const pn::RenderSettings& s,
                    FramebufferImpl& fb, uint32_t first, uint32_t count, const std::function<void(double)>& progress,
                    const std::atomic<bool>* cancel) {
    checkPass(s, fb, first, count);
    pn::RenderControl control;
    control.cancel = cancel;
    if (progress) control.progress = [&](size_t done, size_t total) { progress(double(done) / double(total)); };
    fb.incomplete = true;  // until the pass completes
    const pn::RenderStats st = pn::renderPass(p.prepared, camera, s, fb.film, first, count, control);
    if (st.cancelled)
        fail(ErrorCode::Cancelled, "render cancelled after " + std::to_string(fb.film.sampleCount()) +
                                       " complete samples per pixel; the framebuffer holds a partial pass");
    fb.incomplete = false;
    fb.seed = s.seed;
    fb.renderSeconds += st.renderSeconds;
    return out(st);
}

void checkCameraAndSettings(const Camera& camera, const pn::RenderSettings& s) {
    pn::validateSettings(s);
    pn::validateCamera(in(camera));
}

void copyInto(const std::vector<float>& src, float* dst, size_t floatCount, const char* what) {
    require(dst != nullptr || src.empty(), std::string(what) + ": destination is null");
    require(floatCount >= src.size(), std::string(what) + ": destination holds " + std::to_string(floatCount) +
                                          " floats, the image needs " + std::to_string(src.size()));
    std::copy(src.begin(), src.end(), dst);
}

}  // namespace

// ---------------------------------------------------------------- free functions

const char* version() noexcept { return PENUMBRA_VERSION; }

const char* errorCodeName(ErrorCode code) noexcept {
    switch (code) {
        case ErrorCode::InvalidArgument: return "invalid argument";
        case ErrorCode::FileNotFound: return "file not found";
        case ErrorCode::ParseError: return "parse error";
        case ErrorCode::InvalidScene: return "invalid scene";
        case ErrorCode::IoError: return "I/O error";
        case ErrorCode::OutOfMemory: return "out of memory";
        case ErrorCode::Cancelled: return "cancelled";
        case ErrorCode::Embree: return "Embree error";
        case ErrorCode::Internal: return "internal error";
    }
    return "unknown error";
}

Error::~Error() = default;

void validate(const RenderSettings& settings) {
    guarded([&] { pn::validateSettings(in(settings)); });
}

void validate(const Camera& camera) {
    guarded([&] { pn::validateCamera(in(camera)); });
}

Matrix3x4 Matrix3x4::translate(const Vec3& t) { return out(pn::Transform::translate(in(t))); }
Matrix3x4 Matrix3x4::scale(const Vec3& s) { return out(pn::Transform::scale(in(s))); }
Matrix3x4 Matrix3x4::rotate(float degrees, const Vec3& axis) { return out(pn::Transform::rotate(degrees, in(axis))); }
Matrix3x4 Matrix3x4::operator*(const Matrix3x4& other) const { return out(in(*this) * in(other)); }

// ---------------------------------------------------------------- Scene

Scene::Scene() : impl_(std::make_unique<Impl>()) {}
Scene::~Scene() = default;
Scene::Scene(const Scene& other) : impl_(guarded([&] { return std::make_unique<Impl>(*other.impl_); })) {}
Scene& Scene::operator=(const Scene& other) {
    if (this != &other) impl_ = guarded([&] { return std::make_unique<Impl>(*other.impl_); });
    return *this;
}
// Every method dereferences impl_, so a moved-from object must keep one: move
// construction leaves a fresh empty Impl behind, move assignment swaps.
Scene::Scene(Scene&& other) noexcept : impl_(std::move(other.impl_)) {
    other.impl_ = std::unique_ptr<Impl>(new (std::nothrow) Impl());
}
Scene& Scene::operator=(Scene&& other) noexcept {
    std::swap(impl_, other.impl_);
    return *this;
}

MaterialId Scene::addMaterial(const Material& m) {
    return guarded([&] {
        pn::Scene& s = impl_->scene;
        const std::string what = "material '" + m.name + "'";
        requireColor(m.ka, what + ": ka");
        requireColor(m.kd, what + ": kd");
        requireColor(m.ks, what + ": ks");
        requireColor(m.kr, what + ": kr");
        requireColor(m.ke, what + ": ke");
        require(std::isfinite(m.exponent) && m.exponent >= 0.f, what + ": exponent must be finite and >= 0");
        require(s.materials.size() < std::numeric_limits<MaterialId>::max(), "too many materials");
        pn::Material pm;
        pm.name = m.name;
        pm.ka = in(m.ka);
        pm.kd = in(m.kd);
        pm.ks = in(m.ks);
        pm.exponent = m.exponent;
        pm.kr = in(m.kr);
        pm.ke = in(m.ke);
        pm.twoSidedEmission = m.twoSidedEmission;
        pm.model = m.model == PhongModel::Classic ? pn::PhongModel::Classic : pn::PhongModel::Normalized;
        if (!m.diffuseTexture.empty()) {
            auto it = std::find(s.textures.begin(), s.textures.end(), m.diffuseTexture);
            pm.diffuseTexture = int(it - s.textures.begin());
            if (it == s.textures.end()) s.textures.push_back(m.diffuseTexture);
        }
        s.materials.push_back(pm);
        return MaterialId(s.materials.size() - 1);
    });
}

void Scene::addSphere(const Vec3& center, float radius, MaterialId material) {
    guarded([&] {
        requireFinite(center, "sphere centre");
        require(std::isfinite(radius) && radius > 0.f, "sphere radius must be finite and > 0, got " +
                                                           std::to_string(radius));
        requireMaterial(impl_->scene, material, "sphere");
        impl_->scene.spheres.push_back(pn::Sphere{in(center), radius, material});
    });
}

void Scene::addPlane(const Vec3& point, const Vec3& normal, MaterialId material, bool twoSided) {
    guarded([&] {
        requireFinite(point, "plane point");
        requireDirection(normal, "plane normal");
        requireMaterial(impl_->scene, material, "plane");
        impl_->scene.planes.push_back(pn::Plane{in(point), pn::normalize(in(normal)), twoSided, material});
    });
}

void Scene::addBox(const Vec3& lo, const Vec3& hi, MaterialId material) { addBox(lo, hi, Matrix3x4{}, material); }

void Scene::addBox(const Vec3& lo, const Vec3& hi, const Matrix3x4& worldFromObject, MaterialId material) {
    guarded([&] {
        requireFinite(lo, "box lo");
        requireFinite(hi, "box hi");
        require(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z, "box lo " + str(lo) + " must be below hi " + str(hi) +
                                                               " on every axis");
        for (const auto& row : worldFromObject.m)
            for (float v : row) require(std::isfinite(v), "box transform must be finite");
        pn::Transform t = in(worldFromObject), inverse;
        require(t.inverse(inverse), "box transform is singular");
        requireMaterial(impl_->scene, material, "box");
        impl_->scene.boxes.push_back(pn::makeBox(in(lo), in(hi), t, material));
    });
}

void Scene::addRectangle(const Vec3& corner, const Vec3& edgeA, const Vec3& edgeB, MaterialId material) {
    guarded([&] {
        requireFinite(corner, "rectangle corner");
        requireDirection(edgeA, "rectangle edge a");
        requireDirection(edgeB, "rectangle edge b");
        require(pn::lengthSquared(pn::cross(in(edgeA), in(edgeB))) > 0.f, "rectangle edges must not be parallel");
        requireMaterial(impl_->scene, material, "rectangle");
        impl_->scene.rectangles.push_back(pn::Rectangle{in(corner), in(edgeA), in(edgeB), material});
    });
}

void Scene::addDisk(const Vec3& center, const Vec3& normal, float radius, MaterialId material) {
    guarded([&] {
        requireFinite(center, "disk centre");
        requireDirection(normal, "disk normal");
        require(std::isfinite(radius) && radius > 0.f, "disk radius must be finite and > 0, got " +
                                                           std::to_string(radius));
        requireMaterial(impl_->scene, material, "disk");
        impl_->scene.disks.push_back(pn::Disk{in(center), pn::normalize(in(normal)), radius, material});
    });
}

void Scene::addMesh(const MeshDesc& d) {
    guarded([&] {
        const std::string what = "mesh '" + d.name + "'";
        require(d.vertexCount > 0 && d.triangleCount > 0, what + ": needs at least one vertex and one triangle");
        require(d.positions != nullptr, what + ": positions are null");
        require(d.indices != nullptr, what + ": indices are null");
        require(d.vertexCount <= std::numeric_limits<uint32_t>::max() &&
                    d.triangleCount <= std::numeric_limits<uint32_t>::max() / 3,
                what + ": too many vertices or triangles for 32-bit indices");
        pn::Scene& s = impl_->scene;
        if (!d.faceMaterials) requireMaterial(s, d.material, what);

        pn::TriangleMesh mesh;
        mesh.name = d.name;
        mesh.material = d.material;
        mesh.positions.reserve(d.vertexCount);
        for (size_t i = 0; i < d.vertexCount; ++i) {
            const Vec3 p{d.positions[3 * i], d.positions[3 * i + 1], d.positions[3 * i + 2]};
            require(finite(p), what + ": vertex " + std::to_string(i) + " is not finite");
            mesh.positions.push_back(in(p));
        }
        mesh.indices.assign(d.indices, d.indices + 3 * d.triangleCount);
        for (size_t i = 0; i < mesh.indices.size(); ++i)
            require(mesh.indices[i] < d.vertexCount,
                    what + ": triangle " + std::to_string(i / 3) + " uses vertex " + std::to_string(mesh.indices[i]) +
                        ", but the mesh has " + std::to_string(d.vertexCount) + " vertices");
        if (d.normals) {
            mesh.normals.reserve(d.vertexCount);
            for (size_t i = 0; i < d.vertexCount; ++i) {
                const Vec3 n{d.normals[3 * i], d.normals[3 * i + 1], d.normals[3 * i + 2]};
                require(finite(n), what + ": normal " + std::to_string(i) + " is not finite");
                mesh.normals.push_back(in(n));
            }
        }
        if (d.uvs) {
            mesh.uvs.reserve(d.vertexCount);
            for (size_t i = 0; i < d.vertexCount; ++i) {
                const float u = d.uvs[2 * i], v = d.uvs[2 * i + 1];
                require(std::isfinite(u) && std::isfinite(v), what + ": uv " + std::to_string(i) + " is not finite");
                mesh.uvs.push_back(pn::Vec2f{u, v});
            }
        }
        if (d.faceMaterials) {
            mesh.faceMaterials.assign(d.faceMaterials, d.faceMaterials + d.triangleCount);
            for (size_t t = 0; t < d.triangleCount; ++t)
                requireMaterial(s, mesh.faceMaterials[t], what + ": triangle " + std::to_string(t));
        }
        s.meshes.push_back(std::move(mesh));
    });
}

void Scene::addMesh(const std::vector<float>& positions, const std::vector<std::uint32_t>& indices,
                    MaterialId material) {
    guarded([&] {
        require(positions.size() % 3 == 0, "mesh positions: " + std::to_string(positions.size()) +
                                               " floats is not a multiple of 3");
        require(indices.size() % 3 == 0, "mesh indices: " + std::to_string(indices.size()) +
                                             " indices is not a multiple of 3");
    });
    MeshDesc d;
    d.positions = positions.data();
    d.vertexCount = positions.size() / 3;
    d.indices = indices.data();
    d.triangleCount = indices.size() / 3;
    d.material = material;
    addMesh(d);
}

void Scene::addPointLight(const Vec3& position, const Color& intensity) {
    guarded([&] {
        requireFinite(position, "point light position");
        requireColor(intensity, "point light intensity");
        impl_->scene.pointLights.push_back(pn::PointLight{in(position), in(intensity)});
    });
}

void Scene::addDirectionalLight(const Vec3& direction, const Color& irradiance) {
    guarded([&] {
        requireDirection(direction, "directional light direction");
        requireColor(irradiance, "directional light irradiance");
        impl_->scene.directionalLights.push_back(pn::DirectionalLight{pn::normalize(in(direction)), in(irradiance)});
    });
}

void Scene::setAmbient(const Color& ambient) {
    guarded([&] {
        requireColor(ambient, "ambient light");
        impl_->scene.ambient = in(ambient);
    });
}

void Scene::setBackground(const Color& background) {
    guarded([&] {
        requireColor(background, "background");
        impl_->scene.background = in(background);
    });
}

void Scene::setCamera(const Camera& camera) {
    guarded([&] {
        pn::validateCamera(in(camera));
        impl_->camera = in(camera);
    });
}

std::optional<Camera> Scene::camera() const {
    if (!impl_->camera) return std::nullopt;
    return out(*impl_->camera);
}

Camera Scene::defaultCamera(float aspect, float vfovDegrees) const {
    return guarded([&] { return defaultCameraFor(impl_->camera, impl_->scene.bounds(), aspect, vfovDegrees); });
}

RenderSettings Scene::settings() const { return settingsFrom(impl_->settings); }
std::size_t Scene::materialCount() const { return impl_->scene.materials.size(); }
std::size_t Scene::primitiveCount() const { return impl_->scene.primitiveCount(); }
std::size_t Scene::triangleCount() const { return impl_->scene.triangleCount(); }

// ---------------------------------------------------------------- PreparedScene

PreparedScene::PreparedScene() = default;
PreparedScene::~PreparedScene() = default;
PreparedScene::PreparedScene(const PreparedScene&) = default;
PreparedScene& PreparedScene::operator=(const PreparedScene&) = default;
PreparedScene::PreparedScene(PreparedScene&&) noexcept = default;
PreparedScene& PreparedScene::operator=(PreparedScene&&) noexcept = default;

bool PreparedScene::valid() const noexcept { return impl_ != nullptr; }
std::size_t PreparedScene::primitiveCount() const { return requirePrepared(*this).prepared.scene().primitiveCount(); }
std::size_t PreparedScene::triangleCount() const { return requirePrepared(*this).prepared.scene().triangleCount(); }
std::size_t PreparedScene::lightCount() const { return requirePrepared(*this).prepared.lights().size(); }
std::size_t PreparedScene::droppedTriangles() const {
    return requirePrepared(*this).prepared.fixups().droppedTriangles;
}
std::size_t PreparedScene::droppedShapes() const { return requirePrepared(*this).prepared.fixups().droppedShapes; }
double PreparedScene::buildSeconds() const { return requirePrepared(*this).prepared.buildSeconds(); }

std::optional<Camera> PreparedScene::camera() const {
    const Impl& p = requirePrepared(*this);
    if (!p.camera) return std::nullopt;
    return out(*p.camera);
}

Camera PreparedScene::defaultCamera(float aspect, float vfovDegrees) const {
    const Impl& p = requirePrepared(*this);
    return guarded([&] { return defaultCameraFor(p.camera, p.prepared.scene().bounds(), aspect, vfovDegrees); });
}

RenderSettings PreparedScene::settings() const { return settingsFrom(requirePrepared(*this).settings); }

// ---------------------------------------------------------------- Framebuffer

Framebuffer::Framebuffer() : impl_(std::make_unique<Impl>()) {}

Framebuffer::Framebuffer(const RenderSettings& settings) {
    impl_ = guarded([&] {
        const pn::RenderSettings s = in(settings);
        pn::validateSettings(s);
        const pn::CropWindow w = windowOf(s);
        const uint64_t bytes = pn::Film::bytesNeeded(int64_t(w.x1 - w.x0) * (w.y1 - w.y0), s.aovs);
        const uint64_t ram = physicalMemoryBytes();
        if (ram && bytes > ram / 2)
            fail(ErrorCode::OutOfMemory, "a " + std::to_string(w.x1 - w.x0) + "x" + std::to_string(w.y1 - w.y0) +
                                             " framebuffer needs " + std::to_string(bytes >> 20) +
                                             " MiB, more than half of this machine's memory");
        auto impl = std::make_unique<Impl>();
        impl->film = pn::makeFilm(s);
        impl->seed = s.seed;
        return impl;
    });
}

Framebuffer::~Framebuffer() = default;
Framebuffer::Framebuffer(const Framebuffer& o) : impl_(guarded([&] { return std::make_unique<Impl>(*o.impl_); })) {}
Framebuffer& Framebuffer::operator=(const Framebuffer& o) {
    if (this != &o) impl_ = guarded([&] { return std::make_unique<Impl>(*o.impl_); });
    return *this;
}
Framebuffer::Framebuffer(Framebuffer&& o) noexcept : impl_(std::move(o.impl_)) {
    o.impl_ = std::unique_ptr<Impl>(new (std::nothrow) Impl());
}
Framebuffer& Framebuffer::operator=(Framebuffer&& o) noexcept {
    std::swap(impl_, o.impl_);
    return *this;
}

int Framebuffer::width() const noexcept { return impl_ ? impl_->film.width() : 0; }
int Framebuffer::height() const noexcept { return impl_ ? impl_->film.height() : 0; }
int Framebuffer::fullWidth() const noexcept { return impl_ ? impl_->film.fullWidth() : 0; }
int Framebuffer::fullHeight() const noexcept { return impl_ ? impl_->film.fullHeight() : 0; }
CropWindow Framebuffer::window() const noexcept {
    if (!impl_) return {};
    const pn::CropWindow& w = impl_->film.window();
    return CropWindow{w.x0, w.y0, w.x1, w.y1};
}
std::uint32_t Framebuffer::sampleCount() const noexcept { return impl_ ? impl_->film.sampleCount() : 0; }
bool Framebuffer::hasAovs() const noexcept { return impl_ && impl_->film.hasAovs(); }
bool Framebuffer::incomplete() const noexcept { return impl_ && impl_->incomplete; }

std::vector<float> Framebuffer::rgba() const {
    return guarded([&] { return impl_->film.radianceBuffer(4); });
}

void Framebuffer::readRgba(float* dst, std::size_t floatCount) const {
    guarded([&] {
        const pn::Film& f = impl_->film;
        const size_t n = size_t(f.width()) * size_t(f.height());
        require(floatCount >= 4 * n, "readRgba: destination holds " + std::to_string(floatCount) +
                                         " floats, the image needs " + std::to_string(4 * n));
        require(dst != nullptr || n == 0, "readRgba: destination is null");
        for (size_t i = 0; i < n; ++i) {
            const pn::Rgb L = f.radiance(i);
            dst[4 * i] = L.r;
            dst[4 * i + 1] = L.g;
            dst[4 * i + 2] = L.b;
            dst[4 * i + 3] = 1.f;
        }
    });
}

std::vector<float> Framebuffer::albedo() const {
    return guarded([&] {
        const pn::Film& f = impl_->film;
        require(f.hasAovs(), "albedo: the framebuffer has no AOVs (set RenderSettings::aovs)");
        const size_t n = size_t(f.width()) * size_t(f.height());
        std::vector<float> v(3 * n);
        for (size_t i = 0; i < n; ++i) {
            const pn::Rgb a = f.albedo(i);
            v[3 * i] = a.r;
            v[3 * i + 1] = a.g;
            v[3 * i + 2] = a.b;
        }
        return v;
    });
}

std::vector<float> Framebuffer::normals() const {
    return guarded([&] {
        const pn::Film& f = impl_->film;
        require(f.hasAovs(), "normals: the framebuffer has no AOVs (set RenderSettings::aovs)");
        const size_t n = size_t(f.width()) * size_t(f.height());
        std::vector<float> v(3 * n);
        for (size_t i = 0; i < n; ++i) {
            const pn::Vec3f nn = f.normal(i);
            v[3 * i] = nn.x;
            v[3 * i + 1] = nn.y;
            v[3 * i + 2] = nn.z;
        }
        return v;
    });
}

std::vector<float> Framebuffer::depth() const {
    return guarded([&] {
        const pn::Film& f = impl_->film;
        require(f.hasAovs(), "depth: the framebuffer has no AOVs (set RenderSettings::aovs)");
        const size_t n = size_t(f.width()) * size_t(f.height());
        std::vector<float> v(n);
        for (size_t i = 0; i < n; ++i) v[i] = f.depth(i);
        return v;
    });
}

void Framebuffer::readAlbedo(float* dst, std::size_t floatCount) const {
    const std::vector<float> v = albedo();
    guarded([&] { copyInto(v, dst, floatCount, "readAlbedo"); });
}
void Framebuffer::readNormals(float* dst, std::size_t floatCount) const {
    const std::vector<float> v = normals();
    guarded([&] { copyInto(v, dst, floatCount, "readNormals"); });
}
void Framebuffer::readDepth(float* dst, std::size_t floatCount) const {
    const std::vector<float> v = depth();
    guarded([&] { copyInto(v, dst, floatCount, "readDepth"); });
}

Color Framebuffer::pixel(int x, int y) const {
    return guarded([&] {
        const pn::Film& f = impl_->film;
        require(x >= 0 && y >= 0 && x < f.width() && y < f.height(),
                "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") lies outside the " +
                    std::to_string(f.width()) + "x" + std::to_string(f.height()) + " framebuffer");
        return out(f.radiance(size_t(y) * size_t(f.width()) + size_t(x)));
    });
}

void Framebuffer::clear() {
    impl_->film.clear();
    impl_->incomplete = false;
    impl_->renderSeconds = 0.0;
}

void Framebuffer::writeImage(const std::string& path, const ImageOptions& options) const {
    guarded([&] {
        require(impl_->film.width() > 0, path + ": cannot write an empty framebuffer");
        require(std::isfinite(options.exposure), path + ": exposure must be finite");
        pn::ImageWriteOptions wo;
        wo.exposure = options.exposure;
        wo.aovs = options.aovs;
        wo.metadata = pn::ImageMetadata{int(impl_->film.sampleCount()), impl_->seed, impl_->renderSeconds,
                                        std::string("Penumbra ") + PENUMBRA_VERSION};
        pn::writeImage(path, impl_->film, wo);
    });
}

// ---------------------------------------------------------------- RenderJob

RenderJob::RenderJob() = default;
RenderJob::~RenderJob() = default;
RenderJob::RenderJob(RenderJob&&) noexcept = default;
RenderJob& RenderJob::operator=(RenderJob&&) noexcept = default;

double RenderJob::progress() const noexcept { return impl_ ? impl_->state->progress.load() : 0.0; }
void RenderJob::cancel() noexcept {
    if (impl_) impl_->state->cancel.store(true);
}
bool RenderJob::done() const noexcept { return !impl_ || impl_->state->done.load(); }

void RenderJob::wait() const {
    if (!impl_) return;
    JobState& s = *impl_->state;
    std::unique_lock<std::mutex> lock(s.mutex);
    s.finished.wait(lock, [&] { return s.done.load(); });
}

bool RenderJob::waitFor(std::chrono::milliseconds timeout) const {
    if (!impl_) return true;
    JobState& s = *impl_->state;
    std::unique_lock<std::mutex> lock(s.mutex);
    return s.finished.wait_for(lock, timeout, [&] { return s.done.load(); });
}

JobStatus RenderJob::status() const noexcept { return impl_ ? impl_->state->status.load() : JobStatus::Failed; }

std::optional<Error> RenderJob::error() const {
    if (!impl_) return Error(ErrorCode::InvalidArgument, "empty render job");
    wait();
    return impl_->state->error;
}

RenderStats RenderJob::stats() const {
    if (!impl_) return {};
    wait();
    return impl_->state->stats;
}

const Framebuffer& RenderJob::framebuffer() const {
    require(impl_ != nullptr, "empty render job");
    wait();
    const JobState& s = *impl_->state;
    if (s.error) throw *s.error;
    return s.image;
}

Framebuffer RenderJob::takeFramebuffer() {
    framebuffer();  // waits, throws the job's error
    return std::move(impl_->state->image);
}

// ---------------------------------------------------------------- Renderer

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::Renderer(LogCallback log, LogLevel minLevel) : impl_(std::make_unique<Impl>()) {
    setLog(std::move(log), minLevel);
}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&& o) noexcept : impl_(std::move(o.impl_)) {
    o.impl_ = std::unique_ptr<Impl>(new (std::nothrow) Impl());
}
Renderer& Renderer::operator=(Renderer&& o) noexcept {
    std::swap(impl_, o.impl_);
    return *this;
}

void Renderer::setLog(LogCallback log, LogLevel minLevel) {
    const auto level = static_cast<pn::LogLevel>(static_cast<int>(minLevel));
    if (log) {
        impl_->log = pn::Logger(
            [cb = std::move(log)](pn::LogLevel l, std::string_view m) { cb(static_cast<LogLevel>(int(l)), m); },
            level);
    } else {
        impl_->log = pn::Logger();
        impl_->log.setMinLevel(level);
    }
}

Scene Renderer::loadScene(const std::string& path, const LoadOptions& options) const {
    return guarded([&] {
        require(!path.empty(), "scene path is empty");
        pn::LoadOptions lo;
        lo.strict = options.strict;
        if (options.restrictPaths) {
            // The scene's own folder, so its MTL files, textures and meshes stay readable.
            lo.allowedRoots.push_back(fs::absolute(fs::path(path)).parent_path());
            for (const std::string& root : options.allowedRoots) {
                require(!root.empty(), "allowed root is empty");
                lo.allowedRoots.push_back(fs::absolute(fs::path(root)));
            }
        }
        pn::LoadedScene loaded = pn::loadScene(path, lo, impl_->log);
        Scene scene;
        SceneImpl& s = Access::of(scene);
        s.scene = std::move(loaded.scene);
        s.camera = loaded.camera;
        s.settings = loaded.settings;
        return scene;
    });
}

PreparedScene Renderer::prepare(const Scene& scene, const PrepareOptions& options) const {
    return prepare(Scene(scene), options);
}

PreparedScene Renderer::prepare(Scene&& scene, const PrepareOptions& options) const {
    return guarded([&] {
        SceneImpl& s = Access::of(scene);
        pn::PrepareOptions po;
        po.accelerator = options.accelerator;
        po.quality = options.quality == BuildQuality::Low      ? pn::BuildQuality::Low
                     : options.quality == BuildQuality::Medium ? pn::BuildQuality::Medium
                                                               : pn::BuildQuality::High;
        auto impl =
            std::make_shared<const PreparedImpl>(std::move(s.scene), po, impl_->log, s.camera, s.settings);
        s = SceneImpl{};  // the moved-from scene is empty, not half-moved
        PreparedScene p;
        Access::set(p, std::move(impl));
        return p;
    });
}

Framebuffer Renderer::render(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                             const RenderControl& control) const {
    Framebuffer image(settings);
    render(scene, camera, settings, image, control);
    return image;
}

RenderStats Renderer::render(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                             Framebuffer& image, const RenderControl& control) const {
    return guarded([&] {
        pn::validateSettings(in(settings));
        const uint32_t have = image.sampleCount();
        require(have <= uint32_t(settings.spp),
                "the framebuffer already holds " + std::to_string(have) + " samples per pixel, spp is " +
                    std::to_string(settings.spp));
        return renderPass(scene, camera, settings, image, have, uint32_t(settings.spp) - have, control);
    });
}

RenderStats Renderer::render(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                             float* rgba, std::size_t floatCount, const RenderControl& control) const {
    return guarded([&] {
        const pn::RenderSettings s = in(settings);
        pn::validateSettings(s);
        const pn::CropWindow w = windowOf(s);
        const size_t needed = 4 * size_t(w.x1 - w.x0) * size_t(w.y1 - w.y0);
        require(rgba != nullptr, "render: destination is null");
        require(floatCount >= needed, "render: destination holds " + std::to_string(floatCount) +
                                          " floats, the image needs " + std::to_string(needed));
        Framebuffer image(settings);
        RenderStats st = render(scene, camera, settings, image, control);
        image.readRgba(rgba, floatCount);
        return st;
    });
}

RenderStats Renderer::renderPass(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                                 Framebuffer& image, std::uint32_t firstSample, std::uint32_t sampleCount,
                                 const RenderControl& control) const {
    return guarded([&] {
        const PreparedImpl& p = requirePrepared(scene);
        const pn::RenderSettings s = in(settings);
        checkCameraAndSettings(camera, s);
        return runPass(p, in(camera), s, Access::of(image), firstSample, sampleCount, control.progress,
                       control.cancel);
    });
}

RenderJob Renderer::renderAsync(const PreparedScene& scene, const Camera& camera, const RenderSettings& settings,
                                AsyncOptions options) const {
    return guarded([&] {
        requirePrepared(scene);
        const pn::RenderSettings s = in(settings);
        checkCameraAndSettings(camera, s);
        auto state = std::make_shared<JobState>();
        state->image = Framebuffer(settings);

        auto work = [state, scene, cam = in(camera), s, opts = std::move(options)]() {
            JobResult result;
            const uint32_t spp = uint32_t(s.spp);
            const uint32_t step = opts.passSamples > 0 ? std::min(opts.passSamples, spp) : spp;
            try {
                guarded([&] {
                    const PreparedImpl& p = *Access::of(scene);
                    FramebufferImpl& fb = Access::of(state->image);
                    for (uint32_t first = 0; first < spp; first += step) {
                        if (state->cancel.load())
                            fail(ErrorCode::Cancelled, "render cancelled after " + std::to_string(first) +
                                                           " samples per pixel");
                        const uint32_t count = std::min(step, spp - first);
                        auto progress = [&](double f) {
                            const double done = (double(first) + f * double(count)) / double(spp);
                            state->progress.store(done);
                            if (opts.progress) opts.progress(done);
                        };
                        accumulate(result.stats, runPass(p, cam, s, fb, first, count, progress, &state->cancel));
                        if (opts.onPass) opts.onPass(state->image, first + count);
                    }
                });
                result.status = JobStatus::Finished;
                state->progress.store(1.0);
            } catch (const Error& e) {
                result.status = e.code() == ErrorCode::Cancelled ? JobStatus::Cancelled : JobStatus::Failed;
                result.error = e;
            }
            result.framebuffer = result.status == JobStatus::Finished ? &state->image : nullptr;
            if (opts.onComplete) {
                try {
                    opts.onComplete(result);
                } catch (...) {
                    // A throwing completion callback must not take the process down
                    // (std::terminate on this thread); the job's outcome stands.
                }
            }
            std::lock_guard<std::mutex> lock(state->mutex);
            state->error = result.error;
            state->stats = result.stats;
            state->status.store(result.status);
            state->done.store(true);
            state->finished.notify_all();
        };

        auto impl = std::make_unique<JobImpl>();
        impl->state = state;
        impl->thread = std::thread(std::move(work));
        RenderJob job;
        Access::set(job, std::move(impl));
        return job;
    });
}

}  // namespace pnb
