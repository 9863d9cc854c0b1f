// The JSON "camera" and "render" blocks (SceneReader, json_reader.h).
#include "core/io/json_reader.h"

#include <cmath>
#include <limits>
#include <optional>
#include <type_traits>

#include <penumbra/names.hpp>

namespace penumbra {
namespace fs = std::filesystem;
using namespace json_text;

CameraDesc SceneReader::readCamera(const Json& j, const std::string& ptr) const {
    expectObject(j, ptr);
    checkKeys(j, ptr, {"eye", "look_at", "up", "fov", "aperture", "focus_distance"});
    CameraDesc c;
    if (const Json* v = find(j, "eye")) c.eye = vec3(*v, child(ptr, "eye"));
    if (const Json* v = find(j, "look_at")) c.lookAt = vec3(*v, child(ptr, "look_at"));
    if (const Json* v = find(j, "up")) c.up = vec3(*v, child(ptr, "up"));
    if (const Json* v = find(j, "fov")) {
        c.vfovDegrees = number(*v, child(ptr, "fov"));
        if (!(c.vfovDegrees > 0.f && c.vfovDegrees < 180.f))
            fail(ErrorCode::InvalidScene, child(ptr, "fov"), "must lie in (0, 180) degrees");
    }
    if (const Json* v = find(j, "aperture")) c.aperture = nonNegative(*v, child(ptr, "aperture"));
    if (const Json* v = find(j, "focus_distance")) c.focusDistance = nonNegative(*v, child(ptr, "focus_distance"));
    // Overflow would otherwise read as "the same point" or "up is parallel" below.
    if (!std::isfinite(lengthSquared(c.lookAt - c.eye)))
        fail(ErrorCode::InvalidScene, ptr,
             "\"eye\" and \"look_at\" are too far apart: their distance overflows a 32-bit float");
    if (!std::isfinite(lengthSquared(c.up)))
        fail(ErrorCode::InvalidScene, child(ptr, "up"),
             "too long: its length overflows a 32-bit float (a direction of length 1 will do)");
    try {
        validateCamera(c);
    } catch (const Error& e) {
        std::string msg = e.what();
        if (msg.rfind("camera: ", 0) == 0) msg = msg.substr(8);  // the pointer already says so
        fail(ErrorCode::InvalidScene, ptr, msg);
    }
    return c;
}

SettingsPatch SceneReader::readRender(const Json& j, const std::string& ptr) const {
    expectObject(j, ptr);
    checkKeys(j, ptr,
              {"width", "height", "spp", "light_samples", "max_depth", "seed", "threads", "tile_size",
               "light_selection", "integrator"});
    SettingsPatch p;
    // The ranges are those of validateSettings, so a loaded patch always validates.
    auto intKey = [&](const char* key, std::optional<int>& dst, int64_t lo, int64_t hi) {
        if (const Json* v = find(j, key)) dst = static_cast<int>(integer(*v, child(ptr, key), lo, hi));
    };
    // An enum setting, spelled as pnb::EnumNames spells it.
    auto enumKey = [&](const char* key, auto& dst) {
        using E = typename std::remove_reference_t<decltype(dst)>::value_type;
        if (const Json* v = find(j, key)) {
            const std::string kp = child(ptr, key);
            const std::string s = string(*v, kp);
            if (const std::optional<E> e = pnb::enumFromName<E>(s))
                dst = *e;
            else
                fail(ErrorCode::InvalidScene, kp, "must be " + pnb::enumNameList<E>("\"") + ", got " + quotedValue(s));
        }
    };
    intKey("width", p.width, 1, 1 << 16);
    intKey("height", p.height, 1, 1 << 16);
    intKey("spp", p.spp, 1, 1 << 20);
    intKey("light_samples", p.lightSamples, 1, 1 << 16);
    intKey("max_depth", p.maxDepth, 0, 1000000);
    intKey("threads", p.threads, 0, 4096);
    intKey("tile_size", p.tileSize, 1, 4096);
    if (const Json* v = find(j, "seed")) {
        std::string sp = child(ptr, "seed");
        if (v->is_number_unsigned())
            p.seed = v->get<uint64_t>();
        else
            p.seed = static_cast<uint64_t>(integer(*v, sp, 0, std::numeric_limits<int64_t>::max()));
    }
    enumKey("light_selection", p.lightSelection);
    enumKey("integrator", p.integrator);
    return p;
}
}  // namespace penumbra
