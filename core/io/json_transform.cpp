// JSON transforms (translate, rotate, scale) (SceneReader, json_reader.h).
#include "core/io/json_reader.h"

#include <cmath>


namespace penumbra {
namespace fs = std::filesystem;
using namespace json_text;

Transform SceneReader::readTransform(const Json& j, const std::string& ptr) const {
    expectObject(j, ptr);
    checkKeys(j, ptr, {"translate", "rotate", "scale"});
    Transform s, r, t;
    if (const Json* v = find(j, "scale")) {
        std::string sp = child(ptr, "scale");
        Vec3f f = v->is_number() ? Vec3f(number(*v, sp)) : vec3(*v, sp);
        if (f.x == 0.f || f.y == 0.f || f.z == 0.f) fail(ErrorCode::InvalidScene, sp, "scale factors must not be 0");
        s = Transform::scale(f);
    }
    if (const Json* v = find(j, "rotate")) {
        std::string rp = child(ptr, "rotate");
        if (!v->is_array()) fail(ErrorCode::ParseError, rp, "expected [angle, ax, ay, az] or a list of those");
        if (!v->empty() && (*v)[0].is_number()) {
            r = rotation(*v, rp);
        } else {
            // A list: the first rotation listed is applied first.
            for (size_t i = 0; i < v->size(); ++i) r = rotation((*v)[i], child(rp, i)) * r;
        }
    }
    if (const Json* v = find(j, "translate")) t = Transform::translate(vec3(*v, child(ptr, "translate")));
    Transform m = t * r * s;
    Transform inv;
    if (!std::isfinite(m.determinant()))
        fail(ErrorCode::InvalidScene, ptr, "transform overflows a 32-bit float (its scale is too large)");
    if (!m.inverse(inv)) fail(ErrorCode::InvalidScene, ptr, "transform is singular");
    return m;
}

Transform SceneReader::rotation(const Json& j, const std::string& ptr) const {
    if (!j.is_array() || j.size() != 4)
        fail(ErrorCode::ParseError, ptr, "expected a rotation [angle_degrees, axis_x, axis_y, axis_z]");
    float deg = number(j[0], child(ptr, 0));
    Vec3f axis{number(j[1], child(ptr, 1)), number(j[2], child(ptr, 2)), number(j[3], child(ptr, 3))};
    if (!(lengthSquared(axis) > 0.f)) fail(ErrorCode::InvalidScene, ptr, "rotation axis must not be zero");
    return Transform::rotate(deg, axis);
}
}  // namespace penumbra
