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

// ---------------------------------------------------------------- values

struct Vec3 {
    float x = 0.f, y = 0.f, z = 0.f;
};

/// Linear RGB (reflectance, radiance, intensity or irradiance by context).
struct Color {
    float r = 0.f, g = 0.f, b = 0.f;
};

/// The same value in all three channels.
constexpr Color gray(float v) { return Color{v, v, v}; }

/// Pinhole or thin-lens camera; `up` maps to the top of the image.
struct Camera {
    Vec3 eye{0.f, 1.f, 3.f};
    Vec3 lookAt{0.f, 1.f, 0.f};
    Vec3 up{0.f, 1.f, 0.f};
    float vfovDegrees = 45.f;
    float aperture = 0.f;       ///< lens radius; 0 = pinhole
    float focusDistance = 0.f;  ///< 0 = distance from eye to lookAt
};

// ---------------------------------------------------------------- materials

enum class PhongModel {
    /// f = kd/pi + ks (n+2)/(2 pi) cos^n: energy-conserving when kd + ks <= 1.
    Normalized,
    /// The classic empirical model L = ka La + sum kd Lj (n.l) + ks Lj (v.r)^n (not energy-conserving).
    Classic,
};

/// The reflection model of a material (docs/rendering.md, docs/scene-format.md).
enum class MaterialKind {
    /// The Phong terms ka, kd, ks, exponent and kr (kt and ior for glass): the
    /// model of OBJ/MTL and JSON materials unless they ask for another.
    Phong,
    /// glTF 2.0's metal-roughness model: baseColor, metallic, roughness,
    /// transmission with ior, shaded by a GGX microfacet BSDF
    /// (docs/rendering.md); transmission makes the smooth dielectric, and the
    /// Phong terms but ke are ignored.
    MetalRoughness,
};

/// How a texture repeats outside [0, 1] along one axis (glTF's sampler wrap modes).
enum class TextureWrap { Repeat, ClampToEdge, MirroredRepeat };

/// How a texture is filtered: Linear is bilinear between texels and
/// trilinear across MIP levels when minified; Nearest takes the nearest
/// texel of the full-resolution image (glTF magFilter NEAREST: pixel art).
enum class TextureFilter { Linear, Nearest };

/// One texture of a material: an image and how it is sampled. Image
/// coordinates (s, t) run right and down from the image's top-left corner:
/// glTF's texture coordinates, and (u, 1 - v) of OBJ's.
struct TextureSlot {
    /// The image file; empty = none. Images stored inside a model file (a GLB
    /// buffer, a data: URI) are named "<model file>#image<N>.png" (or .jpg)
    /// here; they are not files, and only the scene that loaded them can use them.
    std::string path;
    int uvSet = 0;    ///< which texture coordinates: 0 or 1 (glTF texCoord)
    int channel = 0;  ///< slots that read one value (metallic, roughness, ...): 0 = R, 1 = G, 2 = B, 3 = A (the grey of an image without alpha)
    /// KHR_texture_transform, applied to (s, t): translate(offset) * rotate(rotation) * scale(scale).
    float offset[2] = {0.f, 0.f};
    float rotation = 0.f;  ///< radians; positive turns the image clockwise as KHR_texture_transform defines it
    float scale[2] = {1.f, 1.f};
    TextureWrap wrapS = TextureWrap::Repeat;
    TextureWrap wrapT = TextureWrap::Repeat;
    TextureFilter filter = TextureFilter::Linear;
};

/// What the alpha of a surface does (glTF alphaMode).
enum class AlphaMode {
    Opaque,  ///< alpha is ignored
    Mask,    ///< the surface is absent where alpha < alphaCutoff
    Blend,   ///< the surface is present with probability alpha (stochastic transparency)
};

/// A material (docs/rendering.md, docs/scene-format.md). Colours are linear
/// RGB in [0, inf); the fields of the other kind are ignored.
struct Material {
    std::string name;
    Color ka{0.f, 0.f, 0.f};    ///< ambient reflectance (times the scene's ambient light)
    Color kd{0.8f, 0.8f, 0.8f}; ///< diffuse albedo
    Color ks{0.f, 0.f, 0.f};    ///< specular (Phong lobe) reflectance
    float exponent = 1.f;       ///< Phong exponent n
    Color kr{0.f, 0.f, 0.f};    ///< mirror reflectance
    Color ke{0.f, 0.f, 0.f};    ///< emitted radiance: makes the surface an area light
    bool twoSidedEmission = false;
    PhongModel model = PhongModel::Normalized;
    std::string diffuseTexture;  ///< image multiplying kd through the mesh UVs; empty = none
    /// Transmission colour: non-zero makes the surface a smooth dielectric (glass) whose
    /// Fresnel reflection replaces kr and whose refracted light is scaled by kt.
    Color kt{0.f, 0.f, 0.f};
    float ior = 1.5f;  ///< index of refraction behind the front side (outside is 1); used when kt > 0 or transmission > 0

    MaterialKind kind = MaterialKind::Phong;
    // Metal-roughness (kind MetalRoughness), as glTF 2.0 defines it.
    Color baseColor{1.f, 1.f, 1.f};  ///< glTF baseColorFactor's RGB
    float metallic = 1.f;            ///< in [0, 1]
    float roughness = 1.f;           ///< in [0, 1] (GGX alpha = roughness^2)
    float transmission = 0.f;        ///< KHR_materials_transmission: share of the dielectric part refracted, [0, 1]
    TextureSlot baseColorTexture;    ///< sRGB colour with alpha; multiplies baseColor and opacity
    TextureSlot metallicTexture;     ///< linear; its channel multiplies metallic (glTF: B of metallicRoughnessTexture)
    TextureSlot roughnessTexture;    ///< linear; its channel multiplies roughness (glTF: G of the same image)
    TextureSlot transmissionTexture; ///< linear; its channel multiplies transmission (glTF: R)

    // Both kinds.
    /// Tangent-space normal map (linear RGB, glTF's convention: +G is +bitangent), or a height map when bumpMap.
    TextureSlot normalTexture;
    float normalScale = 1.f;  ///< glTF normalTexture.scale, MTL -bm: scales the map's X and Y (or the heights)
    bool bumpMap = false;     ///< normalTexture is a height map (MTL bump, map_Bump) rather than a normal map
    TextureSlot emissiveTexture;  ///< sRGB; multiplies ke (glTF emissiveTexture, MTL map_Ke)
    float opacity = 1.f;          ///< alpha factor in [0, 1] (glTF baseColorFactor's alpha)
    TextureSlot opacityTexture;   ///< its channel multiplies the alpha (MTL map_d)
    /// Whether alpha (opacity x the colour texture's alpha x opacityTexture)
    /// hides the surface. The colour texture is baseColorTexture, or the
    /// diffuseTexture of a Phong material.
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;  ///< Mask: the surface is absent where alpha < alphaCutoff
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

/// How radiance is estimated (docs/rendering.md).
enum class IntegratorKind {
    Whitted,  ///< direct light + ambient + mirror and refracted rays (Whitted-style ray tracing)
    Path,     ///< path tracing: indirect light, next-event estimation with MIS, Russian roulette
};

/// How a shading point's light samples choose their lights (docs/rendering.md, "Many lights").
enum class LightSelection {
    All,    ///< every light gets lightSamples samples at every shading point
    Power,  ///< lightSamples samples in total, lights picked in proportion to power
    Tree,   ///< lightSamples samples in total, lights picked by a light hierarchy at each point
    Auto,   ///< Tree for scenes of many lights (path: 8 or more, whitted: 256 or more), else All (the default)
};

/// How the Whitted integrator estimates the direct light of area lights
/// (docs/rendering.md). Point and directional lights are exact in both.
enum class DirectLightSampling {
    Mis,    ///< solid-angle light samples + Phong BRDF samples, power heuristic (default)
    Light,  ///< solid-angle light samples only
};

/// What to render. The same scene, camera and settings give a bit-identical
/// image for any thread count, tile size and split into passes.
struct RenderSettings {
    int width = 512;
    int height = 512;
    int spp = 16;           ///< camera samples per pixel (multi-jittered)
    int lightSamples = 4;   ///< area-light samples per light per shading point (stratified)
    int maxDepth = 10;      ///< whitted: mirror/refraction bounces (0 = none); path: path length in bounces
    std::uint64_t seed = 0;
    int threads = 0;        ///< 0 = all cores; more run as all cores (RenderStats::threads); a TBB arena per render
    int tileSize = 16;
    std::optional<CropWindow> crop;
    LightSelection lightSelection = LightSelection::Auto;
    /// Also accumulate albedo, normal and depth of the first hit. Off unless
    /// asked for (the CLI's --aovs, docs/embedding.md): it costs memory.
    bool aovs = false;
    IntegratorKind integrator = IntegratorKind::Whitted;
    DirectLightSampling directLight = DirectLightSampling::Mis;
};

/// The window a render covers: the crop window, or the whole frame.
inline CropWindow renderWindow(const RenderSettings& s) {
    return s.crop ? *s.crop : CropWindow{0, 0, s.width, s.height};
}

// ---------------------------------------------------------------- rendering

/// Counts and timings of one render call (or of all passes of a job).
struct RenderStats {
    std::uint64_t cameraRays = 0, shadowRays = 0, reflectionRays = 0;
    std::uint64_t invalidRays = 0;       ///< rejected before reaching the accelerator
    std::uint64_t nonFiniteSamples = 0;  ///< NaN/Inf radiance samples dropped
    double renderSeconds = 0.0;
    double mraysPerSecond = 0.0;
    std::uint32_t samplesPerPixel = 0;   ///< in the framebuffer after the call
    int threads = 0;                     ///< threads the render ran on
    std::uint64_t transmissionRays = 0;  ///< refracted rays through dielectrics (both integrators)
    std::uint64_t indirectRays = 0;      ///< path: diffuse and glossy bounce rays
    /// Path lengths: rays traced along each camera sample's path (camera ray included;
    /// whitted: its deepest branch). Sum over samples (mean = pathLengthSum / cameraRays) and maximum.
    std::uint64_t pathLengthSum = 0;
    std::uint32_t pathLengthMax = 0;
    /// whitted: rays sampled from the BRDF for direct light under MIS that are traced (an
    /// occlusion query up to the light a ray meets where the lights have few primitives, else a
    /// closest-hit query that looks for one; shadowRays are the occlusion queries towards sampled
    /// light points).
    std::uint64_t brdfRays = 0;
    /// Pixels whose first camera sample hit a surface (the rest saw the
    /// background or the environment there), summed over passes.
    std::uint64_t pixelsHit = 0;

    /// Every ray traced: the sum of the kinds above (invalid rays are not traced).
    std::uint64_t totalRays() const {
        return cameraRays + shadowRays + reflectionRays + transmissionRays + indirectRays + brdfRays;
    }

    /// Adds the stats of a later pass of the same image (RenderJob::stats sums
    /// its passes so): counts and time add up, samplesPerPixel and threads
    /// become the pass's, the longest path the longer, and the ray rate is
    /// recomputed over the whole.
    RenderStats& operator+=(const RenderStats& pass) {
        cameraRays += pass.cameraRays;
        shadowRays += pass.shadowRays;
        reflectionRays += pass.reflectionRays;
        invalidRays += pass.invalidRays;
        nonFiniteSamples += pass.nonFiniteSamples;
        renderSeconds += pass.renderSeconds;
        transmissionRays += pass.transmissionRays;
        indirectRays += pass.indirectRays;
        pathLengthSum += pass.pathLengthSum;
        pathLengthMax = pass.pathLengthMax > pathLengthMax ? pass.pathLengthMax : pathLengthMax;
        brdfRays += pass.brdfRays;
        pixelsHit += pass.pixelsHit;
        mraysPerSecond = renderSeconds > 0 ? double(totalRays()) / renderSeconds * 1e-6 : 0.0;
        samplesPerPixel = pass.samplesPerPixel;
        threads = pass.threads;
        return *this;
    }
};

// ---------------------------------------------------------------- preparing

/// The structure that answers a prepared scene's ray queries.
enum class AcceleratorKind {
    Embree,  ///< Embree's BVH (the default)
    Naive,   ///< every primitive tested for every ray: the O(N) reference
};

enum class BuildQuality { Low, Medium, High };

}  // namespace pnb
