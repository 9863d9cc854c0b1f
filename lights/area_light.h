// Area lights: rectangles, disks, spheres and the triangles of an emissive
// mesh. sample() draws directions by the solid angle the emitter subtends
// where that is exact and pays (spheres: the cone; rectangles: spherical
// rectangles; large mesh triangles: spherical triangles), by area otherwise
// (disks, parallelograms, small triangles); sampleArea() is the uniform-area
// estimator kept for comparisons. pdf() matches sample() exactly.
#pragma once

#include <cstdint>
#include <vector>

#include "core/scene.h"
#include "core/texture_cache.h"
#include "lights/light.h"
#include "lights/spherical_cap.h"
#include "lights/spherical_rectangle.h"

namespace penumbra {

struct RectangleLanes;  // area_light.cpp

/// Emitters that subtend less than this (steradians) at the shading point are
/// sampled by area: solid-angle sampling gains nothing there and its
/// spherical trigonometry loses precision.
inline constexpr float kSphericalMinSolidAngle = 1e-3f;

/// Rectangles and mesh lights whose bounding sphere subtends less than this
/// (steradians) at the shading point are sampled by area: seen that small,
/// 1/d^2 and cos(theta') hardly vary over them, so the spherical sampling's
/// trigonometry (a few hundred ns a sample) buys little (docs/rendering.md,
/// "Light sampling", has the noise and time measured).
inline constexpr float kSolidAngleSamplingMinBound = 0.5f;

/// Shared estimator step: turns a point sampled on an emitter (with its normal
/// and area pdf) into a solid-angle light sample for shading point p.
/// One-sided emitters emit on the side their normal faces.
std::optional<LightSample> areaLightSample(const Vec3f& p, const SurfaceSample& s, const Rgb& Le, bool twoSided);

/// Solid-angle pdf p_A d^2 / cos(theta') of reaching `point` (normal n) from p
/// with area pdf pdfArea; 0 on the back of a one-sided emitter.
float areaPdfToSolidAngle(const Vec3f& p, const Vec3f& point, const Vec3f& n, float pdfArea, bool twoSided);

class ShapeAreaLight final : public Light {
public:
    enum class Kind { Rectangle, Disk, Sphere };
    ShapeAreaLight(const Scene& scene, Kind kind, uint32_t index);
    std::optional<LightSample> sample(const Vec3f& p, Vec2f u) const override;
    void sampleMany(const Vec3f& p, std::span<const Vec2f> u, std::span<std::optional<LightSample>> out) const override;
    void sampleManyLanes(const Vec3f& p, const float* ux, const float* uy, int n, LightLanes& out) const override;
    void mayReachLanes(const LanePoints& at, int n, int32_t* reach) const override;
    void sampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                     LightLanes& out) const override;
    float pdf(const Vec3f& p, const Hit& onLight) const override;
    std::optional<LightSample> sampleArea(const Vec3f& p, Vec2f u) const override;
    bool mayReach(const Vec3f& p, const Vec3f& n) const override;
    double power() const override;
    std::optional<LightBounds> bounds() const override;
    float area() const { return area_; }

private:
    /// The spherical rectangle sample() uses from p, where it uses one (a true
    /// rectangle, near enough, subtending enough); else it samples by area.
    /// The one-sided check (emitsTowards) is the caller's.
    std::optional<SphericalRectangle> sphericalRectangleAt(const Vec3f& p) const;
    /// A point uniform in the rectangle's area, as a light sample from p.
    std::optional<LightSample> rectangleAreaSample(const Vec3f& p, Vec2f u) const;
    bool emitsTowards(const Vec3f& p) const;
    /// mayReachLanes and sampleLanes of a rectangle: loops over the lanes.
    void rectangleReachLanes(const LanePoints& at, int n, int32_t* reach) const;
    void rectangleSampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                              LightLanes& out) const;
    void rectangleSampleManyLanes(const Vec3f& p, const float* ux, const float* uy, int n, LightLanes& out) const;
    RectangleLanes rectangleLanes() const;

    const Scene& scene_;
    Kind kind_;
    uint32_t index_;
    Rgb Le_;
    bool twoSided_;
    float area_;
    // Computed once, not per sample: the emitter's unit normal (rectangles)
    // or frame (disks) and the area pdf.
    Frame frame_;
    float pdfArea_;
    bool orthogonalEdges_ = false;  // rectangles: spherical sampling needs a true rectangle
    Vec3f boundCenter_;             // rectangles: bounding sphere
    float boundRadius2_ = 0.f;
    Vec3f corner_, edgeA_, edgeB_;  // rectangles: the shape itself, kept here for the per-sample paths
};

/// The emissive triangles of one mesh that share one material. The whole
/// light is sampled by area where its bounding sphere subtends less than
/// kSolidAngleSamplingMinBound. Elsewhere a triangle is picked in proportion
/// to the solid angle it subtends at the shading point (lights of at most
/// kSolidAnglePickMax triangles: quads, boxes) or to its area (larger
/// meshes, where that would cost too much per sample), then sampled by
/// solid angle when it subtends at least kSphericalMinSolidAngle, else by
/// area.
class MeshAreaLight final : public Light {
public:
    static constexpr size_t kSolidAnglePickMax = 16;

    /// Where the material's emission is textured (core/emission.h) and the
    /// mesh has texture coordinates, each sample carries the texture at its
    /// point; power() takes the texture's mean. `textures` may be null.
    MeshAreaLight(const Scene& scene, uint32_t mesh, uint32_t material, std::vector<uint32_t> triangles,
                  const TextureCache* textures = nullptr);
    std::optional<LightSample> sample(const Vec3f& p, Vec2f u) const override;
    float pdf(const Vec3f& p, const Hit& onLight) const override;
    std::optional<LightSample> sampleArea(const Vec3f& p, Vec2f u) const override;
    bool mayReach(const Vec3f& p, const Vec3f& n) const override;
    void mayReachLanes(const LanePoints& at, int n, int32_t* reach) const override;
    void sampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                     LightLanes& out) const override;
    double power() const override;
    std::optional<LightBounds> bounds() const override;
    float area() const { return totalArea_; }
    size_t triangleCount() const { return triangles_.size(); }

private:
    // Copied out of the mesh so a sample touches one triangle record, not three vertices.
    struct Triangle {
        Vec3f p0, e1, e2, n;
        Vec3f centroid;
        float radius2;  // squared distance from the centroid to the farthest vertex
    };
    /// Triangle picked by u.x (by area), with u.x rescaled for reuse inside it.
    size_t pick(Vec2f& u) const;
    float triangleArea(size_t i) const { return cdf_[i] - (i ? cdf_[i - 1] : 0.f); }
    /// Solid angle of triangle i from p when it is sampled by solid angle, else 0.
    float sphericalSolidAngle(size_t i, const Vec3f& p) const;
    /// Small lights: the solid angle of every triangle that emits towards p
    /// (into omegas), and their sum.
    float solidAngles(const Vec3f& p, float* omegas) const;
    /// Sample and pdf of triangle i chosen with probability `share`; omega:
    /// its solid angle from p when already known (< 0: compute it).
    std::optional<LightSample> sampleTriangle(size_t i, const Vec3f& p, Vec2f u, float share, float omega) const;
    float trianglePdf(size_t i, const Vec3f& p, const Vec3f& point, float share, float omega) const;
    /// mayReachLanes, and sampleLanes of a light of at most kSolidAnglePickMax triangles: loops over the lanes.
    void reachLanes(const LanePoints& at, int n, int32_t* reach) const;
    void smallMeshSampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                              LightLanes& out) const;

    /// s with its radiance read from the emissive texture at its point of triangle i, where the emission is textured.
    std::optional<LightSample> textured(size_t i, std::optional<LightSample> s) const;

    Rgb Le_;
    Rgb meanLe_;  // Le_ averaged over the emissive texture (Le_ where there is none)
    bool twoSided_;
    // A textured emitter: its material, mesh and the textures (all null otherwise).
    const Material* material_ = nullptr;
    const TriangleMesh* mesh_ = nullptr;
    const TextureCache* textures_ = nullptr;
    std::vector<Triangle> triangles_;
    std::vector<uint32_t> meshTriangles_;  // the mesh's triangle index of each, ascending
    std::vector<float> cdf_;  // cumulative areas, cdf_[i] = sum of areas of triangles [0, i]
    float totalArea_ = 0.f;
    Vec3f boundCenter_;  // bounding sphere of all the triangles
    float boundRadius2_ = 0.f;
};

}  // namespace penumbra
