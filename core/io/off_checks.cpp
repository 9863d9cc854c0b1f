#include "core/io/off_checks.h"

#include <algorithm>
#include <cstdint>

namespace penumbra {
namespace {

// Assimp's token skipping: spaces, tabs and line ends, and whole lines that start with #.
size_t nextToken(const std::string& b, size_t at) {
    for (;;) {
        while (at < b.size() && (b[at] == ' ' || b[at] == '\t' || b[at] == '\r' || b[at] == '\n')) ++at;
        if (at >= b.size() || b[at] != '#') return at;
        while (at < b.size() && b[at] != '\n' && b[at] != '\r') ++at;
    }
}

// The run of decimal digits at `at` (Assimp's strtoul10 reads exactly that), its value
// without wrapping (saturated above 2^32), and where it ends.
uint64_t digitsAt(const std::string& b, size_t& at) {
    uint64_t v = 0;
    for (; at < b.size() && b[at] >= '0' && b[at] <= '9'; ++at)
        v = std::min<uint64_t>(v * 10 + uint64_t(b[at] - '0'), 1ULL << 33);
    return v;
}

bool startsWith(const std::string& b, size_t at, const char* s) {
    return b.compare(at, std::char_traits<char>::length(s), s) == 0;
}

}  // namespace

std::optional<std::string> offHeaderProblem(const std::string& bytes) {
    size_t at = nextToken(bytes, 0);
    if (startsWith(bytes, at, "ST")) at += 2;
    for (const char* prefix : {"C", "N", "4"})
        if (startsWith(bytes, at, prefix)) ++at;
    const bool dimension = startsWith(bytes, at, "n");
    if (dimension) ++at;
    if (startsWith(bytes, at, "OFF")) at += 3;
    at = nextToken(bytes, at);
    if (dimension) {
        digitsAt(bytes, at);
        at = nextToken(bytes, at);
    }
    const uint64_t vertices = digitsAt(bytes, at);
    at = nextToken(bytes, at);
    const uint64_t faces = digitsAt(bytes, at);
    constexpr uint64_t kMaxCount = 0xffffffffULL;
    if (vertices > kMaxCount || faces > kMaxCount)
        return std::string("the header's vertex or face count does not fit in 32 bits");
    // Every vertex and face is a line of its own: a bound the file must meet.
    const auto lineEnd = [](char c) { return c == '\n' || c == '\r'; };
    const uint64_t lines = 1 + uint64_t(std::count_if(bytes.begin(), bytes.end(), lineEnd));
    if (vertices + faces > lines)
        return "the header declares " + std::to_string(vertices) + " vertices and " + std::to_string(faces) +
               " faces, more than the file's " + std::to_string(lines) + " lines can hold";
    return std::nullopt;
}

}  // namespace penumbra
