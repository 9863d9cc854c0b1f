// The JSON "environment" block (SceneReader, json_reader.h): a constant colour
// or a lat-long image, opened here once (the renderer decodes this descriptor).
#include "core/io/input_file.h"
#include "core/io/json_reader.h"

namespace penumbra {
using namespace json_text;

void SceneReader::readEnvironment(const Json& j, const std::string& ptr, Scene& scene) const {
    expectObject(j, ptr);
    checkKeys(j, ptr, {"color", "image", "rotate", "scale"});
    const Json* color = find(j, "color");
    const Json* image = find(j, "image");
    if (color && image) fail(ErrorCode::InvalidScene, ptr, "give \"color\" or \"image\", not both");
    if (!color && !image) fail(ErrorCode::InvalidScene, ptr, "needs \"color\" or \"image\"");
    EnvironmentDesc env;
    if (color) env.color = colour(*color, child(ptr, "color"));
    if (const Json* v = find(j, "scale")) env.scale = nonNegative(*v, child(ptr, "scale"));
    if (const Json* v = find(j, "rotate")) env.rotateDegrees = number(*v, child(ptr, "rotate"));
    if (image) {
        const std::string ip = child(ptr, "image");
        const std::filesystem::path p = resolvePath(*image, ip);
        // Unlike a missing texture, a missing environment is an error: it is the scene's light.
        try {
            env.imageFile = openInputFile(p, options_);
        } catch (const Error& e) {
            fail(e.code(), ip, std::string("environment image ") + e.what());
        }
        env.image = p.string();
    }
    scene.environment = std::move(env);
}

}  // namespace penumbra
