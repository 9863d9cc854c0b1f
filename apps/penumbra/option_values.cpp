#include "option_values.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void refuse(const std::string& message) { throw std::invalid_argument(message); }

std::vector<std::string> splitCommas(const std::string& s) {
    std::vector<std::string> parts;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) parts.push_back(item);
    if (!s.empty() && s.back() == ',') parts.push_back("");
    return parts;
}

double parseNumber(const std::string& text) {
    size_t used = 0;
    double v = 0.0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size() || !std::isfinite(v)) refuse("'" + text + "' is not a finite number");
    return v;
}

bool hasImageExtension(const fs::path& p) {
    std::string ext = p.extension().string();
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    static const char* const kImages[] = {".exr", ".hdr", ".pfm", ".png", ".jpg", ".jpeg", ".tif", ".tiff"};
    return std::find(std::begin(kImages), std::end(kImages), ext) != std::end(kImages);
}

}  // namespace

pnb::Vec3 parseVec3(const std::string& text) {
    const std::vector<std::string> parts = splitCommas(text);
    if (parts.size() != 3) refuse("expected x,y,z, got '" + text + "'");
    return {float(parseNumber(parts[0])), float(parseNumber(parts[1])), float(parseNumber(parts[2]))};
}

pnb::Color parseColor(const std::string& text) {
    const pnb::Vec3 v = parseVec3(text);
    return {v.x, v.y, v.z};
}

pnb::CropWindow parseCrop(const std::string& text) {
    const std::vector<std::string> parts = splitCommas(text);
    if (parts.size() != 4) refuse("expected x0,y0,x1,y1, got '" + text + "'");
    int v[4];
    for (int i = 0; i < 4; ++i) {
        const double d = parseNumber(parts[i]);
        if (d != std::floor(d) || d < 0 || d > 1e9) refuse("'" + parts[i] + "' is not a pixel coordinate");
        v[i] = int(d);
    }
    return {v[0], v[1], v[2], v[3]};
}

std::variant<pnb::Color, fs::path> parseEnvironment(const std::string& text) {
    std::error_code ec;
    const bool exists = !text.empty() && fs::symlink_status(text, ec).type() != fs::file_type::not_found && !ec;
    if (exists || text.find('/') != std::string::npos) return fs::path(text);
    if (text.find(',') != std::string::npos) {
        pnb::Vec3 c;
        try {
            c = parseVec3(text);
        } catch (const std::invalid_argument&) {
            refuse("expected r,g,b (three finite numbers) or an image file, got '" + text + "' (no such file)");
        }
        if (!(c.x >= 0.f && c.y >= 0.f && c.z >= 0.f) || !std::isfinite(c.x + c.y + c.z))
            refuse("radiance must be finite and >= 0, got '" + text + "'");
        return pnb::Color{c.x, c.y, c.z};
    }
    if (!hasImageExtension(text))
        refuse("expected r,g,b or an image file (.exr .hdr .pfm .png .jpg .tif), got '" + text + "'");
    return fs::path(text);
}

std::string seedProblem(const std::string& v) {
    if (!v.empty() && v[0] == '-') return "must be >= 0";
    if (v.empty() || v.find_first_not_of("0123456789") != std::string::npos) return "'" + v + "' is not an integer";
    errno = 0;
    (void)std::strtoull(v.c_str(), nullptr, 10);
    if (errno == ERANGE) return "'" + v + "' is above the largest seed, 18446744073709551615";
    return {};
}

}  // namespace penumbra::cli
