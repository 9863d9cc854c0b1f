// The benchmark's scenes: procedural bumpy spheres of a chosen triangle count
// in a triangle room with an area light, a scene of analytic shapes, the
// default Cornell box, and any OBJ file placed in the same kind of room.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

#include "core/camera.h"
#include "core/log.h"
#include "core/scene.h"

namespace penumbra::bench {

/// What a scene is in the report: the procedural size series (plotted), the
/// analytic mix, the default scene or a user OBJ.
enum class SceneFamily { Procedural, Mixed, Default, Obj, File };
const char* familyName(SceneFamily f);

struct BenchScene {
    std::string name;
    SceneFamily family = SceneFamily::Procedural;
    Scene scene;  // not finalized yet
    CameraDesc camera;
    /// Light samples and mirror depth of the frame, when the scene file says
    /// (the frame's size and spp are the benchmark's own).
    std::optional<int> lightSamples, maxDepth;
};

/// Triangles of the room addRoom() builds (5 walls and the 2-triangle light).
inline constexpr size_t kRoomTriangles = 12;

/// A closed, displaced latitude-longitude sphere with exactly `triangles`
/// triangles when that count is even (odd counts get one more), wound
/// counter-clockwise seen from outside. triangles must be >= 6.
TriangleMesh bumpySphere(size_t triangles, const Vec3f& center, float radius, uint32_t material);

/// Adds a room of triangles around `object` (floor under it, back and side
/// walls, ceiling; open towards +z where frameBounds puts the camera) with a
/// downward-facing emissive quad under the ceiling, and their materials.
void addRoom(Scene& scene, const Bounds3f& object);

/// Camera looking at `object` the way the CLI frames OBJ files (frameBounds).
CameraDesc frameObject(const Bounds3f& object);

/// A bumpy sphere of `triangles` triangles in the room; triangle-only.
BenchScene proceduralScene(size_t triangles);

/// Spheres, boxes, rectangles, disks and a plane with a bumpy mesh sphere of
/// `meshTriangles` triangles and a rectangle light.
BenchScene mixedScene(size_t meshTriangles);

/// The default Cornell box OBJ, framed by frameObject as the CLI frames it.
BenchScene defaultScene(const std::filesystem::path& obj, const Logger& log);

/// Any OBJ placed on the floor of a room with a light, framed by frameObject.
BenchScene objInRoom(const std::filesystem::path& obj, const Logger& log);

/// A JSON scene file as it stands (its camera, or framed like an OBJ when it
/// has none), named after the file.
BenchScene fileScene(const std::filesystem::path& json, const Logger& log);

/// Short label for a triangle count: 100 -> "1e2", 250 -> "250".
std::string sizeLabel(size_t n);

}  // namespace penumbra::bench
