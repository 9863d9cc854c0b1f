// Parsing and checking of the penumbra command line (CLI11).
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
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
    // --env r,g,b (envColor) or --env FILE (envImage), --env-rotate DEG.
    std::optional<pnb::Color> envColor;
    std::optional<std::filesystem::path> envImage;
    std::optional<float> envRotate;
    std::optional<std::string> integrator;  // "whitted" or "path"
    std::optional<pnb::PhongModel> model;  // --model: materials of mesh and model files
    std::optional<float> smoothAngle;      // --smooth-angle: degrees, [0, 180]
    std::optional<std::string> directLight;  // mis or light
};

/// A bad command-line value found after parsing (checked against the
/// defaults or the scene): reported like CLI11's usage errors, exit code 2.
class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Prints "PROGRAM: error: MESSAGE (see --help)" on one line; returns 2.
int reportUsageError(const std::string& message, const char* program = "penumbra");

/// Parses argv; a repeated option takes its last value. Returns the options,
/// or an exit code when parsing ended the program (help printed: 0; usage
/// error or bad option value printed, as `program`: 2).
struct ParseResult {
    std::optional<Options> options;
    int exitCode = 0;
};
ParseResult parseCommandLine(int argc, char** argv, const char* program = "penumbra");

/// "x,y,z" -> Vec3; throws pnb::Error(InvalidArgument) naming the option.
pnb::Vec3 parseVec3(const std::string& text, const std::string& option);
/// --env's value: "r,g,b" (three finite numbers >= 0) sets o.envColor, an
/// image file name (.exr .hdr .pfm .png .jpg .jpeg .tif .tiff) o.envImage.
/// Throws pnb::Error(InvalidArgument) naming --env for anything else.
void parseEnvironment(const std::string& text, Options& o);

/// "x0,y0,x1,y1" -> CropWindow.
pnb::CropWindow parseCrop(const std::string& text);

}  // namespace penumbra::cli
