// The environment light: radiance arriving from infinitely far away, a
// constant colour or a lat-long (equirectangular) image, sampled in proportion
// to the image's brightness (core/distribution2d.h), or, where BSDF samples
// share the work (MIS), to its brightness above the mean (misSampled). Rays that leave the scene
// see it (Integrator's escaped rays), and shading points sample it like any
// other non-delta light, with LightSample::distance = infinity.
//
// Mapping (y-up world; docs/rendering.md, "Environment light"): a direction
// d = (sin t sin p, cos t, -sin t cos p) in the environment's own frame has
// image coordinates u = 0.5 + p / (2 pi), v = t / pi, with row 0 (v = 0) at the
// top (+y). So the image centre lies along -z (ahead of the default camera),
// u = 0.75 along +x, u = 0.25 along -x and the left/right edge along +z; a
// camera looking along -z sees the image the right way round. rotateDegrees
// turns the environment about +y, counter-clockwise seen from above: with 90,
// what was ahead (-z) lies along -x.
#pragma once

#include <memory>

#include "core/distribution2d.h"
#include "core/rgb_image.h"
#include "lights/light.h"

namespace penumbra {

class EnvironmentLight final : public Light {
public:
    /// A uniform environment of radiance `radiance`, sampled uniformly over the
    /// sphere. sceneRadius: radius of the scene's bounding sphere, for power().
    EnvironmentLight(Rgb radiance, float sceneRadius);
    /// A lat-long image (linear radiance, times `scale`), turned by
    /// rotateDegrees about +y. Throws Error(InvalidArgument) for an empty image.
    EnvironmentLight(RgbImage image, float scale, float rotateDegrees, float sceneRadius);
    ~EnvironmentLight() override;

    /// What a ray leaving the scene along dir sees: the radiance arriving
    /// along -dir, and the solid-angle pdfs with which sample() and
    /// misSampled().sample() return dir (the pdf to weigh an escaped ray
    /// against, MIS). From one texel read.
    struct Lookup {
        Rgb L;
        float pdf;
        float misPdf;
    };
    Lookup lookup(const Vec3f& dir) const;
    /// Radiance arriving along -dir, i.e. what a ray leaving the scene along
    /// dir sees (dir need not be unit length; the zero vector sees nothing).
    Rgb radiance(const Vec3f& dir) const { return lookup(dir).L; }

    /// A direction towards the environment (distance = infinity, point =
    /// p + wi), with L = radiance(wi) and its solid-angle pdf. nullopt where the
    /// pdf is 0 (a black part of the image is never sampled).
    std::optional<LightSample> sample(const Vec3f& p, Vec2f u) const override;
    /// sample() of every wanted lane, the same values, the lanes' texel
    /// searches and reads overlapped (Distribution2D::locateLanes).
    void sampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                     LightLanes& out) const override;
    void sampleMany(const Vec3f& p, std::span<const Vec2f> u,
                    std::span<std::optional<LightSample>> out) const override;
    /// Solid-angle density with which sample() returns unit direction wi, from
    /// any point: 1/(4 pi) for a constant colour, p(u,v) / (2 pi^2 sin t) for
    /// an image. This is the pdf to weigh an escaped ray against (MIS).
    float pdf(const Vec3f& wi) const { return lookup(wi).pdf; }
    /// Light::pdf asks about a point where a ray from p meets the light; no
    /// point lies on the environment (a ray that hits something does not see
    /// it), so 0. Escaped rays use pdf(wi).
    float pdf(const Vec3f&, const Hit&) const override { return 0.f; }
    /// pi^2 R^2 times the mean radiance over the sphere (R: scene radius): the
    /// power of a directional light that gives a surface facing it the
    /// irradiance pi * L the environment gives an unoccluded surface, matching
    /// DirectionalLightSource's pi R^2 E.
    double power() const override { return power_; }

    /// The environment as sampled where every light sample is weighed against
    /// BSDF samples (MIS): an image's map less its mean brightness, so that
    /// light samples go where the image is brighter than the mean and the
    /// BSDF samples alone find the rest (Karlik et al. 2019, "MIS
    /// compensation"; pbrt-v4's compensated distribution). Its samples carry
    /// Lookup::misPdf; it samples nothing where the image is darker than its
    /// mean, so an estimate without BSDF samples must not use it. A constant
    /// environment, or an image with nothing above its mean, is sampled as
    /// sample() samples it. Lives as long as this light.
    const Light& misSampled() const { return *misSampled_; }

    /// Mean radiance over the sphere (solid-angle weighted).
    Rgb meanRadiance() const { return mean_; }
    bool hasImage() const { return width_ > 0; }
    /// The image as lit (non-finite and negative values cleaned, before
    /// `scale`); empty for a constant environment.
    RgbImage image() const;

private:
    // What a light sample or an escaped ray reads of a texel, side by side:
    // one cache line where the image and the densities took two or three.
    struct Texel {
        Rgb radiance;  // cleaned, before scale_
        float pdf[2];  // each Map's density in the texel, over du dv
    };
    // The two importance maps: the image's brightness, and the same less its mean (misSampled).
    enum Map { kFull = 0, kCompensated = 1 };
    class MisSampled;

    Vec3f toWorld(const Vec3f& local) const;
    Vec3f toLocal(const Vec3f& world) const;
    const Texel& texelAt(Vec2f uv) const;
    const Texel& texelAt(const Distribution2D::Cell& c) const {
        return texels_[size_t(c.row) * size_t(width_) + size_t(c.column)];
    }
    /// The sampling of `map`: sample, sampleLanes and sampleMany are these with kFull.
    std::optional<LightSample> sampleMap(Map map, const Vec3f& p, Vec2f u) const;
    void sampleMapLanes(Map map, const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                        LightLanes& out) const;
    void sampleMapMany(Map map, const Vec3f& p, std::span<const Vec2f> u,
                       std::span<std::optional<LightSample>> out) const;
    /// The map's locateLanes, and the located texels fetched (prefetched).
    void locateTexels(Map map, const float* ux, const float* uy, int n, Distribution2D::Cell* cells) const;
    /// The sample at c, a point that the map's distribution located.
    std::optional<LightSample> sampleAt(Map map, const Vec3f& p, const Distribution2D::Cell& c) const;
    const Distribution2D& distribution(Map map) const { return *distributions_[map]; }

    Rgb constant_;
    int width_ = 0, height_ = 0;  // 0 for a constant environment
    std::vector<Texel> texels_;   // row-major, row 0 at the top
    float scale_ = 1.f;
    float cosRot_ = 1.f, sinRot_ = 0.f;
    std::unique_ptr<Distribution2D> distributions_[2];  // images only; by Map
    std::unique_ptr<Light> misSampled_;
    Rgb mean_;
    double power_ = 0.0;
};

}  // namespace penumbra
