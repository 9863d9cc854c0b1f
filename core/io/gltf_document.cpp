// readGltfFile: the checks tinygltf 2.7 needs before it sees a file, and its
// file-system and image callbacks. What the model references is opened
// through the path policy (each file once); image files are opened but not
// read (their descriptors go to the texture cache, as OBJ textures do), and
// images inside the file are kept as bytes, never decoded here.
// tinygltf's parser is compiled here from Debian's header (libtinygltf-dev)
// rather than taken from libtinygltf.so: libdraco, which Assimp loads,
// exports the unversioned symbols of another tinygltf, and the dynamic linker
// bound calls to that copy, whose types differ (a crash). Compiled into this
// library with hidden visibility, nothing can take its place.
// (Its writers use std::ofstream even without file functions: <fstream> first.)
#include <fstream>
#define TINYGLTF_IMPLEMENTATION
#include "core/io/gltf_model.h"

#include <algorithm>
#include <cctype>
#include <limits>
#include <map>
#include <memory>
#include <new>
#include <optional>
#include <set>
#include <utility>

#include "core/error.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

/// Deeper JSON than this is refused before tinygltf parses it: its extras and
/// extensions are copied by a function that recurses once per level (a few
/// hundred thousand levels overflow the stack). Real files nest below 20.
constexpr int kMaxJsonDepth = 256;

/// The extensions read here; a file that requires any other is refused, as the specification asks.
const std::set<std::string> kReadExtensions = {
    "KHR_lights_punctual",      "KHR_materials_emissive_strength", "KHR_materials_ior",
    "KHR_materials_transmission", "KHR_texture_transform",          "KHR_mesh_quantization"};

uint32_t le32(const std::string& b, size_t at) {
    uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[at + i]);
    return v;
}

[[noreturn]] void refuse(const fs::path& file, const std::string& why) {
    throw Error(ErrorCode::ParseError, file.string() + ": cannot read as glTF: " + why);
}

/// A binary glTF's chunks must lie inside the file: tinygltf 2.7 bounds the
/// BIN chunk's payload without its 8-byte header and would read past the end.
void checkBinaryLayout(const fs::path& file, const std::string& bytes) {
    if (bytes.size() < 20) refuse(file, "a binary glTF is at least 20 bytes long, this file has " + std::to_string(bytes.size()));
    if (le32(bytes, 4) != 2)
        refuse(file, "binary glTF version " + std::to_string(le32(bytes, 4)) + " (only glTF 2.0 is read)");
    const uint64_t length = le32(bytes, 8), json = le32(bytes, 12);
    if (length > bytes.size())
        refuse(file, "the header says " + std::to_string(length) + " bytes, the file has " + std::to_string(bytes.size()));
    if (le32(bytes, 16) != 0x4E4F534A || json == 0 || 20 + json > length)
        refuse(file, "the first chunk is not a JSON chunk inside the file");
    const uint64_t bin = 20 + json;
    if (bin == length) return;
    if (bin + 8 > length || le32(bytes, bin + 4) != 0x004E4942 || bin + 8 + le32(bytes, bin) > length)
        refuse(file, "the chunk after the JSON is not a BIN chunk inside the file");
}

/// How deeply arrays and objects nest in JSON text (strings skipped).
int jsonDepth(std::string_view json) {
    int depth = 0, deepest = 0;
    bool inString = false;
    for (size_t i = 0; i < json.size(); ++i) {
        const char c = json[i];
        if (inString) {
            if (c == '\\') ++i;
            else if (c == '"') inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return deepest;
}

bool hasImageExtension(const fs::path& p) {
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
    for (const char* x : {".png", ".jpg", ".jpeg", ".ktx2", ".webp", ".gif", ".bmp", ".tga", ".dds", ".exr", ".hdr"})
        if (e == x) return true;
    return false;
}

/// What the callbacks share while tinygltf reads one file.
struct Reading {
    fs::path file;
    std::string dirPrefix;  // what tinygltf puts before a relative URI ("dir/"; empty for the current folder)
    const LoadOptions& options;
    tinygltf::Model* model = nullptr;
    std::map<std::string, std::shared_ptr<const InputFile>> opened;  // by the name tinygltf asked for
    std::vector<std::pair<std::string, Error>> failed;              // the files that could not be used, in order
    std::optional<Error> refused;                                   // the first outside the allowed folders
    std::shared_ptr<const InputFile> imageFile;                     // an image file tinygltf just "read"
    std::vector<TextureSource> images;
};

bool fileExists(const std::string& path, void* user) {
    Reading& r = *static_cast<Reading*>(user);
    // tinygltf also tries the current folder: only the model's own is asked for.
    if (path.compare(0, r.dirPrefix.size(), r.dirPrefix) != 0) return false;
    if (std::any_of(path.begin(), path.end(), [](char c) { return static_cast<unsigned char>(c) < 32; })) {
        r.failed.emplace_back(path, Error(ErrorCode::ParseError, "cannot read as glTF: a URI holds a control character"));
        return false;
    }
    if (r.opened.count(path)) return true;
    try {
        r.opened.emplace(path, openInputFile(fs::path(path), r.options));
        return true;
    } catch (const Error& e) {
        r.failed.emplace_back(path, e);
        if (e.code() == ErrorCode::InvalidArgument && !r.refused) r.refused = e;
        return false;
    }
}

std::string expandFilePath(const std::string& path, void*) { return path; }

bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    Reading& r = *static_cast<Reading*>(user);
    const auto it = r.opened.find(path);
    if (it == r.opened.end()) {
        if (err) *err = "not opened";
        return false;
    }
    if (hasImageExtension(path)) {
        // Not read now: the texture cache decodes it from this descriptor when the scene is prepared.
        r.imageFile = it->second;
        out->assign(1, 0);
        return true;
    }
    try {
        const std::string bytes = it->second->readAll();
        out->assign(bytes.begin(), bytes.end());
    } catch (const Error& e) {
        r.failed.emplace_back(path, e);
        if (err) *err = e.what();
        return false;
    }
    return true;
}

bool writeWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err = "writing is not supported";
    return false;
}

/// The image loader: keeps where each image's bytes are, decodes nothing.
bool keepImage(tinygltf::Image* image, int index, std::string* err, std::string*, int, int, const unsigned char* bytes,
               int size, void* user) {
    Reading& r = *static_cast<Reading*>(user);
    if (index < 0) return false;
    if (r.images.size() <= size_t(index)) r.images.resize(size_t(index) + 1);
    TextureSource& out = r.images[size_t(index)];
    const std::string where = "images[" + std::to_string(index) + "]";
    if (image->bufferView >= 0) {
        // tinygltf hands over the view's bytes without checking that they lie in the buffer.
        const tinygltf::BufferView& view = r.model->bufferViews[size_t(image->bufferView)];
        const size_t have = r.model->buffers[size_t(view.buffer)].data.size();
        if (view.byteOffset > have || view.byteLength > have - view.byteOffset) {
            if (err)
                *err += where + ": bufferViews[" + std::to_string(image->bufferView) + "] (byteOffset " +
                        std::to_string(view.byteOffset) + ", byteLength " + std::to_string(view.byteLength) +
                        ") reaches past its buffer's " + std::to_string(have) + " bytes";
            return false;
        }
    }
    std::string ext = image->mimeType == "image/png" ? ".png" : image->mimeType == "image/jpeg" ? ".jpg" : "";
    if (r.imageFile) {
        out = TextureSource{r.imageFile->path().string(), TextureColorSpace::FromFile, r.imageFile->fd(), r.imageFile, nullptr};
        r.imageFile.reset();
    } else if (size > 0) {
        // Inside the file (a buffer view, a data: URI), or a file without an image's name, read whole: the bytes.
        out.name = image->uri.empty() ? r.file.string() + "#image" + std::to_string(index) + ext : r.dirPrefix + image->uri;
        out.bytes = std::make_shared<const std::vector<unsigned char>>(bytes, bytes + size);
    }
    return true;
}

/// Refuses what tinygltf accepts but the specification does not let a reader render.
void checkAsset(const fs::path& file, const tinygltf::Model& m) {
    const std::string& v = m.asset.version;
    if (v.empty() || v[0] != '2')
        refuse(file, "asset.version is \"" + v.substr(0, 20) + "\" (only glTF 2.0 is read)");
    if (!m.asset.minVersion.empty() && m.asset.minVersion != "2.0")
        refuse(file, "asset.minVersion is \"" + m.asset.minVersion.substr(0, 20) + "\" (only glTF 2.0 is read)");
    for (const std::string& e : m.extensionsRequired)
        if (!kReadExtensions.count(e))
            refuse(file, "it requires the extension " + e.substr(0, 60) + ", which Penumbra does not read");
}

/// tinygltf's message as one printable line of at most 300 bytes (it may
/// quote a whole data: URI).
std::string oneLine(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    for (char& c : s)
        if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = c == '\n' ? ' ' : '?';
    if (s.size() > 300) s = s.substr(0, 240) + " ... " + s.substr(s.size() - 40);
    return s;
}

}  // namespace

GltfFile readGltfFile(const InputFile& in, const LoadOptions& options, const Logger& log) {
    GltfFile out;
    out.path = in.path();
    const fs::path& file = out.path;
    const std::string bytes = in.readAll();
    if (bytes.empty()) throw Error(ErrorCode::ParseError, file.string() + ": empty file");
    if (bytes.size() >= std::numeric_limits<unsigned int>::max()) refuse(file, "the file is 4 GiB or larger");
    const bool binary = bytes.compare(0, 4, "glTF") == 0;
    std::string_view json = bytes;
    if (binary) {
        checkBinaryLayout(file, bytes);
        json = json.substr(20, le32(bytes, 12));
    }
    if (jsonDepth(json) > kMaxJsonDepth)
        refuse(file, "its JSON nests arrays and objects more than " + std::to_string(kMaxJsonDepth) + " deep");

    const std::string dir = file.parent_path().string();
    Reading r{file, dir.empty() ? "" : dir.back() == '/' ? dir : dir + "/", options};
    r.model = &out.model;
    tinygltf::TinyGLTF reader;
    reader.SetFsCallbacks({&fileExists, &expandFilePath, &readWholeFile, &writeWholeFile, &r});
    reader.SetImageLoader(&keepImage, &r);
    std::string err, warn;
    bool ok = false;
    try {
        const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
        ok = binary ? reader.LoadBinaryFromMemory(&out.model, &err, &warn, data, unsigned(bytes.size()), dir)
                    : reader.LoadASCIIFromString(&out.model, &err, &warn, bytes.data(), unsigned(bytes.size()), dir);
    } catch (const std::bad_alloc&) {
        throw Error(ErrorCode::OutOfMemory, file.string() + ": out of memory while reading the glTF file");
    } catch (const std::exception& e) {
        err = e.what();
    }
    // A file refused by the path policy stays an error, even where tinygltf would only warn (an image).
    if (r.refused) throw Error(r.refused->code(), file.string() + ": " + r.refused->what());
    if (!ok) {
        // A buffer that cannot be read (buffers come before images): that file's error, not tinygltf's summary.
        const bool fileProblem = err.find("File not found") != std::string::npos || err.find("File read error") != std::string::npos;
        if (fileProblem && !r.failed.empty())
            throw Error(r.failed.front().second.code(), file.string() + ": " + r.failed.front().second.what());
        if (err.rfind("[json.exception", 0) == 0) refuse(file, "the JSON is not valid (" + oneLine(err) + ")");
        refuse(file, err.empty() ? std::string("tinygltf gives no reason") : oneLine(err));
    }
    checkAsset(file, out.model);
    out.images = std::move(r.images);
    out.images.resize(out.model.images.size());
    for (size_t i = 0; i < out.images.size(); ++i) {
        if (!out.images[i].name.empty()) continue;
        const std::string& uri = out.model.images[i].uri;
        const auto why = std::find_if(r.failed.begin(), r.failed.end(), [&](const auto& f) { return f.first == r.dirPrefix + uri; });
        log.warn(file.string() + ": images[" + std::to_string(i) + "] " +
                 (why != r.failed.end() ? std::string(why->second.what())
                                        : "('" + uri.substr(0, 80) + "') cannot be read") +
                 "; materials use it without the texture");
    }
    return out;
}

}  // namespace penumbra
