// The environment light: radiance arriving from infinitely far away, a
// constant colour or a lat-long (equirectangular) image, sampled in proportion
// to the image's brightness (core/distribution2d.h). Rays that leave the scene
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

    /// Radiance arriving along -dir, i.e. what a ray leaving the scene along
    /// dir sees (dir need not be unit length; the zero vector sees nothing).
    Rgb radiance(const Vec3f& dir) const;

    /// A direction towards the environment (distance = infinity, point =
    /// p + wi), with L = radiance(wi) and its solid-angle pdf. nullopt where the
    /// pdf is 0 (a black part of the image is never sampled).
    std::optional<LightSample> sample(const Vec3f& p, Vec2f u) const override;
    /// Solid-angle density with which sample() returns unit direction wi, from
    /// any point: 1/(4 pi) for a constant colour, p(u,v) / (2 pi^2 sin t) for
    /// an image. This is the pdf to weigh an escaped ray against (MIS).
    float pdf(const Vec3f& wi) const;
    /// Light::pdf asks about a point where a ray from p meets the light; no
    /// point lies on the environment (a ray that hits something does not see
    /// it), so 0. Escaped rays use pdf(wi).
    float pdf(const Vec3f&, const Hit&) const override { return 0.f; }
    /// pi^2 R^2 times the mean radiance over the sphere (R: scene radius): the
    /// power of a directional light that gives a surface facing it the
    /// irradiance pi * L the environment gives an unoccluded surface, matching
    /// DirectionalLightSource's pi R^2 E.
    double power() const override { return power_; }

    /// Mean radiance over the sphere (solid-angle weighted).
    Rgb meanRadiance() const { return mean_; }
    bool hasImage() const { return image_.width > 0; }
    /// The image as lit (non-finite and negative values cleaned); empty for a constant environment.
    const RgbImage& image() const { return image_; }

private:
    Vec3f toWorld(const Vec3f& local) const;
    Vec3f toLocal(const Vec3f& world) const;
    Rgb texel(Vec2f uv) const;

    Rgb constant_;
    RgbImage image_;  // empty for a constant environment
    float scale_ = 1.f;
    float cosRot_ = 1.f, sinRot_ = 0.f;
    std::unique_ptr<Distribution2D> distribution_;  // images only
    Rgb mean_;
    double power_ = 0.0;
};

}  // namespace penumbra
