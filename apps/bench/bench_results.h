// What one benchmark run measured, per scene and accelerator, and the ratios
// derived from it (the targets).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "bench_scenes.h"
#include "measure.h"
#include "ray_sets.h"

namespace penumbra::bench {

struct AccelFigures {
    bool present = false;
    std::string note;                 // e.g. why it is absent
    double buildSeconds = 0.0;        // best of the builds
    double deviceSeconds = 0.0;       // raw only: rtcNewDevice, not in buildSeconds
    size_t memoryBytes = 0;
    std::array<RateFigures, kRayKindCount> kinds;  // the naive one answers a subset (kinds[k].rays)
    FrameFigures frame;
};

/// Raw Embree packets of one width on one ray kind.
struct PacketFigures {
    int width = 0;
    RayKind kind = RayKind::Camera;
    bool native = false;
    RateFigures rate;
};

struct SceneResult {
    std::string name;
    SceneFamily family = SceneFamily::Procedural;
    size_t triangles = 0, primitives = 0, lights = 0;
    bool triangleOnly = false;
    double prepareSeconds = 0.0;      // PreparedScene: finalize, BVH, lights
    std::array<size_t, kRayKindCount> setRays{};
    int imageSide = 0;
    size_t cameraHits = 0, mirrorRays = 0, randomRays = 0;
    AccelFigures embree, naive, raw;
    /// The renderer's accelerator through intersectPrim only (closest-hit
    /// kinds; no Scene::completeHit): splits its overhead over raw Embree.
    AccelFigures embreeThin;
    /// Raw Embree without RTC_SCENE_FLAG_ROBUST (single rays): what the
    /// renderer's robust traversal costs. Its disagreements are reported,
    /// not checked (without the flag Embree is not watertight).
    AccelFigures rawFast;
    std::vector<PacketFigures> packets;
    std::array<Disagreement, kRayKindCount> naiveVsEmbree, rawVsEmbree, rawFastVsEmbree;
};

/// The ratios for one scene; empty where they do not apply.
struct SceneRatios {
    std::optional<double> cameraOverRaw1, cameraOverRawAll;        // target >= 0.85
    std::array<std::optional<double>, kRayKindCount> kindOverRawAll;  // every kind, all threads
    std::optional<double> frameOverQuery;                          // target <= 2.0
    std::optional<double> renderScaling;                           // target >= 1.85 (two threads)
    std::optional<double> buildOverRaw, buildOverRawWithDevice;    // target <= 1.1
    std::optional<double> memoryOverRaw;                           // target <= 1.2
    std::array<std::optional<double>, kRayKindCount> embreeOverNaive;  // one thread
    std::array<std::optional<double>, kRayKindCount> notRobustOverRaw;  // all threads
};
SceneRatios ratiosOf(const SceneResult& r);

/// Sum over scenes and kinds.
struct AgreementSummary {
    Disagreement naiveVsEmbree, rawVsEmbree;
    bool passed() const {
        return naiveVsEmbree.fraction() <= kMaxDisagreement && rawVsEmbree.fraction() <= kMaxDisagreement;
    }
};
AgreementSummary summarizeAgreement(const std::vector<SceneResult>& results);

}  // namespace penumbra::bench
