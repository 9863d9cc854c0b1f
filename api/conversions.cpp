// Conversions between the public API's values and the internal forms that
// differ from them (the rest are one type: api/include/penumbra/types.hpp).
// Vectors and colours keep internal twins with arithmetic of their own; their
// layouts are pinned here.
#include "api/api_internal.h"

#include <algorithm>
#include <cstddef>
#include <type_traits>

#include "core/io/scene_loader.h"

#define PNB_TWIN_FIELD(pub, pubf, inner, innerf)                                                       \
    static_assert(offsetof(pub, pubf) == offsetof(inner, innerf) &&                                   \
                      sizeof(std::declval<pub>().pubf) == sizeof(std::declval<inner>().innerf),       \
                  #pub "::" #pubf " and " #inner "::" #innerf " differ")
static_assert(sizeof(pnb::Vec3) == sizeof(penumbra::Vec3f) && sizeof(pnb::Color) == sizeof(penumbra::Rgb));
PNB_TWIN_FIELD(pnb::Vec3, z, penumbra::Vec3f, z);
PNB_TWIN_FIELD(pnb::Color, b, penumbra::Rgb, b);
#undef PNB_TWIN_FIELD

namespace pnb {

pn::Vec3f in(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 out(const pn::Vec3f& v) { return {v.x, v.y, v.z}; }
pn::Rgb in(const Color& c) { return {c.r, c.g, c.b}; }
Color out(const pn::Rgb& c) { return {c.r, c.g, c.b}; }

pn::Transform in(const Matrix3x4& m) { return pn::Transform(m.m); }
Matrix3x4 out(const pn::Transform& t) {
    Matrix3x4 m;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) m.m[r][c] = t(r, c);
    return m;
}

RenderSettings settingsFrom(const pn::SettingsPatch& patch) {
    RenderSettings r;  // aovs stay off: they are the host's choice, not the file's
    patch.applyTo(r);
    return r;
}

Camera defaultCameraFor(const std::optional<pn::CameraDesc>& cam, const pn::Bounds3f& bounds, float aspect,
                        float vfov) {
    if (cam) return *cam;
    return pn::frameBounds(bounds, vfov, aspect);
}

void accumulate(RenderStats& total, const RenderStats& pass) {
    total.cameraRays += pass.cameraRays;
    total.shadowRays += pass.shadowRays;
    total.reflectionRays += pass.reflectionRays;
    total.invalidRays += pass.invalidRays;
    total.nonFiniteSamples += pass.nonFiniteSamples;
    total.renderSeconds += pass.renderSeconds;
    total.transmissionRays += pass.transmissionRays;
    total.indirectRays += pass.indirectRays;
    total.pathLengthSum += pass.pathLengthSum;
    total.pathLengthMax = std::max(total.pathLengthMax, pass.pathLengthMax);
    total.brdfRays += pass.brdfRays;
    total.pixelsHit += pass.pixelsHit;
    const double rays = double(total.totalRays());
    total.mraysPerSecond = total.renderSeconds > 0 ? rays / total.renderSeconds * 1e-6 : 0.0;
    total.samplesPerPixel = pass.samplesPerPixel;
    total.threads = pass.threads;
}

const PreparedImpl& requirePrepared(const PreparedScene& p) {
    const PreparedImpl* impl = Access::of(p);
    require(impl != nullptr, "the prepared scene is empty (use Renderer::prepare)");
    return *impl;
}

}  // namespace pnb
