#include "lights/area_light.h"

#include <algorithm>

#include "core/sampling.h"

namespace penumbra {

std::optional<LightSample> areaLightSample(const Vec3f& p, const SurfaceSample& s, const Rgb& Le, bool twoSided) {
    Vec3f d = s.p - p;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0.f) || !(s.pdfArea > 0.f)) return std::nullopt;
    float dist = std::sqrt(dist2);
    Vec3f wi = d / dist;
    float cosLight = -dot(s.n, wi);  // cos(theta') at the light
    if (twoSided) cosLight = std::fabs(cosLight);
    if (!(cosLight > 0.f)) return std::nullopt;
    // Area pdf to solid angle: p_w = p_A * d^2 / cos(theta').
    float pdf = s.pdfArea * dist2 / cosLight;
    if (!std::isfinite(pdf) || !(pdf > 0.f)) return std::nullopt;
    return LightSample{Le, wi, s.p, dist, pdf, false};
}

ShapeAreaLight::ShapeAreaLight(const Scene& scene, Kind kind, uint32_t index) : scene_(scene), kind_(kind), index_(index) {
    uint32_t mat = 0;
    switch (kind) {
        case Kind::Rectangle:
            mat = scene.rectangles[index].material;
            area_ = penumbra::area(scene.rectangles[index]);
            break;
        case Kind::Disk:
            mat = scene.disks[index].material;
            area_ = penumbra::area(scene.disks[index]);
            break;
        case Kind::Sphere:
            mat = scene.spheres[index].material;
            area_ = penumbra::area(scene.spheres[index]);
            break;
    }
    Le_ = scene.materials[mat].ke;
    twoSided_ = scene.materials[mat].twoSidedEmission;
    pdfArea_ = 1.f / area_;
    if (kind == Kind::Rectangle) frame_.n = rectangleNormal(scene.rectangles[index]);
    if (kind == Kind::Disk) frame_ = Frame::fromNormal(scene.disks[index].normal);
}

std::optional<LightSample> ShapeAreaLight::sample(const Vec3f& p, Vec2f u) const {
    // The same points as sampleUniform(shape, u), with the normal, frame and
    // pdf taken from the constructor.
    SurfaceSample s{};
    switch (kind_) {
        case Kind::Rectangle: {
            const Rectangle& q = scene_.rectangles[index_];
            s = {q.p0 + u.x * q.a + u.y * q.b, frame_.n, pdfArea_};
            break;
        }
        case Kind::Disk: {
            const Disk& d = scene_.disks[index_];
            const Vec2f c = squareToConcentricDisk(u);
            s = {d.center + d.radius * (c.x * frame_.s + c.y * frame_.t), d.normal, pdfArea_};
            break;
        }
        case Kind::Sphere: s = sampleUniform(scene_.spheres[index_], u); break;
    }
    return areaLightSample(p, s, Le_, twoSided_);
}

Rgb ShapeAreaLight::power() const { return Le_ * (area_ * kPi * (twoSided_ ? 2.f : 1.f)); }

MeshAreaLight::MeshAreaLight(const Scene& scene, uint32_t mesh, uint32_t material, std::vector<uint32_t> triangles) {
    Le_ = scene.materials[material].ke;
    twoSided_ = scene.materials[material].twoSidedEmission;
    const TriangleMesh& m = scene.meshes[mesh];
    triangles_.reserve(triangles.size());
    cdf_.reserve(triangles.size());
    double acc = 0.0;
    for (uint32_t t : triangles) {
        Vec3f p0, p1, p2;
        m.vertices(t, p0, p1, p2);
        const Vec3f e1 = p1 - p0, e2 = p2 - p0;
        triangles_.push_back(Triangle{p0, e1, e2, normalize(cross(e1, e2))});
        acc += triangleArea(p0, p1, p2);
        cdf_.push_back(static_cast<float>(acc));
    }
    totalArea_ = static_cast<float>(acc);
}

std::optional<LightSample> MeshAreaLight::sample(const Vec3f& p, Vec2f u) const {
    if (triangles_.empty() || !(totalArea_ > 0.f)) return std::nullopt;
    // Pick a triangle in proportion to its area with u.x, then reuse the
    // remainder of u.x inside the chosen triangle so the sample set stays stratified.
    const float target = u.x * totalArea_;
    size_t i = triangles_.size() == 1 ? 0 : size_t(std::upper_bound(cdf_.begin(), cdf_.end(), target) - cdf_.begin());
    i = std::min(i, cdf_.size() - 1);
    const float lo = i ? cdf_[i - 1] : 0.f;
    const float triArea = cdf_[i] - lo;
    const float ux = triArea > 0.f ? std::clamp((target - lo) / triArea, 0.f, 0x1.fffffep-1f) : 0.5f;
    const Triangle& t = triangles_[i];
    const Vec2f b = squareToTriangle(Vec2f{ux, u.y});
    // Uniform over the whole light's area: p_A = 1 / total area.
    const SurfaceSample s{t.p0 + b.x * t.e1 + b.y * t.e2, t.n, 1.f / totalArea_};
    return areaLightSample(p, s, Le_, twoSided_);
}

Rgb MeshAreaLight::power() const { return Le_ * (totalArea_ * kPi * (twoSided_ ? 2.f : 1.f)); }

}  // namespace penumbra
