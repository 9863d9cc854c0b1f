// JSON shapes (sphere, plane, box, rectangle, disk; meshes in json_meshes.cpp) (SceneReader, json_reader.h).
#include "core/io/json_reader.h"

#include <cmath>

namespace penumbra {
namespace fs = std::filesystem;
using namespace json_text;

void SceneReader::readShape(const Json& j, const std::string& ptr, Scene& scene) {
    expectObject(j, ptr);
    std::string type = string(require(j, ptr, "type", "a shape"), child(ptr, "type"));
    if (type == "sphere") {
        checkKeys(j, ptr, {"type", "name", "material", "emission", "center", "radius"});
        Sphere s;
        s.center = vec3(require(j, ptr, "center", "a sphere"), child(ptr, "center"));
        s.radius = positive(require(j, ptr, "radius", "a sphere"), child(ptr, "radius"));
        s.material = shapeMaterial(j, ptr, scene);
        checkRange(bounds(s), ptr);
        scene.spheres.push_back(s);
    } else if (type == "plane") {
        checkKeys(j, ptr, {"type", "name", "material", "point", "normal", "two_sided"});
        Plane p;
        p.point = vec3(require(j, ptr, "point", "a plane"), child(ptr, "point"));
        p.normal = normalize(nonZeroVec3(require(j, ptr, "normal", "a plane"), child(ptr, "normal")));
        if (const Json* v = find(j, "two_sided")) p.twoSided = boolean(*v, child(ptr, "two_sided"));
        p.material = shapeMaterial(j, ptr, scene);
        // An infinite emitter cannot be sampled as a light; say so instead of
        // rendering a plane that glows only where rays happen to hit it.
        if (scene.materials[p.material].isEmissive())
            warnOrFail(ErrorCode::InvalidScene, child(ptr, "material"),
                       "an emissive material on an infinite plane is not sampled as a light");
        scene.planes.push_back(p);
    } else if (type == "box") {
        checkKeys(j, ptr, {"type", "name", "material", "emission", "min", "max", "transform"});
        Vec3f lo = vec3(require(j, ptr, "min", "a box"), child(ptr, "min"));
        Vec3f hi = vec3(require(j, ptr, "max", "a box"), child(ptr, "max"));
        if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z))
            fail(ErrorCode::InvalidScene, child(ptr, "max"), "must be greater than \"min\" in every coordinate");
        Transform t;
        if (const Json* v = find(j, "transform")) t = readTransform(*v, child(ptr, "transform"));
        Box b = makeBox(lo, hi, t, shapeMaterial(j, ptr, scene));
        checkRange(bounds(b), ptr);
        scene.boxes.push_back(b);
    } else if (type == "rectangle") {
        checkKeys(j, ptr, {"type", "name", "material", "emission", "p0", "a", "b"});
        Rectangle q = rectangle(j, ptr);
        q.material = shapeMaterial(j, ptr, scene);
        checkRange(bounds(q), ptr);
        scene.rectangles.push_back(q);
    } else if (type == "disk") {
        checkKeys(j, ptr, {"type", "name", "material", "emission", "center", "normal", "radius"});
        Disk d = disk(j, ptr);
        d.material = shapeMaterial(j, ptr, scene);
        checkRange(bounds(d), ptr);
        scene.disks.push_back(d);
    } else if (type == "mesh") {
        if (find(j, "file"))
            readObjMesh(j, ptr, scene);
        else
            readInlineMesh(j, ptr, scene);
    } else if (type == "instance") {
        readInstance(j, ptr, scene);
    } else {
        fail(ErrorCode::ParseError, child(ptr, "type"),
             "unknown shape type " + quotedValue(type) + " (expected sphere, plane, box, rectangle, disk, mesh or instance)");
    }
}

Rectangle SceneReader::rectangle(const Json& j, const std::string& ptr) const {
    Rectangle q;
    q.p0 = vec3(require(j, ptr, "p0", "a rectangle"), child(ptr, "p0"));
    q.a = vec3(require(j, ptr, "a", "a rectangle"), child(ptr, "a"));
    q.b = vec3(require(j, ptr, "b", "a rectangle"), child(ptr, "b"));
    if (!std::isfinite(area(q)))
        fail(ErrorCode::InvalidScene, ptr, "rectangle's area overflows a 32-bit float (\"a\" and \"b\" are too long)");
    if (!(area(q) > 0.f))
        fail(ErrorCode::InvalidScene, ptr, "rectangle has zero area (\"a\" and \"b\" are parallel or zero)");
    return q;
}

Disk SceneReader::disk(const Json& j, const std::string& ptr) const {
    Disk d;
    d.center = vec3(require(j, ptr, "center", "a disk"), child(ptr, "center"));
    d.normal = normalize(nonZeroVec3(require(j, ptr, "normal", "a disk"), child(ptr, "normal")));
    d.radius = positive(require(j, ptr, "radius", "a disk"), child(ptr, "radius"));
    return d;
}
}  // namespace penumbra
