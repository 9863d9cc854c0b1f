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

float lobePdf(float cosAlpha, float e) { return cosAlpha > 0.f ? (e + 1.f) * kInv2Pi * std::pow(cosAlpha, e) : 0.f; }

}  // namespace

float phongDiffuseProbability(const Material& m, const Rgb& kd) {
    const float wd = kd.average();
    float ws = Rgb(m.ks).average();
    if (m.model == PhongModel::Classic) ws *= 2.f * kPi / (m.exponent + 2.f);
    if (!(ws > 0.f)) return wd > 0.f ? 1.f : 0.f;
    if (!(wd > 0.f)) return 0.f;
    return wd / (wd + ws);
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
    const float pdf = phongPdf(m, kd, n, wo, wi);
    if (!(dot(n, wi) > 0.f) || !(pdf > 0.f)) return std::nullopt;
    const Rgb fCos = phongResponse(m, kd, n, wo, wi, false);
    return PhongSample{wi, fCos, pdf};
}

float phongPdf(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, const Vec3f& wi) {
    const float pd = phongDiffuseProbability(m, kd);
    float pdf = 0.f;
    if (pd > 0.f) pdf += pd * std::max(0.f, dot(n, wi)) * kInvPi;
    if (pd < 1.f) {
        const Vec3f r = 2.f * dot(n, wo) * n - wo;
        pdf += (1.f - pd) * lobePdf(dot(normalize(r), wi), m.exponent);
    }
    return pdf;
}

}  // namespace penumbra
