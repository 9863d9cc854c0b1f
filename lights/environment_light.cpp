#include "lights/environment_light.h"

#include "core/error.h"
#include "core/sampling.h"

namespace penumbra {
namespace {

constexpr float kInv4Pi = 0.25f * kInvPi;

Rgb cleaned(Rgb c) {
    auto ok = [](float v) { return std::isfinite(v) && v > 0.f ? v : 0.f; };
    return {ok(c.r), ok(c.g), ok(c.b)};
}

}  // namespace

EnvironmentLight::EnvironmentLight(Rgb radiance, float sceneRadius) : constant_(cleaned(radiance)), mean_(constant_) {
    power_ = channelMean(mean_) * kPi * kPi * double(sceneRadius) * double(sceneRadius);
}

EnvironmentLight::EnvironmentLight(RgbImage image, float scale, float rotateDegrees, float sceneRadius)
    : image_(std::move(image)), scale_(std::isfinite(scale) && scale > 0.f ? scale : 0.f) {
    const int w = image_.width, h = image_.height;
    if (w <= 0 || h <= 0 || image_.pixels.size() != size_t(w) * size_t(h))
        throw Error(ErrorCode::InvalidArgument, "environment image has no pixels");
    const double rot = std::isfinite(rotateDegrees) ? double(rotateDegrees) * double(kPi) / 180.0 : 0.0;
    cosRot_ = float(std::cos(rot));
    sinRot_ = float(std::sin(rot));
    // Brightness times sin(theta) at each row's centre: the lat-long map
    // squeezes rows towards the poles, whose texels cover less solid angle.
    std::vector<float> f(size_t(w) * size_t(h));
    double sum[3] = {0.0, 0.0, 0.0}, weight = 0.0;
    for (int y = 0; y < h; ++y) {
        const float sinTheta = std::sin(kPi * (float(y) + 0.5f) / float(h));
        for (int x = 0; x < w; ++x) {
            Rgb& c = image_.pixels[size_t(y) * size_t(w) + size_t(x)];
            c = cleaned(c);
            f[size_t(y) * size_t(w) + size_t(x)] = c.average() * sinTheta;
            sum[0] += double(c.r) * sinTheta;
            sum[1] += double(c.g) * sinTheta;
            sum[2] += double(c.b) * sinTheta;
            weight += sinTheta;
        }
    }
    distribution_ = std::make_unique<Distribution2D>(f, w, h);
    mean_ = weight > 0.0 ? Rgb{float(sum[0] / weight), float(sum[1] / weight), float(sum[2] / weight)} * scale_ : Rgb{};
    power_ = channelMean(mean_) * kPi * kPi * double(sceneRadius) * double(sceneRadius);
}

Vec3f EnvironmentLight::toWorld(const Vec3f& l) const {
    return {l.x * cosRot_ + l.z * sinRot_, l.y, -l.x * sinRot_ + l.z * cosRot_};
}

Vec3f EnvironmentLight::toLocal(const Vec3f& w) const {
    return {w.x * cosRot_ - w.z * sinRot_, w.y, w.x * sinRot_ + w.z * cosRot_};
}

Rgb EnvironmentLight::texel(Vec2f uv) const {
    // Nearest texel: the environment is the piecewise-constant function the
    // distribution samples, so pdf and radiance agree exactly.
    const int x = std::clamp(int(uv.x * float(image_.width)), 0, image_.width - 1);
    const int y = std::clamp(int(uv.y * float(image_.height)), 0, image_.height - 1);
    return image_.at(x, y) * scale_;
}

namespace {

// sin(theta) of a unit direction, from x and z: accurate near the poles,
// where sqrt(1 - y^2) loses all its digits.
float sinTheta(const Vec3f& d) { return std::sqrt(d.x * d.x + d.z * d.z); }

// Image coordinates of a unit direction in the environment's own frame.
Vec2f directionToUv(const Vec3f& d) {
    float u = 0.5f + std::atan2(d.x, -d.z) * kInv2Pi;
    if (!(u < 1.f)) u = 0.f;  // atan2 = pi and rounding land on the seam
    if (u < 0.f) u = 0.f;
    const float v = std::atan2(sinTheta(d), d.y) * kInvPi;
    return {u, v};
}

}  // namespace

Rgb EnvironmentLight::radiance(const Vec3f& dir) const {
    if (!hasImage()) return constant_;
    const Vec3f d = normalize(dir);
    if (!(lengthSquared(d) > 0.f)) return Rgb{};
    return texel(directionToUv(toLocal(d)));
}

std::optional<LightSample> EnvironmentLight::sample(const Vec3f& p, Vec2f u) const {
    if (!hasImage()) {
        if (constant_.isBlack()) return std::nullopt;
        const Vec3f wi = squareToUniformSphere(u);
        return LightSample{constant_, wi, p + wi, kInfinity, kInv4Pi, false};
    }
    const Distribution2D::Sample s = distribution_->sample(u);
    if (!(s.pdf > 0.f)) return std::nullopt;
    const float theta = kPi * s.uv.y, phi = 2.f * kPi * (s.uv.x - 0.5f);
    const float sinTheta = std::sin(theta);
    if (!(sinTheta > 0.f)) return std::nullopt;
    const Vec3f local{sinTheta * std::sin(phi), std::cos(theta), -sinTheta * std::cos(phi)};
    const Vec3f wi = normalize(toWorld(local));
    const float pdf = s.pdf / (2.f * kPi * kPi * sinTheta);
    const Rgb L = texel(s.uv);
    if (L.isBlack()) return std::nullopt;
    return LightSample{L, wi, p + wi, kInfinity, pdf, false};
}

float EnvironmentLight::pdf(const Vec3f& wi) const {
    if (!hasImage()) return constant_.isBlack() ? 0.f : kInv4Pi;
    const Vec3f d = toLocal(normalize(wi));
    const float s = sinTheta(d);
    if (!(s > 0.f)) return 0.f;
    return distribution_->pdf(directionToUv(d)) / (2.f * kPi * kPi * s);
}

}  // namespace penumbra
