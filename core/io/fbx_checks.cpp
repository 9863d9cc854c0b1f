#include "core/io/fbx_checks.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/io/nesting_checks.h"

namespace penumbra {
namespace {

struct Invalid {
    std::string why;
};

/// An element as Assimp's parser sees it: its key, the scope it is in, and
/// its first values (as written: ids are numbers in FBX 7, names in FBX 6).
struct Element {
    std::string key, scope;
    std::vector<std::string> values;
};

/// The Model objects and the connections (parent, child) among everything.
struct Hierarchy {
    std::unordered_set<std::string> models;
    std::vector<std::pair<std::string, std::string>> links;

    void add(const Element& e) {
        if (e.key == "Model" && e.scope == "Objects" && !e.values.empty()) models.insert(e.values[0]);
        if ((e.key == "C" || e.key == "Connect") && e.scope == "Connections" && e.values.size() >= 3)
            links.emplace_back(e.values[2], e.values[1]);
    }
};

uint64_t littleEndian(std::string_view b, size_t at, size_t bytes) {
    uint64_t v = 0;
    for (size_t i = bytes; i-- > 0;) v = (v << 8) | static_cast<unsigned char>(b[at + i]);
    return v;
}

std::string lineOf(std::string_view b, size_t at) {
    return "line " + std::to_string(1 + std::count(b.begin(), b.begin() + std::ptrdiff_t(at), '\n'));
}

bool space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

/// Assimp's ASCII tokenizer and parser: text up to the first NUL, ';'
/// comments to the end of the line, double-quoted strings, a token followed
/// by ':' is a key that starts an element, '{' '}' open and close its scope,
/// and a '}' at the top level ends the file. Where Assimp's parser would
/// throw, the file is refused: the parser leaks every scope it has built,
/// and fuzzing cannot tell that leak from one of Penumbra's.
void scanText(std::string_view b, Hierarchy& h) {
    b = b.substr(0, b.find('\0'));
    std::vector<std::string> scopes;
    Element e;
    enum class Last { None, Key, Data, Comma } last = Last::None;  // in the element being read; None: between elements
    const auto malformed = [&](size_t at, const std::string& what) {
        throw Invalid{lineOf(b, at) + ": " + what + " (not an FBX scope, element or value)"};
    };
    const auto finish = [&] {
        if (last != Last::None) h.add(e);
        last = Last::None;
    };
    for (size_t i = 0; i < b.size();) {
        const char c = b[i];
        if (space(c)) {
            ++i;
        } else if (c == ';') {
            while (i < b.size() && b[i] != '\n' && b[i] != '\r') ++i;
        } else if (c == ',' || c == '{') {
            if (last == Last::None) malformed(i, std::string("'") + c + "' where a key was expected");
            if (c == ',') last = Last::Comma;
            if (c == '{') {
                finish();
                scopes.push_back(e.key);
                if (scopes.size() > kMaxModelNesting) throw Invalid{nestingProblem("FBX scopes", lineOf(b, i))};
            }
            ++i;
        } else if (c == '}') {
            finish();
            if (scopes.empty()) return;  // Assimp's parser stops here
            scopes.pop_back();
            ++i;
        } else {
            const size_t from = i;
            if (c == '"') {
                i = b.find('"', i + 1);
                i = i == std::string_view::npos ? b.size() : i + 1;
            }
            while (i < b.size() && !space(b[i]) && !std::strchr(",:;{}\"", b[i])) ++i;
            const std::string token(b.substr(from, i - from));
            size_t next = i;
            while (next < b.size() && space(b[next])) ++next;
            if (next < b.size() && b[next] == ':') {
                if (token.empty()) malformed(next, "a ':' without a key");
                finish();
                e = Element{token, scopes.empty() ? std::string() : scopes.back(), {}};
                last = Last::Key;
                i = next + 1;
            } else {
                if (last == Last::None) malformed(from, "a value where a key was expected");
                if (last == Last::Data) malformed(from, "two values without a comma between them");
                if (e.values.size() < 3) e.values.push_back(token);
                last = Last::Data;
            }
        }
    }
    if (last == Last::Key || last == Last::Comma) malformed(b.size(), "the file ends inside an element");
    if (!scopes.empty()) malformed(b.size(), "the file ends inside " + std::to_string(scopes.size()) + " scope(s)");
    finish();
}

/// One property of a binary record at `at` (advanced past it): integers and
/// strings as text, other types skipped; nullopt past `limit`.
std::optional<std::string> binaryProperty(std::string_view b, uint64_t& at, uint64_t limit) {
    if (at >= limit) return std::nullopt;
    const char type = b[at++];
    const auto need = [&](uint64_t n) { return at + n <= limit; };
    uint64_t size = 0;
    std::string text;
    switch (type) {
        case 'C': size = 1; break;
        case 'Y': size = 2; break;
        case 'F': size = 4; break;
        case 'D': size = 8; break;
        case 'I':
            if (!need(4)) return std::nullopt;
            text = std::to_string(int32_t(littleEndian(b, at, 4)));
            size = 4;
            break;
        case 'L':
            if (!need(8)) return std::nullopt;
            text = std::to_string(int64_t(littleEndian(b, at, 8)));
            size = 8;
            break;
        case 'S':
        case 'R':
            if (!need(4)) return std::nullopt;
            size = 4 + littleEndian(b, at, 4);
            if (need(size)) text = std::string(b.substr(at + 4, size - 4));
            break;
        case 'f': case 'd': case 'l': case 'i': case 'b':
            if (!need(12)) return std::nullopt;
            size = 12 + littleEndian(b, at + 8, 4);
            break;
        default: return std::nullopt;
    }
    if (!need(size)) return std::nullopt;
    at += size;
    return text;
}

/// Assimp's binary tokenizer (ReadScope) as a loop: each record holds its end
/// offset, property count and length and a name; a record that ends after its
/// properties holds nested records and a zero sentinel block. Where the
/// tokenizer would fail, it stops before recursing, and so does the scan.
void scanBinary(std::string_view b, Hierarchy& h) {
    constexpr size_t kHeader = 27;  // magic, 5 bytes, the version at byte 23
    if (b.size() < kHeader) return;
    const bool wide = littleEndian(b, 23, 4) >= 7500;
    const size_t word = wide ? 8 : 4, sentinel = wide ? 25 : 13;
    std::vector<std::pair<uint64_t, std::string>> open;  // records whose nested records are read: end, name
    for (uint64_t at = kHeader;;) {
        const uint64_t limit = open.empty() ? b.size() : open.back().first - sentinel;
        if (!open.empty() && at >= limit) {
            at = open.back().first;
            open.pop_back();
            continue;
        }
        if (at + word > limit) return;
        const uint64_t end = littleEndian(b, at, word);
        at += word;
        if (end == 0) {
            if (open.empty()) return;  // the footer
            continue;
        }
        if (end > limit || end < at || at + 2 * word + 1 > limit) return;
        const uint64_t count = littleEndian(b, at, word), length = littleEndian(b, at + word, word);
        at += 2 * word;
        const size_t nameLength = static_cast<unsigned char>(b[at]);
        if (at + 1 + nameLength + length > limit) return;
        Element e{std::string(b.substr(at + 1, nameLength)), open.empty() ? std::string() : open.back().second, {}};
        at += 1 + nameLength;
        uint64_t p = at;
        for (uint64_t k = 0; k < std::min<uint64_t>(count, 3); ++k)
            if (auto v = binaryProperty(b, p, at + length)) e.values.push_back(*v);
        h.add(e);
        at += length;
        if (at > end) return;
        if (at < end) {
            if (end - at < sentinel) return;
            open.emplace_back(end, e.key);
            if (open.size() > kMaxModelNesting) throw Invalid{nestingProblem("FBX records", "byte " + std::to_string(at))};
        }
    }
}

/// Assimp converts the models from the root down, following connections from
/// parent to child Model, with no memory of where it has been.
void checkHierarchy(const Hierarchy& h) {
    std::unordered_map<std::string, std::vector<std::string>> children;
    for (const auto& [parent, child] : h.links)
        if (h.models.count(child)) children[parent].push_back(child);
    enum class Mark { Open, Done };
    std::unordered_map<std::string, Mark> marks;
    std::unordered_map<std::string, size_t> depth;  // models below, counting itself
    for (const auto& entry : children) {
        const std::string& root = entry.first;
        if (marks.count(root)) continue;
        std::vector<std::pair<std::string, size_t>> stack{{root, 0}};
        marks[root] = Mark::Open;
        while (!stack.empty()) {
            const std::string node = stack.back().first;
            const auto it = children.find(node);
            const size_t next = stack.back().second++;
            if (it != children.end() && next < it->second.size()) {
                const std::string& c = it->second[next];
                const auto m = marks.find(c);
                if (m != marks.end() && m->second == Mark::Open)
                    throw Invalid{"FBX model " + c.substr(0, 40) + " is connected below itself"};
                if (m == marks.end()) {
                    marks[c] = Mark::Open;
                    stack.emplace_back(c, 0);
                }
                continue;
            }
            size_t d = 0;
            if (it != children.end())
                for (const std::string& c : it->second) d = std::max(d, depth[c]);
            depth[node] = d + h.models.count(node);
            if (depth[node] > kMaxModelNesting)
                throw Invalid{nestingProblem("FBX models (through their Connections)", "model " + node.substr(0, 40))};
            marks[node] = Mark::Done;
            stack.pop_back();
        }
    }
}

}  // namespace

std::optional<std::string> fbxProblem(std::string_view bytes) {
    Hierarchy h;
    try {
        if (bytes.substr(0, 18) == "Kaydara FBX Binary")
            scanBinary(bytes, h);
        else
            scanText(bytes, h);
        checkHierarchy(h);
    } catch (const Invalid& e) {
        return e.why;
    }
    return std::nullopt;
}

}  // namespace penumbra
