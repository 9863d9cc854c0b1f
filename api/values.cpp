// The API's free functions: version, validation, matrix helpers.
#include "api/api_internal.h"

namespace pnb {

const char* version() noexcept { return PENUMBRA_VERSION; }

void validate(const RenderSettings& settings) {
    guarded([&] { pn::validateSettings(settings); });
}

void validate(const Camera& camera) {
    guarded([&] { pn::validateCamera(camera); });
}

Matrix3x4 Matrix3x4::translate(const Vec3& t) { return out(pn::Transform::translate(in(t))); }
Matrix3x4 Matrix3x4::scale(const Vec3& s) { return out(pn::Transform::scale(in(s))); }
Matrix3x4 Matrix3x4::rotate(float degrees, const Vec3& axis) { return out(pn::Transform::rotate(degrees, in(axis))); }
Matrix3x4 Matrix3x4::operator*(const Matrix3x4& other) const { return out(in(*this) * in(other)); }

}  // namespace pnb
