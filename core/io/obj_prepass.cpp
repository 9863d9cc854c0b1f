#include "core/io/obj_prepass.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <climits>
#include <optional>

#include "core/io/obj_text.h"

namespace penumbra {
namespace {

using namespace obj_text;

// Written in place of an index that tinyobjloader would reject or resolve to
// a negative number; it is out of range for any real file, so the validation
// treats it like any other bad index.
constexpr const char* kBadIndex = "2147483647";

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

}  // namespace

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
                    if (hasVt) {
                        f += '/';
                        f += fixComponent(comp[1], nvt);
                    }
                    if (hasVn) {
                        f += hasVt ? "/" : "//";
                        f += fixComponent(comp[2], nvn);
                    }
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

}  // namespace penumbra
