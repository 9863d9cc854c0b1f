// Parsing and checking of the penumbra command line (CLI11).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <cstdint>
#include <penumbra/penumbra.hpp>

namespace penumbra::cli {

/// Everything the command line says. Optional fields override the scene file.
struct Options {
    std::filesystem::path scene;
    std::filesystem::path output;
    std::optional<int> width, height, spp, lightSamples, maxDepth, threads, tileSize;
    std::optional<uint64_t> seed;
    std::string accel = "embree";
    std::string buildQuality = "high";
    std::optional<pnb::Vec3> eye, lookAt, up;
    std::optional<float> fov, aperture, focusDistance;
    std::optional<pnb::Color> ambient, background;  // checked by pnb::Scene when applied
    std::optional<pnb::CropWindow> crop;
    std::optional<std::string> lightSelection;
    float exposure = 0.f;
    bool aovs = false;
    bool quiet = false;
    bool strict = false;
    std::filesystem::path statsJson;
    std::optional<std::string> directLight;  // mis, light or area
};

/// Parses argv. Returns the options, or an exit code when parsing ended the
/// program (help printed: 0; usage error printed: 2).
struct ParseResult {
    std::optional<Options> options;
    int exitCode = 0;
};
ParseResult parseCommandLine(int argc, char** argv);

/// "x,y,z" -> Vec3; throws pnb::Error(InvalidArgument) naming the option.
pnb::Vec3 parseVec3(const std::string& text, const std::string& option);
/// "x0,y0,x1,y1" -> CropWindow.
pnb::CropWindow parseCrop(const std::string& text);

}  // namespace penumbra::cli
