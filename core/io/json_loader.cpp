// The JSON scene file as a whole: opened once, parsed (json_document.cpp),
// then read top-down by SceneReader (json_*.cpp).
#include "core/io/json_loader.h"

#include <new>

#include "core/io/input_file.h"
#include "core/io/json_reader.h"

namespace penumbra {
using namespace json_text;

LoadedScene SceneReader::read(const Json& root) {
    LoadedScene out;
    out.sourcePath = path_;
    if (!root.is_object()) fail(ErrorCode::ParseError, "", "the top level must be a JSON object, got " + typeName(root));
    checkKeys(root, "", {"camera", "render", "background", "ambient", "materials", "shapes", "lights", "prototypes",
                         "environment"});
    Scene& scene = out.scene;
    // Materials first: shapes refer to them by name wherever they appear in the file.
    if (const Json* m = find(root, "materials")) readMaterials(*m, "/materials", scene);
    if (const Json* c = find(root, "camera")) out.camera = readCamera(*c, "/camera");
    if (const Json* r = find(root, "render")) out.settings = readRender(*r, "/render");
    if (const Json* b = find(root, "background")) scene.background = colour(*b, "/background");
    if (const Json* a = find(root, "ambient")) scene.ambient = colour(*a, "/ambient");
    // Prototypes before shapes: instances name them.
    if (const Json* p = find(root, "prototypes")) readPrototypes(*p, "/prototypes", scene);
    if (const Json* e = find(root, "environment")) readEnvironment(*e, "/environment", scene);
    if (const Json* s = find(root, "shapes")) {
        expectType(*s, "/shapes", Json::value_t::array, "an array");
        for (size_t i = 0; i < s->size(); ++i) readShape((*s)[i], child("/shapes", i), scene);
    }
    if (const Json* l = find(root, "lights")) {
        expectType(*l, "/lights", Json::value_t::array, "an array");
        for (size_t i = 0; i < l->size(); ++i) readLight((*l)[i], child("/lights", i), scene);
    } else {
        scene.pointLights.insert(scene.pointLights.end(), modelPointLights_.begin(), modelPointLights_.end());
        scene.directionalLights.insert(scene.directionalLights.end(), modelDirectionalLights_.begin(),
                                       modelDirectionalLights_.end());
    }
    if (!out.camera) out.camera = modelCamera_;
    scene.countExpansion(copies_);  // Scene::finalize's copies, refused here with the file's name
    copies_.check(file_ + ": nested prototypes and emissive instances");
    log_.debug(file_ + ": " + std::to_string(scene.primitiveCount()) + " primitive(s), " +
               std::to_string(scene.materials.size()) + " material(s)");
    return out;
}

LoadedScene loadJsonScene(const std::filesystem::path& path, const LoadOptions& options, const Logger& log) {
    const std::string file = path.string();
    try {
        // A scene "file" that is a directory or FIFO is reported like a missing one (FileNotFound).
        std::string text = openInputFile(path, options, ErrorCode::FileNotFound)->readAll();
        Json root = parseJsonDocument(text, file);
        text = std::string();  // the document holds everything from here on
        SceneReader reader(path, options, log);
        return reader.read(root);
    } catch (const Error&) {
        throw;
    } catch (const nlohmann::json::exception& e) {
        throw Error(ErrorCode::ParseError, file + ": " + e.what());
    } catch (const std::bad_alloc&) {
        throw Error(ErrorCode::OutOfMemory, file + ": out of memory while loading the scene");
    } catch (const std::filesystem::filesystem_error& e) {
        throw Error(ErrorCode::IoError, file + ": " + e.what());
    } catch (const std::exception& e) {
        throw Error(ErrorCode::Internal, file + ": " + e.what());
    }
}

}  // namespace penumbra
