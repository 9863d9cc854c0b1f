#include "lights/light_set.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/error.h"
#include "lights/area_light.h"
#include "lights/delta_lights.h"
#include "lights/environment_light.h"

namespace penumbra {

namespace {

// One area light per emissive shape of one kind, in the shapes' order;
// index[i]: the light of shape i (-1: it emits nothing).
template <class Shape>
void addShapeLights(const Scene& scene, const std::vector<Shape>& shapes, ShapeAreaLight::Kind kind,
                    std::vector<std::unique_ptr<Light>>& lights, std::vector<int32_t>& index, float& totalArea) {
    index.assign(shapes.size(), -1);
    for (uint32_t i = 0; i < shapes.size(); ++i) {
        if (!scene.materials[shapes[i].material].isEmissive()) continue;
        index[i] = int32_t(lights.size());
        auto l = std::make_unique<ShapeAreaLight>(scene, kind, i);
        totalArea += l->area();
        lights.push_back(std::move(l));
    }
}

}  // namespace

LightSet::LightSet(const Scene& scene, RgbImage environmentImage, const TextureCache* textures)
    : scene_(scene), textures_(textures) {
    // Area lights first (rectangles, disks, spheres, then each mesh's emissive
    // materials), then point, directional and environment lights.
    addShapeLights(scene, scene.rectangles, ShapeAreaLight::Kind::Rectangle, lights_, rectangleLight_, totalArea_);
    addShapeLights(scene, scene.disks, ShapeAreaLight::Kind::Disk, lights_, diskLight_, totalArea_);
    addShapeLights(scene, scene.spheres, ShapeAreaLight::Kind::Sphere, lights_, sphereLight_, totalArea_);
    addMeshLights();
    areaLights_ = lights_.size();
    addEmitterBounds();
    addDeltaAndEnvironmentLights(std::move(environmentImage));
    std::vector<double> powers;
    for (const auto& l : lights_) powers.push_back(l->power());
    powerPicker_ = std::make_unique<PowerLightPicker>(powers);
    std::vector<std::optional<LightBounds>> lightBounds;
    for (const auto& l : lights_) lightBounds.push_back(l->bounds());
    bvhPicker_ = std::make_unique<BVHLightPicker>(lightBounds, powers);
}

void LightSet::addMeshLights() {
    meshLights_.resize(scene_.meshes.size());
    for (uint32_t m = 0; m < scene_.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene_.meshes[m];
        std::map<uint32_t, std::vector<uint32_t>> byMaterial;  // ordered: deterministic light order
        for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
            uint32_t mat = mesh.materialOf(t);
            if (!scene_.materials[mat].isEmissive()) continue;
            Vec3f p0, p1, p2;
            mesh.vertices(t, p0, p1, p2);
            if (triangleArea(p0, p1, p2) > 0.f) byMaterial[mat].push_back(t);
        }
        for (auto& [mat, tris] : byMaterial) {
            auto l = std::make_unique<MeshAreaLight>(scene_, m, mat, std::move(tris), textures_);
            if (!(l->area() > 0.f)) continue;
            meshLights_[m].emplace_back(mat, uint32_t(lights_.size()));
            totalArea_ += l->area();
            lights_.push_back(std::move(l));
        }
    }
}

void LightSet::addEmitterBounds() {
    // Bounding spheres of the area lights, in the order they were added, and
    // each light's primitives (for firstEmitterHit): a mesh light is every
    // triangle of its material, as lightOf() counts them (degenerate ones
    // too: no ray meets them).
    const auto addLight = [&](const Vec3f& center, float radius2, std::initializer_list<PrimRef> prims) {
        bounds_.push_back({center, radius2});
        emitters_.push_back({uint32_t(emitterPrims_.size()), uint32_t(prims.size())});
        emitterPrims_.insert(emitterPrims_.end(), prims);
    };
    const auto addBounded = [&](const Bounds3f& b, PrimRef prim) {
        addLight(b.center(), 0.25f * lengthSquared(b.diagonal()), {prim});
    };
    const Scene& scene = scene_;
    for (uint32_t i = 0; i < scene.rectangles.size(); ++i)
        if (rectangleLight_[i] >= 0)
            addBounded(penumbra::bounds(scene.rectangles[i]), PrimRef{ShapeKind::Rectangle, i, 0, 0});
    for (uint32_t i = 0; i < scene.disks.size(); ++i)
        if (diskLight_[i] >= 0) addBounded(penumbra::bounds(scene.disks[i]), PrimRef{ShapeKind::Disk, i, 0, 0});
    for (uint32_t i = 0; i < scene.spheres.size(); ++i)
        if (sphereLight_[i] >= 0)
            addLight(scene.spheres[i].center, scene.spheres[i].radius * scene.spheres[i].radius,
                     {PrimRef{ShapeKind::Sphere, i, 0, 0}});
    for (uint32_t m = 0; m < scene.meshes.size(); ++m)
        for (const auto& entry : meshLights_[m]) {
            const uint32_t mat = entry.first;
            Bounds3f b;
            const TriangleMesh& mesh = scene.meshes[m];
            const uint32_t first = uint32_t(emitterPrims_.size());
            for (uint32_t t = 0; t < mesh.triangleCount(); ++t)
                if (mesh.materialOf(t) == mat) {
                    Vec3f p0, p1, p2;
                    mesh.vertices(t, p0, p1, p2);
                    b.extend(p0);
                    b.extend(p1);
                    b.extend(p2);
                    emitterPrims_.push_back(PrimRef{ShapeKind::Mesh, m, t, 0});
                }
            bounds_.push_back({b.center(), 0.25f * lengthSquared(b.diagonal())});
            emitters_.push_back({first, uint32_t(emitterPrims_.size()) - first});
        }
}

void LightSet::addDeltaAndEnvironmentLights(RgbImage environmentImage) {
    const Scene& scene = scene_;
    const Bounds3f b = scene.bounds();
    const float radius = b.empty() ? 1.f : 0.5f * length(b.diagonal());
    bounds_.resize(lights_.size() + scene.pointLights.size() + scene.directionalLights.size());
    for (const auto& p : scene.pointLights) lights_.push_back(std::make_unique<PointLightSource>(p));
    for (const auto& d : scene.directionalLights) lights_.push_back(std::make_unique<DirectionalLightSource>(d, radius));
    if (!scene.environment) return;
    const EnvironmentDesc& e = *scene.environment;
    std::unique_ptr<EnvironmentLight> env;
    if (e.image.empty()) {
        env = std::make_unique<EnvironmentLight>(e.color * e.scale, radius);
    } else {
        if (environmentImage.pixels.empty())
            throw Error(ErrorCode::InvalidArgument, e.image + ": environment image was not decoded");
        env = std::make_unique<EnvironmentLight>(std::move(environmentImage), e.scale, e.rotateDegrees, radius);
    }
    environment_ = env.get();
    lights_.push_back(std::move(env));
}

LightSet::~LightSet() = default;

std::optional<LightSet::EmitterHit> LightSet::firstEmitterHit(const Ray& ray) const {
    Ray r = ray;  // shrinks to the closest hit so far, as in the naive accelerator
    std::optional<EmitterHit> best;
    const float dd = dot(ray.d, ray.d);
    for (size_t light = 0; light < emitters_.size(); ++light) {
        // The light's bounding sphere first (most rays pass every light by):
        // skip where the ray's line passes farther from its centre than its
        // radius, or where it lies wholly behind the origin, each by a margin
        // of 1e-6 of the centre's distance, above the rounding of these few
        // operations (so no ray that meets the light is skipped).
        const BoundingSphere& bound = bounds_[light];
        const Vec3f oc = bound.center - ray.o;
        const float along = dot(oc, ray.d) / dd;
        const Vec3f off = oc - along * ray.d;
        const float reach =
            std::sqrt(bound.radius2) + 1e-6f * (std::fabs(oc.x) + std::fabs(oc.y) + std::fabs(oc.z));
        if (dot(off, off) > reach * reach || along * std::sqrt(dd) < -reach) continue;
        const EmitterRange& range = emitters_[light];
        for (uint32_t k = range.first; k < range.first + range.count; ++k) {
            const PrimRef& ref = emitterPrims_[k];
            std::optional<PrimHit> h;
            switch (ref.kind) {
                case ShapeKind::Rectangle: h = intersect(scene_.rectangles[ref.object], r); break;
                case ShapeKind::Disk: h = intersect(scene_.disks[ref.object], r); break;
                case ShapeKind::Sphere: h = intersect(scene_.spheres[ref.object], r); break;
                case ShapeKind::Mesh: {
                    Vec3f p0, p1, p2;
                    scene_.meshes[ref.object].vertices(ref.prim, p0, p1, p2);
                    h = intersectTriangle(p0, p1, p2, r);
                    break;
                }
                default: break;
            }
            if (!h) continue;
            r.tfar = h->t;
            best = EmitterHit{light, ref, *h};
        }
    }
    return best;
}

std::optional<size_t> LightSet::lightOf(const Hit& hit) const {
    const auto found = [](const std::vector<int32_t>& v, uint32_t i) -> std::optional<size_t> {
        if (i < v.size() && v[i] >= 0) return size_t(v[i]);
        return std::nullopt;
    };
    switch (hit.ref.kind) {
        case ShapeKind::Rectangle: return found(rectangleLight_, hit.ref.object);
        case ShapeKind::Disk: return found(diskLight_, hit.ref.object);
        case ShapeKind::Sphere: return found(sphereLight_, hit.ref.object);
        case ShapeKind::Mesh:
            if (hit.ref.object < meshLights_.size())
                for (const auto& [mat, light] : meshLights_[hit.ref.object])
                    if (mat == hit.material) return size_t(light);
            return std::nullopt;
        default: return std::nullopt;
    }
}

}  // namespace penumbra
