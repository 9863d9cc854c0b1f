#include "core/io/mtl_files.h"

#include <algorithm>
#include <iterator>
#include <system_error>
#include <vector>

#include "core/io/input_file.h"
#include "core/io/obj_text.h"
#include "core/io/path_policy.h"

namespace penumbra {
namespace fs = std::filesystem;
using namespace obj_text;

namespace {

std::string name(const fs::path& p) { return p.string(); }

/// Whether anything (a file, folder, FIFO, even a dangling or looping symlink) has this name.
bool anythingAt(const fs::path& p) {
    std::error_code ec;
    return fs::symlink_status(p, ec).type() != fs::file_type::not_found && !ec;
}

/// tinyobjloader reads a malformed number in an MTL statement as 0 without
/// a word; one warning per file names the first (line and token) and counts them.
void checkNumbers(std::string_view text, const fs::path& file, std::string* warn) {
    static constexpr std::string_view kNumeric[] = {"Ka", "Kd", "Ks", "Ke", "Kt", "Tf", "Ns", "Ni", "d", "Tr", "illum"};
    size_t bad = 0;
    std::string first;
    uint32_t lineNo = 0;
    for (std::string_view line : splitLines(text)) {
        ++lineNo;
        auto tok = splitBlank(trim(line));
        if (tok.empty() || std::find(std::begin(kNumeric), std::end(kNumeric), tok[0]) == std::end(kNumeric)) continue;
        for (size_t i = 1; i < tok.size() && i <= 3; ++i) {
            if (tok[i][0] == '#') break;
            if (finiteNumber(tok[i])) continue;
            if (bad++ == 0)
                first = "line " + std::to_string(lineNo) + ": '" + printable(tok[i]) + "' in " + std::string(tok[0]);
            break;
        }
    }
    if (bad > 0 && warn)
        *warn += name(file) + ": " + std::to_string(bad) +
                 " statement(s) with a malformed or non-finite number, read as 0 (first at " + first + ")\n";
}

}  // namespace

std::optional<fs::path> resolveCaseInsensitive(const fs::path& base, const fs::path& rel) {
    std::error_code ec;
    fs::path exact = rel.is_absolute() ? rel : base / rel;
    if (anythingAt(exact)) return exact.lexically_normal();
    fs::path cur = rel.is_absolute() ? rel.root_path() : base;
    fs::path parts = rel.is_absolute() ? rel.relative_path() : rel;
    for (const fs::path& part : parts) {
        if (part.empty() || part == "." || part == ".." || anythingAt(cur / part)) {
            cur /= part;
            continue;
        }
        std::optional<fs::path> match;
        for (fs::directory_iterator it(cur.empty() ? fs::path(".") : cur, ec), end; !ec && it != end;
             it.increment(ec))
            if (iequals(it->path().filename().string(), part.string())) {
                match = it->path();
                break;
            }
        if (!match) return std::nullopt;
        cur = *match;
    }
    if (!anythingAt(cur)) return std::nullopt;
    return cur.lexically_normal();
}

std::optional<MtlText> MtlLibraries::read(const std::string& matId, std::string* warn) {
    fs::path rel(std::string(trim(matId)));
    fs::path candidate = rel.is_absolute() ? rel : dir_ / rel;
    try {
        // Before probing the file system for other capitalisations.
        checkPathAllowed(candidate, options_, /*willRead=*/false);
    } catch (const Error& e) {
        if (!error) error = e;
        return std::nullopt;
    }
    std::optional<fs::path> file = resolveCaseInsensitive(dir_, rel);
    MtlText out;
    try {
        if (!file) throw Error(ErrorCode::FileNotFound, name(candidate) + ": file not found");
        out.file = *file;
        out.text = openInputFile(*file, options_)->readAll();
    } catch (const Error& e) {
        if (e.code() == ErrorCode::InvalidArgument) {
            if (!error) error = e;
        } else if (warn) {
            *warn += std::string("material library ") + e.what() + "\n";
        }
        return std::nullopt;
    }
    stripBom(out.text);
    if (auto bad = binaryDataProblem(out.text)) {
        if (warn) *warn += "material library " + name(out.file) + ":" + *bad + "; ignored\n";
        return std::nullopt;
    }
    checkNumbers(out.text, out.file, warn);
    return out;
}

}  // namespace penumbra
