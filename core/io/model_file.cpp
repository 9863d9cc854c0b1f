#include "core/io/model_file.h"

#include <algorithm>
#include <cctype>
#include <new>

#include "core/error.h"
#include "core/io/gltf_loader.h"
#include "core/io/obj_loader.h"

namespace penumbra {
namespace fs = std::filesystem;

namespace {

std::string lowerExtension(const fs::path& p) {
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
    return e;
}

}  // namespace

bool isModelExtension(const std::string& extension) {
    std::string e = extension;
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
    return e == ".obj" || isGltfExtension(e) || (e != ".json" && assimpReadsExtension(e));
}

std::string modelFormatsText() {
    std::string text = ".obj, .gltf, .glb";
    for (const std::string& e : assimpExtensions())
        if (e != ".obj" && e != ".json" && !isGltfExtension(e)) text += ", " + e;
    return text;
}

ModelFile appendModelFile(Scene& scene, const InputFile& model, const Transform& worldFromObject,
                          const LoadOptions& options, const Logger& log) {
    const std::string ext = lowerExtension(model.path());
    ModelFile out;
    if (ext == ".obj") {
        out.stats = appendObj(scene, model, worldFromObject, options, log);
    } else if (isGltfExtension(ext)) {
        out.stats = appendGltf(scene, model, worldFromObject, options, log, out.extras);
    } else if (isModelExtension(ext)) {
        out.stats = appendAssimp(scene, model, worldFromObject, options, log, out.extras);
    } else {
        throw Error(ErrorCode::InvalidArgument, model.path().string() + ": unknown mesh format " +
                                                    (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
                                                    " (supported: " + modelFormatsText() + ")");
    }
    return out;
}

LoadedScene loadModelScene(const fs::path& path, const LoadOptions& options, const Logger& log) {
    LoadedScene loaded;
    loaded.sourcePath = path;
    ModelFile model;
    try {
        model = appendModelFile(loaded.scene, *openInputFile(path, options), Transform(), options, log);
    } catch (const std::bad_alloc&) {
        throw Error(ErrorCode::OutOfMemory, path.string() + ": out of memory while loading the scene");
    }
    if (model.stats.triangles == 0)
        throw Error(ErrorCode::InvalidScene,
                    path.string() + ": nothing to render " +
                        (model.stats.droppedFaces ? "(all " + std::to_string(model.stats.droppedFaces) +
                                                        " face(s) were dropped for non-finite or missing vertex positions)"
                                                  : std::string("(the file has no triangles)")));
    loaded.camera = model.extras.camera;
    Scene& s = loaded.scene;
    s.pointLights.insert(s.pointLights.end(), model.extras.pointLights.begin(), model.extras.pointLights.end());
    s.directionalLights.insert(s.directionalLights.end(), model.extras.directionalLights.begin(),
                               model.extras.directionalLights.end());
    return loaded;
}

}  // namespace penumbra
