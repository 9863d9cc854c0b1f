// pnb::Scene: a scene built in code, every value checked as it is added.
#include "api/api_internal.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/io/input_file.h"

namespace pnb {

namespace {

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

// A MeshDesc checked and copied (addMesh, addPrototypeMesh).
pn::TriangleMesh meshFrom(const pn::Scene& s, const MeshDesc& d) {
    const std::string what = "mesh '" + d.name + "'";
    require(d.vertexCount > 0 && d.triangleCount > 0, what + ": needs at least one vertex and one triangle");
    require(d.positions != nullptr, what + ": positions are null");
    require(d.indices != nullptr, what + ": indices are null");
    require(d.vertexCount <= std::numeric_limits<uint32_t>::max() &&
                d.triangleCount <= std::numeric_limits<uint32_t>::max() / 3,
            what + ": too many vertices or triangles for 32-bit indices");
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
    return mesh;
}

}  // namespace

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

pn::Material checkedMaterial(const Material& m, const TextureBinder& texture) {
    const std::string what = "material '" + m.name + "'";
    requireColor(m.ka, what + ": ka");
    requireColor(m.kd, what + ": kd");
    requireColor(m.ks, what + ": ks");
    requireColor(m.kr, what + ": kr");
    requireColor(m.ke, what + ": ke");
    require(std::isfinite(m.exponent) && m.exponent >= 0.f, what + ": exponent must be finite and >= 0");
    requireColor(m.kt, what + ": kt");
    require(std::isfinite(m.ior) && m.ior > 0.f, what + ": ior must be finite and > 0");
    if (auto problem = pn::materialProblem(m)) fail(ErrorCode::InvalidArgument, what + ": " + *problem);
    pn::Material pm{m};
    // Transmission is the smooth dielectric's (core/material.h), as loaders make it.
    if (pm.kind == MaterialKind::MetalRoughness) pn::mapTransmissionOntoGlass(pm);
    pn::bindTextures(pm, texture);
    return pm;
}

MaterialId Scene::addMaterial(const Material& m) {
    return guarded([&] {
        pn::Scene& s = impl_->scene;
        // Named in code: opened by name, once, when the scene is prepared.
        pn::Material pm = checkedMaterial(m, [&](std::string& path, pn::TextureColorSpace space) {
            return s.addTexture(pn::TextureSource{path, space});
        });
        require(s.materials.size() < std::numeric_limits<MaterialId>::max(), "too many materials");
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
    guarded([&] { impl_->scene.meshes.push_back(meshFrom(impl_->scene, d)); });
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
        pn::validateCamera(camera);
        impl_->camera = camera;
    });
}

std::optional<Camera> Scene::camera() const {
    if (!impl_->camera) return std::nullopt;
    return *impl_->camera;
}

Camera Scene::defaultCamera(float aspect, float vfovDegrees) const {
    return guarded([&] { return defaultCameraFor(impl_->camera, impl_->scene.bounds(), aspect, vfovDegrees); });
}

RenderSettings Scene::settings() const { return settingsFrom(impl_->settings); }
std::size_t Scene::materialCount() const { return impl_->scene.materials.size(); }
std::size_t Scene::primitiveCount() const { return impl_->scene.primitiveCount(); }
std::size_t Scene::triangleCount() const { return impl_->scene.triangleCount(); }

PrototypeId Scene::addPrototype(const std::string& name) {
    return guarded([&] {
        pn::Scene& s = impl_->scene;
        require(s.prototypes.size() < std::numeric_limits<PrototypeId>::max(), "too many prototypes");
        s.prototypes.push_back(pn::Prototype{name, {}});
        return PrototypeId(s.prototypes.size() - 1);
    });
}

namespace {
void requirePrototype(const pn::Scene& s, PrototypeId id, const char* what) {
    require(id < s.prototypes.size(), std::string(what) + ": prototype id " + std::to_string(id) +
                                          " does not exist (the scene has " + std::to_string(s.prototypes.size()) +
                                          " prototypes)");
}
}  // namespace

void Scene::addPrototypeMesh(PrototypeId prototype, const MeshDesc& d) {
    guarded([&] {
        pn::Scene& s = impl_->scene;
        requirePrototype(s, prototype, "addPrototypeMesh");
        pn::TriangleMesh mesh = meshFrom(s, d);
        s.prototypes[prototype].meshes.push_back(std::move(mesh));
    });
}

std::size_t Scene::addInstance(PrototypeId prototype, const Matrix3x4& worldFromObject,
                              std::optional<MaterialId> material) {
    return guarded([&] {
        pn::Scene& s = impl_->scene;
        requirePrototype(s, prototype, "addInstance");
        for (const auto& row : worldFromObject.m)
            for (float v : row) require(std::isfinite(v), "instance transform must be finite");
        const pn::Transform t = in(worldFromObject);
        pn::Transform inverse;
        require(std::isfinite(t.determinant()) && t.inverse(inverse), "instance transform is singular");
        if (material) requireMaterial(s, *material, "instance");
        s.instances.push_back(pn::makeInstance(prototype, t, material ? *material : pn::kNoMaterialOverride));
        return s.instances.size() - 1;
    });
}

std::size_t Scene::prototypeCount() const { return impl_->scene.prototypes.size(); }
std::size_t Scene::instanceCount() const { return impl_->scene.instances.size(); }
void Scene::setEnvironment(const Color& radiance, float scale) {
    guarded([&] {
        requireColor(radiance, "environment radiance");
        require(std::isfinite(scale) && scale >= 0.f, "environment scale must be finite and >= 0");
        pn::EnvironmentDesc env;
        env.color = in(radiance);
        env.scale = scale;
        impl_->scene.environment = std::move(env);
    });
}

void Scene::setEnvironmentImage(const std::string& path, float rotateDegrees, float scale) {
    guarded([&] {
        require(!path.empty(), "environment image path is empty");
        require(std::isfinite(rotateDegrees), path + ": environment rotation must be finite");
        require(std::isfinite(scale) && scale >= 0.f, path + ": environment scale must be finite and >= 0");
        pn::EnvironmentDesc env;
        // Opened now, once: prepare() decodes this descriptor, never the path again.
        env.imageFile = pn::openInputFile(path, pn::LoadOptions{}, ErrorCode::IoError);
        env.image = path;
        env.rotateDegrees = rotateDegrees;
        env.scale = scale;
        impl_->scene.environment = std::move(env);
    });
}

void Scene::clearEnvironment() { impl_->scene.environment.reset(); }
bool Scene::hasEnvironment() const { return impl_->scene.environment.has_value(); }
void Scene::setDefaultLight(bool enabled) { impl_->scene.defaultLight = enabled; }
bool Scene::defaultLight() const { return impl_->scene.defaultLight; }

}  // namespace pnb
