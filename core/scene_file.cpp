// The JSON scene format (docs/scene-format.md). The file is parsed into a DOM
// with nlohmann::ordered_json (so materials keep their file order and errors
// come in file order), then walked by SceneReader, which validates every key
// and reports problems with the file name and the JSON pointer of the value.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <new>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <unordered_set>
#include <vector>

#include "core/error.h"
#include "core/scene_loader.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using Keys = std::initializer_list<std::string_view>;

// Keys and names quoted in messages are cut to this many bytes: a message stays
// readable however long the file's strings are.
constexpr size_t kMaxQuoted = 64;

/// Escapes one reference token of a JSON pointer (RFC 6901: '~' -> "~0", '/' -> "~1").
std::string pointerToken(std::string_view key) {
    std::string out;
    const bool cut = key.size() > kMaxQuoted;
    key = key.substr(0, kMaxQuoted);
    out.reserve(key.size() + 3);
    for (char c : key) {
        if (c == '~')
            out += "~0";
        else if (c == '/')
            out += "~1";
        else
            out += c;
    }
    if (cut) out += "...";
    return out;
}

/// A string from the file, in double quotes, cut to kMaxQuoted bytes.
std::string quotedValue(std::string_view s) {
    return "\"" + std::string(s.substr(0, kMaxQuoted)) + (s.size() > kMaxQuoted ? "...\"" : "\"");
}

/// Control characters (a JSON string may hold "\n") would split the one-line message.
std::string oneLine(std::string s) {
    for (char& c : s)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    return s;
}

std::string child(const std::string& ptr, std::string_view key) { return ptr + "/" + pointerToken(key); }
std::string child(const std::string& ptr, size_t index) { return ptr + "/" + std::to_string(index); }

/// 1-based line and column of a 0-based byte offset (clamped to the end of the text).
std::pair<size_t, size_t> lineColumn(const std::string& text, size_t offset) {
    offset = std::min(offset, text.size());
    size_t line = 1, lineStart = 0;
    for (size_t i = 0; i < offset; ++i) {
        if (text[i] == '\n') {
            ++line;
            lineStart = i + 1;
        }
    }
    return {line, offset - lineStart + 1};
}

/// Caps text quoted from the file (nlohmann quotes whole tokens: a 10 MB string
/// or number would make a 10 MB message) and keeps the message on one line.
std::string shortened(std::string s) {
    constexpr size_t kMax = 200;
    if (s.size() > kMax) s = s.substr(0, kMax) + "...";
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    return s;
}

/// nlohmann's message without its "[json.exception...] parse error at line L, column C: "
/// prefix (its line/column count the character after the error, so we compute our own).
std::string parseErrorDetail(const std::string& what) {
    std::string s = what;
    if (auto close = s.find("] "); s.rfind("[json.exception", 0) == 0 && close != std::string::npos) s = s.substr(close + 2);
    if (s.rfind("parse error", 0) == 0) {
        if (auto colon = s.find(": "); colon != std::string::npos) s = s.substr(colon + 2);
    }
    if (s.rfind("syntax error ", 0) == 0) s = s.substr(13);
    return shortened(s);
}

/// Where a number literal that overflowed (nlohmann reports no position for
/// that) first appears as a whole token; npos when it cannot be found.
size_t findNumberToken(const std::string& text, const std::string& token) {
    auto isNumberChar = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+'; };
    for (size_t pos = text.find(token); pos != std::string::npos; pos = text.find(token, pos + 1)) {
        bool startOk = pos == 0 || !isNumberChar(text[pos - 1]);
        size_t end = pos + token.size();
        bool endOk = end >= text.size() || !isNumberChar(text[end]);
        if (startOk && endOk) return pos;
    }
    return std::string::npos;
}

/// Tracks the JSON pointer of the value being parsed so that duplicate keys,
/// which nlohmann silently resolves to the last one, can be reported.
class DuplicateKeyCheck {
public:
    explicit DuplicateKeyCheck(std::string file) : file_(std::move(file)) {}

    bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
        using E = Json::parse_event_t;
        switch (event) {
            case E::object_start:
                startElement();
                stack_.push_back(Frame{false, {}, 0, {}});
                break;
            case E::array_start:
                startElement();
                stack_.push_back(Frame{true, {}, 0, {}});
                break;
            case E::object_end:
            case E::array_end:
                if (!stack_.empty()) stack_.pop_back();
                break;
            case E::key: {
                Frame& top = stack_.back();
                top.key = parsed.get<std::string>();
                if (!top.keys.insert(top.key).second)
                    throw Error(ErrorCode::ParseError, oneLine(file_ + ": " + pointer() + ": duplicate key"));
                break;
            }
            case E::value:
                startElement();
                break;
        }
        return true;
    }

private:
    struct Frame {
        bool isArray;
        std::string key;  // objects: the key being parsed
        size_t count;     // arrays: elements started so far
        std::unordered_set<std::string> keys;
    };

    void startElement() {
        if (!stack_.empty() && stack_.back().isArray) ++stack_.back().count;
    }
    std::string pointer() const {
        std::string p;
        for (const Frame& f : stack_) p = f.isArray ? child(p, f.count - 1) : child(p, f.key);
        return p;
    }

    std::string file_;
    std::vector<Frame> stack_;
};

/// Reads a file whole; FileNotFound for a missing file or a directory.
std::string readText(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw Error(ErrorCode::FileNotFound, path.string() + ": file not found");
    if (fs::is_directory(path, ec))
        throw Error(ErrorCode::FileNotFound, path.string() + ": is a directory, not a scene file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorCode::IoError, path.string() + ": cannot open for reading");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw Error(ErrorCode::IoError, path.string() + ": read failed");
    return ss.str();
}

Json parseJson(const std::string& text, const std::string& file) {
    try {
        return Json::parse(text, DuplicateKeyCheck(file), /*allow_exceptions=*/true, /*ignore_comments=*/true);
    } catch (const nlohmann::json::parse_error& e) {
        // e.byte counts the characters read, the offending one included.
        size_t offset = e.byte > 0 ? static_cast<size_t>(e.byte) - 1 : 0;
        auto [line, col] = lineColumn(text, offset);
        throw Error(ErrorCode::ParseError, file + ":" + std::to_string(line) + ":" + std::to_string(col) +
                                               ": JSON syntax error: " + parseErrorDetail(e.what()));
    } catch (const nlohmann::json::out_of_range& e) {
        // Number overflow ("1e999"): nlohmann gives the literal but no position.
        std::string what = e.what(), where = file;
        if (auto q0 = what.find('\''), q1 = what.rfind('\''); q0 != std::string::npos && q1 > q0) {
            size_t pos = findNumberToken(text, what.substr(q0 + 1, q1 - q0 - 1));
            if (pos != std::string::npos) {
                auto [line, col] = lineColumn(text, pos);
                where += ":" + std::to_string(line) + ":" + std::to_string(col);
            }
        }
        throw Error(ErrorCode::ParseError, where + ": JSON number out of range: " + parseErrorDetail(what));
    }
}

/// Walks the parsed document and fills a LoadedScene. Every accessor takes the
/// JSON pointer of the value it reads, for error messages.
class SceneReader {
public:
    SceneReader(const fs::path& path, const LoadOptions& options, const Logger& log)
        : path_(path), dir_(path.parent_path()), file_(path.string()), options_(options), log_(log) {}

    LoadedScene read(const Json& root) {
        LoadedScene out;
        out.sourcePath = path_;
        if (!root.is_object()) fail(ErrorCode::ParseError, "", "the top level must be a JSON object, got " + typeName(root));
        checkKeys(root, "", {"camera", "render", "background", "ambient", "materials", "shapes", "lights"});
        Scene& scene = out.scene;
        // Materials first: shapes refer to them by name wherever they appear in the file.
        if (const Json* m = find(root, "materials")) readMaterials(*m, "/materials", scene);
        if (const Json* c = find(root, "camera")) out.camera = readCamera(*c, "/camera");
        if (const Json* r = find(root, "render")) out.settings = readRender(*r, "/render");
        if (const Json* b = find(root, "background")) scene.background = colour(*b, "/background");
        if (const Json* a = find(root, "ambient")) scene.ambient = colour(*a, "/ambient");
        if (const Json* s = find(root, "shapes")) {
            expectType(*s, "/shapes", Json::value_t::array, "an array");
            for (size_t i = 0; i < s->size(); ++i) readShape((*s)[i], child("/shapes", i), scene);
        }
        if (const Json* l = find(root, "lights")) {
            expectType(*l, "/lights", Json::value_t::array, "an array");
            for (size_t i = 0; i < l->size(); ++i) readLight((*l)[i], child("/lights", i), scene);
        }
        log_.debug(file_ + ": " + std::to_string(scene.primitiveCount()) + " primitive(s), " +
                   std::to_string(scene.materials.size()) + " material(s)");
        return out;
    }

private:
    // ---- errors and basic accessors -------------------------------------------------

    [[noreturn]] void fail(ErrorCode code, const std::string& ptr, const std::string& msg) const {
        throw Error(code, oneLine(ptr.empty() ? file_ + ": " + msg : file_ + ": " + ptr + ": " + msg));
    }

    /// A problem that is skipped with a warning, or an error in strict mode.
    void warnOrFail(ErrorCode code, const std::string& ptr, const std::string& msg) const {
        if (options_.strict) fail(code, ptr, msg);
        log_.warn(oneLine(file_ + ": " + ptr + ": " + msg));
    }

    static std::string typeName(const Json& j) {
        if (j.is_number()) return "a number";
        if (j.is_boolean()) return "a boolean";
        if (j.is_string()) return "a string";
        if (j.is_array()) return "an array";
        if (j.is_object()) return "an object";
        return "null";
    }

    void expectType(const Json& j, const std::string& ptr, Json::value_t type, const char* what) const {
        if (j.type() != type) fail(ErrorCode::ParseError, ptr, std::string("expected ") + what + ", got " + typeName(j));
    }

    static const Json* find(const Json& obj, const char* key) {
        auto it = obj.find(key);
        return it == obj.end() ? nullptr : &*it;
    }

    const Json& require(const Json& obj, const std::string& ptr, const char* key, const char* what) const {
        const Json* j = find(obj, key);
        if (!j) fail(ErrorCode::ParseError, child(ptr, key), std::string("missing (required for ") + what + ")");
        return *j;
    }

    /// Rejects keys outside `allowed`, listing the accepted ones.
    void checkKeys(const Json& obj, const std::string& ptr, Keys allowed) const {
        for (auto it = obj.begin(); it != obj.end(); ++it) {
            bool known = false;
            for (std::string_view k : allowed) known = known || it.key() == k;
            if (known) continue;
            std::string list;
            for (std::string_view k : allowed) list += (list.empty() ? "" : ", ") + std::string(k);
            fail(ErrorCode::ParseError, child(ptr, it.key()), "unknown key (expected one of: " + list + ")");
        }
    }

    void expectObject(const Json& j, const std::string& ptr) const {
        expectType(j, ptr, Json::value_t::object, "an object");
    }

    /// A finite number (finite also after narrowing to float).
    float number(const Json& j, const std::string& ptr) const {
        if (!j.is_number()) fail(ErrorCode::ParseError, ptr, "expected a number, got " + typeName(j));
        float v = static_cast<float>(j.get<double>());
        if (!std::isfinite(v)) fail(ErrorCode::InvalidScene, ptr, "must be finite (fits in a 32-bit float)");
        return v;
    }

    float positive(const Json& j, const std::string& ptr) const {
        float v = number(j, ptr);
        if (!(v > 0.f)) fail(ErrorCode::InvalidScene, ptr, "must be > 0");
        return v;
    }

    float nonNegative(const Json& j, const std::string& ptr) const {
        float v = number(j, ptr);
        if (!(v >= 0.f)) fail(ErrorCode::InvalidScene, ptr, "must be >= 0");
        return v;
    }

    /// An integer in [lo, hi]; integral floating-point literals (512.0) are accepted.
    int64_t integer(const Json& j, const std::string& ptr, int64_t lo, int64_t hi) const {
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
            if (d < static_cast<double>(lo) || d > static_cast<double>(hi)) fail(ErrorCode::InvalidScene, ptr, range);
            v = static_cast<int64_t>(d);
        } else {
            fail(ErrorCode::ParseError, ptr, "expected an integer, got " + typeName(j));
        }
        if (v < lo || v > hi) fail(ErrorCode::InvalidScene, ptr, range);
        return v;
    }

    bool boolean(const Json& j, const std::string& ptr) const {
        if (!j.is_boolean()) fail(ErrorCode::ParseError, ptr, "expected true or false, got " + typeName(j));
        return j.get<bool>();
    }

    std::string string(const Json& j, const std::string& ptr) const {
        if (!j.is_string()) fail(ErrorCode::ParseError, ptr, "expected a string, got " + typeName(j));
        return j.get<std::string>();
    }

    Vec3f vec3(const Json& j, const std::string& ptr) const {
        if (!j.is_array() || j.size() != 3) fail(ErrorCode::ParseError, ptr, "expected an array of 3 numbers [x, y, z]");
        return {number(j[0], child(ptr, 0)), number(j[1], child(ptr, 1)), number(j[2], child(ptr, 2))};
    }

    Vec3f nonZeroVec3(const Json& j, const std::string& ptr) const {
        Vec3f v = vec3(j, ptr);
        if (!(lengthSquared(v) > 0.f)) fail(ErrorCode::InvalidScene, ptr, "must not be the zero vector");
        return v;
    }

    /// [r, g, b] or one number for grey; every component finite and >= 0.
    Rgb colour(const Json& j, const std::string& ptr) const {
        if (j.is_number()) return Rgb(nonNegative(j, ptr));
        if (!j.is_array() || j.size() != 3)
            fail(ErrorCode::ParseError, ptr, "expected a colour: [r, g, b] or one number, got " + typeName(j));
        return {nonNegative(j[0], child(ptr, 0)), nonNegative(j[1], child(ptr, 1)), nonNegative(j[2], child(ptr, 2))};
    }

    /// Relative paths are relative to the scene file's folder; every path is
    /// checked against the allowed roots before anything reads it.
    fs::path resolvePath(const Json& j, const std::string& ptr) const {
        std::string s = string(j, ptr);
        if (s.empty()) fail(ErrorCode::InvalidScene, ptr, "must not be empty");
        fs::path p(s);
        if (p.is_relative()) p = dir_ / p;
        p = p.lexically_normal();
        try {
            checkPathAllowed(p, options_);
        } catch (const Error& e) {
            fail(e.code(), ptr, e.what());
        }
        return p;
    }

    // ---- camera and render settings --------------------------------------------------

    CameraDesc readCamera(const Json& j, const std::string& ptr) const {
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
        try {
            validateCamera(c);
        } catch (const Error& e) {
            std::string msg = e.what();
            if (msg.rfind("camera: ", 0) == 0) msg = msg.substr(8);  // the pointer already says so
            fail(ErrorCode::InvalidScene, ptr, msg);
        }
        return c;
    }

    SettingsPatch readRender(const Json& j, const std::string& ptr) const {
        expectObject(j, ptr);
        checkKeys(j, ptr,
                  {"width", "height", "spp", "light_samples", "max_depth", "seed", "threads", "tile_size",
                   "light_selection"});
        SettingsPatch p;
        // The ranges are those of validateSettings, so a loaded patch always validates.
        auto intKey = [&](const char* key, std::optional<int>& dst, int64_t lo, int64_t hi) {
            if (const Json* v = find(j, key)) dst = static_cast<int>(integer(*v, child(ptr, key), lo, hi));
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
        if (const Json* v = find(j, "light_selection")) {
            std::string sp = child(ptr, "light_selection");
            std::string s = string(*v, sp);
            if (s == "all")
                p.lightSelection = LightSelection::All;
            else if (s == "power")
                p.lightSelection = LightSelection::Power;
            else
                fail(ErrorCode::InvalidScene, sp, "must be \"all\" or \"power\", got " + quotedValue(s));
        }
        return p;
    }

    // ---- materials -------------------------------------------------------------------

    void readMaterials(const Json& j, const std::string& ptr, Scene& scene) {
        if (j.is_object()) {
            for (auto it = j.begin(); it != j.end(); ++it) {
                std::string mp = child(ptr, it.key());
                if (it.key().empty()) fail(ErrorCode::InvalidScene, mp, "material name must not be empty");
                addMaterial(readMaterial(it.value(), mp, it.key(), false, scene), mp, scene);
            }
        } else if (j.is_array()) {
            for (size_t i = 0; i < j.size(); ++i) {
                std::string mp = child(ptr, i);
                expectObject(j[i], mp);
                std::string name = string(require(j[i], mp, "name", "a material in an array"), child(mp, "name"));
                if (name.empty()) fail(ErrorCode::InvalidScene, child(mp, "name"), "must not be empty");
                addMaterial(readMaterial(j[i], mp, name, true, scene), mp, scene);
            }
        } else {
            fail(ErrorCode::ParseError, ptr, "expected an object {name: material} or an array of named materials, got " +
                                                 typeName(j));
        }
    }

    void addMaterial(Material m, const std::string& ptr, Scene& scene) {
        if (names_.count(m.name)) fail(ErrorCode::InvalidScene, ptr, "material " + quotedValue(m.name) + " is defined twice");
        names_[m.name] = static_cast<uint32_t>(scene.materials.size());
        scene.materials.push_back(std::move(m));
    }

    Material readMaterial(const Json& j, const std::string& ptr, const std::string& name, bool named, Scene& scene) {
        expectObject(j, ptr);
        if (named)
            checkKeys(j, ptr, {"name", "ka", "kd", "ks", "n", "exponent", "kr", "ke", "two_sided", "model", "texture"});
        else
            checkKeys(j, ptr, {"ka", "kd", "ks", "n", "exponent", "kr", "ke", "two_sided", "model", "texture"});
        Material m;
        m.name = name;
        if (const Json* v = find(j, "ka")) m.ka = colour(*v, child(ptr, "ka"));
        if (const Json* v = find(j, "kd")) m.kd = colour(*v, child(ptr, "kd"));
        if (const Json* v = find(j, "ks")) m.ks = colour(*v, child(ptr, "ks"));
        if (const Json* v = find(j, "kr")) m.kr = colour(*v, child(ptr, "kr"));
        if (const Json* v = find(j, "ke")) m.ke = colour(*v, child(ptr, "ke"));
        const Json* n = find(j, "n");
        const Json* e = find(j, "exponent");
        if (n && e) fail(ErrorCode::ParseError, child(ptr, "exponent"), "\"n\" and \"exponent\" are the same key; give one");
        if (n) m.exponent = nonNegative(*n, child(ptr, "n"));
        if (e) m.exponent = nonNegative(*e, child(ptr, "exponent"));
        if (const Json* v = find(j, "two_sided")) m.twoSidedEmission = boolean(*v, child(ptr, "two_sided"));
        if (const Json* v = find(j, "model")) {
            std::string mp = child(ptr, "model");
            std::string s = string(*v, mp);
            if (s == "normalized")
                m.model = PhongModel::Normalized;
            else if (s == "classic")
                m.model = PhongModel::Classic;
            else
                fail(ErrorCode::InvalidScene, mp, "must be \"normalized\" or \"classic\", got " + quotedValue(s));
        }
        if (const Json* v = find(j, "texture")) m.diffuseTexture = texture(*v, child(ptr, "texture"), scene);
        return m;
    }

    /// Index of the texture in Scene::textures (shared by materials naming the
    /// same file), or -1 when the file is missing and that is only a warning.
    int texture(const Json& j, const std::string& ptr, Scene& scene) const {
        fs::path p = resolvePath(j, ptr);
        std::error_code ec;
        if (!fs::is_regular_file(p, ec)) {
            warnOrFail(ErrorCode::FileNotFound, ptr, "texture file not found: " + p.string());
            return -1;
        }
        std::string key = p.string();
        for (size_t i = 0; i < scene.textures.size(); ++i)
            if (scene.textures[i] == key) return static_cast<int>(i);
        scene.textures.push_back(key);
        return static_cast<int>(scene.textures.size() - 1);
    }

    /// The material a shape without "material" gets: the file's "default", or a new grey one.
    uint32_t defaultMaterial(Scene& scene) {
        if (auto it = names_.find("default"); it != names_.end()) return it->second;
        Material m;
        m.name = "default";
        names_[m.name] = static_cast<uint32_t>(scene.materials.size());
        scene.materials.push_back(m);
        return names_[m.name];
    }

    uint32_t emissiveCopy(uint32_t base, const Rgb& ke, const std::string& ptr, Scene& scene) const {
        Material m = scene.materials[base];
        m.name += "@" + ptr;
        m.ke = ke;
        scene.materials.push_back(std::move(m));
        return static_cast<uint32_t>(scene.materials.size() - 1);
    }

    /// "material" (or the default), made private and emissive by "emission".
    uint32_t shapeMaterial(const Json& j, const std::string& ptr, Scene& scene) {
        uint32_t id;
        if (const Json* v = find(j, "material")) {
            std::string mp = child(ptr, "material");
            std::string name = string(*v, mp);
            auto it = names_.find(name);
            if (it == names_.end()) fail(ErrorCode::InvalidScene, mp, "unknown material " + quotedValue(name));
            id = it->second;
        } else {
            id = defaultMaterial(scene);
        }
        if (const Json* v = find(j, "emission")) id = emissiveCopy(id, colour(*v, child(ptr, "emission")), ptr, scene);
        return id;
    }

    // ---- transforms ------------------------------------------------------------------

    Transform readTransform(const Json& j, const std::string& ptr) const {
        expectObject(j, ptr);
        checkKeys(j, ptr, {"translate", "rotate", "scale"});
        Transform s, r, t;
        if (const Json* v = find(j, "scale")) {
            std::string sp = child(ptr, "scale");
            Vec3f f = v->is_number() ? Vec3f(number(*v, sp)) : vec3(*v, sp);
            if (f.x == 0.f || f.y == 0.f || f.z == 0.f) fail(ErrorCode::InvalidScene, sp, "scale factors must not be 0");
            s = Transform::scale(f);
        }
        if (const Json* v = find(j, "rotate")) {
            std::string rp = child(ptr, "rotate");
            if (!v->is_array()) fail(ErrorCode::ParseError, rp, "expected [angle, ax, ay, az] or a list of those");
            if (!v->empty() && (*v)[0].is_number()) {
                r = rotation(*v, rp);
            } else {
                // A list: the first rotation listed is applied first.
                for (size_t i = 0; i < v->size(); ++i) r = rotation((*v)[i], child(rp, i)) * r;
            }
        }
        if (const Json* v = find(j, "translate")) t = Transform::translate(vec3(*v, child(ptr, "translate")));
        Transform m = t * r * s;
        Transform inv;
        if (!m.inverse(inv)) fail(ErrorCode::InvalidScene, ptr, "transform is singular");
        return m;
    }

    Transform rotation(const Json& j, const std::string& ptr) const {
        if (!j.is_array() || j.size() != 4)
            fail(ErrorCode::ParseError, ptr, "expected a rotation [angle_degrees, axis_x, axis_y, axis_z]");
        float deg = number(j[0], child(ptr, 0));
        Vec3f axis{number(j[1], child(ptr, 1)), number(j[2], child(ptr, 2)), number(j[3], child(ptr, 3))};
        if (!(lengthSquared(axis) > 0.f)) fail(ErrorCode::InvalidScene, ptr, "rotation axis must not be zero");
        return Transform::rotate(deg, axis);
    }

    // ---- shapes ----------------------------------------------------------------------

    void readShape(const Json& j, const std::string& ptr, Scene& scene) {
        expectObject(j, ptr);
        std::string type = string(require(j, ptr, "type", "a shape"), child(ptr, "type"));
        if (type == "sphere") {
            checkKeys(j, ptr, {"type", "name", "material", "emission", "center", "radius"});
            Sphere s;
            s.center = vec3(require(j, ptr, "center", "a sphere"), child(ptr, "center"));
            s.radius = positive(require(j, ptr, "radius", "a sphere"), child(ptr, "radius"));
            s.material = shapeMaterial(j, ptr, scene);
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
            scene.boxes.push_back(makeBox(lo, hi, t, shapeMaterial(j, ptr, scene)));
        } else if (type == "rectangle") {
            checkKeys(j, ptr, {"type", "name", "material", "emission", "p0", "a", "b"});
            Rectangle q = rectangle(j, ptr);
            q.material = shapeMaterial(j, ptr, scene);
            scene.rectangles.push_back(q);
        } else if (type == "disk") {
            checkKeys(j, ptr, {"type", "name", "material", "emission", "center", "normal", "radius"});
            Disk d = disk(j, ptr);
            d.material = shapeMaterial(j, ptr, scene);
            scene.disks.push_back(d);
        } else if (type == "mesh") {
            if (find(j, "file"))
                readObjMesh(j, ptr, scene);
            else
                readInlineMesh(j, ptr, scene);
        } else {
            fail(ErrorCode::ParseError, child(ptr, "type"),
                 "unknown shape type " + quotedValue(type) + " (expected sphere, plane, box, rectangle, disk or mesh)");
        }
    }

    Rectangle rectangle(const Json& j, const std::string& ptr) const {
        Rectangle q;
        q.p0 = vec3(require(j, ptr, "p0", "a rectangle"), child(ptr, "p0"));
        q.a = vec3(require(j, ptr, "a", "a rectangle"), child(ptr, "a"));
        q.b = vec3(require(j, ptr, "b", "a rectangle"), child(ptr, "b"));
        if (!(area(q) > 0.f) || !std::isfinite(area(q)))
            fail(ErrorCode::InvalidScene, ptr, "rectangle has zero area (\"a\" and \"b\" are parallel or zero)");
        return q;
    }

    Disk disk(const Json& j, const std::string& ptr) const {
        Disk d;
        d.center = vec3(require(j, ptr, "center", "a disk"), child(ptr, "center"));
        d.normal = normalize(nonZeroVec3(require(j, ptr, "normal", "a disk"), child(ptr, "normal")));
        d.radius = positive(require(j, ptr, "radius", "a disk"), child(ptr, "radius"));
        return d;
    }

    void readObjMesh(const Json& j, const std::string& ptr, Scene& scene) {
        checkKeys(j, ptr, {"type", "name", "material", "emission", "file", "transform"});
        std::string fp = child(ptr, "file");
        fs::path file = resolvePath(*find(j, "file"), fp);
        std::error_code ec;
        if (!fs::is_regular_file(file, ec)) fail(ErrorCode::FileNotFound, fp, "mesh file not found: " + file.string());
        Transform t;
        if (const Json* v = find(j, "transform")) t = readTransform(*v, child(ptr, "transform"));
        // Resolve the material before loading, so a bad name fails fast.
        std::optional<uint32_t> override;
        if (find(j, "material")) override = shapeMaterial(j, ptr, scene);

        const size_t firstMesh = scene.meshes.size();
        ObjStats stats;
        try {
            stats = appendObj(scene, file, t, options_, log_);
        } catch (const Error& e) {
            fail(e.code(), ptr, e.what());
        }
        if (stats.triangles == 0) warnOrFail(ErrorCode::InvalidScene, fp, "mesh file has no triangles: " + file.string());

        std::string name;
        if (const Json* v = find(j, "name")) name = string(*v, child(ptr, "name"));
        std::map<uint32_t, uint32_t> emissive;  // MTL material -> its emissive copy
        const Json* emission = override ? nullptr : find(j, "emission");
        Rgb ke = emission ? colour(*emission, child(ptr, "emission")) : Rgb();
        auto remap = [&](uint32_t& id) {
            if (id >= scene.materials.size()) return;  // finalize() repairs it
            auto [it, fresh] = emissive.try_emplace(id, 0);
            if (fresh) it->second = emissiveCopy(id, ke, ptr, scene);
            id = it->second;
        };
        for (size_t i = firstMesh; i < scene.meshes.size(); ++i) {
            TriangleMesh& m = scene.meshes[i];
            if (!name.empty()) m.name = name;
            if (override) {
                m.material = *override;
                m.faceMaterials.clear();
            } else if (emission) {
                remap(m.material);
                for (uint32_t& id : m.faceMaterials) remap(id);
            }
        }
    }

    /// Numbers of an array given either nested ([[x, y, z], ...]) or flat
    /// ([x, y, z, ...]), flattened; T is float (finite numbers) or uint32_t (indices).
    template <class T>
    std::vector<T> tuples(const Json& j, const std::string& ptr, size_t arity, const char* what) const {
        if (!j.is_array()) fail(ErrorCode::ParseError, ptr, std::string("expected an array of ") + what);
        std::vector<T> out;
        bool nested = !j.empty() && j[0].is_array();
        out.reserve(nested ? j.size() * arity : j.size());
        auto element = [&](const Json& e, size_t i, size_t k) {
            if constexpr (std::is_same_v<T, float>) {
                if (e.is_number()) {
                    float v = static_cast<float>(e.get<double>());
                    if (std::isfinite(v)) return out.push_back(v);
                }
                number(e, nested ? child(child(ptr, i), k) : child(ptr, i));  // throws the precise error
            } else {
                if (e.is_number_unsigned()) return out.push_back(static_cast<T>(std::min<uint64_t>(e.get<uint64_t>(), UINT32_MAX)));
                // Integral floats are accepted; anything else throws the precise error.
                out.push_back(static_cast<T>(integer(e, nested ? child(child(ptr, i), k) : child(ptr, i), 0, UINT32_MAX)));
            }
        };
        if (nested) {
            for (size_t i = 0; i < j.size(); ++i) {
                const Json& t = j[i];
                if (!t.is_array() || t.size() != arity)
                    fail(ErrorCode::ParseError, child(ptr, i),
                         "expected an array of " + std::to_string(arity) + " numbers (all entries nested alike)");
                for (size_t k = 0; k < arity; ++k) element(t[k], i, k);
            }
        } else {
            if (j.size() % arity != 0)
                fail(ErrorCode::ParseError, ptr,
                     "a flat array needs a multiple of " + std::to_string(arity) + " numbers, got " + std::to_string(j.size()));
            for (size_t i = 0; i < j.size(); ++i) element(j[i], i, 0);
        }
        return out;
    }

    void readInlineMesh(const Json& j, const std::string& ptr, Scene& scene) {
        checkKeys(j, ptr, {"type", "name", "material", "emission", "vertices", "indices", "normals", "uvs", "transform"});
        TriangleMesh m;
        m.name = "mesh@" + ptr;
        if (const Json* v = find(j, "name")) m.name = string(*v, child(ptr, "name"));
        std::vector<float> p = tuples<float>(require(j, ptr, "vertices", "an inline mesh"), child(ptr, "vertices"), 3,
                                             "vertices [x, y, z]");
        std::vector<uint32_t> idx = tuples<uint32_t>(require(j, ptr, "indices", "an inline mesh"), child(ptr, "indices"),
                                                     3, "triangles [i, j, k]");
        const size_t nv = p.size() / 3;
        if (idx.empty()) fail(ErrorCode::InvalidScene, child(ptr, "indices"), "a mesh needs at least one triangle");
        for (size_t i = 0; i < idx.size(); ++i) {
            if (idx[i] >= nv) {
                const Json& ij = j["indices"];
                std::string ip = ij[0].is_array() ? child(child(child(ptr, "indices"), i / 3), i % 3)
                                                  : child(child(ptr, "indices"), i);
                fail(ErrorCode::InvalidScene, ip,
                     "vertex index " + std::to_string(idx[i]) + " out of range (the mesh has " + std::to_string(nv) +
                         " vertices)");
            }
        }
        Transform t;
        if (const Json* v = find(j, "transform")) t = readTransform(*v, child(ptr, "transform"));
        m.positions.reserve(nv);
        for (size_t i = 0; i < nv; ++i) m.positions.push_back(t.applyPoint({p[3 * i], p[3 * i + 1], p[3 * i + 2]}));
        m.indices = std::move(idx);
        if (const Json* v = find(j, "normals")) {
            std::string np = child(ptr, "normals");
            std::vector<float> n = tuples<float>(*v, np, 3, "normals [x, y, z]");
            if (n.size() / 3 != nv)
                fail(ErrorCode::InvalidScene, np,
                     "has " + std::to_string(n.size() / 3) + " normals for " + std::to_string(nv) + " vertices");
            for (size_t i = 0; i < nv; ++i)
                m.normals.push_back(normalize(t.applyNormal({n[3 * i], n[3 * i + 1], n[3 * i + 2]})));
        }
        if (const Json* v = find(j, "uvs")) {
            std::string up = child(ptr, "uvs");
            std::vector<float> uv = tuples<float>(*v, up, 2, "texture coordinates [u, v]");
            if (uv.size() / 2 != nv)
                fail(ErrorCode::InvalidScene, up,
                     "has " + std::to_string(uv.size() / 2) + " texture coordinates for " + std::to_string(nv) + " vertices");
            for (size_t i = 0; i < nv; ++i) m.uvs.push_back({uv[2 * i], uv[2 * i + 1]});
        }
        m.material = shapeMaterial(j, ptr, scene);
        scene.meshes.push_back(std::move(m));
    }

    // ---- lights ----------------------------------------------------------------------

    void readLight(const Json& j, const std::string& ptr, Scene& scene) {
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
            scene.rectangles.push_back(q);
        } else if (type == "disk") {
            checkKeys(j, ptr, {"type", "name", "center", "normal", "radius", "radiance", "two_sided"});
            Disk d = disk(j, ptr);
            d.material = lightMaterial(j, ptr, scene);
            scene.disks.push_back(d);
        } else if (type == "sphere") {
            checkKeys(j, ptr, {"type", "name", "center", "radius", "radiance", "two_sided"});
            Sphere s;
            s.center = vec3(require(j, ptr, "center", "a sphere light"), child(ptr, "center"));
            s.radius = positive(require(j, ptr, "radius", "a sphere light"), child(ptr, "radius"));
            s.material = lightMaterial(j, ptr, scene);
            scene.spheres.push_back(s);
        } else {
            fail(ErrorCode::ParseError, child(ptr, "type"),
                 "unknown light type " + quotedValue(type) + " (expected point, directional, ambient, rectangle, disk or sphere)");
        }
    }

    /// An area light is an emitting shape: black, non-reflective, ke = radiance.
    uint32_t lightMaterial(const Json& j, const std::string& ptr, Scene& scene) const {
        Material m;
        m.name = "light@" + ptr;
        if (const Json* v = find(j, "name")) m.name = string(*v, child(ptr, "name"));
        m.ka = m.kd = m.ks = m.kr = Rgb(0.f);
        m.ke = colour(require(j, ptr, "radiance", "an area light"), child(ptr, "radiance"));
        if (const Json* v = find(j, "two_sided")) m.twoSidedEmission = boolean(*v, child(ptr, "two_sided"));
        scene.materials.push_back(std::move(m));
        return static_cast<uint32_t>(scene.materials.size() - 1);
    }

    fs::path path_, dir_;
    std::string file_;
    const LoadOptions& options_;
    const Logger& log_;
    std::map<std::string, uint32_t> names_;  // JSON material name -> Scene::materials index
};

}  // namespace

LoadedScene loadJsonScene(const std::filesystem::path& path, const LoadOptions& options, const Logger& log) {
    const std::string file = path.string();
    try {
        checkPathAllowed(path, options);
        std::string text = readText(path);
        Json root = parseJson(text, file);
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
