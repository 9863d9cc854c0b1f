#include "bench_scenes.h"

#include <cmath>

#include "core/error.h"
#include "core/io/scene_loader.h"

namespace penumbra::bench {
namespace {

// Two triangles covering centre +- u +- v, wound so that they face `facing`.
void addQuad(TriangleMesh& m, const Vec3f& centre, Vec3f u, Vec3f v, const Vec3f& facing, uint32_t material) {
    if (dot(cross(u, v), facing) < 0.f) std::swap(u, v);
    const auto base = static_cast<uint32_t>(m.positions.size());
    m.positions.push_back(centre - u - v);
    m.positions.push_back(centre + u - v);
    m.positions.push_back(centre + u + v);
    m.positions.push_back(centre - u + v);
    for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + i);
    m.faceMaterials.push_back(material);
    m.faceMaterials.push_back(material);
}

Material diffuse(const char* name, Rgb kd) {
    Material m;
    m.name = name;
    m.kd = kd;
    return m;
}

Bounds3f meshBounds(const Scene& s) {
    Bounds3f b;
    for (const auto& m : s.meshes)
        for (const Vec3f& p : m.positions) b.extend(p);
    return b;
}

}  // namespace

const char* familyName(SceneFamily f) {
    switch (f) {
        case SceneFamily::Procedural: return "procedural";
        case SceneFamily::Mixed: return "mixed";
        case SceneFamily::Default: return "default";
        case SceneFamily::Obj: return "obj";
        case SceneFamily::File: return "file";
    }
    return "?";
}

std::string sizeLabel(size_t n) {
    int e = 0;
    size_t v = n;
    while (v >= 10 && v % 10 == 0) {
        v /= 10;
        ++e;
    }
    return v == 1 && e >= 2 ? "1e" + std::to_string(e) : std::to_string(n);
}

TriangleMesh bumpySphere(size_t triangles, const Vec3f& center, float radius, uint32_t material) {
    if (triangles < 6) throw Error(ErrorCode::InvalidArgument, "a bumpy sphere needs at least 6 triangles");
    // triangles = 2 * segments * rings (two caps of `segments` triangles and
    // rings - 1 bands of quads). Pick segments ~ 2 * rings for square-ish cells.
    const size_t half = (triangles + 1) / 2;
    size_t segments = half, rings = 1;
    double bestScore = kInfinity;
    for (size_t s = 3; s <= half; ++s) {
        if (half % s) continue;
        const double score = std::fabs(double(s) - 2.0 * double(half / s));
        if (score < bestScore) {
            bestScore = score;
            segments = s;
            rings = half / s;
        }
    }
    TriangleMesh m;
    m.name = "bumpy_sphere";
    m.material = material;
    m.positions.reserve(segments * rings + 2);
    m.indices.reserve(6 * segments * rings);
    // Smooth low-frequency bumps plus a finer ripple; both vanish at the poles.
    auto point = [&](double theta, double phi) {
        const double r = radius * (1.0 + 0.12 * std::sin(5.0 * theta) * std::cos(4.0 * phi) +
                                   0.03 * std::sin(23.0 * theta) * std::sin(19.0 * phi));
        return center + Vec3f{float(r * std::sin(theta) * std::cos(phi)), float(r * std::cos(theta)),
                              float(r * std::sin(theta) * std::sin(phi))};
    };
    m.positions.push_back(center + Vec3f{0.f, radius, 0.f});  // north pole
    for (size_t i = 1; i <= rings; ++i) {
        const double theta = kPi * double(i) / double(rings + 1);
        for (size_t j = 0; j < segments; ++j) m.positions.push_back(point(theta, 2.0 * kPi * double(j) / double(segments)));
    }
    m.positions.push_back(center - Vec3f{0.f, radius, 0.f});  // south pole
    const auto south = static_cast<uint32_t>(m.positions.size() - 1);
    auto at = [&](size_t ring, size_t seg) { return static_cast<uint32_t>(1 + (ring - 1) * segments + seg % segments); };
    // With phi growing from +x towards +z, (a, b, c) below is counter-clockwise seen from outside.
    for (size_t j = 0; j < segments; ++j) {
        for (uint32_t i : {0u, at(1, j + 1), at(1, j)}) m.indices.push_back(i);
        for (size_t i = 1; i < rings; ++i) {
            const uint32_t a = at(i, j), b = at(i, j + 1), c = at(i + 1, j + 1), d = at(i + 1, j);
            for (uint32_t k : {a, b, c, a, c, d}) m.indices.push_back(k);
        }
        for (uint32_t i : {south, at(rings, j), at(rings, j + 1)}) m.indices.push_back(i);
    }
    return m;
}

void addRoom(Scene& scene, const Bounds3f& object) {
    const auto first = static_cast<uint32_t>(scene.materials.size());
    scene.materials.push_back(diffuse("room_white", Rgb(0.73f, 0.71f, 0.68f)));
    scene.materials.push_back(diffuse("room_red", Rgb(0.63f, 0.06f, 0.05f)));
    scene.materials.push_back(diffuse("room_green", Rgb(0.15f, 0.45f, 0.09f)));
    Material lamp = diffuse("room_light", Rgb(0.f));
    lamp.ke = Rgb(15.f, 14.f, 12.f);
    scene.materials.push_back(lamp);
    const uint32_t white = first, red = first + 1, green = first + 2, light = first + 3;

    const Vec3f c = object.center();
    float r = 0.5f * length(object.diagonal());
    if (!(r > 0.f) || !std::isfinite(r)) r = 1.f;
    const float floorY = object.lo.y, ceilingY = object.lo.y + 3.f * r;
    const float midY = 0.5f * (floorY + ceilingY), halfY = 0.5f * (ceilingY - floorY);
    const float w = 2.f * r;  // half width and half depth

    TriangleMesh room;
    room.name = "room";
    room.material = white;
    const Vec3f X{1.f, 0.f, 0.f}, Y{0.f, 1.f, 0.f}, Z{0.f, 0.f, 1.f};
    addQuad(room, Vec3f{c.x, floorY, c.z}, X * w, Z * w, Y, white);
    addQuad(room, Vec3f{c.x, ceilingY, c.z}, X * w, Z * w, -Y, white);
    addQuad(room, Vec3f{c.x, midY, c.z - w}, X * w, Y * halfY, Z, white);
    addQuad(room, Vec3f{c.x - w, midY, c.z}, Z * w, Y * halfY, X, red);
    addQuad(room, Vec3f{c.x + w, midY, c.z}, Z * w, Y * halfY, -X, green);
    scene.meshes.push_back(std::move(room));

    TriangleMesh lampMesh;
    lampMesh.name = "room_light";
    lampMesh.material = light;
    addQuad(lampMesh, Vec3f{c.x, ceilingY - 1e-3f * r, c.z}, X * (0.35f * r), Z * (0.35f * r), -Y, light);
    scene.meshes.push_back(std::move(lampMesh));
}

CameraDesc frameObject(const Bounds3f& object) { return frameBounds(object, 40.f, 4.f / 3.f); }

BenchScene proceduralScene(size_t triangles) {
    BenchScene b;
    b.name = "sphere-" + sizeLabel(triangles);
    b.family = SceneFamily::Procedural;
    Material m;
    m.name = "bumpy";
    m.kd = Rgb(0.45f, 0.5f, 0.55f);
    m.ks = Rgb(0.2f);
    m.exponent = 40.f;
    m.kr = Rgb(0.3f);
    b.scene.materials.push_back(m);
    b.scene.meshes.push_back(bumpySphere(triangles, Vec3f{0.f, 1.f, 0.f}, 1.f, 0));
    const Bounds3f object = meshBounds(b.scene);
    addRoom(b.scene, object);
    b.camera = frameObject(object);
    return b;
}

BenchScene mixedScene(size_t meshTriangles) {
    BenchScene b;
    b.name = "mixed";
    b.family = SceneFamily::Mixed;
    Scene& s = b.scene;
    s.materials.push_back(diffuse("white", Rgb(0.73f, 0.71f, 0.68f)));  // 0
    s.materials.push_back(diffuse("red", Rgb(0.63f, 0.06f, 0.05f)));     // 1
    Material mirror = diffuse("mirror", Rgb(0.f));
    mirror.kr = Rgb(0.9f);
    s.materials.push_back(mirror);  // 2
    Material glossy = diffuse("glossy", Rgb(0.3f, 0.4f, 0.6f));
    glossy.ks = Rgb(0.3f);
    glossy.exponent = 60.f;
    s.materials.push_back(glossy);  // 3
    Material lamp = diffuse("lamp", Rgb(0.f));
    lamp.ke = Rgb(12.f);
    s.materials.push_back(lamp);  // 4

    s.planes.push_back(Plane{Vec3f{0.f, 0.f, 0.f}, Vec3f{0.f, 1.f, 0.f}, true, 0});
    s.rectangles.push_back(Rectangle{Vec3f{-3.f, 0.f, -3.f}, Vec3f{6.f, 0.f, 0.f}, Vec3f{0.f, 4.f, 0.f}, 0});   // back
    s.rectangles.push_back(Rectangle{Vec3f{-3.f, 0.f, 3.f}, Vec3f{0.f, 0.f, -6.f}, Vec3f{0.f, 4.f, 0.f}, 1});   // left
    s.rectangles.push_back(Rectangle{Vec3f{3.f, 0.f, -3.f}, Vec3f{0.f, 0.f, 6.f}, Vec3f{0.f, 4.f, 0.f}, 0});    // right
    s.rectangles.push_back(Rectangle{Vec3f{-0.6f, 3.9f, -0.6f}, Vec3f{1.2f, 0.f, 0.f}, Vec3f{0.f, 0.f, 1.2f}, 4});  // light, facing down
    s.spheres.push_back(Sphere{Vec3f{-1.3f, 0.7f, -0.5f}, 0.7f, 2});
    for (int i = 0; i < 12; ++i) {
        const float a = 2.f * kPi * float(i) / 12.f;
        s.spheres.push_back(Sphere{Vec3f{2.2f * std::cos(a), 0.15f, 0.8f + 1.2f * std::sin(a)}, 0.15f, uint32_t(i % 2 ? 3 : 1)});
    }
    s.boxes.push_back(makeBox(Vec3f{-0.5f, 0.f, -0.5f}, Vec3f{0.5f, 1.4f, 0.5f},
                              Transform::translate(Vec3f{1.4f, 0.f, -1.2f}) * Transform::rotate(25.f, Vec3f{0.f, 1.f, 0.f}), 0));
    s.disks.push_back(Disk{Vec3f{0.f, 2.2f, -2.9f}, Vec3f{0.f, 0.f, 1.f}, 0.6f, 3});
    s.meshes.push_back(bumpySphere(meshTriangles, Vec3f{0.2f, 0.65f, 0.6f}, 0.6f, 3));
    b.camera.eye = Vec3f{0.f, 2.f, 8.f};
    b.camera.lookAt = Vec3f{0.f, 1.2f, 0.f};
    b.camera.vfovDegrees = 40.f;
    return b;
}

BenchScene defaultScene(const std::filesystem::path& obj, const Logger& log) {
    BenchScene b;
    b.name = "cornell";
    b.family = SceneFamily::Default;
    b.scene = loadObjScene(obj, LoadOptions{}, log).scene;
    // Framed as the CLI frames OBJ files (the box is open towards the camera).
    b.camera = frameObject(b.scene.bounds());
    return b;
}

BenchScene objInRoom(const std::filesystem::path& obj, const Logger& log) {
    BenchScene b;
    b.name = obj.stem().string();
    b.family = SceneFamily::Obj;
    b.scene = loadObjScene(obj, LoadOptions{}, log).scene;
    const Bounds3f object = b.scene.bounds();
    if (object.empty()) throw Error(ErrorCode::InvalidScene, obj.string() + ": no geometry to benchmark");
    addRoom(b.scene, object);
    b.camera = frameObject(object);
    return b;
}

BenchScene fileScene(const std::filesystem::path& json, const Logger& log) {
    BenchScene b;
    b.name = json.stem().string();
    b.family = SceneFamily::File;
    LoadedScene loaded = loadScene(json, LoadOptions{}, log);
    b.scene = std::move(loaded.scene);
    b.camera = loaded.camera ? *loaded.camera : frameObject(b.scene.bounds());
    b.lightSamples = loaded.settings.lightSamples;
    b.maxDepth = loaded.settings.maxDepth;
    return b;
}

}  // namespace penumbra::bench
