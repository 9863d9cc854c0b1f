// Assimp's side of the loaders, the one file that includes it. The model's
// bytes come from the descriptor opened after the path check and reach Assimp
// through ReadFileFromMemory; what the model references (a glTF .bin, ...) is
// opened through PolicyIOSystem, which asks the same path policy and opens
// each file once. Materials become MTL-like records for MaterialConverter, so
// textures are resolved and handed on by descriptor as for OBJ files.
#include "core/io/assimp_loader.h"

#include <assimp/BaseImporter.h>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/importerdesc.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <new>
#include <set>
#include <sstream>
#include <string_view>
#include <tuple>

#include "core/error.h"
#include "core/io/off_checks.h"
#include "core/io/mesh_options.h"
#include "core/io/mtl_materials.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

/// A file's bytes as an Assimp stream (read-only).
class MemoryStream final : public Assimp::IOStream {
public:
    explicit MemoryStream(std::string bytes) : bytes_(std::move(bytes)) {}
    size_t Read(void* buffer, size_t size, size_t count) override {
        if (size == 0 || pos_ >= bytes_.size()) return 0;
        const size_t n = std::min(count, (bytes_.size() - pos_) / size);
        std::memcpy(buffer, bytes_.data() + pos_, n * size);
        pos_ += n * size;
        return n;
    }
    size_t Write(const void*, size_t, size_t) override { return 0; }
    aiReturn Seek(size_t offset, aiOrigin origin) override {
        size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? pos_ : bytes_.size();
        if (origin != aiOrigin_SET && origin != aiOrigin_CUR && origin != aiOrigin_END) return aiReturn_FAILURE;
        if (offset > bytes_.size() - base) return aiReturn_FAILURE;
        pos_ = base + offset;
        return aiReturn_SUCCESS;
    }
    size_t Tell() const override { return pos_; }
    size_t FileSize() const override { return bytes_.size(); }
    void Flush() override {}

private:
    std::string bytes_;
    size_t pos_ = 0;
};

/// The files a model references, opened through the path policy (relative
/// names against the model's folder), each once; the first failure is kept
/// so that the error names the file instead of Assimp's summary.
class PolicyIOSystem final : public Assimp::IOSystem {
public:
    PolicyIOSystem(fs::path dir, const LoadOptions& options) : dir_(std::move(dir)), options_(options) {}

    bool Exists(const char* file) const override { return open(file) != nullptr; }
    char getOsSeparator() const override { return '/'; }
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (mode && (std::strchr(mode, 'w') || std::strchr(mode, 'a') || std::strchr(mode, '+'))) return nullptr;
        const InputFile* in = open(file);
        if (!in) {
            if (!error && failures_.count(resolve(file))) error = failures_.at(resolve(file));
            return nullptr;
        }
        try {
            return new MemoryStream(in->readAll());
        } catch (const Error& e) {
            if (!error) error = e;
            return nullptr;
        }
    }
    void Close(Assimp::IOStream* stream) override { delete stream; }
    bool ComparePaths(const char* a, const char* b) const override { return resolve(a) == resolve(b); }

    std::optional<Error> error;  // the first referenced file that could not be opened or read

private:
    fs::path resolve(const char* file) const {
        fs::path p(file ? file : "");
        return (p.is_absolute() ? p : dir_ / p).lexically_normal();
    }
    const InputFile* open(const char* file) const {
        const fs::path p = resolve(file);
        if (auto it = opened_.find(p); it != opened_.end()) return it->second.get();
        if (failures_.count(p)) return nullptr;
        try {
            return opened_.emplace(p, openInputFile(p, options_)).first->second.get();
        } catch (const Error& e) {
            failures_.emplace(p, e);
            return nullptr;
        }
    }

    fs::path dir_;
    const LoadOptions& options_;
    mutable std::map<fs::path, std::unique_ptr<InputFile>> opened_;
    mutable std::map<fs::path, Error> failures_;
};

Transform toTransform(const aiMatrix4x4& m) {
    const float rows[3][4] = {{m.a1, m.a2, m.a3, m.a4}, {m.b1, m.b2, m.b3, m.b4}, {m.c1, m.c2, m.c3, m.c4}};
    return Transform(rows);
}

Vec3f vec(const aiVector3D& v) { return {v.x, v.y, v.z}; }

/// Non-finite or negative components read as 0.
float clean(float v) { return std::isfinite(v) && v > 0.f ? v : 0.f; }

/// A node's transform to the model's root (the product along its parents).
Transform globalOf(const aiNode* node) {
    Transform t;
    for (int depth = 0; node && depth < 4096; node = node->mParent, ++depth) t = toTransform(node->mTransformation) * t;
    return t;
}

/// The material as an MTL record (docs/mtl-mapping.md, "Assimp formats").
MtlMaterial phongOf(const aiMaterial& a, const fs::path& file, const Logger& log, const std::string& where) {
    MtlMaterial m;
    aiString name;
    m.name = a.Get(AI_MATKEY_NAME, name) == aiReturn_SUCCESS ? std::string(name.C_Str()) : std::string("material");
    m.file = file;
    m.illum = 2;
    auto set = [](float out[3], const aiColor3D& c, float scale = 1.f) {
        out[0] = clean(c.r) * scale;
        out[1] = clean(c.g) * scale;
        out[2] = clean(c.b) * scale;
    };

    aiColor4D base4;
    float metallic = 0.f, roughness = 1.f;
    const bool pbr = a.Get(AI_MATKEY_BASE_COLOR, base4) == aiReturn_SUCCESS ||
                     a.Get(AI_MATKEY_METALLIC_FACTOR, metallic) == aiReturn_SUCCESS;
    if (pbr) {
        // Metallic-roughness as Phong: the diffuse part is the non-metal share of
        // the base colour less the dielectric's 4% specular; F0 (4% for
        // dielectrics, the base colour for metals) becomes ks with the Phong
        // exponent of the same Beckmann-like width, or a mirror when polished.
        aiColor3D base(1.f, 1.f, 1.f);
        if (a.Get(AI_MATKEY_BASE_COLOR, base4) == aiReturn_SUCCESS) base = aiColor3D(base4.r, base4.g, base4.b);
        else a.Get(AI_MATKEY_COLOR_DIFFUSE, base);
        metallic = 1.f;  // glTF's defaults
        roughness = 1.f;
        a.Get(AI_MATKEY_METALLIC_FACTOR, metallic);
        a.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness);
        metallic = std::isfinite(metallic) ? std::clamp(metallic, 0.f, 1.f) : 1.f;
        roughness = std::isfinite(roughness) ? std::clamp(roughness, 0.f, 1.f) : 1.f;
        float f0[3];
        const float b[3] = {clean(base.r), clean(base.g), clean(base.b)};
        for (int i = 0; i < 3; ++i) {
            m.diffuse[i] = (1.f - metallic) * (1.f - 0.04f) * b[i];
            f0[i] = 0.04f * (1.f - metallic) + metallic * b[i];
        }
        if (roughness <= 0.05f) {
            m.illum = 3;  // the converter takes a reflecting material's Ks as its mirror colour
            std::copy(f0, f0 + 3, m.specular);
        } else {
            const float alpha = roughness * roughness;
            const float blinn = 2.f / (alpha * alpha) - 2.f;
            m.shininess = std::clamp(blinn / 4.f, 1.f, 10000.f);
            std::copy(f0, f0 + 3, m.specular);
        }
    } else {
        aiColor3D c(0.8f, 0.8f, 0.8f);
        a.Get(AI_MATKEY_COLOR_DIFFUSE, c);
        set(m.diffuse, c);
        c = aiColor3D(0.f, 0.f, 0.f);
        float strength = 1.f;
        if (a.Get(AI_MATKEY_COLOR_SPECULAR, c) == aiReturn_SUCCESS) {
            a.Get(AI_MATKEY_SHININESS_STRENGTH, strength);
            set(m.specular, c, clean(strength));
        }
        float shininess = 0.f;
        if (a.Get(AI_MATKEY_SHININESS, shininess) == aiReturn_SUCCESS && std::isfinite(shininess) && shininess >= 1.f)
            m.shininess = std::min(shininess, 10000.f);
        c = aiColor3D(0.f, 0.f, 0.f);
        if (a.Get(AI_MATKEY_COLOR_AMBIENT, c) == aiReturn_SUCCESS) set(m.ambient, c);
    }
    aiColor3D e(0.f, 0.f, 0.f);
    float intensity = 1.f;
    a.Get(AI_MATKEY_COLOR_EMISSIVE, e);
    a.Get(AI_MATKEY_EMISSIVE_INTENSITY, intensity);
    set(m.emission, e, clean(intensity));

    aiString tex;
    if (a.GetTexture(aiTextureType_BASE_COLOR, 0, &tex) == aiReturn_SUCCESS ||
        a.GetTexture(aiTextureType_DIFFUSE, 0, &tex) == aiReturn_SUCCESS) {
        std::string t = tex.C_Str();
        if (!t.empty() && t[0] == '*')
            log.warn(where + " '" + m.name + "': embedded textures are not supported; using the base colour alone");
        else
            m.diffuseTexture = t;
    }
    return m;
}

/// Per-triangle colour from the first vertex-colour set, quantised to 8 bits
/// so that triangles of one colour share a material.
std::array<uint8_t, 3> triangleColour(const aiMesh& mesh, const uint32_t* corners) {
    float sum[3] = {0.f, 0.f, 0.f};
    for (unsigned k = 0; k < 3; ++k) {
        const aiColor4D& c = mesh.mColors[0][corners[k]];
        const float v[3] = {c.r, c.g, c.b};
        for (int i = 0; i < 3; ++i) sum[i] += std::isfinite(v[i]) ? std::clamp(v[i], 0.f, 1.f) : 1.f;
    }
    std::array<uint8_t, 3> q{};
    for (int i = 0; i < 3; ++i) q[i] = static_cast<uint8_t>(std::lround(sum[i] / 3.f * 255.f));
    return q;
}

/// Bytes of a PLY scalar type; 0 for an unknown name.
size_t plyTypeSize(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

/// Assimp 5.2.5's PLY reader loops for ever on a header without a clean
/// `end_header` line (a truncated file, junk after the keyword), reads past
/// its buffer when a header line it does not know shifts properties to
/// another element, and reserves what an element count claims. So PLY
/// headers are checked here first: known lines only, `end_header` alone on
/// its line, and element counts the rest of the file can hold (at least 2
/// bytes per ASCII value, the fixed sizes in binary files).
std::optional<std::string> plyHeaderProblem(const std::string& bytes) {
    bool binary = false, haveFormat = false, ended = false;
    struct Element {
        std::string name;
        uint64_t count = 0, minBytes = 0;
    };
    std::vector<Element> elements;
    size_t pos = 0;
    for (int n = 1; pos < bytes.size() && !ended; ++n) {
        const size_t eol = bytes.find('\n', pos);
        if (eol == std::string::npos) break;  // the header never ends
        std::string line = bytes.substr(pos, eol - pos);
        pos = eol + 1;
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
        if (n == 1) {
            if (line != "ply") return std::string("not a PLY file (no 'ply' line first)");
            continue;
        }
        if (line == "end_header") {
            ended = true;
            continue;
        }
        std::istringstream in(line);
        std::vector<std::string> t;
        for (std::string w; in >> w;) t.push_back(w);
        const std::string where = "header line " + std::to_string(n) + ": ";
        if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
        if (t[0] == "format" && t.size() == 3 &&
            (t[1] == "ascii" || t[1] == "binary_little_endian" || t[1] == "binary_big_endian")) {
            binary = t[1] != "ascii";
            haveFormat = true;
        } else if (t[0] == "element" && t.size() == 3 && !t[2].empty() && t[2].size() <= 10 &&
                   t[2].find_first_not_of("0123456789") == std::string::npos) {
            elements.push_back({t[1], std::stoull(t[2]), 0});
        } else if (t[0] == "property" && !elements.empty() && t.size() == 3 && plyTypeSize(t[1])) {
            elements.back().minBytes += binary ? plyTypeSize(t[1]) : 2;
        } else if (t[0] == "property" && !elements.empty() && t.size() == 5 && t[1] == "list" && plyTypeSize(t[2]) &&
                   plyTypeSize(t[3])) {
            elements.back().minBytes += binary ? plyTypeSize(t[2]) : 2;
        } else {
            std::string shown = line.substr(0, 60);
            for (char& c : shown)
                if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
            return where + "'" + shown + "' is not a PLY header line";
        }
    }
    if (!ended) return std::string("the header has no end_header line (a truncated file?)");
    if (!haveFormat) return std::string("the header has no format line");
    const uint64_t body = bytes.size() - pos;
    for (const Element& e : elements)
        if (e.minBytes && e.count > body / e.minBytes)
            return "element '" + e.name.substr(0, 40) + "' declares " + std::to_string(e.count) +
                   " items, more than the file's " + std::to_string(body) + " bytes of data can hold";
    return std::nullopt;
}

/// A number as Assimp's fast_atoreal_move reads it whole: it throws on "1e",
/// ".", "abc" and leaves the rest of "1,5" or "1x" for the next token.
bool stlNumber(std::string_view w) {
    size_t i = 0, digits = 0;
    auto run = [&] {
        const size_t from = i;
        while (i < w.size() && w[i] >= '0' && w[i] <= '9') ++i;
        return i - from;
    };
    if (i < w.size() && (w[i] == '+' || w[i] == '-')) ++i;
    digits = run();
    if (i < w.size() && w[i] == '.') {
        ++i;
        digits += run();
    }
    if (!digits) return false;
    if (i < w.size() && (w[i] == 'e' || w[i] == 'E')) {
        ++i;
        if (i < w.size() && (w[i] == '+' || w[i] == '-')) ++i;
        if (!run()) return false;
    }
    return i == w.size();
}

/// Assimp 5.2.5's ASCII STL reader keeps each solid's aiMesh and aiNode in
/// local vectors until the file is read, so when it throws inside a solid they
/// leak (2,464 bytes; LeakSanitizer in fuzz_model, reproduced with
/// Importer::ReadFileFromMemory alone): a facet of other than three vertices, a
/// number it cannot parse ("1e", "abc"), a line break inside a vertex, a file
/// that ends in a facet, a name of 1024 bytes. So a file it would read as ASCII
/// (text starting with "solid", after a UTF-8 byte-order mark, whose size is not
/// a binary STL's for the count at byte 80, as its IsBinarySTL decides) must be
/// well formed here first: solids of facets of three vertices, one statement a
/// line, numbers as C writes them, no control characters. UTF-16 and UTF-32
/// text, which it converts first, is refused.
std::optional<std::string> stlTextProblem(const std::string& bytes) {
    const std::string_view all = bytes;
    auto startsWith = [&](std::string_view p) { return all.substr(0, p.size()) == p; };
    using namespace std::string_view_literals;
    if (startsWith("\xfe\xff"sv) || startsWith("\xff\xfe"sv) || startsWith("\0\0\xfe\xff"sv))
        return std::string("UTF-16 or UTF-32 text (a byte-order mark) is not supported");
    std::string_view text = all;
    if (startsWith("\xef\xbb\xbf"sv)) text.remove_prefix(3);
    if (all.size() >= 84 && text.size() >= 84) {
        uint32_t count = 0;
        for (int i = 3; i >= 0; --i) count = (count << 8) | static_cast<unsigned char>(text[80 + i]);
        if (uint64_t(count * 50u + 84u) == all.size()) return std::nullopt;  // binary
    }
    const size_t first = text.find_first_not_of(" \t\r\n");
    if (first == std::string_view::npos || text.substr(first, 5) != "solid") return std::nullopt;

    enum class In { Nothing, Solid, Facet, Loop, EndLoop, EndFacet } in = In::Nothing;
    int vertices = 0;
    size_t lineNumber = 0;
    for (size_t pos = 0; pos < text.size();) {
        const size_t eol = std::min(text.find_first_of("\r\n", pos), text.size());
        const std::string_view line = text.substr(pos, eol - pos);
        pos = eol + (eol < text.size() && text[eol] == '\r' && eol + 1 < text.size() && text[eol + 1] == '\n' ? 2 : 1);
        ++lineNumber;
        const std::string where = "line " + std::to_string(lineNumber) + ": ";
        if (std::any_of(line.begin(), line.end(), [](char c) { return static_cast<unsigned char>(c) < 32 && c != '\t'; }))
            return where + "a control character in an ASCII STL file";
        std::vector<std::string_view> w;
        for (size_t i = 0; i < line.size();) {
            const size_t from = line.find_first_not_of(" \t", i);
            if (from == std::string_view::npos) break;
            const size_t to = std::min(line.find_first_of(" \t", from), line.size());
            w.push_back(line.substr(from, to - from));
            i = to;
        }
        if (w.empty()) continue;
        auto numbers = [&](size_t from) {
            return w.size() == from + 3 && stlNumber(w[from]) && stlNumber(w[from + 1]) && stlNumber(w[from + 2]);
        };
        std::string shown(line.substr(0, 60));
        for (char& c : shown)
            if (static_cast<unsigned char>(c) > 126) c = '?';
        const std::string bad = where + "'" + shown + "' where ";
        switch (in) {
            case In::Nothing:
                if (w[0] != "solid") return bad + "'solid NAME' was expected";
                if (w.size() > 1 && w[1].size() >= 1024) return where + "the solid's name is 1024 bytes or longer";
                for (size_t k = 1; k < w.size(); ++k)
                    if (w[k] == "facet" || w[k] == "vertex" || w[k].substr(0, 8) == "endsolid")
                        return where + "the solid's name holds the keyword '" + std::string(w[k].substr(0, 20)) + "'";
                in = In::Solid;
                break;
            case In::Solid:
                if (w[0] == "endsolid") {
                    in = In::Nothing;
                } else if (w[0] == "facet" && w.size() > 1 && w[1] == "normal" && numbers(2)) {
                    in = In::Facet;
                } else {
                    return bad + "'facet normal X Y Z' or 'endsolid' was expected";
                }
                break;
            case In::Facet:
                if (w.size() != 2 || w[0] != "outer" || w[1] != "loop") return bad + "'outer loop' was expected";
                in = In::Loop;
                vertices = 0;
                break;
            case In::Loop:
                if (w[0] != "vertex" || !numbers(1)) return bad + "'vertex X Y Z' was expected (three a facet)";
                if (++vertices == 3) in = In::EndLoop;
                break;
            case In::EndLoop:
                if (w.size() != 1 || w[0] != "endloop") return bad + "'endloop' was expected (three vertices a facet)";
                in = In::EndFacet;
                break;
            case In::EndFacet:
                if (w.size() != 1 || w[0] != "endfacet") return bad + "'endfacet' was expected";
                in = In::Solid;
                break;
        }
    }
    if (in != In::Nothing) return std::string("the file ends inside a solid (no 'endsolid')");
    return std::nullopt;
}

/// Inputs Assimp is known to mishandle (hang on, read out of bounds, leak), refused first.
std::optional<std::string> knownProblem(const std::string& format, const std::string& bytes) {
    if (format == "ply") return plyHeaderProblem(bytes);
    if (format == "stl") return stlTextProblem(bytes);
    if (format == "off") return offHeaderProblem(bytes);
    return std::nullopt;
}

/// Assimp picks the importer by the extension, but where several claim it
/// (glTF 1 and 2 both read .gltf and .glb; three read .xml) and none of them
/// accepts the file, it tries every importer's signature instead: a fuzzed
/// .gltf was read by the ASE importer, and a PLY header in a .gltf hangs the
/// PLY reader, past the checks above. So the claimants are asked first, as
/// Assimp asks them, and a file none of them accepts is refused.
std::optional<std::string> noClaimantAccepts(const Assimp::Importer& importer, Assimp::IOSystem& io,
                                             const std::string& format, const std::string& bytes) {
    std::vector<Assimp::BaseImporter*> claimants;
    std::string names;
    for (size_t i = 0; i < importer.GetImporterCount(); ++i) {
        const aiImporterDesc* d = importer.GetImporterInfo(i);
        std::istringstream in(d && d->mFileExtensions ? d->mFileExtensions : "");
        for (std::string e; in >> e;)
            if (lower(e) == format) {
                claimants.push_back(importer.GetImporter(i));
                names += std::string(names.empty() ? "" : ", ") + d->mName;
                break;
            }
    }
    if (claimants.size() < 2) return std::nullopt;  // Assimp uses the one without asking
    Assimp::MemoryIOSystem memory(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), &io);
    const std::string name = std::string(AI_MEMORYIO_MAGIC_FILENAME) + "." + format;
    for (Assimp::BaseImporter* claimant : claimants) {
        try {
            if (claimant && claimant->CanRead(name, &memory, true)) return std::nullopt;
        } catch (const std::exception&) {
            // not this one
        }
    }
    return "none of Assimp's readers of ." + format + " files accepts it (" + names + ")";
}

std::string formatName(const fs::path& p) {
    std::string e = p.extension().string();
    return e.empty() ? std::string("a model") : lower(e.substr(1));
}

/// The formats whose Assimp 5.2.5 importer leaks what it has read when it
/// throws on a malformed file, in ways no check here can foresee (each found by
/// fuzz_model and reproduced with Importer::ReadFileFromMemory alone):
/// - dae: ColladaParser parses the whole file in its constructor, so when it
///   throws ("Unknown reference format" for an <instance_geometry> without a
///   url, and many more) its destructor never runs and the nodes and meshes it
///   read leak (1,456 bytes in 9 allocations for one input).
/// - ply: PLYImporter deletes its half-built mesh when the body parser returns
///   false but not when it throws (a value fast_atoreal_move cannot read in an
///   ASCII body, "File corrupted" where a binary body ends early): 1,432 bytes.
constexpr std::array<std::string_view, 2> kLeakingImporters = {"dae", "ply"};

/// Importer::ReadFileFromMemory for those formats, apart: the leak is Assimp's,
/// and tests/fuzz/lsan.supp names this function, so that fuzz_model reports the
/// leaks of everything else. Never inlined, so that it is on the stack.
[[gnu::noinline]] const aiScene* assimpReadLeakingOnError(Assimp::Importer& importer, const std::string& bytes,
                                                           unsigned flags, const std::string& format) {
    return importer.ReadFileFromMemory(bytes.data(), bytes.size(), flags, format.c_str());
}

}  // namespace

bool assimpReadsExtension(const std::string& extension) {
    const std::string e = lower(extension);
    if (e.size() < 2 || e[0] != '.') return false;
    return Assimp::Importer().IsExtensionSupported(e);
}

std::vector<std::string> assimpExtensions() {
    std::string list;
    Assimp::Importer().GetExtensionList(list);  // "*.3ds;*.dae;..."
    std::vector<std::string> out;
    std::istringstream in(list);
    std::string item;
    while (std::getline(in, item, ';')) {
        if (item.rfind("*.", 0) == 0) out.push_back(lower(item.substr(1)));
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

ObjStats appendAssimp(Scene& scene, const InputFile& model, const Transform& worldFromObject, const LoadOptions& options,
                      const Logger& log, ModelExtras& extras) {
    const fs::path& path = model.path();
    const std::string file = path.string();
    const std::string format = formatName(path);

    Assimp::Importer importer;
    auto* io = new PolicyIOSystem(path.parent_path(), options);
    importer.SetIOHandler(io);  // the importer owns it
    const aiScene* s = nullptr;
    {
        const std::string bytes = model.readAll();
        if (bytes.empty()) throw Error(ErrorCode::ParseError, file + ": empty file");
        if (auto why = knownProblem(format, bytes)) throw Error(ErrorCode::ParseError, file + ": cannot read as " + format + ": " + *why);
        if (auto why = noClaimantAccepts(importer, *io, format, bytes))
            throw Error(ErrorCode::ParseError, file + ": cannot read as " + format + ": " + *why);
        try {
            // Validation only: Debian's Assimp aborts (ai_assert) in its triangulation
            // step on faces it does not expect, so polygons are split below, as OBJ's are.
            const unsigned flags = aiProcess_ValidateDataStructure;
            s = std::find(kLeakingImporters.begin(), kLeakingImporters.end(), format) != kLeakingImporters.end()
                    ? assimpReadLeakingOnError(importer, bytes, flags, format)
                    : importer.ReadFileFromMemory(bytes.data(), bytes.size(), flags, format.c_str());
        } catch (const std::bad_alloc&) {
            throw Error(ErrorCode::OutOfMemory, file + ": out of memory while reading the " + format + " file");
        } catch (const std::exception& e) {
            throw Error(ErrorCode::ParseError, file + ": cannot read as " + format + ": " + e.what());
        }
    }
    if (!s || (s->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !s->mRootNode) {
        if (io->error) throw Error(io->error->code(), file + ": " + io->error->what());
        std::string why = importer.GetErrorString();
        // Assimp names the in-memory file by a magic name of its own: name the real one.
        for (size_t at; (at = why.find("$$$___magic___$$$")) != std::string::npos;) {
            const size_t stop = why.find_first_of(" :,;'\"", at);
            why.replace(at, (stop == std::string::npos ? why.size() : stop) - at, path.filename().string());
        }
        for (char& c : why)
            if (c == '\n' || c == '\r') c = ' ';
        if (why.empty()) why = "the file is incomplete";
        throw Error(ErrorCode::ParseError, file + ": cannot read as " + format + ": " + why);
    }

    // Materials, appended after the scene's own.
    const uint32_t materialBase = static_cast<uint32_t>(scene.materials.size());
    MaterialConverter converter(scene, path, options, log);
    for (unsigned i = 0; i < s->mNumMaterials; ++i)
        scene.materials.push_back(converter.convert(phongOf(*s->mMaterials[i], path, log, file + ": material")));
    converter.flushWarnings();
    const size_t modelMaterials = scene.materials.size() - materialBase;
    std::map<std::tuple<uint32_t, uint8_t, uint8_t, uint8_t>, uint32_t> tinted;  // (material, colour) -> material
    auto materialOf = [&](unsigned index) {
        return index < modelMaterials ? materialBase + index : converter.defaultMaterial();
    };

    // Meshes, placed by their nodes (walked without recursion: a file may nest deeply).
    ObjStats stats;
    const size_t firstMesh = scene.meshes.size();
    std::vector<std::pair<const aiNode*, Transform>> stack{{s->mRootNode, worldFromObject}};
    std::set<const aiNode*> visited;  // a node graph is a tree; a broken file must not loop
    while (!stack.empty()) {
        auto [node, parent] = stack.back();
        stack.pop_back();
        if (!visited.insert(node).second) continue;
        const Transform t = parent * toTransform(node->mTransformation);
        const bool mirrored = t.determinant() < 0.f;  // keeps the front side the front side, as for OBJ
        for (unsigned c = node->mNumChildren; c-- > 0;)
            if (node->mChildren[c]) stack.emplace_back(node->mChildren[c], t);
        for (unsigned k = 0; k < node->mNumMeshes; ++k) {
            if (node->mMeshes[k] >= s->mNumMeshes) continue;
            const aiMesh& am = *s->mMeshes[node->mMeshes[k]];
            if (!am.mVertices || !am.mFaces) continue;
            TriangleMesh m;
            m.name = am.mName.length ? std::string(am.mName.C_Str()) : path.stem().string();
            if (node->mName.length && m.name != node->mName.C_Str()) m.name = std::string(node->mName.C_Str()) + "/" + m.name;
            m.material = materialOf(am.mMaterialIndex);
            m.positions.reserve(am.mNumVertices);
            for (unsigned v = 0; v < am.mNumVertices; ++v) m.positions.push_back(t.applyPoint(vec(am.mVertices[v])));
            if (am.mNormals) {
                m.normals.reserve(am.mNumVertices);
                for (unsigned v = 0; v < am.mNumVertices; ++v) m.normals.push_back(t.applyNormal(vec(am.mNormals[v])));
            }
            if (am.mTextureCoords[0]) {
                m.uvs.reserve(am.mNumVertices);
                for (unsigned v = 0; v < am.mNumVertices; ++v) m.uvs.push_back({am.mTextureCoords[0][v].x, am.mTextureCoords[0][v].y});
            }
            const bool colours = am.mColors[0] != nullptr && m.material >= materialBase;
            m.indices.reserve(size_t(am.mNumFaces) * 3);
            std::vector<Vec3f> polygon;
            std::vector<std::array<uint32_t, 3>> split;
            std::vector<uint32_t> triangles;
            for (unsigned f = 0; f < am.mNumFaces; ++f) {
                const aiFace& face = am.mFaces[f];
                if (face.mNumIndices < 3 || !face.mIndices) continue;  // points and lines
                // Faces on missing or non-finite positions (NaN in the file, or beyond
                // float range after the node's transform) are dropped, as OBJ's are.
                if (std::any_of(face.mIndices, face.mIndices + face.mNumIndices,
                                [&](unsigned i) { return i >= am.mNumVertices || !isFinite(m.positions[i]); })) {
                    ++stats.droppedFaces;
                    continue;
                }
                triangles.assign(face.mIndices, face.mIndices + 3);
                if (face.mNumIndices > 3) {
                    polygon.clear();
                    for (unsigned c = 0; c < face.mNumIndices; ++c) polygon.push_back(vec(am.mVertices[face.mIndices[c]]));
                    split.clear();
                    triangulate(polygon, split);
                    triangles.clear();
                    for (const auto& tri : split)
                        for (uint32_t c : tri) triangles.push_back(face.mIndices[c]);
                }
                for (size_t first = 0; first + 3 <= triangles.size(); first += 3) {
                    const uint32_t* tri = triangles.data() + first;
                    if (mirrored)
                        m.indices.insert(m.indices.end(), {tri[0], tri[2], tri[1]});
                    else
                        m.indices.insert(m.indices.end(), tri, tri + 3);
                    if (colours) {
                        const auto q = triangleColour(am, triangles.data() + first);
                        uint32_t id = m.material;
                        if (q != std::array<uint8_t, 3>{255, 255, 255}) {
                            auto [it, fresh] = tinted.try_emplace({m.material, q[0], q[1], q[2]}, 0);
                            if (fresh) {
                                Material tint = scene.materials[m.material];
                                tint.kd = Rgb(tint.kd) * Rgb(q[0] / 255.f, q[1] / 255.f, q[2] / 255.f);
                                tint.name += "*vertex colour";
                                it->second = static_cast<uint32_t>(scene.materials.size());
                                scene.materials.push_back(tint);
                            }
                            id = it->second;
                        }
                        m.faceMaterials.push_back(id);
                    }
                }
            }
            if (m.indices.empty()) continue;
            if (!std::all_of(m.positions.begin(), m.positions.end(), [](const Vec3f& p) { return isFinite(p); }))
                keepUsedVertices(m);  // a loaded mesh holds finite positions only
            if (!m.faceMaterials.empty() &&
                std::all_of(m.faceMaterials.begin(), m.faceMaterials.end(), [&](uint32_t id) { return id == m.material; }))
                m.faceMaterials.clear();
            stats.triangles += m.triangleCount();
            for (size_t tri = 0; tri < m.triangleCount(); ++tri)
                stats.emissiveTriangles += scene.materials[m.materialOf(tri)].isEmissive();
            scene.meshes.push_back(std::move(m));
        }
    }
    stats.materials = scene.materials.size() - materialBase;
    applyMeshOptions(scene, firstMesh, materialBase, options);

    // The first camera, through its node.
    for (unsigned i = 0; i < s->mNumCameras && !extras.camera; ++i) {
        const aiCamera& c = *s->mCameras[i];
        const aiNode* node = s->mRootNode->FindNode(c.mName);
        const Transform t = worldFromObject * globalOf(node);
        // The position is relative to the node, but Assimp's glTF importer
        // also copies the node's translation into it: counted once.
        Vec3f local = vec(c.mPosition);
        if (node && local.x == node->mTransformation.a4 && local.y == node->mTransformation.b4 &&
            local.z == node->mTransformation.c4)
            local = Vec3f{};
        CameraDesc cam;
        cam.eye = t.applyPoint(local);
        const Vec3f dir = t.applyVector(vec(c.mLookAt)), up = t.applyVector(vec(c.mUp));
        const float l = length(dir);
        if (!(l > 0.f) || !std::isfinite(l) || !(length(up) > 0.f)) continue;
        cam.lookAt = cam.eye + dir / l;
        cam.up = up;
        // Assimp's horizontal angle (the full angle, as its glTF and COLLADA importers fill it) as a vertical one.
        const float aspect = c.mAspect > 0.f && std::isfinite(c.mAspect) ? c.mAspect : 1.f;
        if (c.mHorizontalFOV > 0.f && c.mHorizontalFOV < kPi) {
            const float vfov = 2.f * std::atan(std::tan(0.5f * c.mHorizontalFOV) / aspect) * 180.f / kPi;
            if (vfov > 0.f && vfov < 180.f) cam.vfovDegrees = vfov;
        }
        if (isFinite(cam.eye) && isFinite(cam.lookAt) && isFinite(cam.up)) extras.camera = cam;
    }
    // Lights, through their nodes.
    size_t skipped = 0;
    for (unsigned i = 0; i < s->mNumLights; ++i) {
        const aiLight& l = *s->mLights[i];
        const Transform t = worldFromObject * globalOf(s->mRootNode->FindNode(l.mName));
        const Rgb colour(clean(l.mColorDiffuse.r), clean(l.mColorDiffuse.g), clean(l.mColorDiffuse.b));
        if (l.mType == aiLightSource_POINT || l.mType == aiLightSource_SPOT) {
            if (l.mType == aiLightSource_SPOT) ++skipped;
            const Vec3f p = t.applyPoint(vec(l.mPosition));
            if (isFinite(p)) extras.pointLights.push_back({p, colour});
        } else if (l.mType == aiLightSource_DIRECTIONAL) {
            const Vec3f d = t.applyVector(vec(l.mDirection));
            const float len = length(d);
            if (len > 0.f && std::isfinite(len)) extras.directionalLights.push_back({d / len, colour});
        } else {
            ++skipped;
        }
    }
    if (skipped)
        log.warn(file + ": " + std::to_string(skipped) +
                 " spot, ambient or area light(s): spot lights shine as point lights, the others are skipped");
    return stats;
}

}  // namespace penumbra
