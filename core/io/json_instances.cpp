// JSON prototypes and instances (SceneReader, json_reader.h): "prototypes" are
// named groups of meshes read once, "instance" shapes place them. Embree
// instances one level deep, so an instance inside a prototype is flattened
// into copies of the prototype it names (resolved depth first, cycles refused).
#include "core/io/json_reader.h"

#include <algorithm>

namespace penumbra {
using namespace json_text;

void SceneReader::readPrototypes(const Json& j, const std::string& ptr, Scene& scene) {
    expectType(j, ptr, Json::value_t::array, "an array");
    // Names first, so prototypes may name each other in any order.
    for (size_t i = 0; i < j.size(); ++i) {
        const std::string p = child(ptr, i);
        expectObject(j[i], p);
        checkKeys(j[i], p, {"name", "shapes"});
        const std::string np = child(p, "name");
        const std::string name = string(require(j[i], p, "name", "a prototype"), np);
        if (name.empty()) fail(ErrorCode::InvalidScene, np, "prototype names must not be empty");
        if (!prototypeEntries_.try_emplace(name, PrototypeEntry{&j[i], p}).second)
            fail(ErrorCode::InvalidScene, np, "prototype " + quotedValue(name) + " is defined twice");
    }
    // Then every one in file order, unused ones included (their errors count too).
    for (size_t i = 0; i < j.size(); ++i) resolvePrototype(j[i]["name"].get<std::string>(), child(ptr, i), scene);
}

uint32_t SceneReader::resolvePrototype(const std::string& name, const std::string& refPtr, Scene& scene) {
    auto it = prototypeEntries_.find(name);
    if (it == prototypeEntries_.end()) {
        std::string known;
        for (const auto& [n, e] : prototypeEntries_) known += (known.empty() ? "" : ", ") + quotedValue(n);
        fail(ErrorCode::InvalidScene, refPtr,
             "unknown prototype " + quotedValue(name) +
                 (known.empty() ? std::string(" (the file defines no \"prototypes\")") : " (known: " + known + ")"));
    }
    PrototypeEntry& e = it->second;
    if (e.index) return *e.index;
    if (std::find(resolving_.begin(), resolving_.end(), name) != resolving_.end()) {
        std::string chain;
        for (auto c = std::find(resolving_.begin(), resolving_.end(), name); c != resolving_.end(); ++c)
            chain += quotedValue(*c) + " -> ";
        fail(ErrorCode::InvalidScene, refPtr, "prototype cycle: " + chain + quotedValue(name));
    }
    resolving_.push_back(name);
    Prototype proto;
    proto.name = name;
    const Json& shapes = require(*e.json, e.ptr, "shapes", "a prototype");
    const std::string sp = child(e.ptr, "shapes");
    expectType(shapes, sp, Json::value_t::array, "an array");
    if (shapes.empty()) fail(ErrorCode::InvalidScene, sp, "a prototype needs at least one mesh");
    for (size_t i = 0; i < shapes.size(); ++i) {
        const Json& s = shapes[i];
        const std::string p = child(sp, i);
        expectObject(s, p);
        const std::string type = string(require(s, p, "type", "a shape"), child(p, "type"));
        if (type == "mesh") {
            // The mesh readers append to Scene::meshes (and their materials to
            // Scene::materials); the new meshes move into the prototype.
            const size_t first = scene.meshes.size();
            readShape(s, p, scene);
            for (size_t k = first; k < scene.meshes.size(); ++k) proto.meshes.push_back(std::move(scene.meshes[k]));
            scene.meshes.resize(first);
        } else if (type == "instance") {
            const PlacedPrototype placed = readPlacement(s, p, scene);
            for (const TriangleMesh& m : scene.prototypes[placed.prototype].meshes) {
                TriangleMesh copy = placedCopy(m, placed.worldFromObject);
                if (placed.material != kNoMaterialOverride) {
                    copy.material = placed.material;
                    copy.faceMaterials.clear();
                }
                proto.meshes.push_back(std::move(copy));
            }
        } else {
            fail(ErrorCode::InvalidScene, child(p, "type"),
                 "a prototype holds meshes and instances only, not " + quotedValue(type));
        }
    }
    resolving_.pop_back();
    e.index = static_cast<uint32_t>(scene.prototypes.size());
    scene.prototypes.push_back(std::move(proto));
    return *e.index;
}

SceneReader::PlacedPrototype SceneReader::readPlacement(const Json& j, const std::string& ptr, Scene& scene) {
    checkKeys(j, ptr, {"type", "name", "prototype", "transform", "material"});
    PlacedPrototype placed;
    const std::string pp = child(ptr, "prototype");
    placed.prototype = resolvePrototype(string(require(j, ptr, "prototype", "an instance"), pp), pp, scene);
    if (const Json* v = find(j, "transform")) placed.worldFromObject = readTransform(*v, child(ptr, "transform"));
    if (find(j, "material")) placed.material = shapeMaterial(j, ptr, scene);
    Instance in = makeInstance(placed.prototype, placed.worldFromObject);
    checkRange(instanceBounds(scene.prototypes[placed.prototype], in), ptr);
    return placed;
}

void SceneReader::readInstance(const Json& j, const std::string& ptr, Scene& scene) {
    const PlacedPrototype placed = readPlacement(j, ptr, scene);
    scene.instances.push_back(makeInstance(placed.prototype, placed.worldFromObject, placed.material));
}

}  // namespace penumbra
