#include "shading/phong_sampling.h"

#include <algorithm>
#include <cmath>

#include "core/sampling.h"
#include "shading/phong.h"

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

PhongSample phongEvaluate(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, const Vec3f& wi) {
    const float pd = phongDiffuseProbability(m, kd);
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
        const float specular = Rgb(m.ks).maxComponent() > 0.f ? lobe : 0.f;
        const float norm = m.model == PhongModel::Normalized ? (e + 2.f) * kInv2Pi : 1.f;
        fCos = (kd * kInvPi + m.ks * (norm * specular)) * cosTheta;
    }
    return PhongSample{wi, fCos, pdf};
}

std::optional<PhongSample> samplePhong(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, Vec2f u) {
    const float pd = phongDiffuseProbability(m, kd);
    if (pd <= 0.f && Rgb(m.ks).isBlack()) return std::nullopt;
    Vec3f wi;
    if (u.x < pd) {
        u.x = std::min(u.x / pd, 0x1.fffffep-1f);
        wi = Frame::fromNormal(n).toWorld(squareToCosineHemisphere(u));
    } else {
        u.x = std::min((u.x - pd) / (1.f - pd), 0x1.fffffep-1f);
        const Vec3f r = normalize(2.f * dot(n, wo) * n - wo);
        wi = Frame::fromNormal(r).toWorld(squareToPhongLobe(u, m.exponent));
    }
    wi = normalize(wi);
    if (!(dot(n, wi) > 0.f)) return std::nullopt;
    const PhongSample s = phongEvaluate(m, kd, n, wo, wi);
    if (!(s.pdf > 0.f)) return std::nullopt;
    return s;
}

float phongPdf(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, const Vec3f& wi) {
    return phongEvaluate(m, kd, n, wo, wi).pdf;
}

}  // namespace penumbra
