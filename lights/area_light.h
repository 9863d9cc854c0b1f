// Area lights: uniform sampling by area on a rectangle, disk, sphere or the
// triangles of an emissive mesh (picked in proportion to their area).
#pragma once

#include <cstdint>
#include <vector>

#include "core/scene.h"
#include "lights/light.h"

namespace penumbra {

/// Shared estimator step: turns a point sampled on an emitter (with its normal
/// and area pdf) into a solid-angle light sample for shading point p.
/// One-sided emitters emit on the side their normal faces.
std::optional<LightSample> areaLightSample(const Vec3f& p, const SurfaceSample& s, const Rgb& Le, bool twoSided);

class ShapeAreaLight final : public Light {
public:
    enum class Kind { Rectangle, Disk, Sphere };
    ShapeAreaLight(const Scene& scene, Kind kind, uint32_t index);
    std::optional<LightSample> sample(const Vec3f& p, Vec2f u) const override;
    Rgb power() const override;
    float area() const { return area_; }

private:
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
};

/// The emissive triangles of one mesh that share one material.
class MeshAreaLight final : public Light {
public:
    MeshAreaLight(const Scene& scene, uint32_t mesh, uint32_t material, std::vector<uint32_t> triangles);
    std::optional<LightSample> sample(const Vec3f& p, Vec2f u) const override;
    Rgb power() const override;
    float area() const { return totalArea_; }
    size_t triangleCount() const { return triangles_.size(); }

private:
    // Copied out of the mesh so a sample touches one cache line, not three vertices.
    struct Triangle {
        Vec3f p0, e1, e2, n;
    };
    Rgb Le_;
    bool twoSided_;
    std::vector<Triangle> triangles_;
    std::vector<float> cdf_;  // cumulative areas, cdf_[i] = sum of areas of triangles [0, i]
    float totalArea_ = 0.f;
};

}  // namespace penumbra
