// OBJ/MTL loading (appendObj, loadObjScene) on top of tinyobjloader.
//
// tinyobjloader is lenient in ways a renderer cannot be: it keeps out-of-range
// face indices, turns `nan` into 0, fails the whole file on a zero index, and
// reads `1.#IND` as 1. So the OBJ text goes through a small pre-pass first
// (BOM, line endings, face indices, coordinate checks), tinyobjloader parses the
// result without triangulating, and every face is validated here before it is
// triangulated and de-indexed into TriangleMeshes. docs/mtl-mapping.md lists
// the material mapping and every warning.
#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "core/error.h"
#include "core/scene_loader.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

// Written in place of an index that tinyobjloader would reject or resolve to
// a negative number; it is out of range for any real file, so the validation
// below treats it like any other bad index.
constexpr const char* kBadIndex = "2147483647";
// tinyobjloader stores the corner count of a face in an unsigned char; bigger
// faces bypass it (BigFace).
constexpr size_t kMaxFaceCorners = 255;
// Ear clipping is cubic in the worst case; bigger polygons are fanned.
constexpr size_t kMaxEarClipCorners = 512;

std::string name(const fs::path& p) { return p.string(); }

bool isBlank(char c) { return c == ' ' || c == '\t'; }

std::string_view trim(std::string_view s) {
    size_t b = 0, e = s.size();
    while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
    return s.substr(b, e - b);
}

std::vector<std::string_view> splitBlank(std::string_view s) {
    std::vector<std::string_view> out;
    size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && isBlank(s[i])) ++i;
        size_t b = i;
        while (i < s.size() && !isBlank(s[i])) ++i;
        if (i > b) out.push_back(s.substr(b, i - b));
    }
    return out;
}

bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i])))
            return false;
    return true;
}

/// Reads a whole file; the errors tell a missing file from a directory from an unreadable one.
std::string readFile(const fs::path& path) {
    std::error_code ec;
    fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st)) throw Error(ErrorCode::FileNotFound, name(path) + ": file not found");
    if (fs::is_directory(st)) throw Error(ErrorCode::IoError, name(path) + ": is a directory, not a file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorCode::IoError, name(path) + ": cannot open the file for reading");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw Error(ErrorCode::IoError, name(path) + ": read error");
    return ss.str();
}

void stripBom(std::string& s) {
    if (s.size() >= 3 && s.compare(0, 3, "\xEF\xBB\xBF") == 0) s.erase(0, 3);
}

/// OBJ and MTL are text: a NUL byte means binary data (or UTF-16), which
/// tinyobjloader would read as garbage. Returns "<line>: ..." naming the first one.
std::optional<std::string> binaryDataProblem(std::string_view text) {
    size_t z = text.find('\0');
    if (z == std::string_view::npos) return std::nullopt;
    size_t line = 1 + static_cast<size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(z), '\n'));
    return std::to_string(line) + ": binary data (a NUL byte), not a text file";
}

/// A token from a file, made safe for a one-line message: printable ASCII
/// only, and at most 40 characters.
std::string printable(std::string_view tok) {
    std::string out;
    for (char ch : tok.substr(0, 40)) out += (ch >= 0x20 && ch < 0x7f) ? ch : '?';
    if (tok.size() > 40) out += "...";
    return out;
}

/// Splits text into lines the way tinyobjloader does (\n, \r\n or a lone \r).
std::vector<std::string_view> splitLines(std::string_view text) {
    std::vector<std::string_view> lines;
    size_t b = 0;
    for (size_t i = 0; i < text.size(); ++i) {
        if (text[i] == '\n' || text[i] == '\r') {
            lines.push_back(text.substr(b, i - b));
            if (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
            b = i + 1;
        }
    }
    if (b < text.size()) lines.push_back(text.substr(b));
    return lines;
}

/// A coordinate token is usable when it is a complete, finite number as a float
/// (`nan`, `inf`, `1e39`, `1.#IND` and garbage are not).
bool finiteNumber(std::string_view tok) {
    std::string s(tok);
    char* end = nullptr;
    double d = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0') return false;
    return std::isfinite(d) && std::fabs(d) <= static_cast<double>(std::numeric_limits<float>::max());
}

/// The index of an OBJ face component as atoi reads it (leading digits; trailing
/// characters ignored); nullopt when there are no digits or it overflows int.
std::optional<long long> parseIndex(std::string_view s) {
    size_t i = 0;
    bool neg = false;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) neg = s[i++] == '-';
    long long v = 0;
    size_t digits = 0;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) {
        v = v * 10 + (s[i++] - '0');
        if (v > INT_MAX) return std::nullopt;
        ++digits;
    }
    if (digits == 0) return std::nullopt;
    return neg ? -v : v;
}

/// One face component as an absolute 1-based index, or INT_MAX (out of range
/// for any real file) when it is zero, missing or resolves before the first element.
long long absoluteIndex(std::string_view comp, size_t countSoFar) {
    auto idx = parseIndex(comp);
    if (!idx || *idx == 0) return INT_MAX;
    if (*idx > 0) return *idx;
    long long abs = static_cast<long long>(countSoFar) + *idx;  // relative: -1 = the last one so far
    if (abs < 0) return INT_MAX;
    return abs + 1;
}

/// One face component rewritten to an absolute 1-based index, or kBadIndex.
std::string fixComponent(std::string_view comp, size_t countSoFar) {
    long long abs = absoluteIndex(comp, countSoFar);
    return abs == INT_MAX ? std::string(kBadIndex) : std::to_string(abs);
}

/// A face with more corners than tinyobjloader can count: it parses a triangle
/// in its place (keeping the shape, material and face order), and the loader
/// takes the corners from here.
struct BigFace {
    size_t face;                           // index among the faces tinyobjloader reports
    std::vector<tinyobj::index_t> corners;  // 0-based, -1 for no vt / vn, like tinyobjloader's
};

struct PreparedObj {
    std::string text;                 // what tinyobjloader parses
    std::vector<uint8_t> badVertex;   // per `v` line: a coordinate is not a finite number
    std::vector<uint32_t> faceLines;  // 1-based line of each face tinyobjloader will report, in order
    std::vector<BigFace> bigFaces;    // faces of more than kMaxFaceCorners corners, in order
    size_t invalidFaces = 0;          // face lines removed (fewer than 3 corners)
    uint32_t firstInvalidLine = 0;
};

/// Normalises the OBJ text for tinyobjloader: LF line endings; relative and
/// zero indices made absolute or marked bad; trailing comments on face lines
/// dropped; line and point primitives (not rendered) and skin weights removed,
/// since tinyobjloader fails the whole file on some of their errors.
/// Line numbers are kept, so the face lines can be reported.
PreparedObj prepareObj(std::string_view text) {
    PreparedObj out;
    out.text.reserve(text.size() + text.size() / 16);
    size_t nv = 0, nvt = 0, nvn = 0;
    uint32_t lineNo = 0;
    for (std::string_view line : splitLines(text)) {
        ++lineNo;
        size_t s = 0;
        while (s < line.size() && isBlank(line[s])) ++s;
        std::string_view tok = line.substr(s);
        auto starts = [&](std::string_view kw) {
            return tok.size() > kw.size() && tok.substr(0, kw.size()) == kw && isBlank(tok[kw.size()]);
        };
        if (starts("v")) {
            auto t = splitBlank(tok.substr(2));
            bool bad = false;
            for (size_t i = 0; i < std::min<size_t>(3, t.size()); ++i) bad = bad || !finiteNumber(t[i]);
            out.badVertex.push_back(bad ? 1 : 0);
            ++nv;
            out.text.append(line);
        } else if (starts("vt")) {
            ++nvt;
            out.text.append(line);
        } else if (starts("vn")) {
            ++nvn;
            out.text.append(line);
        } else if (starts("f")) {
            std::string_view body = tok.substr(2);
            body = body.substr(0, std::min(body.size(), body.find('#')));
            auto corners = splitBlank(body);
            if (corners.size() < 3) {
                if (out.invalidFaces++ == 0) out.firstInvalidLine = lineNo;
            } else {
                const bool big = corners.size() > kMaxFaceCorners;
                if (big) out.bigFaces.push_back({out.faceLines.size(), {}});
                std::string f = "f";
                for (size_t ci = 0; ci < corners.size(); ++ci) {
                    std::string_view c = corners[ci];
                    std::array<std::string_view, 3> comp{};
                    size_t k = 0, b = 0;
                    for (size_t i = 0; i <= c.size() && k < 3; ++i)
                        if (i == c.size() || c[i] == '/') {
                            comp[k++] = c.substr(b, i - b);
                            b = i + 1;
                        }
                    bool hasVt = k > 1 && !comp[1].empty();
                    bool hasVn = k > 2 && !comp[2].empty();
                    if (big) {
                        // INT_MAX - 1 as a 0-based index is out of range like kBadIndex.
                        auto zeroBased = [](long long abs) { return static_cast<int>(abs - 1); };
                        out.bigFaces.back().corners.push_back(
                            {zeroBased(absoluteIndex(comp[0], nv)), hasVn ? zeroBased(absoluteIndex(comp[2], nvn)) : -1,
                             hasVt ? zeroBased(absoluteIndex(comp[1], nvt)) : -1});
                        if (ci >= 3) continue;  // tinyobjloader sees the first three corners only
                    }
                    f += ' ';
                    f += fixComponent(comp[0], nv);
                    if (hasVt) f += "/" + fixComponent(comp[1], nvt);
                    if (hasVn) f += (hasVt ? "/" : "//") + fixComponent(comp[2], nvn);
                }
                out.text += f;
                out.faceLines.push_back(lineNo);
            }
        } else if (starts("l") || starts("p") || starts("vw")) {
            // not rendered; left out so their errors cannot fail the file
        } else {
            out.text.append(line);
        }
        out.text += '\n';
    }
    return out;
}

/// Finds `rel` below `base`, matching each path component case-insensitively
/// when the exact name does not exist (OBJ files written on Windows often
/// disagree with the files' capitalisation).
std::optional<fs::path> resolveCaseInsensitive(const fs::path& base, const fs::path& rel) {
    std::error_code ec;
    fs::path exact = rel.is_absolute() ? rel : base / rel;
    if (fs::is_regular_file(exact, ec)) return exact.lexically_normal();
    fs::path cur = rel.is_absolute() ? rel.root_path() : base;
    fs::path parts = rel.is_absolute() ? rel.relative_path() : rel;
    for (const fs::path& part : parts) {
        if (part.empty() || part == "." || part == ".." || fs::exists(cur / part, ec)) {
            cur /= part;
            continue;
        }
        std::optional<fs::path> match;
        for (fs::directory_iterator it(cur.empty() ? fs::path(".") : cur, ec), end; !ec && it != end;
             it.increment(ec))
            if (iequals(it->path().filename().string(), part.string())) {
                match = it->path();
                break;
            }
        if (!match) return std::nullopt;
        cur = *match;
    }
    if (!fs::is_regular_file(cur, ec)) return std::nullopt;
    return cur.lexically_normal();
}

/// Reads `mtllib` files relative to the OBJ's folder, refusing paths outside
/// the allowed roots before opening them; strips BOMs; trims material names
/// (`newmtl tallBox ` must match `usemtl tallBox`). Remembers which file each
/// material came from, for texture paths and warnings.
class MtlReader : public tinyobj::MaterialReader {
public:
    struct Source {
        fs::path file;
        size_t begin, end;  // material index range
    };

    MtlReader(fs::path objDir, const LoadOptions& options) : dir_(std::move(objDir)), options_(options) {}

    bool operator()(const std::string& matId, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* matMap, std::string* warn, std::string* err) override {
        fs::path rel(std::string(trim(matId)));
        fs::path candidate = rel.is_absolute() ? rel : dir_ / rel;
        try {
            checkPathAllowed(candidate, options_, /*willRead=*/false);
        } catch (const Error& e) {
            if (!error) error = e;
            return false;
        }
        std::optional<fs::path> file = resolveCaseInsensitive(dir_, rel);
        if (file) {
            try {
                checkPathAllowed(*file, options_);
            } catch (const Error& e) {
                if (!error) error = e;
                return false;
            }
        }
        std::string text;
        try {
            if (!file) throw Error(ErrorCode::FileNotFound, name(candidate) + ": file not found");
            text = readFile(*file);
        } catch (const Error& e) {
            if (warn) *warn += std::string("material library ") + e.what() + "\n";
            return false;
        }
        stripBom(text);
        if (auto bad = binaryDataProblem(text)) {
            if (warn) *warn += "material library " + name(*file) + ":" + *bad + "; ignored\n";
            return false;
        }
        checkNumbers(text, *file, warn);
        std::istringstream in(text);
        std::map<std::string, int> local;
        size_t begin = materials->size();
        std::string w, e;
        tinyobj::LoadMtl(&local, materials, &in, &w, &e);
        for (size_t i = begin; i < materials->size(); ++i) {
            auto& m = (*materials)[i];
            m.name = std::string(trim(m.name));
            matMap->insert({m.name, static_cast<int>(i)});
        }
        sources.push_back({*file, begin, materials->size()});
        if (warn && !w.empty()) *warn += w;
        if (err && !e.empty()) *err += e;
        return true;
    }

    const Source* sourceOf(size_t material) const {
        for (const auto& s : sources)
            if (material >= s.begin && material < s.end) return &s;
        return nullptr;
    }

    std::vector<Source> sources;
    std::optional<Error> error;  // a refused path; rethrown after parsing

private:
    /// tinyobjloader reads a malformed number in an MTL statement as 0 without
    /// a word; one warning per file names the first (line and token) and counts them.
    static void checkNumbers(std::string_view text, const fs::path& file, std::string* warn) {
        static constexpr std::string_view kNumeric[] = {"Ka", "Kd", "Ks", "Ke", "Kt", "Tf", "Ns", "Ni", "d", "Tr", "illum"};
        size_t bad = 0;
        std::string first;
        uint32_t lineNo = 0;
        for (std::string_view line : splitLines(text)) {
            ++lineNo;
            auto tok = splitBlank(trim(line));
            if (tok.empty() || std::find(std::begin(kNumeric), std::end(kNumeric), tok[0]) == std::end(kNumeric)) continue;
            for (size_t i = 1; i < tok.size() && i <= 3; ++i) {
                if (tok[i][0] == '#') break;
                if (finiteNumber(tok[i])) continue;
                if (bad++ == 0)
                    first = "line " + std::to_string(lineNo) + ": '" + printable(tok[i]) + "' in " + std::string(tok[0]);
                break;
            }
        }
        if (bad > 0 && warn)
            *warn += name(file) + ": " + std::to_string(bad) +
                     " statement(s) with a malformed or non-finite number, read as 0 (first at " + first + ")\n";
    }

    fs::path dir_;
    const LoadOptions& options_;
};

Rgb toRgb(const tinyobj::real_t c[3], bool& clamped) {
    Rgb r;
    float* out[3] = {&r.r, &r.g, &r.b};
    for (int i = 0; i < 3; ++i) {
        float v = static_cast<float>(c[i]);
        if (!std::isfinite(v) || v < 0.f) {
            clamped = true;
            v = 0.f;
        }
        *out[i] = v;
    }
    return r;
}

std::string rgbText(const tinyobj::real_t c[3]) {
    std::ostringstream ss;
    ss << c[0] << ' ' << c[1] << ' ' << c[2];
    return ss.str();
}

/// Converts the MTL materials and resolves their diffuse textures.
class MaterialConverter {
public:
    MaterialConverter(Scene& scene, const fs::path& objPath, const MtlReader& reader, const LoadOptions& options,
                      const Logger& log)
        : scene_(scene), obj_(objPath), reader_(reader), options_(options), log_(log) {}

    Material convert(const tinyobj::material_t& t, size_t index) {
        const MtlReader::Source* src = reader_.sourceOf(index);
        fs::path mtl = src ? src->file : obj_;
        std::string where = name(mtl) + ": material '" + t.name + "'";

        Material m;
        m.name = t.name;
        m.model = PhongModel::Normalized;
        bool clamped = false;
        m.ka = toRgb(t.ambient, clamped);
        m.kd = toRgb(t.diffuse, clamped);
        m.ks = toRgb(t.specular, clamped);
        m.ke = toRgb(t.emission, clamped);
        float ns = static_cast<float>(t.shininess);
        m.exponent = std::isfinite(ns) && ns >= 0.f ? ns : 1.f;
        clamped = clamped || m.exponent != ns;
        if (clamped) log_.warn(where + ": negative or non-finite values replaced by 0 (Ns by 1)");

        if (m.ka.maxComponent() > 1.5f)
            log_.warn(where + ": Ka " + rgbText(t.ambient) +
                      " looks like a light source; Penumbra takes emission from Ke only (add 'Ke " +
                      rgbText(t.ambient) + "' to make it emit)");

        int illum = t.illum;
        if (illum >= 3 && illum <= 9) {
            // The Ks of a reflecting material is the mirror's colour, not a highlight.
            m.kr = m.ks;
            m.ks = Rgb(0.f);
            if (illum == 4 || illum == 6 || illum == 7 || illum == 9) note(transparentIllum_, where, illum);
        } else if (illum < 0 || illum > 9) {
            note(unknownIllum_, where, illum);
        }

        for (const auto& [key, value] : t.unknown_parameter) {
            if (!unknownKeys_.insert({name(mtl), key}).second) continue;
            // A few by name; past that (a binary or foreign file) one line counts the rest.
            if (++unknownKeyCount_[name(mtl)] <= kMaxUnknownKeyWarnings)
                log_.warn(name(mtl) + ": ignoring unknown MTL key '" + printable(key) + "'");
        }

        if (!t.diffuse_texname.empty()) m.diffuseTexture = texture(t.diffuse_texname, mtl, where);
        return m;
    }

    /// The one grey material for faces without a (known) material; added on first use.
    uint32_t defaultMaterial() {
        if (!default_) {
            Material d;
            d.name = "default";
            d.kd = Rgb(0.8f);
            default_ = static_cast<uint32_t>(scene_.materials.size());
            scene_.materials.push_back(d);
        }
        return *default_;
    }

    /// Once per OBJ: one warning for all materials with the same unsupported illum kind.
    void flushWarnings() {
        if (!transparentIllum_.empty())
            log_.warn(name(obj_) + ": transparency/refraction is not supported (" + transparentIllum_ +
                      "); rendering the mirror part only");
        if (!unknownIllum_.empty())
            log_.warn(name(obj_) + ": unknown illum model (" + unknownIllum_ + "); using lit Phong");
        for (const auto& [file, count] : unknownKeyCount_)
            if (count > kMaxUnknownKeyWarnings)
                log_.warn(file + ": ignoring " + std::to_string(count - kMaxUnknownKeyWarnings) +
                          " more unknown MTL key(s)");
    }

private:
    static void note(std::string& list, const std::string& where, int illum) {
        if (!list.empty()) list += ", ";
        list += where + " illum " + std::to_string(illum);
    }

    int texture(const std::string& texName, const fs::path& mtl, const std::string& where) {
        std::string rel = texName;
        std::replace(rel.begin(), rel.end(), '\\', '/');
        rel = std::string(trim(rel));
        fs::path dir = mtl.parent_path();
        fs::path relPath(rel);
        // Checked before probing the file system, and again after matching names.
        checkPathAllowed(relPath.is_absolute() ? relPath : dir / relPath, options_, /*willRead=*/false);
        std::optional<fs::path> file = resolveCaseInsensitive(dir, relPath);
        if (!file) {
            if (missingTextures_.insert(name(mtl) + "\n" + rel).second)
                log_.warn(where + ": texture '" + rel + "' not found (looked in " + name(dir.empty() ? "." : dir) +
                          "); using Kd without texture");
            return -1;
        }
        checkPathAllowed(*file, options_);
        std::string path = file->string();
        auto it = std::find(scene_.textures.begin(), scene_.textures.end(), path);
        if (it != scene_.textures.end()) return static_cast<int>(it - scene_.textures.begin());
        scene_.textures.push_back(path);
        return static_cast<int>(scene_.textures.size() - 1);
    }

    Scene& scene_;
    fs::path obj_;
    const MtlReader& reader_;
    const LoadOptions& options_;
    const Logger& log_;
    std::optional<uint32_t> default_;
    std::string transparentIllum_, unknownIllum_;
    static constexpr size_t kMaxUnknownKeyWarnings = 5;
    std::set<std::pair<std::string, std::string>> unknownKeys_;
    std::map<std::string, size_t> unknownKeyCount_;
    std::set<std::string> missingTextures_;
};

/// Splits a polygon into triangles (corner indices), keeping its winding.
/// Quads take the shorter diagonal when both are valid (like tinyobjloader);
/// bigger polygons are ear-clipped in their best-fit plane, so concave ones
/// keep their shape; a polygon without ears (self-intersecting, degenerate) is fanned.
void triangulate(const std::vector<Vec3f>& p, std::vector<std::array<uint32_t, 3>>& out) {
    const size_t n = p.size();
    out.clear();
    if (n == 3) {
        out.push_back({0, 1, 2});
        return;
    }
    Vec3f normal{};  // Newell's method: robust for non-planar and concave polygons
    for (size_t i = 0; i < n; ++i) {
        const Vec3f &a = p[i], &b = p[(i + 1) % n];
        normal += Vec3f{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
    }
    auto fan = [&](const std::vector<uint32_t>& v) {
        for (size_t i = 1; i + 1 < v.size(); ++i) out.push_back({v[0], v[i], v[i + 1]});
    };
    if (n == 4) {
        auto faces = [&](uint32_t a, uint32_t b, uint32_t c) {
            return dot(cross(p[b] - p[a], p[c] - p[a]), normal) > 0.f;
        };
        bool splitA = faces(0, 1, 2) && faces(0, 2, 3);  // diagonal 0-2
        bool splitB = faces(0, 1, 3) && faces(1, 2, 3);  // diagonal 1-3
        bool useA = splitA && (!splitB || lengthSquared(p[2] - p[0]) <= lengthSquared(p[3] - p[1]));
        if (useA || !splitB) {
            out.push_back({0, 1, 2});
            out.push_back({0, 2, 3});
        } else {
            out.push_back({0, 1, 3});
            out.push_back({1, 2, 3});
        }
        return;
    }
    std::vector<uint32_t> rest(n);
    for (size_t i = 0; i < n; ++i) rest[i] = static_cast<uint32_t>(i);
    if (lengthSquared(normal) == 0.f || !isFinite(normal) || n > kMaxEarClipCorners) {
        fan(rest);
        return;
    }
    // Project onto the plane that drops the normal's dominant axis, oriented so the polygon is counter-clockwise.
    int k = maxDimension(abs(normal));
    int u = (k + 1) % 3, w = (k + 2) % 3;
    if (normal[k] < 0.f) std::swap(u, w);
    auto cross2 = [&](uint32_t a, uint32_t b, uint32_t c) {
        return (p[b][u] - p[a][u]) * (p[c][w] - p[a][w]) - (p[b][w] - p[a][w]) * (p[c][u] - p[a][u]);
    };
    while (rest.size() > 3) {
        const size_t m = rest.size();
        bool clipped = false;
        for (size_t i = 0; i < m && !clipped; ++i) {
            uint32_t a = rest[(i + m - 1) % m], b = rest[i], c = rest[(i + 1) % m];
            if (!(cross2(a, b, c) > 0.f)) continue;  // reflex or collinear corner
            bool inside = false;
            for (size_t j = 0; j < m && !inside; ++j) {
                uint32_t q = rest[j];
                if (q == a || q == b || q == c || p[q] == p[a] || p[q] == p[b] || p[q] == p[c]) continue;
                inside = cross2(a, b, q) >= 0.f && cross2(b, c, q) >= 0.f && cross2(c, a, q) >= 0.f;
            }
            if (inside) continue;
            out.push_back({a, b, c});
            rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(i));
            clipped = true;
        }
        if (!clipped) {
            fan(rest);
            return;
        }
    }
    out.push_back({rest[0], rest[1], rest[2]});
}

struct VertexKey {
    int v, vt, vn;
    bool operator==(const VertexKey&) const = default;
};
struct VertexKeyHash {
    size_t operator()(const VertexKey& k) const {
        uint64_t h = static_cast<uint32_t>(k.v);
        h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint32_t>(k.vt);
        h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint32_t>(k.vn);
        return static_cast<size_t>(h ^ (h >> 29));
    }
};

std::string lineNote(uint32_t line) { return line > 0 ? " (first at line " + std::to_string(line) + ")" : ""; }

/// Lines of tinyobjloader's warnings, without those this loader reports
/// itself more precisely or that concern ignored keys, each distinct line once.
std::vector<std::string> filterTinyObjWarnings(const std::string& warn) {
    static constexpr std::string_view kOwn[] = {"Vertex indices out of bounds", "Vertex normal indices out of bounds",
                                                "Vertex texcoord indices out of bounds", "Degenerated face found",
                                                "Face with invalid vertex index",
                                                // d and Tr (dissolve) are not used
                                                "Both `d` and `Tr`"};
    std::vector<std::string> out;
    std::set<std::string> seen;
    std::istringstream in(warn);
    std::string line;
    while (std::getline(in, line)) {
        std::string_view t = trim(line);
        if (t.empty() || t == ".") continue;
        bool own = false;
        for (auto k : kOwn) own = own || t.substr(0, k.size()) == k;
        if (!own && seen.insert(std::string(t)).second) out.emplace_back(t);
    }
    return out;
}

}  // namespace

ObjStats appendObj(Scene& scene, const std::filesystem::path& objPath, const Transform& worldFromObject,
                   const LoadOptions& options, const Logger& log) {
    const std::string file = name(objPath);
    checkPathAllowed(objPath, options);
    std::string text = readFile(objPath);
    stripBom(text);
    if (auto bad = binaryDataProblem(text)) throw Error(ErrorCode::ParseError, file + ":" + *bad);
    PreparedObj prep = prepareObj(text);
    text.clear();
    text.shrink_to_fit();

    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> mtls;
    std::string warn, err;
    MtlReader reader(objPath.parent_path(), options);
    bool ok;
    {
        std::istringstream in(std::move(prep.text));
        ok = tinyobj::LoadObj(&attrib, &shapes, &mtls, &warn, &err, &in, &reader, /*triangulate=*/false,
                              /*default_vcols_fallback=*/false);
    }
    if (reader.error) throw *reader.error;
    if (!ok) throw Error(ErrorCode::ParseError, file + ": " + std::string(trim(err.empty() ? "parse error" : err)));
    for (const auto& w : filterTinyObjWarnings(warn)) log.warn(file + ": " + w);
    for (const auto& e : filterTinyObjWarnings(err)) log.warn(file + ": " + e);

    ObjStats stats;

    // Materials: appended after the scene's own, in MTL order.
    const uint32_t materialBase = static_cast<uint32_t>(scene.materials.size());
    MaterialConverter converter(scene, objPath, reader, options, log);
    for (size_t i = 0; i < mtls.size(); ++i) scene.materials.push_back(converter.convert(mtls[i], i));
    converter.flushWarnings();

    // Vertex data in world space, validated once.
    const size_t nv = attrib.vertices.size() / 3, nn = attrib.normals.size() / 3, nt = attrib.texcoords.size() / 2;
    std::vector<Vec3f> pos(nv);
    std::vector<uint8_t> posOk(nv);
    for (size_t i = 0; i < nv; ++i) {
        Vec3f p{attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]};
        bool good = isFinite(p) && !(i < prep.badVertex.size() && prep.badVertex[i]);
        pos[i] = good ? worldFromObject.applyPoint(p) : Vec3f{};
        posOk[i] = good && isFinite(pos[i]);
    }
    std::vector<Vec3f> nrm(nn);
    for (size_t i = 0; i < nn; ++i) {
        Vec3f n{attrib.normals[3 * i], attrib.normals[3 * i + 1], attrib.normals[3 * i + 2]};
        n = normalize(worldFromObject.applyNormal(n));
        nrm[i] = isFinite(n) ? n : Vec3f{};
    }
    // A mirroring placement turns counter-clockwise into clockwise; swap to keep the front side.
    const bool flipWinding = worldFromObject.determinant() < 0.f;

    size_t totalFaces = 0;
    for (const auto& s : shapes) totalFaces += s.mesh.num_face_vertices.size();
    const bool haveLines = totalFaces == prep.faceLines.size();

    size_t badFaces = prep.invalidFaces, badNormalFaces = 0, badUvFaces = 0, degenerate = 0;
    uint32_t firstBadLine = prep.firstInvalidLine, firstBadNormalLine = 0, firstBadUvLine = 0;
    auto noteLine = [&](uint32_t& first, size_t face) {
        if (haveLines && (first == 0 || prep.faceLines[face] < first)) first = prep.faceLines[face];
    };

    std::vector<Vec3f> poly;
    std::vector<std::array<uint32_t, 3>> tris;
    size_t faceNo = 0, nextBig = 0;
    for (size_t si = 0; si < shapes.size(); ++si) {
        const tinyobj::mesh_t& sm = shapes[si].mesh;
        TriangleMesh mesh;
        std::string shapeName(trim(shapes[si].name));
        mesh.name = shapeName.empty() ? objPath.stem().string() : shapeName;
        std::unordered_map<VertexKey, uint32_t, VertexKeyHash> vertexOf;
        bool anyNormals = false, anyUvs = false;
        std::vector<uint32_t> faceMats;

        size_t offset = 0;
        for (size_t f = 0; f < sm.num_face_vertices.size(); ++f, ++faceNo) {
            size_t n = sm.num_face_vertices[f];
            if (offset + n > sm.indices.size()) break;  // cannot happen with tinyobjloader; guards the reads
            const tinyobj::index_t* c = &sm.indices[offset];
            offset += n;
            if (haveLines && nextBig < prep.bigFaces.size() && prep.bigFaces[nextBig].face == faceNo) {
                c = prep.bigFaces[nextBig].corners.data();
                n = prep.bigFaces[nextBig].corners.size();
                ++nextBig;
            }

            bool good = n >= 3;
            for (size_t i = 0; i < n && good; ++i) {
                int vi = c[i].vertex_index;
                good = vi >= 0 && static_cast<size_t>(vi) < nv && posOk[vi];
            }
            if (!good) {
                ++badFaces;
                noteLine(firstBadLine, faceNo);
                continue;
            }
            // Normals and UVs are all-or-nothing per face.
            bool useN = true, useUv = true, badN = false, badUv = false;
            for (size_t i = 0; i < n; ++i) {
                int vn = c[i].normal_index, vt = c[i].texcoord_index;
                if (vn < 0) useN = false;
                else if (static_cast<size_t>(vn) >= nn) badN = true;
                else if (lengthSquared(nrm[vn]) == 0.f) useN = false;
                if (vt < 0) useUv = false;
                else if (static_cast<size_t>(vt) >= nt) badUv = true;
                else if (!std::isfinite(attrib.texcoords[2 * vt]) || !std::isfinite(attrib.texcoords[2 * vt + 1]))
                    useUv = false;
            }
            if (badN) {
                ++badNormalFaces;
                noteLine(firstBadNormalLine, faceNo);
            }
            if (badUv) {
                ++badUvFaces;
                noteLine(firstBadUvLine, faceNo);
            }
            useN = useN && !badN;
            useUv = useUv && !badUv;

            int mid = f < sm.material_ids.size() ? sm.material_ids[f] : -1;
            uint32_t material = mid >= 0 && static_cast<size_t>(mid) < mtls.size()
                                    ? materialBase + static_cast<uint32_t>(mid)
                                    : converter.defaultMaterial();

            poly.resize(n);
            for (size_t i = 0; i < n; ++i) poly[i] = pos[c[i].vertex_index];
            triangulate(poly, tris);
            for (auto t : tris) {
                const Vec3f &p0 = poly[t[0]], &p1 = poly[t[1]], &p2 = poly[t[2]];
                if (!(lengthSquared(cross(p1 - p0, p2 - p0)) > 0.f)) {
                    ++degenerate;  // also keeps zero-area emitters out of the light set
                    continue;
                }
                if (flipWinding) std::swap(t[1], t[2]);
                for (uint32_t corner : t) {
                    const tinyobj::index_t& ix = c[corner];
                    VertexKey key{ix.vertex_index, useUv ? ix.texcoord_index : -1, useN ? ix.normal_index : -1};
                    auto [it, inserted] = vertexOf.try_emplace(key, static_cast<uint32_t>(mesh.positions.size()));
                    if (inserted) {
                        mesh.positions.push_back(pos[key.v]);
                        mesh.normals.push_back(key.vn >= 0 ? nrm[key.vn] : Vec3f{});
                        mesh.uvs.push_back(key.vt >= 0 ? Vec2f{attrib.texcoords[2 * key.vt],
                                                               attrib.texcoords[2 * key.vt + 1]}
                                                       : Vec2f{});
                        anyNormals = anyNormals || key.vn >= 0;
                        anyUvs = anyUvs || key.vt >= 0;
                    }
                    mesh.indices.push_back(it->second);
                }
                faceMats.push_back(material);
                if (scene.materials[material].isEmissive()) ++stats.emissiveTriangles;
            }
        }
        if (mesh.indices.empty()) continue;
        if (!anyNormals) mesh.normals.clear();
        if (!anyUvs) mesh.uvs.clear();
        mesh.material = faceMats[0];
        if (!std::all_of(faceMats.begin(), faceMats.end(), [&](uint32_t m) { return m == faceMats[0]; }))
            mesh.faceMaterials = std::move(faceMats);
        stats.triangles += mesh.triangleCount();
        scene.meshes.push_back(std::move(mesh));
    }

    if (badFaces > 0) {
        std::string what = std::to_string(badFaces) +
                           " face(s) with invalid vertex indices, fewer than 3 vertices or non-finite positions" +
                           lineNote(firstBadLine);
        if (options.strict) throw Error(ErrorCode::ParseError, file + ": " + what);
        log.warn(file + ": dropped " + what);
    }
    if (badNormalFaces > 0)
        log.warn(file + ": " + std::to_string(badNormalFaces) +
                 " face(s) with invalid normal indices use the geometric normal" +
                 lineNote(firstBadNormalLine));
    if (badUvFaces > 0)
        log.warn(file + ": " + std::to_string(badUvFaces) +
                 " face(s) with invalid texture coordinate indices have no UVs" +
                 lineNote(firstBadUvLine));
    if (degenerate > 0)
        log.info(file + ": skipped " + std::to_string(degenerate) + " degenerate (zero-area) triangle(s)");

    stats.droppedFaces = badFaces + degenerate;
    stats.materials = scene.materials.size() - materialBase;
    return stats;
}

LoadedScene loadObjScene(const std::filesystem::path& path, const LoadOptions& options, const Logger& log) {
    LoadedScene loaded;
    loaded.sourcePath = path;
    ObjStats stats;
    try {
        stats = appendObj(loaded.scene, path, Transform(), options, log);
    } catch (const std::bad_alloc&) {
        throw Error(ErrorCode::OutOfMemory, name(path) + ": out of memory while loading the scene");
    }
    if (stats.triangles == 0)
        throw Error(ErrorCode::InvalidScene,
                    name(path) + ": no faces to render" +
                        (stats.droppedFaces ? " (all " + std::to_string(stats.droppedFaces) +
                                                  " face(s) or triangle(s) were invalid or degenerate)"
                                            : std::string()));
    return loaded;
}

}  // namespace penumbra
