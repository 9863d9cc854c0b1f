#include "shading/bsdf/phong_sampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/sampling.h"
#include "shading/bsdf/phong.h"

namespace penumbra {

namespace {

// Direction around the z axis with pdf (e+1)/(2 pi) cos^e(alpha).
Vec3f squareToPhongLobe(Vec2f u, float e) {
    const float cosAlpha = std::pow(1.f - u.x, 1.f / (e + 1.f));  // 1 - u.x in (0, 1]: no 0^(1/(e+1)) = 0 at u = 0
    const float sinAlpha = std::sqrt(std::max(0.f, 1.f - cosAlpha * cosAlpha));
    const float phi = 2.f * kPi * u.y;
    return {sinAlpha * std::cos(phi), sinAlpha * std::sin(phi), cosAlpha};
}

}  // namespace

float phongDiffuseProbability(const Material& m, const Rgb& kd) {
    const float wd = kd.average();
    float ws = Rgb(m.ks).average();
    if (m.model == PhongModel::Classic) ws *= 2.f * kPi / (m.exponent + 2.f);
    if (!(ws > 0.f)) return wd > 0.f ? 1.f : 0.f;
    if (!(wd > 0.f)) return 0.f;
    return wd / (wd + ws);
}

namespace {

// phongEvaluate with the diffuse lobe's probability pd given.
BsdfSample evaluateWith(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, const Vec3f& wi, float pd) {
    const float cosTheta = dot(n, wi);
    // cos(alpha) between wi and the mirror direction of wo, computed as
    // phongResponse does (the mirror direction of wi against wo: the same angle).
    const Vec3f r = 2.f * cosTheta * n - wi;
    const float cosAlpha = dot(r, wo);
    const float e = m.exponent;
    const float lobe = cosAlpha > 0.f && pd < 1.f ? std::pow(cosAlpha, e) : 0.f;
    float pdf = pd > 0.f ? pd * std::max(0.f, cosTheta) * kInvPi : 0.f;
    pdf += (1.f - pd) * (e + 1.f) * kInv2Pi * lobe;
    Rgb fCos;
    if (cosTheta > 0.f) {
        const float specular = m.isGlossy() ? lobe : 0.f;
        const float norm = m.model == PhongModel::Normalized ? (e + 2.f) * kInv2Pi : 1.f;
        fCos = (kd * kInvPi + m.ks * (norm * specular)) * cosTheta;
    }
    return BsdfSample{wi, fCos, pdf};
}

Vec3f mirrorOf(const Vec3f& n, const Vec3f& wo) { return normalize(2.f * dot(n, wo) * n - wo); }

// The lobe u picks (diffuse where u.x < pd) and u with u.x rescaled to [0, 1) within that lobe's share.
std::pair<bool, Vec2f> pickLobe(Vec2f u, float pd) {
    const bool diffuse = u.x < pd;
    u.x = std::min(diffuse ? u.x / pd : (u.x - pd) / (1.f - pd), 0x1.fffffep-1f);
    return {diffuse, u};
}

// samplePhong's direction once the diffuse lobe's probability pd is known;
// the frames of the two lobes (about n, about the mirror direction of wo)
// come from diffuseFrame() and lobeFrame(), asked only for the lobe u picks.
template <class DiffuseFrame, class LobeFrame>
std::optional<Vec3f> sampleLobeDirection(const Material& m, const Vec3f& n, Vec2f u, float pd,
                                         const DiffuseFrame& diffuseFrame, const LobeFrame& lobeFrame) {
    if (pd <= 0.f && !m.isGlossy()) return std::nullopt;
    const auto [diffuse, v] = pickLobe(u, pd);
    Vec3f wi = diffuse ? diffuseFrame().toWorld(squareToCosineHemisphere(v))
                       : lobeFrame().toWorld(squareToPhongLobe(v, m.exponent));
    wi = normalize(wi);
    if (!(dot(n, wi) > 0.f)) return std::nullopt;
    return wi;
}

// The sample of that direction: f cos and pdf, none where the pdf is zero.
std::optional<BsdfSample> evaluated(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo,
                                     const std::optional<Vec3f>& wi, float pd) {
    if (!wi) return std::nullopt;
    const BsdfSample s = evaluateWith(m, kd, n, wo, *wi, pd);
    if (!(s.pdf > 0.f)) return std::nullopt;
    return s;
}

}  // namespace

BsdfSample phongEvaluate(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, const Vec3f& wi) {
    return evaluateWith(m, kd, n, wo, wi, phongDiffuseProbability(m, kd));
}

std::optional<BsdfSample> samplePhong(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, Vec2f u) {
    const float pd = phongDiffuseProbability(m, kd);
    const std::optional<Vec3f> wi = sampleLobeDirection(
        m, n, u, pd, [&] { return Frame::fromNormal(n); }, [&] { return Frame::fromNormal(mirrorOf(n, wo)); });
    return evaluated(m, kd, n, wo, wi, pd);
}

PhongSampler::PhongSampler(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo)
    : m_(m), kd_(kd), n_(n), wo_(wo), pd_(phongDiffuseProbability(m, kd)) {
    if (pd_ > 0.f) diffuse_ = Frame::fromNormal(n);
    if (pd_ < 1.f) lobe_ = Frame::fromNormal(mirrorOf(n, wo));
}

std::optional<Vec3f> PhongSampler::direction(Vec2f u) const {
    return sampleLobeDirection(
        m_, n_, u, pd_, [this]() -> const Frame& { return diffuse_; }, [this]() -> const Frame& { return lobe_; });
}

BsdfSample PhongSampler::evaluate(const Vec3f& wi) const { return evaluateWith(m_, kd_, n_, wo_, wi, pd_); }

PhongSampler::Polar PhongSampler::polar(Vec2f u) const {
    const auto [diffuse, v] = pickLobe(u, pd_);
    if (!diffuse) return {false, v.x, 8.f * v.y};  // squareToPhongLobe: cos = (1 - v.x)^(1/(e+1)), phi = 2 pi v.y
    // squareToConcentricDisk: the radius is the larger of |x|, |y|; the angle
    // pi/4 y/x or pi/2 - pi/4 x/y, half a turn on where that radius is negative.
    const float x = 2.f * v.x - 1.f, y = 2.f * v.y - 1.f;
    const float ax = std::fabs(x), ay = std::fabs(y);
    if (ax > ay) return {true, ax, (x > 0.f ? 0.f : 4.f) + y / x};
    if (ay == 0.f) return {true, 0.f, 0.f};  // the centre: the axis itself
    return {true, ay, (y > 0.f ? 2.f : 6.f) - x / y};
}

std::pair<float, float> PhongSampler::polarRange(bool diffuse, Angle minAngle, Angle maxAngle) const {
    constexpr float kNone = std::numeric_limits<float>::infinity();
    // Neither lobe samples past a quarter turn from its axis: none where
    // minAngle lies in (pi/2, pi), its cosine below 0.
    if (minAngle.cos < 0.0) return {kNone, -kNone};
    // The coordinate of angle a, a monotone function on [0, pi/2]; the ends
    // of the range rounded outwards to floats. minAngle <= 0 where its sine
    // is (in (-pi/2, pi)); maxAngle >= pi/2 where its cosine is <= 0 (in
    // [0, 3 pi/2)).
    const double e1 = double(m_.exponent) + 1.0;
    const auto coordinate = [&](Angle a) { return diffuse ? a.sin : 1.0 - std::pow(a.cos, e1); };
    const float lo = minAngle.sin <= 0.0 ? -kNone : std::nextafter(float(coordinate(minAngle)), -kNone);
    const float hi = maxAngle.cos <= 0.0 ? kNone : std::nextafter(float(coordinate(maxAngle)), kNone);
    return {lo, hi};
}

std::optional<BsdfSample> PhongSampler::sample(Vec2f u) const { return evaluated(m_, kd_, n_, wo_, direction(u), pd_); }

float phongPdf(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, const Vec3f& wi) {
    return phongEvaluate(m, kd, n, wo, wi).pdf;
}

}  // namespace penumbra
