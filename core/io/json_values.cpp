// Errors and basic accessors of the JSON scene reader (SceneReader, json_reader.h).
#include "core/io/json_reader.h"

#include <cmath>
#include <limits>

#include "core/io/path_policy.h"
#include "core/scene_range.h"

namespace penumbra {
namespace fs = std::filesystem;
using namespace json_text;

void SceneReader::fail(ErrorCode code, const std::string& ptr, const std::string& msg) const {
    throw Error(code, oneLine(ptr.empty() ? file_ + ": " + msg : file_ + ": " + shortPointer(ptr) + ": " + msg));
}

void SceneReader::warnOrFail(ErrorCode code, const std::string& ptr, const std::string& msg) const {
    if (options_.strict) fail(code, ptr, msg);
    log_.warn(oneLine(file_ + ": " + shortPointer(ptr) + ": " + msg));
}

std::string SceneReader::typeName(const Json& j) {
    if (j.is_number()) return "a number";
    if (j.is_boolean()) return "a boolean";
    if (j.is_string()) return "a string";
    if (j.is_array()) return "an array";
    if (j.is_object()) return "an object";
    return "null";
}

void SceneReader::expectType(const Json& j, const std::string& ptr, Json::value_t type, const char* what) const {
    if (j.type() != type) fail(ErrorCode::ParseError, ptr, std::string("expected ") + what + ", got " + typeName(j));
}

const Json* SceneReader::find(const Json& obj, const char* key) {
    auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
}

const Json& SceneReader::require(const Json& obj, const std::string& ptr, const char* key, const char* what) const {
    const Json* j = find(obj, key);
    if (!j) fail(ErrorCode::ParseError, child(ptr, key), std::string("missing (required for ") + what + ")");
    return *j;
}

void SceneReader::checkKeys(const Json& obj, const std::string& ptr, Keys allowed) const {
    checkKeys(obj, ptr, std::span<const std::string_view>(allowed.begin(), allowed.size()));
}

void SceneReader::checkKeys(const Json& obj, const std::string& ptr, std::span<const std::string_view> allowed) const {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
        bool known = false;
        for (std::string_view k : allowed) known = known || it.key() == k;
        if (known) continue;
        std::string list;
        for (std::string_view k : allowed) list += (list.empty() ? "" : ", ") + std::string(k);
        fail(ErrorCode::ParseError, child(ptr, it.key()), "unknown key (expected one of: " + list + ")");
    }
}

void SceneReader::expectObject(const Json& j, const std::string& ptr) const {
    expectType(j, ptr, Json::value_t::object, "an object");
}

float SceneReader::number(const Json& j, const std::string& ptr) const {
    if (!j.is_number()) fail(ErrorCode::ParseError, ptr, "expected a number, got " + typeName(j));
    float v = static_cast<float>(j.get<double>());
    if (!std::isfinite(v)) fail(ErrorCode::InvalidScene, ptr, "must be finite (fits in a 32-bit float)");
    return v;
}

float SceneReader::positive(const Json& j, const std::string& ptr) const {
    float v = number(j, ptr);
    if (!(v > 0.f)) fail(ErrorCode::InvalidScene, ptr, "must be > 0");
    return v;
}

float SceneReader::nonNegative(const Json& j, const std::string& ptr) const {
    float v = number(j, ptr);
    if (!(v >= 0.f)) fail(ErrorCode::InvalidScene, ptr, "must be >= 0");
    return v;
}

int64_t SceneReader::integer(const Json& j, const std::string& ptr, int64_t lo, int64_t hi) const {
    std::string range = "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    if (j.is_number_unsigned()) {
        uint64_t u = j.get<uint64_t>();
        if (u > static_cast<uint64_t>(hi) || static_cast<int64_t>(u) < lo) fail(ErrorCode::InvalidScene, ptr, range);
        return static_cast<int64_t>(u);
    }
    int64_t v = 0;
    if (j.is_number_integer()) {
        v = j.get<int64_t>();
    } else if (j.is_number_float()) {
        double d = j.get<double>();
        if (!std::isfinite(d) || d != std::floor(d)) fail(ErrorCode::ParseError, ptr, "expected an integer");
        // Above 2^53 a number written with a fraction or exponent is not the integer it shows
        // (9223372036854775807.0 reads as 2^63, which int64 cannot hold): refuse, never convert.
        if (std::fabs(d) > 0x1p53)
            fail(ErrorCode::ParseError, ptr,
                 "integer written as a floating-point number is too large to be exact (above 2^53); "
                 "write it without a fraction or exponent");
        if (d < static_cast<double>(lo) || d > static_cast<double>(hi)) fail(ErrorCode::InvalidScene, ptr, range);
        v = static_cast<int64_t>(d);
    } else {
        fail(ErrorCode::ParseError, ptr, "expected an integer, got " + typeName(j));
    }
    if (v < lo || v > hi) fail(ErrorCode::InvalidScene, ptr, range);
    return v;
}

bool SceneReader::boolean(const Json& j, const std::string& ptr) const {
    if (!j.is_boolean()) fail(ErrorCode::ParseError, ptr, "expected true or false, got " + typeName(j));
    return j.get<bool>();
}

std::string SceneReader::string(const Json& j, const std::string& ptr) const {
    if (!j.is_string()) fail(ErrorCode::ParseError, ptr, "expected a string, got " + typeName(j));
    return j.get<std::string>();
}

Vec3f SceneReader::vec3(const Json& j, const std::string& ptr) const {
    if (!j.is_array() || j.size() != 3) fail(ErrorCode::ParseError, ptr, "expected an array of 3 numbers [x, y, z]");
    float v[3];
    for (size_t k = 0; k < 3; ++k) {
        // The pointer of a component is built only for its error (a million spheres, three each).
        if (j[k].is_number() && std::isfinite(v[k] = static_cast<float>(j[k].get<double>()))) continue;
        v[k] = number(j[k], child(ptr, k));
    }
    return {v[0], v[1], v[2]};
}

Vec3f SceneReader::nonZeroVec3(const Json& j, const std::string& ptr) const {
    Vec3f v = vec3(j, ptr);
    if (!std::isfinite(lengthSquared(v)))
        fail(ErrorCode::InvalidScene, ptr, "too long: its length overflows a 32-bit float (a direction of length 1 will do)");
    if (!(lengthSquared(v) > 0.f)) fail(ErrorCode::InvalidScene, ptr, "must not be the zero vector");
    return v;
}

Rgb SceneReader::colour(const Json& j, const std::string& ptr) const {
    if (j.is_number()) return Rgb(nonNegative(j, ptr));
    if (!j.is_array() || j.size() != 3)
        fail(ErrorCode::ParseError, ptr, "expected a colour: [r, g, b] or one number, got " + typeName(j));
    float c[3];
    for (size_t k = 0; k < 3; ++k) {
        if (j[k].is_number() && (c[k] = static_cast<float>(j[k].get<double>())) >= 0.f && std::isfinite(c[k])) continue;
        c[k] = nonNegative(j[k], child(ptr, k));
    }
    return {c[0], c[1], c[2]};
}

fs::path SceneReader::resolvePath(const Json& j, const std::string& ptr) const {
    std::string s = string(j, ptr);
    if (s.empty()) fail(ErrorCode::InvalidScene, ptr, "must not be empty");
    fs::path p(s);
    if (p.is_relative()) p = dir_ / p;
    p = p.lexically_normal();
    try {
        checkPathAllowed(p, options_, /*willRead=*/false);  // the open checks the file read
    } catch (const Error& e) {
        fail(e.code(), ptr, e.what());
    }
    return p;
}
}  // namespace penumbra

namespace penumbra {

void SceneReader::checkRange(const Bounds3f& b, const std::string& ptr) const {
    if (!withinSceneRange(b))
        fail(ErrorCode::InvalidScene, ptr,
             "reaches beyond +-1.8e18, the largest coordinate the accelerators represent (it would not render)");
}

}  // namespace penumbra
