// The coordinate range every accelerator can represent. Embree drops a
// primitive whose bounds reach beyond +-1.844e18 (its FLT_LARGE) without a
// word while the naive accelerator would still show it, so scenes are held to
// this range before either sees them: loaders refuse what lies beyond it,
// Scene::finalize drops it (for scenes built in code) with a warning.
#pragma once

#include <cstddef>

#include "core/math.h"

namespace penumbra {

class Scene;

constexpr float kMaxSceneCoordinate = 1.844e18f;

/// Whether every coordinate of `b` lies strictly within +-kMaxSceneCoordinate.
bool withinSceneRange(const Bounds3f& b);
/// Whether every coordinate of `p` lies strictly within +-kMaxSceneCoordinate.
bool withinSceneRange(const Vec3f& p);

struct RangeDrops {
    size_t shapes = 0;
    size_t triangles = 0;
    size_t instances = 0;
};

/// Removes the finite shapes (planes are infinite and tested analytically) and
/// the triangles that reach beyond the range; meshes left empty are removed.
/// Prototype triangles are held to the range in object space (Embree builds
/// their BVH there), instances by their world-space bounds.
RangeDrops dropBeyondSceneRange(Scene& scene);

}  // namespace penumbra
