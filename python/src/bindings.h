// Shared pieces of the `penumbra` Python module (pybind11 over the public
// C++ API, <penumbra/penumbra.hpp>; nothing of the renderer's internals).
#pragma once

#include <penumbra/penumbra.hpp>

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <memory>
#include <optional>
#include <string>

namespace py = pybind11;

// Vec3 and Color travel as 3-tuples; any sequence of three numbers converts
// to them (a Color also from one number: gray). That reads like Python
// (`kd=(0.7, 0.2, 0.1)`) and keeps numpy rows usable as points.
namespace pybind11::detail {

bool loadTriple(handle src, bool convert, float out[3], bool allowScalar);

template <>
struct type_caster<pnb::Vec3> {
    PYBIND11_TYPE_CASTER(pnb::Vec3, const_name("tuple[float, float, float]"));
    bool load(handle src, bool convert) {
        float v[3];
        if (!loadTriple(src, convert, v, false)) return false;
        value = pnb::Vec3{v[0], v[1], v[2]};
        return true;
    }
    static handle cast(const pnb::Vec3& v, return_value_policy, handle) {
        return make_tuple(v.x, v.y, v.z).release();
    }
};

template <>
struct type_caster<pnb::Color> {
    PYBIND11_TYPE_CASTER(pnb::Color, const_name("tuple[float, float, float]"));
    bool load(handle src, bool convert) {
        float v[3];
        if (!loadTriple(src, convert, v, true)) return false;
        value = pnb::Color{v[0], v[1], v[2]};
        return true;
    }
    static handle cast(const pnb::Color& c, return_value_policy, handle) {
        return make_tuple(c.r, c.g, c.b).release();
    }
};

}  // namespace pybind11::detail

namespace pnbpy {

/// A Python callable that may be dropped on a thread without the GIL (job
/// threads own copies of the callbacks): the last owner takes the GIL to
/// release it.
class PyCallable {
public:
    PyCallable() = default;
    explicit PyCallable(py::object fn);
    explicit operator bool() const { return fn_ != nullptr; }
    const py::object& get() const { return *fn_; }

private:
    std::shared_ptr<py::object> fn_;
};

/// A framebuffer as Python holds it: the API's Framebuffer plus a flag that
/// refuses reads and a second render while a render writes into it (the
/// C++ type is not thread-safe, and Python threads make overlap easy).
struct PyFramebuffer {
    pnb::Framebuffer fb;
    std::atomic<bool> busy{false};

    PyFramebuffer() = default;
    explicit PyFramebuffer(pnb::Framebuffer f) : fb(std::move(f)) {}
    /// Throws Error(InvalidArgument) while a render writes into it.
    const pnb::Framebuffer& readable() const;
};

/// Marks a framebuffer busy for the lifetime of a render call.
class BusyLease {
public:
    explicit BusyLease(PyFramebuffer& f);
    ~BusyLease();
    BusyLease(const BusyLease&) = delete;
    BusyLease& operator=(const BusyLease&) = delete;

private:
    PyFramebuffer& f_;
};

/// The radiance (H x W x 3) or, with AOVs, radiance + albedo + normal + depth
/// (H x W x 10, the channel order of the CLI's EXR) as a new float32 array.
py::array_t<float> framebufferArray(const pnb::Framebuffer& fb);
/// A render result: framebufferArray viewed as penumbra.Image (an ndarray
/// that shows itself in Jupyter), remembering its framebuffer and stats.
py::object makeImage(std::shared_ptr<PyFramebuffer> fb, const pnb::RenderStats& stats);

/// Settings from `base` with the keyword arguments that name settings
/// applied (width=, height=, spp=, ...); unknown names raise TypeError.
pnb::RenderSettings settingsWith(pnb::RenderSettings base, const py::kwargs& kwargs);
/// Converts a str or os.PathLike to a path string.
std::string pathString(const py::handle& path);

/// A setting given as an enum value or by its name (pnb::EnumNames, the
/// command line's spelling); another name raises penumbra.Error.
template <class E>
E enumFrom(const py::handle& value, const char* setting) {
    if (py::isinstance<py::str>(value)) {
        const std::string s = value.cast<std::string>();
        if (const std::optional<E> e = pnb::enumFromName<E>(s)) return *e;
        throw pnb::Error(pnb::ErrorCode::InvalidArgument,
                         std::string(setting) + " must be " + pnb::enumNameList<E>("'") + ", got '" + s + "'");
    }
    return value.cast<E>();
}

/// A penumbra.Error instance carrying the message and code of `e`.
py::object errorObject(const pnb::Error& e);

void bindErrors(py::module_& m);
void bindValues(py::module_& m);
void bindScene(py::module_& m);
void bindFramebuffer(py::module_& m);
void bindRenderer(py::module_& m);

}  // namespace pnbpy
