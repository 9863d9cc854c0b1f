#include "core/scene.h"

#include <algorithm>
#include <optional>
#include <string>

#include "core/lane_clones.h"
#include "core/mesh_convexity.h"
#include "core/mesh_tangents.h"
#include "core/scene_range.h"

namespace penumbra {
namespace {

template <class T, class Pred>
size_t eraseIf(std::vector<T>& v, Pred bad) {
    size_t before = v.size();
    v.erase(std::remove_if(v.begin(), v.end(), bad), v.end());
    return before - v.size();
}

// Drops the bad triangles of one mesh; returns how many were dropped.
size_t repairMesh(TriangleMesh& m, const Logger& log) {
    const size_t nv = m.positions.size();
    const size_t nt = m.triangleCount();
    if (m.indices.size() % 3 != 0) m.indices.resize(nt * 3);
    if (!m.faceMaterials.empty() && m.faceMaterials.size() != nt) {
        log.warn("mesh '" + m.name + "': per-face material count does not match the triangles; using one material");
        m.faceMaterials.clear();
    }
    // Per-vertex arrays of another length than the positions are dropped.
    auto perVertex = [&](auto& values, const std::string& what) {
        if (values.empty() || values.size() == nv) return;
        log.warn("mesh '" + m.name + "': " + what);
        values.clear();
    };
    perVertex(m.normals, "normal count does not match the vertices; using geometric normals");
    perVertex(m.uvs, "UV count does not match the vertices; ignoring UVs");
    perVertex(m.uvs1, "second UV set's count does not match the vertices; ignoring it");
    perVertex(m.tangents, "tangent count does not match the vertices; ignoring the tangents");
    for (auto& n : m.normals)
        if (!isFinite(n)) n = Vec3f{};  // completeHit falls back to the geometric normal

    size_t kept = 0;
    for (size_t t = 0; t < nt; ++t) {
        uint32_t i0 = m.indices[3 * t], i1 = m.indices[3 * t + 1], i2 = m.indices[3 * t + 2];
        bool ok = i0 < nv && i1 < nv && i2 < nv;
        if (ok) {
            const Vec3f &p0 = m.positions[i0], &p1 = m.positions[i1], &p2 = m.positions[i2];
            ok = isFinite(p0) && isFinite(p1) && isFinite(p2) && lengthSquared(cross(p1 - p0, p2 - p0)) > 0.f;
        }
        if (!ok) continue;
        if (kept != t) {
            m.indices[3 * kept] = i0;
            m.indices[3 * kept + 1] = i1;
            m.indices[3 * kept + 2] = i2;
            if (!m.faceMaterials.empty()) m.faceMaterials[kept] = m.faceMaterials[t];
        }
        ++kept;
    }
    m.indices.resize(kept * 3);
    if (!m.faceMaterials.empty()) m.faceMaterials.resize(kept);
    return nt - kept;
}

// Drops the instances no accelerator can place: an unknown prototype, a
// non-finite or singular transform; refreshes the others' inverses.
size_t dropBadInstances(std::vector<Instance>& instances, size_t prototypeCount) {
    const size_t dropped = eraseIf(instances, [&](const Instance& in) {
        return in.prototype >= prototypeCount || !placeable(in.worldFromObject);
    });
    for (auto& in : instances) in.worldFromObject.inverse(in.objectFromWorld);
    return dropped;
}

// The rule of core/instance.h: an instance that would emit light becomes
// ordinary meshes, so the light set sees each copy as an area light.
void expandEmissiveInstances(Scene& s) {
    eraseIf(s.instances, [&](const Instance& in) {
        if (!s.expandsInstance(in)) return false;
        appendPlacedCopies(s.prototypes[in.prototype], in.worldFromObject, in.material, s.meshes);
        return true;
    });
}

// Drops the analytic shapes whose parameters are non-finite or degenerate
// (normalising the rest's normals, building boxes' frames); returns how many.
size_t dropBadShapes(Scene& scene) {
    size_t dropped = 0;
    dropped += eraseIf(scene.spheres, [](const Sphere& s) {
        return !isFinite(s.center) || !std::isfinite(s.radius) || !(s.radius > 0.f);
    });
    dropped += eraseIf(scene.planes, [](const Plane& p) {
        return !isFinite(p.point) || !isFinite(p.normal) || !(lengthSquared(p.normal) > 0.f);
    });
    for (auto& p : scene.planes) p.normal = normalize(p.normal);
    dropped += eraseIf(scene.boxes, [](const Box& b) {
        Transform inv;
        return !isFinite(b.lo) || !isFinite(b.hi) || b.lo.x > b.hi.x || b.lo.y > b.hi.y || b.lo.z > b.hi.z ||
               !finiteTransform(b.worldFromObject) || !b.worldFromObject.inverse(inv);
    });
    for (auto& b : scene.boxes) b = makeBox(b.lo, b.hi, b.worldFromObject, b.material);
    dropped += eraseIf(scene.rectangles, [](const Rectangle& q) {
        return !isFinite(q.p0) || !isFinite(q.a) || !isFinite(q.b) || !(area(q) > 0.f);
    });
    dropped += eraseIf(scene.disks, [](const Disk& d) {
        return !isFinite(d.center) || !isFinite(d.normal) || !(lengthSquared(d.normal) > 0.f) ||
               !std::isfinite(d.radius) || !(d.radius > 0.f);
    });
    for (auto& d : scene.disks) d.normal = normalize(d.normal);
    return dropped;
}

// Material ids out of range fall back to material 0, texture references out
// of range to none; returns how many material ids fell back.
size_t fixMaterialReferences(Scene& s, std::vector<uint8_t>& uvNeeded) {
    size_t badIds = 0;
    const uint32_t nm = static_cast<uint32_t>(s.materials.size());
    auto fixId = [&](uint32_t& id) {
        if (id >= nm) {
            id = 0;
            ++badIds;
        }
    };
    for (auto& x : s.spheres) fixId(x.material);
    for (auto& x : s.planes) fixId(x.material);
    for (auto& x : s.boxes) fixId(x.material);
    for (auto& x : s.rectangles) fixId(x.material);
    for (auto& x : s.disks) fixId(x.material);
    for (auto& m : s.meshes) {
        fixId(m.material);
        for (auto& id : m.faceMaterials) fixId(id);
    }
    for (auto& p : s.prototypes) {
        for (auto& m : p.meshes) {
            fixId(m.material);
            for (auto& id : m.faceMaterials) fixId(id);
        }
    }
    for (auto& in : s.instances)
        if (in.material != kNoMaterialOverride) fixId(in.material);
    const int nt = static_cast<int>(s.textures.size());
    uvNeeded.clear();
    for (auto& m : s.materials) {
        if (m.textureIndex >= nt) m.textureIndex = -1;
        for (TextureRef* r : {&m.baseColorMap, &m.metallicMap, &m.roughnessMap, &m.transmissionMap, &m.normalMap,
                              &m.emissiveMap, &m.opacityMap})
            if (r->texture >= nt) *r = TextureRef{};
        uvNeeded.push_back(m.needsUv());
    }
    return badIds;
}

// Scene::convexMeshOf of each mesh. A mesh counts as convex where its slack
// is under half the smallest ray offset anywhere in its box (rayOffsetScale of
// the box's point nearest the origin by the largest component). The tests take
// triangles x vertices steps: past 2^23 of them in all, the remaining meshes
// are not tested, so that no scene of many meshes loads much slower.
std::vector<int32_t> convexMeshIndices(const std::vector<TriangleMesh>& meshes) {
    std::vector<int32_t> out;
    size_t budget = size_t(1) << 23;
    for (size_t i = 0; i < meshes.size(); ++i) {
        const TriangleMesh& m = meshes[i];
        const size_t nv = m.positions.size();
        const bool affordable = nv > 0 && m.triangleCount() <= budget / nv;
        bool convex = false;
        if (affordable) {
            budget -= m.triangleCount() * nv;
            const Bounds3f b = bounds(m);
            Vec3f nearest;
            for (int a = 0; a < 3; ++a) nearest[a] = std::max(0.f, std::max(b.lo[a], -b.hi[a]));
            convex = convexSlack(m) < 0.5f * rayOffsetScale(nearest);
        }
        out.push_back(convex ? int32_t(i) : -1);
    }
    return out;
}

}  // namespace

SceneFixups Scene::finalize(const Logger& log) {
    SceneFixups fix;
    if (materials.empty()) {
        Material def;
        def.name = "default";
        materials.push_back(def);
    }
    for (size_t i = 0; i < instances.size(); ++i)
        if (instances[i].sourceIndex == Instance::kUnnumbered) instances[i].sourceIndex = static_cast<uint32_t>(i);
    fix.droppedInstances += dropBadInstances(instances, prototypes.size());
    CopyCount copies;
    countExpansion(copies);
    copies.check("the scene's emissive instances (expanded into meshes, each an area light)");
    expandEmissiveInstances(*this);
    for (auto& m : meshes) fix.droppedTriangles += repairMesh(m, log);
    eraseIf(meshes, [](const TriangleMesh& m) { return m.indices.empty(); });
    for (auto& p : prototypes) {
        for (auto& m : p.meshes) fix.droppedTriangles += repairMesh(m, log);
        eraseIf(p.meshes, [](const TriangleMesh& m) { return m.indices.empty(); });
    }
    fix.droppedInstances += eraseIf(instances, [&](const Instance& in) { return prototypes[in.prototype].meshes.empty(); });

    fix.droppedShapes += dropBadShapes(*this);
    const RangeDrops beyond = dropBeyondSceneRange(*this);  // the same scene for every accelerator

    const size_t badIds = fixMaterialReferences(*this, uvNeeded_);

    if (fix.droppedTriangles)
        log.warn("dropped " + std::to_string(fix.droppedTriangles) +
                 " triangle(s) with out-of-range indices, non-finite coordinates or zero area");
    if (fix.droppedShapes)
        log.warn("dropped " + std::to_string(fix.droppedShapes) + " shape(s) with non-finite or degenerate parameters");
    if (beyond.shapes || beyond.triangles)
        log.warn("dropped " + std::to_string(beyond.shapes) + " shape(s) and " + std::to_string(beyond.triangles) +
                 " triangle(s) reaching beyond +-1.8e18, the largest coordinate the accelerators represent");
    if (beyond.instances)
        log.warn("dropped " + std::to_string(beyond.instances) +
                 " instance(s) reaching beyond +-1.8e18, the largest coordinate the accelerators represent");
    fix.droppedShapes += beyond.shapes;
    fix.droppedTriangles += beyond.triangles;
    if (fix.droppedInstances)
        log.warn("dropped " + std::to_string(fix.droppedInstances) +
                 " instance(s) with an unknown or empty prototype or a non-finite or singular transform");
    fix.droppedInstances += beyond.instances;
    if (badIds) log.warn(std::to_string(badIds) + " material reference(s) out of range; using material 0");
    convexMeshes_ = convexMeshIndices(meshes);
    return fix;
}

int Scene::addTexture(TextureSource source) {
    for (size_t i = 0; i < textures.size(); ++i)
        if (textures[i].name == source.name && textures[i].colorSpace == source.colorSpace) return static_cast<int>(i);
    textures.push_back(std::move(source));
    return static_cast<int>(textures.size() - 1);
}

const TextureSource* Scene::findTexture(const std::string& name) const {
    for (const TextureSource& t : textures)
        if (t.name == name) return &t;
    return nullptr;
}

bool Scene::expandsInstance(const Instance& in) const {
    if (materials.empty()) return false;  // finalize() adds the default material first
    if (in.material != kNoMaterialOverride) return materials[in.material < materials.size() ? in.material : 0].isEmissive();
    return in.prototype < prototypes.size() && prototypes[in.prototype].usesEmissive(materials);
}

void Scene::countExpansion(CopyCount& count) const {
    for (const Instance& in : instances)
        if (in.prototype < prototypes.size() && expandsInstance(in))
            count.add(1, prototypes[in.prototype].triangleCount(), prototypes[in.prototype].vertexCount());
}

bool Scene::hasLight() const {
    if (!pointLights.empty() || !directionalLights.empty() || environment || !ambient.isBlack() || !background.isBlack())
        return true;
    const auto emits = [&](uint32_t m) { return m < materials.size() && materials[m].isEmissive(); };
    if (std::none_of(materials.begin(), materials.end(), [](const Material& m) { return m.isEmissive(); })) return false;
    const auto anyShape = [&](const auto& shapes) {
        return std::any_of(shapes.begin(), shapes.end(), [&](const auto& s) { return emits(s.material); });
    };
    if (anyShape(spheres) || anyShape(planes) || anyShape(boxes) || anyShape(rectangles) || anyShape(disks)) return true;
    for (const TriangleMesh& mesh : meshes)
        for (size_t t = 0; t < mesh.triangleCount(); ++t)
            if (emits(mesh.materialOf(t))) return true;
    return false;
}

Bounds3f Scene::bounds() const {
    Bounds3f b;
    for (const auto& s : spheres) b.extend(penumbra::bounds(s));
    for (const auto& s : boxes) b.extend(penumbra::bounds(s));
    for (const auto& s : rectangles) b.extend(penumbra::bounds(s));
    for (const auto& s : disks) b.extend(penumbra::bounds(s));
    for (const auto& m : meshes) b.extend(penumbra::bounds(m));
    std::vector<std::optional<Bounds3f>> prototypeBounds(prototypes.size());  // each a pass over its vertices, once
    for (const auto& in : instances) {
        if (in.prototype >= prototypes.size()) continue;
        std::optional<Bounds3f>& object = prototypeBounds[in.prototype];
        if (!object) object = prototypes[in.prototype].bounds();
        b.extend(instanceBounds(*object, in.worldFromObject));
    }
    return b;
}

size_t Scene::triangleCount() const {
    size_t n = 0;
    for (const auto& m : meshes) n += m.triangleCount();
    for (const auto& in : instances)
        if (in.prototype < prototypes.size()) n += prototypes[in.prototype].triangleCount();
    return n;
}

const TriangleMesh* Scene::meshOf(const PrimRef& ref, Transform* worldFromObject) const {
    if (ref.kind == ShapeKind::Mesh) {
        if (worldFromObject) *worldFromObject = Transform();
        return &meshes[ref.object];
    }
    if (ref.kind != ShapeKind::Instance) return nullptr;
    const Instance& in = instances[ref.object];
    if (worldFromObject) *worldFromObject = in.worldFromObject;
    return &prototypes[in.prototype].meshes[ref.part];
}

size_t Scene::primitiveCount() const {
    return triangleCount() + spheres.size() + planes.size() + boxes.size() + rectangles.size() + disks.size();
}

void Scene::completeInstanceHit(const PrimRef& ref, float u, float v, Hit& h) const {
    // The triangle is placed first and completed as a copy of the placed
    // vertices would be (normals as placedCopy transforms them), so an
    // instance hit equals the copy's hit bit for bit given the same (u, v);
    // a mirroring transform thereby flips the front, as it does for the copy.
    const Instance& in = instances[ref.object];
    const TriangleMesh& m = prototypes[in.prototype].meshes[ref.part];
    const Transform& place = in.worldFromObject;
    const uint32_t* idx = &m.indices[3 * size_t(ref.prim)];
    TriangleCorners c;
    Vec3f n[3];
    Vec2f uv[3];
    for (int k = 0; k < 3; ++k) {
        c.p[k] = place.applyPoint(m.positions[idx[k]]);
        if (!m.normals.empty()) n[k] = normalize(place.applyNormal(m.normals[idx[k]]));
        if (!m.uvs.empty()) uv[k] = m.uvs[idx[k]];
    }
    c.n = m.normals.empty() ? nullptr : n;
    c.uv = m.uvs.empty() ? nullptr : uv;
    completeTriangleHit(c, u, v, h);
    h.material = in.material != kNoMaterialOverride ? in.material : m.materialOf(ref.prim);
}

PENUMBRA_LANE_CLONES void Scene::completeHit(const Ray& ray, const PrimRef& ref, float t, float u, float v, Hit& h) const {
    // Each shape completes its own hits beside its intersection test (core/shapes.cpp).
    // A sphere, plane or box computes its uv only for a textured material.
    const auto completeAnalytic = [&](const auto& shape) {
        penumbra::completeHit(shape, ray, t, h, textured(shape.material));
    };
    switch (ref.kind) {
        case ShapeKind::Mesh: completeTriangleHit(meshes[ref.object], ref.prim, u, v, h); break;
        case ShapeKind::Sphere: completeAnalytic(spheres[ref.object]); break;
        case ShapeKind::Plane: completeAnalytic(planes[ref.object]); break;
        case ShapeKind::Box: completeAnalytic(boxes[ref.object]); break;
        case ShapeKind::Rectangle: penumbra::completeHit(rectangles[ref.object], u, v, h); break;
        case ShapeKind::Disk: penumbra::completeHit(disks[ref.object], u, v, h); break;
        case ShapeKind::Instance: completeInstanceHit(ref, u, v, h); break;
    }
    h.t = t;
    h.ref = ref;
}

std::optional<Scene::HitTriangle> Scene::hitTriangle(const Hit& h) const {
    HitTriangle t;
    t.mesh = meshOf(h.ref, &t.place);
    if (!t.mesh) return std::nullopt;
    t.idx = &t.mesh->indices[3 * size_t(h.ref.prim)];
    for (int k = 0; k < 3; ++k) t.p[k] = t.place.applyPoint(t.mesh->positions[t.idx[k]]);
    // h.p = (1 - u - v) p0 + u p1 + v p2: solved for (u, v) in the triangle's plane.
    const Vec3f e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0], d = h.p - t.p[0];
    const float a = dot(e1, e1), b = dot(e1, e2), c = dot(e2, e2), d1 = dot(d, e1), d2 = dot(d, e2);
    const float det = a * c - b * b;
    t.bary = det != 0.f ? Vec2f{(c * d1 - b * d2) / det, (a * d2 - b * d1) / det} : Vec2f{};
    return t;
}

Vec2f Scene::uv1At(const Hit& h) const {
    const std::optional<HitTriangle> t = hitTriangle(h);
    if (!t || t->mesh->uvs1.empty()) return h.uv;
    const float u = t->bary.x, v = t->bary.y, w = 1.f - u - v;
    const Vec2f a = t->mesh->uvs1[t->idx[0]], b = t->mesh->uvs1[t->idx[1]], c = t->mesh->uvs1[t->idx[2]];
    return {w * a.x + u * b.x + v * c.x, w * a.y + u * b.y + v * c.y};
}

Tangent Scene::tangentAt(const Hit& h, int uvSet) const {
    const Tangent any{anyPerpendicular(h.ns), 1.f};
    const std::optional<HitTriangle> t = hitTriangle(h);
    if (!t) {
        const uint32_t i = h.ref.object;
        std::optional<UvDerivatives> d;
        switch (h.ref.kind) {
            case ShapeKind::Sphere: d = uvDerivatives(spheres[i], h.p); break;
            case ShapeKind::Plane: d = uvDerivatives(planes[i]); break;
            case ShapeKind::Box: d = uvDerivatives(boxes[i], h.ng); break;
            case ShapeKind::Rectangle: d = uvDerivatives(rectangles[i]); break;
            case ShapeKind::Disk: d = uvDerivatives(disks[i]); break;
            default: break;
        }
        return d ? tangentFrom(d->dpdu, d->dpdv, h.ns).value_or(any) : any;
    }
    const TriangleMesh& m = *t->mesh;
    if (!m.tangents.empty()) {
        const float u = t->bary.x, v = t->bary.y, w = 1.f - u - v;
        const Tangent &a = m.tangents[t->idx[0]], &b = m.tangents[t->idx[1]], &c = m.tangents[t->idx[2]];
        Vec3f dir = t->place.applyVector(w * a.direction + u * b.direction + v * c.direction);
        dir = dir - dot(dir, h.ns) * h.ns;
        const float l = length(dir);
        // A mirroring placement flips the handedness, as placedCopy does.
        const float sign = t->place.determinant() < 0.f ? -a.sign : a.sign;
        return l > 0.f && std::isfinite(l) ? Tangent{dir / l, sign} : any;
    }
    const std::vector<Vec2f>& uvs = uvSet == 1 && !m.uvs1.empty() ? m.uvs1 : m.uvs;
    if (uvs.empty()) return any;
    const Vec2f uv[3] = {uvs[t->idx[0]], uvs[t->idx[1]], uvs[t->idx[2]]};
    return triangleTangent(t->p, uv, h.ns).value_or(any);
}

}  // namespace penumbra
