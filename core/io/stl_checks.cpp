#include "core/io/stl_checks.h"

#include <algorithm>
#include <cstdint>
#include <string_view>
#include <vector>

namespace penumbra {
namespace {

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

}  // namespace

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

}  // namespace penumbra
