#include "core/io/ply_checks.h"

#include <cstdint>
#include <sstream>
#include <vector>

namespace penumbra {
namespace {

/// Bytes of a PLY scalar type; 0 for an unknown name.
size_t plyTypeSize(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

}  // namespace

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

}  // namespace penumbra
