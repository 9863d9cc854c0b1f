// The ray sets every accelerator answers: generated once per scene, then
// replayed identically through Embree, the naive loop and raw Embree.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "accel/accelerator.h"
#include "core/camera.h"
#include "core/ray.h"
#include "lights/light_set.h"

namespace penumbra::bench {

enum class RayKind { Camera = 0, Shadow = 1, Incoherent = 2 };
inline constexpr int kRayKindCount = 3;
inline constexpr std::array<RayKind, kRayKindCount> kRayKinds{RayKind::Camera, RayKind::Shadow, RayKind::Incoherent};
const char* rayKindName(RayKind k);
/// Shadow rays are occlusion queries; the others ask for the closest hit.
inline bool isOcclusion(RayKind k) { return k == RayKind::Shadow; }

struct RaySets {
    std::array<std::vector<Ray>, kRayKindCount> rays;  // indexed by RayKind
    int imageSide = 0;       // the camera rays cover an imageSide^2 image ...
    size_t cameraHits = 0;   // ... of which this many hit something
    size_t mirrorRays = 0;   // the incoherent set: mirror bounces ...
    size_t randomRays = 0;   // ... and uniformly random hemisphere directions

    const std::vector<Ray>& of(RayKind k) const { return rays[size_t(k)]; }
};

/// Builds the sets for a finalized scene:
///  - camera: `cameraRays` rays through jittered pixel positions of a square
///    image, ordered in 4x4 pixel blocks (so 16 consecutive rays are coherent);
///  - shadow: from every camera hit to a point on each light, the 16 points of
///    a block being one multi-jittered set (rays below the surface, which the
///    integrator never traces, are left out);
///  - incoherent: from every camera hit, alternately the mirror bounce and a
///    uniformly random direction in the hemisphere the viewer sees.
/// First hits come from `accel` (run with `threads` threads).
RaySets makeRaySets(const Accelerator& accel, const LightSet& lights, const CameraDesc& camera, size_t cameraRays,
                    uint64_t seed, int threads);

/// Every ceil(n / count)-th index of [0, n): an evenly spread subset of at
/// most `count` indices (all of them when count >= n).
std::vector<size_t> spreadSubset(size_t n, size_t count);

}  // namespace penumbra::bench
