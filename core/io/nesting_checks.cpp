#include "core/io/nesting_checks.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace penumbra {
namespace {

std::string lineOf(std::string_view b, size_t at) {
    return "line " + std::to_string(1 + std::count(b.begin(), b.begin() + std::ptrdiff_t(at), '\n'));
}

/// Text .x files: Assimp's parser recurses once per Frame, and every frame
/// opens a brace. Every '{' counts; a '}' closes a level only where it is
/// surely a token to Assimp: not after '#' or "//" on its line (a comment) and
/// not between a '"' and a later '"' followed by ';' (a string, which Assimp
/// reads raw in texture file names).
std::optional<std::string> xTextNesting(std::string_view b) {
    size_t depth = 0, nextQuote = b.find('"');  // the first '"' at or after i
    bool quoteBefore = false, commentOnLine = false;
    for (size_t i = 0; i < b.size(); ++i) {
        const char c = b[i];
        if (nextQuote != std::string_view::npos && nextQuote < i) {
            quoteBefore = true;
            nextQuote = b.find('"', i);
        }
        if (c == '\n' || c == '\r') commentOnLine = false;
        if (c == '#' || (c == '/' && i + 1 < b.size() && b[i + 1] == '/')) commentOnLine = true;
        if (c == '{' && ++depth > kMaxModelNesting) return nestingProblem("DirectX .x braces", lineOf(b, i));
        if (c != '}' || depth == 0 || commentOnLine) continue;
        const bool inString =
            quoteBefore && nextQuote != std::string_view::npos && nextQuote + 1 < b.size() && b[nextQuote + 1] == ';';
        if (!inString) --depth;
    }
    return std::nullopt;
}

/// Assimp's AC3D reader (LoadObjectSection) as a cursor over its lines:
/// GetNextLine skips line ends and the next line's leading blanks and fails
/// at a blank line or the end; tokens match at the cursor.
class Ac3dCursor {
public:
    explicit Ac3dCursor(std::string_view b) : b_(b) {
        for (size_t i = 0; i < b.size(); ++i)
            if (b[i] == '\n') newlines_.push_back(i);
    }
    char at(size_t i) const { return i < b_.size() ? b_[i] : '\0'; }
    static bool lineEnd(char c) { return c == '\r' || c == '\n' || c == '\0' || c == '\f'; }
    bool nextLine() {
        while (!(at(p_) == '\r' || at(p_) == '\n' || at(p_) == '\0')) ++p_;
        while (at(p_) == '\r' || at(p_) == '\n') ++p_;
        while (at(p_) == ' ' || at(p_) == '\t') ++p_;
        return !lineEnd(at(p_));
    }
    /// The line is processed again (Assimp steps back one byte, onto the line end before it).
    void again() { p_ = p_ > 0 ? p_ - 1 : 0; }
    bool token(std::string_view t) {
        if (b_.substr(std::min(p_, b_.size()), t.size()) != t) return false;
        const char after = at(p_ + t.size());
        if (!(after == ' ' || after == '\t' || lineEnd(after))) return false;
        p_ += t.size() + 1;
        return true;
    }
    uint64_t number() {
        while (at(p_) == ' ' || at(p_) == '\t') ++p_;
        uint64_t v = 0;
        for (; at(p_) >= '0' && at(p_) <= '9'; ++p_) v = std::min<uint64_t>(v * 10 + uint64_t(at(p_) - '0'), UINT32_MAX);
        return v;
    }
    bool numeric() const { return (at(p_) >= '0' && at(p_) <= '9') || at(p_) == '-' || at(p_) == '+'; }
    /// Lines after the cursor's: no count in a well-formed file claims more.
    uint64_t linesLeft() const {
        return uint64_t(newlines_.end() - std::upper_bound(newlines_.begin(), newlines_.end(), p_)) + 1;
    }
    std::string where() const { return lineOf(b_, std::min(p_, b_.size())); }
    size_t position() const { return p_; }
    void seek(size_t p) { p_ = p; }

private:
    std::string_view b_;
    size_t p_ = 0;
    std::vector<size_t> newlines_;
};

struct Ac3dStop {
    std::optional<std::string> problem;  // empty: Assimp would stop there with an error of its own
};

void checkCount(Ac3dCursor& c, uint64_t n, const char* what) {
    if (n > c.linesLeft())
        throw Ac3dStop{c.where() + ": '" + what + " " + std::to_string(n) + "' claims more lines than the " +
                       std::to_string(c.linesLeft()) + " the file has left"};
}

/// One surface's mat and refs lines (refs consume the lines they count).
void surface(Ac3dCursor& c, bool q3d) {
    for (bool refs = false;;) {
        if (!c.nextLine()) throw Ac3dStop{};
        if (c.token("mat")) continue;
        const size_t start = c.position();
        if (!c.token("refs") || (q3d && refs)) {
            c.seek(start);
            c.again();
            return;
        }
        const uint64_t m = c.number();
        checkCount(c, m, "refs");
        for (uint64_t k = 0; k < m && c.nextLine(); ++k) refs = true;
    }
}

/// The lines of an object header that Assimp consumes itself: vertices and surfaces.
void skipHeaderData(Ac3dCursor& c) {
    if (c.token("numvert")) {
        const uint64_t n = c.number();
        checkCount(c, n, "numvert");
        for (uint64_t i = 0; i < n; ++i) {
            if (!c.nextLine()) break;
            if (!c.numeric()) {
                c.again();
                break;
            }
        }
    } else if (c.token("numsurf")) {
        const uint64_t n = c.number();
        checkCount(c, n, "numsurf");
        bool q3d = false;  // Assimp's workaround for surfaces without a SURF line, once on for the object
        for (uint64_t i = 0; i < n; ++i) {
            const size_t start = c.position();
            c.nextLine();
            if (!c.token("SURF")) {
                q3d = true;
                c.again();
            }
            surface(c, q3d);
            if (c.position() == start)  // Assimp would add the same empty surface n times
                throw Ac3dStop{c.where() + ": 'numsurf " + std::to_string(n) + "' is followed by fewer surfaces"};
        }
    }
}

/// One object's header up to its kids line; the kids count, or nullopt where
/// the file ends first.
std::optional<uint64_t> objectHeader(Ac3dCursor& c) {
    while (c.nextLine()) {
        if (c.token("kids")) {
            const uint64_t n = c.number();
            checkCount(c, n, "kids");
            c.nextLine();
            return n;
        }
        skipHeaderData(c);
    }
    return std::nullopt;
}

/// One top-level object and its descendants, with the stack of the objects
/// whose kids are being read (their counts left).
void ac3dObject(Ac3dCursor& c) {
    if (!c.token("OBJECT")) return;
    std::vector<uint64_t> kidsLeft;
    for (std::optional<uint64_t> kids = objectHeader(c);;) {
        if (!kids) {
            if (!kidsLeft.empty()) kidsLeft.pop_back();  // the parent stops reading kids
        } else if (*kids > 0) {
            kidsLeft.push_back(*kids);
            if (kidsLeft.size() >= kMaxModelNesting)
                throw Ac3dStop{nestingProblem("AC3D objects", c.where())};
        }
        while (!kidsLeft.empty() && kidsLeft.back() == 0) kidsLeft.pop_back();
        if (kidsLeft.empty()) return;
        --kidsLeft.back();
        if (!c.token("OBJECT")) {
            kidsLeft.pop_back();
            kids = 0;
            continue;
        }
        kids = objectHeader(c);
    }
}

}  // namespace

std::string nestingProblem(const std::string& what, const std::string& where) {
    return what + " nest deeper than " + std::to_string(kMaxModelNesting) + " levels (" + where +
           "); Assimp's reader recurses once per level, so deeper files are refused";
}

std::optional<std::string> xFileNestingProblem(std::string_view bytes) {
    if (bytes.size() < 16 || bytes.substr(0, 4) != "xof ") return std::nullopt;  // Assimp refuses it itself
    const std::string_view format = bytes.substr(8, 4);
    if (format == "bin " || format == "tzip" || format == "bzip")
        return "binary and compressed DirectX .x files are not supported (their frame nesting cannot be checked "
               "before Assimp reads them); save it as text .x";
    return xTextNesting(bytes);
}

std::optional<std::string> ac3dNestingProblem(std::string_view bytes) {
    Ac3dCursor c(bytes);
    try {
        while (c.nextLine()) ac3dObject(c);
    } catch (const Ac3dStop& stop) {
        return stop.problem;
    }
    return std::nullopt;
}

}  // namespace penumbra
