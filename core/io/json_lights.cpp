// JSON lights (point, directional, ambient, and area lights as emitting shapes) (SceneReader, json_reader.h).
#include "core/io/json_reader.h"


namespace penumbra {
namespace fs = std::filesystem;
using namespace json_text;

void SceneReader::readLight(const Json& j, const std::string& ptr, Scene& scene) {
    expectObject(j, ptr);
    std::string type = string(require(j, ptr, "type", "a light"), child(ptr, "type"));
    if (type == "point") {
        checkKeys(j, ptr, {"type", "name", "position", "intensity"});
        PointLight l;
        l.position = vec3(require(j, ptr, "position", "a point light"), child(ptr, "position"));
        l.intensity = colour(require(j, ptr, "intensity", "a point light"), child(ptr, "intensity"));
        scene.pointLights.push_back(l);
    } else if (type == "directional") {
        checkKeys(j, ptr, {"type", "name", "direction", "irradiance"});
        DirectionalLight l;
        l.direction = normalize(nonZeroVec3(require(j, ptr, "direction", "a directional light"), child(ptr, "direction")));
        l.irradiance = colour(require(j, ptr, "irradiance", "a directional light"), child(ptr, "irradiance"));
        scene.directionalLights.push_back(l);
    } else if (type == "ambient") {
        checkKeys(j, ptr, {"type", "name", "radiance"});
        scene.ambient += colour(require(j, ptr, "radiance", "an ambient light"), child(ptr, "radiance"));
    } else if (type == "rectangle") {
        checkKeys(j, ptr, {"type", "name", "p0", "a", "b", "radiance", "two_sided"});
        Rectangle q = rectangle(j, ptr);
        q.material = lightMaterial(j, ptr, scene);
        checkRange(bounds(q), ptr);
        scene.rectangles.push_back(q);
    } else if (type == "disk") {
        checkKeys(j, ptr, {"type", "name", "center", "normal", "radius", "radiance", "two_sided"});
        Disk d = disk(j, ptr);
        d.material = lightMaterial(j, ptr, scene);
        checkRange(bounds(d), ptr);
        scene.disks.push_back(d);
    } else if (type == "sphere") {
        checkKeys(j, ptr, {"type", "name", "center", "radius", "radiance", "two_sided"});
        Sphere s;
        s.center = vec3(require(j, ptr, "center", "a sphere light"), child(ptr, "center"));
        s.radius = positive(require(j, ptr, "radius", "a sphere light"), child(ptr, "radius"));
        s.material = lightMaterial(j, ptr, scene);
        checkRange(bounds(s), ptr);
        scene.spheres.push_back(s);
    } else {
        fail(ErrorCode::ParseError, child(ptr, "type"),
             "unknown light type " + quotedValue(type) + " (expected point, directional, ambient, rectangle, disk or sphere)");
    }
}

uint32_t SceneReader::lightMaterial(const Json& j, const std::string& ptr, Scene& scene) const {
    Material m;
    m.name = "light@" + ptr;
    if (const Json* v = find(j, "name")) m.name = string(*v, child(ptr, "name"));
    m.ka = m.kd = m.ks = m.kr = Rgb(0.f);
    m.ke = colour(require(j, ptr, "radiance", "an area light"), child(ptr, "radiance"));
    if (const Json* v = find(j, "two_sided")) m.twoSidedEmission = boolean(*v, child(ptr, "two_sided"));
    scene.materials.push_back(std::move(m));
    return static_cast<uint32_t>(scene.materials.size() - 1);
}
}  // namespace penumbra
