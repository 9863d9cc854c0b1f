#include "core/io/json_text.h"

#include <algorithm>

namespace penumbra::json_text {

std::string pointerToken(std::string_view key) {
    std::string out;
    const bool cut = key.size() > kMaxQuoted;
    key = key.substr(0, kMaxQuoted);
    out.reserve(key.size() + 3);
    for (char c : key) {
        if (c == '~')
            out += "~0";
        else if (c == '/')
            out += "~1";
        else
            out += c;
    }
    if (cut) out += "...";
    return out;
}

std::string shortPointer(const std::string& ptr) {
    if (ptr.size() <= kMaxPointer) return ptr;
    // Cut at token boundaries so the head and tail stay valid pointer pieces.
    const size_t headEnd = ptr.rfind('/', kMaxPointer / 3);
    const size_t tailBegin = ptr.find('/', ptr.size() - 2 * kMaxPointer / 3);
    if (headEnd == std::string::npos || headEnd == 0 || tailBegin == std::string::npos || tailBegin <= headEnd)
        return ptr.substr(0, kMaxPointer) + "...";
    const auto levels = [&](size_t b, size_t e) {
        return static_cast<size_t>(std::count(ptr.begin() + static_cast<std::ptrdiff_t>(b),
                                               ptr.begin() + static_cast<std::ptrdiff_t>(e), '/'));
    };
    return ptr.substr(0, headEnd) + "/...(" + std::to_string(levels(headEnd, tailBegin)) + " levels)..." +
           ptr.substr(tailBegin);
}

std::string quotedValue(std::string_view s) {
    std::string out = "\"";
    out.append(s.substr(0, kMaxQuoted));
    out += s.size() > kMaxQuoted ? "...\"" : "\"";
    return out;
}

std::string oneLine(std::string s) {
    for (char& c : s)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
    return s;
}

}  // namespace penumbra::json_text
