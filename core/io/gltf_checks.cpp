#include "core/io/gltf_checks.h"

#include "core/io/json_document.h"  // nlohmann-json, from its one include point

#include <algorithm>
#include <cstdint>
#include <string_view>

namespace penumbra {
namespace {

uint32_t le32(std::string_view b, size_t at) {
    uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[at + i]);
    return v;
}

/// Assimp 5.2.5 leaks the buffer of a glTF `data:` URI whose base64 holds a
/// byte outside ASCII: Base64::Decode allocates the output, then its DecodeChar
/// throws on the byte and the buffer is never freed (LeakSanitizer, the fuzz
/// target fuzz_model; reproduced with Importer::ReadFileFromMemory alone). Its
/// ParseDataURI also takes a string that starts with U+0010 for a URI it has
/// already parsed and reads the payload at offsets stored in its next bytes.
/// Such strings are invalid in a glTF anyway (URIs are ASCII), so the JSON's
/// strings are checked first, decoded as rapidjson decodes them.
std::optional<std::string> stringProblem(std::string_view json) {
    auto hex = [](char c) {
        return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
    };
    for (size_t i = 0; i < json.size(); ++i) {
        if (json[i] != '"') continue;  // outside strings, valid JSON has no quote
        std::string head;              // the first decoded bytes
        bool ascii = true;
        for (++i; i < json.size() && json[i] != '"'; ++i) {
            unsigned c = static_cast<unsigned char>(json[i]);
            if (c == '\\' && i + 1 < json.size()) {
                const char e = json[++i];
                c = static_cast<unsigned char>(e == 'b' ? '\b' : e == 'f' ? '\f' : e == 'n' ? '\n' : e == 'r' ? '\r' : e == 't' ? '\t' : e);
                if (e == 'u' && i + 4 < json.size()) {
                    c = 0;
                    for (int k = 1; k <= 4; ++k) c = c * 16 + static_cast<unsigned>(std::max(hex(json[i + k]), 0));
                    i += 4;
                }
            }
            if (c >= 0x80) ascii = false;
            if (head.size() < 5) head += static_cast<char>(std::min(c, 0x80u));
        }
        if (!head.empty() && head[0] == '\x10')
            return std::string("a JSON string starts with the control character U+0010");
        if (!ascii && head == "data:") return std::string("a data: URI holds a character that is not ASCII");
    }
    return std::nullopt;
}

/// A problem found in the document's structure.
struct Invalid {
    std::string why;
};

/// collection[ref]: by index in an array (glTF 2) or by key in an object (glTF 1).
const Json& item(const Json& doc, const char* collection, const Json& ref, const std::string& where) {
    const auto c = doc.find(collection);
    if (c != doc.end() && c->is_array() && ref.is_number_unsigned() && ref.get<uint64_t>() < c->size())
        return (*c)[ref.get<size_t>()];
    if (c != doc.end() && c->is_object() && ref.is_string()) {
        const auto it = c->find(ref.get<std::string>());
        if (it != c->end() && it->is_object()) return *it;
    }
    throw Invalid{where + " names no entry of '" + collection + "'"};
}

/// A non-negative integer member (`fallback` when absent), below 2^53.
uint64_t count(const Json& o, const char* key, const std::string& where, uint64_t fallback = 0) {
    const auto it = o.find(key);
    if (it == o.end()) return fallback;
    if (!it->is_number_unsigned() || it->get<uint64_t>() >= (uint64_t(1) << 53))
        throw Invalid{where + "." + key + " is not a whole number >= 0"};
    return it->get<uint64_t>();
}

std::string named(const char* collection, const Json& ref) {
    return std::string(collection) + "[" + (ref.is_string() ? ref.get<std::string>().substr(0, 40) : ref.dump()) + "]";
}

/// Bytes of one component of `o`'s componentType.
uint64_t componentBytes(const Json& o, const std::string& where) {
    const uint64_t type = count(o, "componentType", where);
    const uint64_t size = type == 5120 || type == 5121   ? 1
                          : type == 5122 || type == 5123 ? 2
                          : type == 5124 || type == 5125 || type == 5126 ? 4
                                                                         : 0;
    if (!size) throw Invalid{where + ".componentType is not a glTF component type"};
    return size;
}

/// Bytes of one element: component size times components (as Assimp reads them, unpadded).
uint64_t elementBytes(const Json& accessor, const std::string& where) {
    const uint64_t size = componentBytes(accessor, where);
    const auto t = accessor.find("type");
    const std::string name = t != accessor.end() && t->is_string() ? t->get<std::string>() : "";
    const uint64_t n = name == "SCALAR" ? 1 : name == "VEC2" ? 2 : name == "VEC3" ? 3 : name == "VEC4" || name == "MAT2" ? 4
                       : name == "MAT3" ? 9 : name == "MAT4" ? 16 : 0;
    if (!n) throw Invalid{where + ".type is not a glTF accessor type"};
    return size * n;
}

/// The buffer view, checked against its buffer; returns its byte length.
uint64_t viewBytes(const Json& doc, const Json& ref, const std::string& by, uint64_t binaryChunk) {
    const std::string where = named("bufferViews", ref);
    const Json& view = item(doc, "bufferViews", ref, by + " (bufferView)");
    const auto b = view.find("buffer");
    if (b == view.end()) throw Invalid{where + " has no buffer"};
    const Json& buffer = item(doc, "buffers", *b, where + ".buffer");
    const uint64_t bufferBytes = count(buffer, "byteLength", named("buffers", *b));
    if (!buffer.contains("uri") && binaryChunk != UINT64_MAX && bufferBytes > binaryChunk)
        throw Invalid{named("buffers", *b) + ".byteLength " + std::to_string(bufferBytes) + " is more than the " +
                      std::to_string(binaryChunk) + " bytes of the binary chunk"};
    const uint64_t offset = count(view, "byteOffset", where), length = count(view, "byteLength", where);
    if (offset + length > bufferBytes)
        throw Invalid{where + " (byteOffset " + std::to_string(offset) + ", byteLength " + std::to_string(length) +
                      ") reaches past its buffer's " + std::to_string(bufferBytes) + " bytes"};
    return length;
}

/// Every accessor's and sparse part's bytes lie inside its buffer view.
void checkAccessors(const Json& doc, uint64_t binaryChunk) {
    const auto accessors = doc.find("accessors");
    if (accessors == doc.end() || !(accessors->is_array() || accessors->is_object())) return;
    for (auto it = accessors->begin(); it != accessors->end(); ++it) {
        const Json& a = *it;
        const std::string where =
            accessors->is_array() ? "accessors[" + std::to_string(std::distance(accessors->begin(), it)) + "]"
                                  : "accessors[" + it.key().substr(0, 40) + "]";
        if (!a.is_object()) throw Invalid{where + " is not an object"};
        const uint64_t element = elementBytes(a, where);
        const uint64_t n = count(a, "count", where);
        if (const auto v = a.find("bufferView"); v != a.end() && n > 0) {
            const uint64_t length = viewBytes(doc, *v, where, binaryChunk);
            const Json& view = item(doc, "bufferViews", *v, where);
            uint64_t stride = count(view, "byteStride", named("bufferViews", *v));
            if (!stride) stride = count(a, "byteStride", where);  // glTF 1 keeps it on the accessor
            if (!stride) stride = element;
            const uint64_t end = count(a, "byteOffset", where) + (n - 1) * stride + element;
            if (end > length)
                throw Invalid{where + " reads bytes up to " + std::to_string(end) + " of " + named("bufferViews", *v) +
                              ", which has " + std::to_string(length)};
        }
        const auto sparse = a.find("sparse");
        if (sparse == a.end()) continue;
        if (!sparse->is_object()) throw Invalid{where + ".sparse is not an object"};
        const uint64_t m = count(*sparse, "count", where + ".sparse");
        if (m > n) throw Invalid{where + ".sparse.count is more than the accessor's count"};
        for (const char* part : {"indices", "values"}) {
            const std::string at = where + ".sparse." + part;
            const auto p = sparse->find(part);
            if (p == sparse->end() || !p->is_object() || !p->contains("bufferView")) throw Invalid{at + " has no bufferView"};
            const uint64_t each = std::string(part) == "values" ? element : componentBytes(*p, at);
            const uint64_t end = count(*p, "byteOffset", at) + m * each;
            const uint64_t length = viewBytes(doc, (*p)["bufferView"], at, binaryChunk);
            if (end > length) throw Invalid{at + " reads bytes up to " + std::to_string(end) + " of a buffer view of " + std::to_string(length)};
        }
    }
}

}  // namespace

std::optional<std::string> gltfProblem(const std::string& bytes) {
    // The JSON: the whole file, or the chunk at byte 20 of a binary glTF
    // (versions 1 and 2 both store its length at byte 12); it ends at a NUL, as
    // for rapidjson. Version 2's binary chunk, if any, follows it (4-aligned).
    std::string_view json = bytes;
    uint64_t binaryChunk = UINT64_MAX;  // none: buffers without a uri are not checked against it
    if (bytes.size() >= 20 && bytes.compare(0, 4, "glTF") == 0) {
        const uint32_t length = le32(bytes, 12);
        json = json.substr(20, length);
        const uint64_t bin = 20 + ((uint64_t(length) + 3) & ~uint64_t(3));
        binaryChunk = 0;
        if (le32(bytes, 4) == 2 && bin + 8 <= bytes.size() && bytes.compare(bin + 4, 4, std::string("BIN\0", 4)) == 0)
            binaryChunk = std::min<uint64_t>(le32(bytes, bin), bytes.size() - bin - 8);
        else if (le32(bytes, 4) != 2)
            binaryChunk = UINT64_MAX;  // glTF 1's binary body: Assimp's own checks
    }
    json = json.substr(0, json.find('\0'));
    if (auto problem = stringProblem(json)) return problem;

    // Assimp 5.2.5 bounds an accessor by its buffer view's length but not by
    // its own byteOffset, and reads past the buffer (an ASan heap-buffer-overflow
    // from a .gltf whose accessor starts 20 bytes later). So every accessor must
    // lie inside its buffer view, and every view inside its buffer.
    const Json doc = Json::parse(json.begin(), json.end(), nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return std::string("the JSON is not valid (glTF is UTF-8 JSON)");
    try {
        checkAccessors(doc, binaryChunk);
    } catch (const Invalid& e) {
        return e.why;
    }
    return std::nullopt;
}

}  // namespace penumbra
