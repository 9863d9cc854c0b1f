// The JSON scene reader (docs/scene-format.md): walks a parsed document and
// fills a LoadedScene, validating every key; errors name the file and the JSON
// pointer of the value. One class, its members defined by topic in the
// json_*.cpp files beside this header (internal to core/io).
#pragma once

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "core/io/json_document.h"
#include "core/io/json_text.h"
#include "core/io/loaded_scene.h"
#include "core/log.h"

namespace penumbra {

class SceneReader {
public:
    using Keys = std::initializer_list<std::string_view>;

    SceneReader(const std::filesystem::path& path, const LoadOptions& options, const Logger& log)
        : path_(path), dir_(path.parent_path()), file_(path.string()), options_(options), log_(log) {}

    // ---- the whole file (json_loader.cpp)
    LoadedScene read(const Json& root);

private:
    // ---- errors and basic accessors (json_values.cpp)
    [[noreturn]] void fail(ErrorCode code, const std::string& ptr, const std::string& msg) const;
    /// A problem that is skipped with a warning, or an error in strict mode.
    void warnOrFail(ErrorCode code, const std::string& ptr, const std::string& msg) const;
    static std::string typeName(const Json& j);
    void expectType(const Json& j, const std::string& ptr, Json::value_t type, const char* what) const;
    static const Json* find(const Json& obj, const char* key);
    const Json& require(const Json& obj, const std::string& ptr, const char* key, const char* what) const;
    /// Rejects keys outside `allowed`, listing the accepted ones.
    void checkKeys(const Json& obj, const std::string& ptr, Keys allowed) const;
    void checkKeys(const Json& obj, const std::string& ptr, std::span<const std::string_view> allowed) const;
    void expectObject(const Json& j, const std::string& ptr) const;
    /// A finite number (finite also after narrowing to float).
    float number(const Json& j, const std::string& ptr) const;
    float positive(const Json& j, const std::string& ptr) const;
    float nonNegative(const Json& j, const std::string& ptr) const;
    /// An integer in [lo, hi]; integral floating-point literals (512.0) are accepted.
    int64_t integer(const Json& j, const std::string& ptr, int64_t lo, int64_t hi) const;
    bool boolean(const Json& j, const std::string& ptr) const;
    std::string string(const Json& j, const std::string& ptr) const;
    Vec3f vec3(const Json& j, const std::string& ptr) const;
    Vec3f nonZeroVec3(const Json& j, const std::string& ptr) const;
    /// [r, g, b] or one number for grey; every component finite and >= 0.
    Rgb colour(const Json& j, const std::string& ptr) const;
    /// Relative paths are relative to the scene file's folder; every path is
    /// checked against the allowed roots before anything reads it.
    std::filesystem::path resolvePath(const Json& j, const std::string& ptr) const;

    // ---- camera and render settings (json_camera.cpp)
    CameraDesc readCamera(const Json& j, const std::string& ptr) const;
    SettingsPatch readRender(const Json& j, const std::string& ptr) const;

    // ---- materials (json_materials.cpp)
    void readMaterials(const Json& j, const std::string& ptr, Scene& scene);
    void addMaterial(Material m, const std::string& ptr, Scene& scene);
    Material readMaterial(const Json& j, const std::string& ptr, const std::string& name, bool named, Scene& scene);
    void readPhong(const Json& j, const std::string& ptr, Material& m, Scene& scene);
    void readMetalRoughness(const Json& j, const std::string& ptr, Material& m, Scene& scene);
    /// The keys of both models: normal or bump map, emission map, opacity, alpha mode.
    void readSharedMaps(const Json& j, const std::string& ptr, Material& m, Scene& scene);
    /// The texture slot material[key] (a file name, or an object with "file"
    /// and sampling keys) into `slot`, resolved; an unused ref when absent.
    TextureRef textureSlot(const Json& material, const std::string& materialPtr, const char* key,
                           TextureColorSpace space, int defaultChannel, TextureSlot& slot, Scene& scene);
    /// texture() for a slot's file; the slot's path becomes the file's (empty when unusable).
    int slotFile(const Json& j, const std::string& ptr, TextureColorSpace space, TextureSlot& slot, Scene& scene) const;
    /// Index of the texture in Scene::textures (shared by materials naming the
    /// same file), or -1 when the file is missing and that is only a warning.
    int texture(const Json& j, const std::string& ptr, Scene& scene, TextureColorSpace space) const;
    /// The material a shape without "material" gets: the file's "default", or a new grey one.
    uint32_t defaultMaterial(Scene& scene);
    uint32_t emissiveCopy(uint32_t base, const Rgb& ke, const std::string& ptr, Scene& scene) const;
    /// "material" (or the default), made private and emissive by "emission".
    uint32_t shapeMaterial(const Json& j, const std::string& ptr, Scene& scene);

    // ---- transforms (json_transform.cpp)
    Transform readTransform(const Json& j, const std::string& ptr) const;
    Transform rotation(const Json& j, const std::string& ptr) const;

    // ---- shapes (json_shapes.cpp)
    void readShape(const Json& j, const std::string& ptr, Scene& scene);
    Rectangle rectangle(const Json& j, const std::string& ptr) const;
    Disk disk(const Json& j, const std::string& ptr) const;

    // ---- meshes (model files and inline) (json_meshes.cpp)
    void readObjMesh(const Json& j, const std::string& ptr, Scene& scene);
    /// Numbers of an array given either nested ([[x, y, z], ...]) or flat
    /// ([x, y, z, ...]), flattened; T is float (finite numbers) or uint32_t (indices).
    template <class T>
    std::vector<T> tuples(const Json& j, const std::string& ptr, size_t arity, const char* what) const;
    void readInlineMesh(const Json& j, const std::string& ptr, Scene& scene);

    // ---- lights (json_lights.cpp)
    void readLight(const Json& j, const std::string& ptr, Scene& scene);
    /// An area light is an emitting shape: black, non-reflective, ke = radiance.
    uint32_t lightMaterial(const Json& j, const std::string& ptr, Scene& scene) const;

    // ---- prototypes and instances (json_instances.cpp)
    struct PrototypeEntry {
        const Json* json = nullptr;
        std::string ptr;
        std::optional<uint32_t> index;  // in Scene::prototypes, once read
    };
    struct PlacedPrototype {
        uint32_t prototype = 0;
        Transform worldFromObject;
        uint32_t material = kNoMaterialOverride;
    };
    /// One shape of a prototype as read: its meshes, or a placement of another prototype.
    struct PrototypePart {
        std::vector<TriangleMesh> meshes;
        std::optional<PlacedPrototype> placed;
        std::string ptr;
    };
    void readPrototypes(const Json& j, const std::string& ptr, Scene& scene);
    /// The prototypes that `e` places, with the JSON pointer of each name.
    std::vector<std::pair<std::string, std::string>> placedPrototypes(const PrototypeEntry& e) const;
    /// Every prototype's name, each after the prototypes it places; refuses
    /// unknown names and cycles. A loop with a stack of its own (no recursion).
    std::vector<std::string> prototypeOrder(const Json& j) const;
    /// Index in Scene::prototypes of the prototype `name` (`read`: it has been
    /// read; else only its existence is checked); refPtr is where the name was given.
    uint32_t resolvePrototype(const std::string& name, const std::string& refPtr, bool read) const;
    /// A prototype's shapes in order: meshes read, placements parsed, nothing copied.
    std::vector<PrototypePart> readPrototypeParts(const PrototypeEntry& e, Scene& scene);
    /// Fills `proto` with the parts' meshes and copies of the prototypes they place.
    void flatten(std::vector<PrototypePart>& parts, Prototype& proto, const Scene& scene) const;
    /// The keys of an "instance" entry, checked.
    PlacedPrototype parsePlacement(const Json& j, const std::string& ptr, Scene& scene);
    /// Refuses a placement reaching beyond what the accelerators represent.
    void checkPlacementRange(const PlacedPrototype& placed, const std::string& ptr) const;
    void readInstance(const Json& j, const std::string& ptr, Scene& scene);
    // ---- the environment light (json_environment.cpp)
    void readEnvironment(const Json& j, const std::string& ptr, Scene& scene) const;

    /// Refuses a shape whose bounds reach beyond what the accelerators represent.
    void checkRange(const Bounds3f& b, const std::string& ptr) const;

    std::filesystem::path path_, dir_;
    std::string file_;
    const LoadOptions& options_;
    const Logger& log_;
    std::map<std::string, uint32_t> names_;  // JSON material name -> Scene::materials index
    std::map<std::string, PrototypeEntry> prototypeEntries_;  // by name
    CopyCount copies_;                       // the copies the file asks for (core/instance.h)
    std::vector<Bounds3f> prototypeBounds_;  // by Scene::prototypes index, once flattened
    // What model files named by meshes say of the view and the lights.
    std::optional<CameraDesc> modelCamera_;
    std::vector<PointLight> modelPointLights_;
    std::vector<DirectionalLight> modelDirectionalLights_;
};

}  // namespace penumbra
