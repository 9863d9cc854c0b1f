// Conversions between the public API's values and the internal forms that
// differ from them (the rest are one type: api/include/penumbra/types.hpp).
#include "api/api_internal.h"

#include "core/scene_loader.h"

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

pn::CameraDesc in(const Camera& c) {
    pn::CameraDesc d;
    d.eye = in(c.eye);
    d.lookAt = in(c.lookAt);
    d.up = in(c.up);
    d.vfovDegrees = c.vfovDegrees;
    d.aperture = c.aperture;
    d.focusDistance = c.focusDistance;
    return d;
}
Camera out(const pn::CameraDesc& d) {
    Camera c;
    c.eye = out(d.eye);
    c.lookAt = out(d.lookAt);
    c.up = out(d.up);
    c.vfovDegrees = d.vfovDegrees;
    c.aperture = d.aperture;
    c.focusDistance = d.focusDistance;
    return c;
}

RenderSettings settingsFrom(const pn::SettingsPatch& patch) {
    RenderSettings r;  // aovs stay off: they are the host's choice, not the file's
    patch.applyTo(r);
    return r;
}

Camera defaultCameraFor(const std::optional<pn::CameraDesc>& cam, const pn::Bounds3f& bounds, float aspect,
                        float vfov) {
    if (cam) return out(*cam);
    return out(pn::frameBounds(bounds, vfov, aspect));
}

RenderStats out(const pn::RenderStats& s) {
    RenderStats r;
    r.cameraRays = s.rays.camera;
    r.shadowRays = s.rays.shadow;
    r.reflectionRays = s.rays.reflection;
    r.invalidRays = s.invalidRays;
    r.nonFiniteSamples = s.rays.nonFinite;
    r.renderSeconds = s.renderSeconds;
    r.mraysPerSecond = s.mraysPerSecond;
    r.samplesPerPixel = s.samplesPerPixel;
    r.threads = s.threads;
    return r;
}

void accumulate(RenderStats& total, const RenderStats& pass) {
    total.cameraRays += pass.cameraRays;
    total.shadowRays += pass.shadowRays;
    total.reflectionRays += pass.reflectionRays;
    total.invalidRays += pass.invalidRays;
    total.nonFiniteSamples += pass.nonFiniteSamples;
    total.renderSeconds += pass.renderSeconds;
    const double rays = double(total.cameraRays + total.shadowRays + total.reflectionRays);
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
