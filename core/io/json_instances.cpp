// JSON prototypes and instances (SceneReader, json_reader.h): "prototypes" are
// named groups of meshes read once, "instance" shapes place them. Embree
// instances one level deep, so an instance inside a prototype is flattened
// into copies of the prototype it names. Prototypes may place each other
// 10,000 levels deep, so they are ordered with a loop (each after those it
// places, cycles refused), read, counted (the copies must stay within
// CopyCount's limit), and only then flattened, in that order.
#include "core/io/json_reader.h"

#include <algorithm>
#include <unordered_map>

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
    // Then every one (unused ones included: their errors count too), each
    // after those it places, as prototypes of their own meshes and placements.
    const size_t first = scene.prototypes.size();
    std::vector<std::vector<PrototypePart>> parts;
    for (const std::string& name : prototypeOrder(j)) {
        PrototypeEntry& e = prototypeEntries_.at(name);
        parts.push_back(readPrototypeParts(e, scene));
        e.index = static_cast<uint32_t>(scene.prototypes.size());
        scene.prototypes.push_back(Prototype{name, {}});
    }
    // The copies that flattening makes, counted before any is made.
    std::vector<CopyCount> flat(parts.size());
    for (size_t k = 0; k < parts.size(); ++k)
        for (const PrototypePart& part : parts[k]) {
            for (const TriangleMesh& m : part.meshes) flat[k].add(1, m.triangleCount(), m.positions.size());
            if (!part.placed) continue;
            const CopyCount& placed = flat[part.placed->prototype - first];
            flat[k].add(1, placed.triangles(), placed.vertices());
            copies_.add(1, placed.triangles(), placed.vertices());
        }
    copies_.check(file_ + ": " + ptr + ": prototypes placed inside prototypes");
    for (size_t k = 0; k < parts.size(); ++k) {
        flatten(parts[k], scene.prototypes[first + k], scene);
        prototypeBounds_.push_back(scene.prototypes[first + k].bounds());
    }
}

std::vector<std::pair<std::string, std::string>> SceneReader::placedPrototypes(const PrototypeEntry& e) const {
    std::vector<std::pair<std::string, std::string>> out;
    const Json* shapes = find(*e.json, "shapes");
    if (!shapes || !shapes->is_array()) return out;  // reading the prototype reports it
    for (size_t i = 0; i < shapes->size(); ++i) {
        const Json& s = (*shapes)[i];
        const Json* type = s.is_object() ? find(s, "type") : nullptr;
        const Json* name = s.is_object() ? find(s, "prototype") : nullptr;
        if (type && *type == "instance" && name && name->is_string())
            out.emplace_back(name->get<std::string>(), child(child(child(e.ptr, "shapes"), i), "prototype"));
    }
    return out;
}

std::vector<std::string> SceneReader::prototypeOrder(const Json& j) const {
    std::vector<std::string> order;
    enum class Mark { Open, Done };
    std::unordered_map<std::string, Mark> marks;
    struct Frame {
        std::string name;
        std::vector<std::pair<std::string, std::string>> placed;  // (name, where it is named)
        size_t next = 0;
    };
    for (size_t i = 0; i < j.size(); ++i) {
        const std::string first = j[i]["name"].get<std::string>();
        if (marks.count(first)) continue;
        std::vector<Frame> stack{{first, placedPrototypes(prototypeEntries_.at(first))}};
        marks[first] = Mark::Open;
        while (!stack.empty()) {
            Frame& top = stack.back();
            if (top.next == top.placed.size()) {
                marks[top.name] = Mark::Done;
                order.push_back(top.name);
                stack.pop_back();
                continue;
            }
            // Named copies, not structured bindings: clang 14 (the fuzz build) cannot capture those.
            const std::string name = top.placed[top.next].first, where = top.placed[top.next].second;
            ++top.next;
            resolvePrototype(name, where, false);  // refuses unknown names
            const auto mark = marks.find(name);
            if (mark != marks.end() && mark->second == Mark::Open) {
                std::string chain;
                auto c = std::find_if(stack.begin(), stack.end(), [&](const Frame& f) { return f.name == name; });
                for (; c != stack.end(); ++c) chain += quotedValue(c->name) + " -> ";
                fail(ErrorCode::InvalidScene, where, "prototype cycle: " + chain + quotedValue(name));
            }
            if (mark != marks.end()) continue;
            marks[name] = Mark::Open;
            stack.push_back({name, placedPrototypes(prototypeEntries_.at(name))});
        }
    }
    return order;
}

uint32_t SceneReader::resolvePrototype(const std::string& name, const std::string& refPtr, bool read) const {
    auto it = prototypeEntries_.find(name);
    if (it == prototypeEntries_.end()) {
        std::string known;
        for (const auto& [n, e] : prototypeEntries_) known += (known.empty() ? "" : ", ") + quotedValue(n);
        fail(ErrorCode::InvalidScene, refPtr,
             "unknown prototype " + quotedValue(name) +
                 (known.empty() ? std::string(" (the file defines no \"prototypes\")") : " (known: " + known + ")"));
    }
    return read ? *it->second.index : 0;
}

std::vector<SceneReader::PrototypePart> SceneReader::readPrototypeParts(const PrototypeEntry& e, Scene& scene) {
    const Json& shapes = require(*e.json, e.ptr, "shapes", "a prototype");
    const std::string sp = child(e.ptr, "shapes");
    expectType(shapes, sp, Json::value_t::array, "an array");
    if (shapes.empty()) fail(ErrorCode::InvalidScene, sp, "a prototype needs at least one mesh");
    std::vector<PrototypePart> parts;
    for (size_t i = 0; i < shapes.size(); ++i) {
        const Json& s = shapes[i];
        PrototypePart& part = parts.emplace_back();
        part.ptr = child(sp, i);
        expectObject(s, part.ptr);
        const std::string type = string(require(s, part.ptr, "type", "a shape"), child(part.ptr, "type"));
        if (type == "mesh") {
            // The mesh readers append to Scene::meshes (and their materials to
            // Scene::materials); the new meshes move into the prototype.
            const size_t first = scene.meshes.size();
            readShape(s, part.ptr, scene);
            for (size_t k = first; k < scene.meshes.size(); ++k) part.meshes.push_back(std::move(scene.meshes[k]));
            scene.meshes.resize(first);
        } else if (type == "instance") {
            part.placed = parsePlacement(s, part.ptr, scene);
        } else {
            fail(ErrorCode::InvalidScene, child(part.ptr, "type"),
                 "a prototype holds meshes and instances only, not " + quotedValue(type));
        }
    }
    return parts;
}

void SceneReader::flatten(std::vector<PrototypePart>& parts, Prototype& proto, const Scene& scene) const {
    for (PrototypePart& part : parts) {
        for (TriangleMesh& m : part.meshes) proto.meshes.push_back(std::move(m));
        if (!part.placed) continue;
        const PlacedPrototype& placed = *part.placed;
        checkPlacementRange(placed, part.ptr);
        appendPlacedCopies(scene.prototypes[placed.prototype], placed.worldFromObject, placed.material, proto.meshes);
    }
}

SceneReader::PlacedPrototype SceneReader::parsePlacement(const Json& j, const std::string& ptr, Scene& scene) {
    checkKeys(j, ptr, {"type", "name", "prototype", "transform", "material"});
    PlacedPrototype placed;
    const std::string pp = child(ptr, "prototype");
    placed.prototype = resolvePrototype(string(require(j, ptr, "prototype", "an instance"), pp), pp, true);
    if (const Json* v = find(j, "transform")) placed.worldFromObject = readTransform(*v, child(ptr, "transform"));
    if (find(j, "material")) placed.material = shapeMaterial(j, ptr, scene);
    return placed;
}

void SceneReader::checkPlacementRange(const PlacedPrototype& placed, const std::string& ptr) const {
    checkRange(instanceBounds(prototypeBounds_.at(placed.prototype), placed.worldFromObject), ptr);
}

void SceneReader::readInstance(const Json& j, const std::string& ptr, Scene& scene) {
    const PlacedPrototype placed = parsePlacement(j, ptr, scene);
    checkPlacementRange(placed, ptr);
    scene.instances.push_back(makeInstance(placed.prototype, placed.worldFromObject, placed.material));
}

}  // namespace penumbra
