// Framebuffer: accumulated samples, read out as float32 numpy arrays (row 0
// on top, like the images the library writes).
#include "bindings.h"

#include <vector>

namespace pnbpy {

namespace {

[[noreturn]] void invalid(const std::string& message) { throw pnb::Error(pnb::ErrorCode::InvalidArgument, message); }

// An (h, w, channels) array, or (h, w) for one channel.
py::array_t<float> planes(int w, int h, py::ssize_t channels) {
    if (channels == 1) return py::array_t<float>({py::ssize_t(h), py::ssize_t(w)});
    return py::array_t<float>({py::ssize_t(h), py::ssize_t(w), channels});
}

// Copies `src` (n values per pixel) into channels [first, first + n) of dst.
void scatter(const std::vector<float>& src, int n, float* dst, int channels, int first, std::size_t pixels) {
    for (std::size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < n; ++c) dst[i * channels + first + c] = src[i * n + c];
}

py::array_t<float> channelsOf(const pnb::Framebuffer& fb, int n, std::vector<float> (pnb::Framebuffer::*read)() const) {
    std::vector<float> v;
    {
        py::gil_scoped_release release;
        v = (fb.*read)();
    }
    py::array_t<float> a = planes(fb.width(), fb.height(), n);
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
}

py::array_t<float> rgbOf(const pnb::Framebuffer& fb) {
    std::vector<float> rgba;
    {
        py::gil_scoped_release release;
        rgba = fb.rgba();
    }
    py::array_t<float> a = planes(fb.width(), fb.height(), 3);
    float* d = a.mutable_data();
    const std::size_t n = std::size_t(fb.width()) * std::size_t(fb.height());
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) d[i * 3 + c] = rgba[i * 4 + c];
    return a;
}

}  // namespace

const pnb::Framebuffer& PyFramebuffer::readable() const {
    if (busy.load()) invalid("the framebuffer is being rendered into; read it after the render returns");
    return fb;
}

BusyLease::BusyLease(PyFramebuffer& f) : f_(f) {
    bool expected = false;
    if (!f_.busy.compare_exchange_strong(expected, true))
        invalid("the framebuffer is already being rendered into by another call");
}

BusyLease::~BusyLease() { f_.busy.store(false); }

py::array_t<float> framebufferArray(const pnb::Framebuffer& fb) {
    if (!fb.hasAovs()) return rgbOf(fb);
    std::vector<float> rgba, albedo, normals, depth;
    {
        py::gil_scoped_release release;
        rgba = fb.rgba();
        albedo = fb.albedo();
        normals = fb.normals();
        depth = fb.depth();
    }
    const std::size_t n = std::size_t(fb.width()) * std::size_t(fb.height());
    py::array_t<float> a = planes(fb.width(), fb.height(), 10);
    float* d = a.mutable_data();
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) d[i * 10 + c] = rgba[i * 4 + c];
    scatter(albedo, 3, d, 10, 3, n);
    scatter(normals, 3, d, 10, 6, n);
    scatter(depth, 1, d, 10, 9, n);
    return a;
}

py::object makeImage(std::shared_ptr<PyFramebuffer> fb, const pnb::RenderStats& stats) {
    py::array_t<float> a = framebufferArray(fb->readable());
    py::object image = py::module_::import("penumbra._image").attr("Image");
    return image.attr("_wrap")(a, py::cast(std::move(fb)), py::cast(stats));
}

void bindFramebuffer(py::module_& m) {
    py::class_<PyFramebuffer, std::shared_ptr<PyFramebuffer>>(
        m, "Framebuffer",
        "Accumulated samples of one render window (the crop window or the whole frame), plus AOVs when the "
        "settings ask for them. Readouts average the samples so far; row 0 is the top row.")
        .def(py::init([](const std::optional<pnb::RenderSettings>& settings, const py::kwargs& kw) {
                 const pnb::RenderSettings s = settingsWith(settings.value_or(pnb::RenderSettings{}), kw);
                 return std::make_shared<PyFramebuffer>(pnb::Framebuffer(s));
             }),
             py::arg("settings") = py::none(),
             "A framebuffer for `settings` (or RenderSettings(**keywords)): size, crop window, AOVs.")
        .def_property_readonly("width", [](const PyFramebuffer& f) { return f.fb.width(); })
        .def_property_readonly("height", [](const PyFramebuffer& f) { return f.fb.height(); })
        .def_property_readonly("full_width", [](const PyFramebuffer& f) { return f.fb.fullWidth(); })
        .def_property_readonly("full_height", [](const PyFramebuffer& f) { return f.fb.fullHeight(); })
        .def_property_readonly("window",
                               [](const PyFramebuffer& f) {
                                   const pnb::CropWindow w = f.fb.window();
                                   return py::make_tuple(w.x0, w.y0, w.x1, w.y1);
                               })
        .def_property_readonly("sample_count", [](const PyFramebuffer& f) { return f.fb.sampleCount(); })
        .def_property_readonly("has_aovs", [](const PyFramebuffer& f) { return f.fb.hasAovs(); })
        .def_property_readonly("incomplete", [](const PyFramebuffer& f) { return f.fb.incomplete(); },
                               "True after a cancelled or failed pass; clear() before rendering into it again.")
        .def_property_readonly("shape",
                               [](const PyFramebuffer& f) {
                                   return py::make_tuple(f.fb.height(), f.fb.width(), f.fb.hasAovs() ? 10 : 3);
                               })
        .def("array", [](const PyFramebuffer& f) { return framebufferArray(f.readable()); },
             "float32 (H, W, 3) radiance, or (H, W, 10) with AOVs: R G B, albedo R G B, normal X Y Z, depth.")
        .def("__array__",
             [](const PyFramebuffer& f, const py::object& dtype, const py::kwargs&) {
                 py::array a = framebufferArray(f.readable());
                 return dtype.is_none() ? a : py::array(a.attr("astype")(dtype));
             },
             py::arg("dtype") = py::none())
        .def("rgb", [](const PyFramebuffer& f) { return rgbOf(f.readable()); }, "float32 (H, W, 3) radiance.")
        .def("rgba",
             [](const PyFramebuffer& f) { return channelsOf(f.readable(), 4, &pnb::Framebuffer::rgba); },
             "float32 (H, W, 4) radiance with alpha 1.")
        .def("albedo", [](const PyFramebuffer& f) { return channelsOf(f.readable(), 3, &pnb::Framebuffer::albedo); })
        .def("normals", [](const PyFramebuffer& f) { return channelsOf(f.readable(), 3, &pnb::Framebuffer::normals); })
        .def("depth", [](const PyFramebuffer& f) { return channelsOf(f.readable(), 1, &pnb::Framebuffer::depth); },
             "float32 (H, W): distance along the camera ray, 0 where nothing was hit.")
        .def("pixel", [](const PyFramebuffer& f, int x, int y) { return f.readable().pixel(x, y); }, py::arg("x"),
             py::arg("y"))
        .def("clear",
             [](PyFramebuffer& f) {
                 BusyLease lease(f);
                 f.fb.clear();
             },
             "Forgets all samples.")
        .def("copy", [](const PyFramebuffer& f) { return std::make_shared<PyFramebuffer>(f.readable()); })
        .def(
            "write",
            [](const PyFramebuffer& f, const py::object& path, float exposure, bool aovs) {
                const pnb::Framebuffer& fb = f.readable();
                const std::string p = pathString(path);
                pnb::ImageOptions o;
                o.exposure = exposure;
                o.aovs = aovs;
                py::gil_scoped_release release;
                fb.writeImage(p, o);
            },
            py::arg("path"), py::kw_only(), py::arg("exposure") = 0.f, py::arg("aovs") = false,
            "Writes the image: .exr/.hdr/.pfm linear, .png/.jpg/.tif exposure-scaled (stops) and sRGB-encoded. "
            "All or nothing (temporary file + rename). With aovs=True an EXR gets the extra channels, other "
            "formats a sibling <stem>.aovs.exr.")
        .def("__repr__", [](const PyFramebuffer& f) {
            return "<penumbra.Framebuffer " + std::to_string(f.fb.width()) + "x" + std::to_string(f.fb.height()) + ", " +
                   std::to_string(f.fb.sampleCount()) + " spp" + (f.fb.hasAovs() ? ", AOVs" : "") +
                   (f.fb.incomplete() ? ", incomplete" : "") + ">";
        });
}

}  // namespace pnbpy
