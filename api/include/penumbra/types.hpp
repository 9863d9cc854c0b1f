// The value types that cross Penumbra's API, defined once: hosts use them
// through <penumbra/penumbra.hpp>, the library uses the same types inside
// (core/render_settings.h, core/error.h, ... name them with using-declarations),
// and the C API's structs are checked against them at compile time
// (api/c_api_types.cpp). Standard types only; usable from C++17 and later.
//
// Adding a render setting: a field in RenderSettings below, its check in
// core/render_settings.cpp, its C field in penumbra.h (+ api/c_api_types.cpp's
// copy and static_assert), and wherever it takes effect.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#ifndef PENUMBRA_API
#if defined(__GNUC__) || defined(__clang__)
#define PENUMBRA_API __attribute__((visibility("default")))
#else
#define PENUMBRA_API
#endif
#endif

namespace pnb {

// ---------------------------------------------------------------- errors

/// What went wrong; the values equal the C API's pnb_status codes.
enum class ErrorCode {
    InvalidArgument = 1,  ///< bad argument, setting or handle
    FileNotFound = 2,
    ParseError = 3,       ///< malformed OBJ/MTL/JSON content
    InvalidScene = 4,     ///< scene content that cannot be rendered
    IoError = 5,          ///< reading or writing failed
    OutOfMemory = 6,
    Cancelled = 7,        ///< the host cancelled the render
    Embree = 8,           ///< the ray-tracing kernel reported an error
    Internal = 9,         ///< a bug, or an exception from a host callback
};

/// Short English name of a code ("invalid argument", ...).
PENUMBRA_API const char* errorCodeName(ErrorCode code) noexcept;

/// The one exception type the library throws, inside and across the API.
/// what() names the file and line or JSON path where that applies
/// ("scene.json: /shapes/3/radius: must be > 0").
class PENUMBRA_API Error : public std::runtime_error {
public:
    Error(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
    Error(const Error&) = default;
    Error& operator=(const Error&) = default;
    ~Error() override;
    /// The kind of failure.
    ErrorCode code() const noexcept { return code_; }

private:
    ErrorCode code_;
};

// ---------------------------------------------------------------- logging

enum class LogLevel { Debug = 0, Info = 1, Warning = 2, Error = 3 };

// ---------------------------------------------------------------- materials

enum class PhongModel {
    /// f = kd/pi + ks (n+2)/(2 pi) cos^n: energy-conserving when kd + ks <= 1.
    Normalized,
    /// The lecture's empirical L = ka La + sum kd Lj (n.l) + ks Lj (v.r)^n.
    Classic,
};

// ---------------------------------------------------------------- render settings

/// Pixel window [x0, x1) x [y0, y1) of the full frame. Pixels keep their
/// full-frame coordinates (and so their samples), so crops tile into the
/// exact full-frame image.
struct CropWindow {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
constexpr bool operator==(const CropWindow& a, const CropWindow& b) {
    return a.x0 == b.x0 && a.y0 == b.y0 && a.x1 == b.x1 && a.y1 == b.y1;
}
constexpr bool operator!=(const CropWindow& a, const CropWindow& b) { return !(a == b); }

enum class LightSelection {
    All,    ///< every light gets lightSamples samples at every shading point
    Power,  ///< lightSamples samples in total, lights picked in proportion to power
};

/// What to render. The same scene, camera and settings give a bit-identical
/// image for any thread count, tile size and split into passes.
struct RenderSettings {
    int width = 512;
    int height = 512;
    int spp = 16;           ///< camera samples per pixel (multi-jittered)
    int lightSamples = 4;   ///< area-light samples per light per shading point (multi-jittered)
    int maxDepth = 10;      ///< mirror bounces; 0 = no reflection rays
    std::uint64_t seed = 0;
    int threads = 0;        ///< 0 = all cores; each render runs in its own TBB arena
    int tileSize = 16;
    std::optional<CropWindow> crop;
    LightSelection lightSelection = LightSelection::All;
    /// Also accumulate albedo, normal and depth of the first hit. Off unless
    /// asked for (the CLI's --aovs, docs/embedding.md): it costs memory.
    bool aovs = false;
};

// ---------------------------------------------------------------- preparing

enum class BuildQuality { Low, Medium, High };

}  // namespace pnb
