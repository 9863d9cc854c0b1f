// The penumbra command line (shared by penumbra-mpi): what it says, bound by
// CLI11 straight into typed fields, and how a bad value is reported.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

#include <penumbra/penumbra.hpp>

namespace penumbra::cli {

/// Everything the command line says. Optional fields override the scene file.
/// Values that only make sense with the scene's or the library's limits
/// (sizes, counts, the camera, light radiance) are checked by the library
/// (pnb::validate, pnb::Scene) before any work: option_checks.h.
struct Options {
    std::filesystem::path scene;
    std::filesystem::path output;
    std::optional<int> width, height, spp, lightSamples, maxDepth, threads, tileSize;
    std::optional<uint64_t> seed;
    pnb::AcceleratorKind accel = pnb::AcceleratorKind::Embree;
    pnb::BuildQuality buildQuality = pnb::BuildQuality::High;
    std::optional<pnb::Vec3> eye, lookAt, up;
    std::optional<float> fov, aperture, focusDistance;
    std::optional<pnb::Color> ambient, background;
    std::optional<pnb::CropWindow> crop;
    std::optional<pnb::LightSelection> lightSelection;
    float exposure = 0.f;
    bool aovs = false;
    bool quiet = false;
    bool strict = false;
    std::filesystem::path statsJson;
    // --env r,g,b (envColor) or --env FILE (envImage), --env-rotate DEG.
    std::optional<pnb::Color> envColor;
    std::optional<std::filesystem::path> envImage;
    std::optional<float> envRotate;
    std::optional<pnb::IntegratorKind> integrator;
    std::optional<pnb::PhongModel> model;                   // --model: materials of mesh and model files
    std::optional<float> smoothAngle;                       // --smooth-angle: degrees, [0, 180]
    std::optional<pnb::DirectLightSampling> directLight;
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

}  // namespace penumbra::cli
