#include "core/io/obj_text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace penumbra::obj_text {

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

void stripBom(std::string& s) {
    if (s.size() >= 3 && s.compare(0, 3, "\xEF\xBB\xBF") == 0) s.erase(0, 3);
}

std::optional<std::string> binaryDataProblem(std::string_view text) {
    size_t z = text.find('\0');
    if (z == std::string_view::npos) return std::nullopt;
    size_t line = 1 + static_cast<size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(z), '\n'));
    return std::to_string(line) + ": binary data (a NUL byte), not a text file";
}

std::string printable(std::string_view tok) {
    std::string out;
    for (char ch : tok.substr(0, 40)) out += (ch >= 0x20 && ch < 0x7f) ? ch : '?';
    if (tok.size() > 40) out += "...";
    return out;
}

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

bool finiteNumber(std::string_view tok) {
    std::string s(tok);
    char* end = nullptr;
    double d = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0') return false;
    return std::isfinite(d) && std::fabs(d) <= static_cast<double>(std::numeric_limits<float>::max());
}

}  // namespace penumbra::obj_text
