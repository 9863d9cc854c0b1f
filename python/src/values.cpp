// Plain values of the API: enums, Material, Camera, RenderSettings,
// Matrix3x4, RenderStats; and the keyword-argument form of RenderSettings
// that the render calls share.
#include "bindings.h"

#include <cmath>
#include <cstdint>
#include <limits>

namespace pybind11::detail {

bool loadTriple(handle src, bool convert, float out[3], bool allowScalar) {
    if (!src || isinstance<str>(src) || isinstance<bytes>(src)) return false;
    if (allowScalar && (PyFloat_Check(src.ptr()) || PyLong_Check(src.ptr()) ||
                        (convert && PyNumber_Check(src.ptr()) && !PySequence_Check(src.ptr())))) {
        make_caster<float> c;
        if (!c.load(src, convert)) return false;
        out[0] = out[1] = out[2] = cast_op<float>(c);
        return true;
    }
    if (!PySequence_Check(src.ptr())) return false;
    const Py_ssize_t n = PySequence_Size(src.ptr());
    if (n != 3) {
        PyErr_Clear();
        return false;
    }
    for (Py_ssize_t i = 0; i < 3; ++i) {
        object item = reinterpret_steal<object>(PySequence_GetItem(src.ptr(), i));
        if (!item) {
            PyErr_Clear();
            return false;
        }
        make_caster<float> c;
        if (!c.load(item, true)) return false;  // numpy scalars and ints are fine inside a triple
        out[i] = cast_op<float>(c);
    }
    return true;
}

}  // namespace pybind11::detail

namespace pnbpy {

namespace {

[[noreturn]] void invalid(const std::string& message) { throw pnb::Error(pnb::ErrorCode::InvalidArgument, message); }

int intSetting(const char* name, const py::handle& value) {
    if (!py::isinstance<py::int_>(value) || py::isinstance<py::bool_>(value))
        throw py::type_error(std::string(name) + " must be an int, got " + std::string(py::str(value.get_type().attr("__name__"))));
    const long long v = value.cast<long long>();  // OverflowError for huge ints
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
        invalid(std::string(name) + " is out of range: " + std::to_string(v));
    return int(v);
}

std::uint64_t seedSetting(const py::handle& value) {
    if (!py::isinstance<py::int_>(value) || py::isinstance<py::bool_>(value))
        throw py::type_error("seed must be an int");
    if (value.cast<py::int_>() < py::int_(0) ||
        value.cast<py::int_>() > py::int_(std::numeric_limits<std::uint64_t>::max()))
        invalid("seed must be in [0, 2**64), got " + std::string(py::str(value)));
    return value.cast<std::uint64_t>();
}

std::optional<pnb::CropWindow> cropFrom(const py::handle& value) {
    if (value.is_none()) return std::nullopt;
    const auto v = value.cast<std::vector<py::object>>();
    if (v.size() != 4) invalid("crop must be (x0, y0, x1, y1), got " + std::to_string(v.size()) + " values");
    return pnb::CropWindow{intSetting("crop x0", v[0]), intSetting("crop y0", v[1]), intSetting("crop x1", v[2]),
                           intSetting("crop y1", v[3])};
}

pnb::LightSelection selectionFrom(const py::handle& value) { return enumFrom<pnb::LightSelection>(value, "light_selection"); }

pnb::IntegratorKind integratorFrom(const py::handle& value) { return enumFrom<pnb::IntegratorKind>(value, "integrator"); }

pnb::DirectLightSampling directLightFrom(const py::handle& value) {
    return enumFrom<pnb::DirectLightSampling>(value, "direct_light");
}

py::object cropTuple(const std::optional<pnb::CropWindow>& c) {
    if (!c) return py::none();
    return py::make_tuple(c->x0, c->y0, c->x1, c->y1);
}

std::string settingsRepr(const pnb::RenderSettings& s) {
    std::string r = "RenderSettings(width=" + std::to_string(s.width) + ", height=" + std::to_string(s.height) +
                    ", spp=" + std::to_string(s.spp) + ", light_samples=" + std::to_string(s.lightSamples) +
                    ", max_depth=" + std::to_string(s.maxDepth) + ", seed=" + std::to_string(s.seed) +
                    ", threads=" + std::to_string(s.threads) + ", tile_size=" + std::to_string(s.tileSize);
    if (s.crop)
        r += ", crop=(" + std::to_string(s.crop->x0) + ", " + std::to_string(s.crop->y0) + ", " +
             std::to_string(s.crop->x1) + ", " + std::to_string(s.crop->y1) + ")";
    r += ", light_selection='" + std::string(pnb::enumName(s.lightSelection)) + "'";
    r += std::string(", aovs=") + (s.aovs ? "True" : "False");
    r += ", integrator='" + std::string(pnb::enumName(s.integrator)) + "'";
    r += ", direct_light='" + std::string(pnb::enumName(s.directLight)) + "')";
    return r;
}

pnb::Matrix3x4 matrixFrom(const py::handle& obj) {
    auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(obj);
    if (!a || a.ndim() != 2 || a.shape(1) != 4 || (a.shape(0) != 3 && a.shape(0) != 4))
        throw py::type_error("Matrix3x4 needs a 3x4 or 4x4 array-like");
    if (a.shape(0) == 4 && (a.at(3, 0) != 0.f || a.at(3, 1) != 0.f || a.at(3, 2) != 0.f || a.at(3, 3) != 1.f))
        invalid("Matrix3x4: the last row of a 4x4 matrix must be (0, 0, 0, 1)");
    pnb::Matrix3x4 m;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) m.m[r][c] = a.at(r, c);
    return m;
}

}  // namespace

std::string pathString(const py::handle& path) {
    return py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
}

pnb::RenderSettings settingsWith(pnb::RenderSettings s, const py::kwargs& kwargs) {
    for (auto [key, value] : kwargs) {
        const std::string k = key.cast<std::string>();
        if (value.is_none()) continue;  // None: keep the base value
        if (k == "width") s.width = intSetting("width", value);
        else if (k == "height") s.height = intSetting("height", value);
        else if (k == "spp") s.spp = intSetting("spp", value);
        else if (k == "light_samples") s.lightSamples = intSetting("light_samples", value);
        else if (k == "max_depth") s.maxDepth = intSetting("max_depth", value);
        else if (k == "seed") s.seed = seedSetting(value);
        else if (k == "threads") s.threads = intSetting("threads", value);
        else if (k == "tile_size") s.tileSize = intSetting("tile_size", value);
        else if (k == "crop") s.crop = cropFrom(value);
        else if (k == "light_selection") s.lightSelection = selectionFrom(value);
        else if (k == "aovs") s.aovs = value.cast<bool>();
        else if (k == "integrator") s.integrator = integratorFrom(value);
        else if (k == "direct_light") s.directLight = directLightFrom(value);
        else throw py::type_error("unexpected keyword argument '" + k + "'");
    }
    return s;
}

void bindValues(py::module_& m) {
    py::enum_<pnb::LogLevel>(m, "LogLevel")
        .value("Debug", pnb::LogLevel::Debug)
        .value("Info", pnb::LogLevel::Info)
        .value("Warning", pnb::LogLevel::Warning)
        .value("Error", pnb::LogLevel::Error);
    py::enum_<pnb::PhongModel>(m, "PhongModel", "Normalized: f = kd/pi + ks (n+2)/(2 pi) cos^n; Classic: the lecture's "
                                                "empirical model.")
        .value("Normalized", pnb::PhongModel::Normalized)
        .value("Classic", pnb::PhongModel::Classic);
    py::enum_<pnb::MaterialKind>(m, "MaterialKind", "Phong: the Phong terms; MetalRoughness: glTF 2.0's metal-roughness BSDF")
        .value("Phong", pnb::MaterialKind::Phong)
        .value("MetalRoughness", pnb::MaterialKind::MetalRoughness);
    py::enum_<pnb::LightSelection>(m, "LightSelection")
        .value("All", pnb::LightSelection::All)
        .value("Power", pnb::LightSelection::Power)
        .value("Tree", pnb::LightSelection::Tree)
        .value("Auto", pnb::LightSelection::Auto);
    py::enum_<pnb::IntegratorKind>(m, "IntegratorKind")
        .value("Whitted", pnb::IntegratorKind::Whitted)
        .value("Path", pnb::IntegratorKind::Path);
    py::enum_<pnb::DirectLightSampling>(m, "DirectLightSampling",
                                        "Mis: light + BRDF samples (default); Light: light samples only")
        .value("Mis", pnb::DirectLightSampling::Mis)
        .value("Light", pnb::DirectLightSampling::Light);
    py::enum_<pnb::AcceleratorKind>(m, "AcceleratorKind")
        .value("Embree", pnb::AcceleratorKind::Embree)
        .value("Naive", pnb::AcceleratorKind::Naive);
    py::enum_<pnb::BuildQuality>(m, "BuildQuality")
        .value("Low", pnb::BuildQuality::Low)
        .value("Medium", pnb::BuildQuality::Medium)
        .value("High", pnb::BuildQuality::High);
    py::enum_<pnb::JobStatus>(m, "JobStatus")
        .value("Running", pnb::JobStatus::Running)
        .value("Finished", pnb::JobStatus::Finished)
        .value("Cancelled", pnb::JobStatus::Cancelled)
        .value("Failed", pnb::JobStatus::Failed);

    const pnb::Material dm;
    // A texture slot as its image path (the slot's other settings keep their defaults).
    const auto slotPath = [](pnb::TextureSlot pnb::Material::*slot) {
        return py::cpp_function([slot](const pnb::Material& mat) { return (mat.*slot).path; });
    };
    const auto setSlotPath = [](pnb::TextureSlot pnb::Material::*slot) {
        return py::cpp_function([slot](pnb::Material& mat, std::string path) { (mat.*slot).path = std::move(path); });
    };
    py::class_<pnb::Material>(m, "Material",
                              "A material: Phong, or metal-roughness (kind); colours are linear RGB triples (or one number: gray).")
        .def(py::init([](const pnb::Color& kd, const pnb::Color& ks, float exponent, const pnb::Color& kr,
                         const pnb::Color& ke, const pnb::Color& ka, bool twoSidedEmission, pnb::PhongModel model,
                         std::string diffuseTexture, std::string name, const pnb::Color& kt, float ior,
                         pnb::MaterialKind kind, const pnb::Color& baseColor, float metallic, float roughness,
                         float transmission, std::string baseColorTexture, std::string metallicRoughnessTexture,
                         std::string normalTexture, float normalScale, std::string emissiveTexture) {
                 pnb::Material mat;
                 mat.kind = kind;
                 mat.baseColor = baseColor;
                 mat.metallic = metallic;
                 mat.roughness = roughness;
                 mat.transmission = transmission;
                 mat.baseColorTexture.path = std::move(baseColorTexture);
                 if (!metallicRoughnessTexture.empty()) {
                     // glTF's layout: B metallic, G roughness.
                     mat.metallicTexture.path = mat.roughnessTexture.path = std::move(metallicRoughnessTexture);
                     mat.metallicTexture.channel = 2;
                     mat.roughnessTexture.channel = 1;
                 }
                 mat.normalTexture.path = std::move(normalTexture);
                 mat.normalScale = normalScale;
                 mat.emissiveTexture.path = std::move(emissiveTexture);
                 mat.kd = kd;
                 mat.ks = ks;
                 mat.exponent = exponent;
                 mat.kr = kr;
                 mat.ke = ke;
                 mat.ka = ka;
                 mat.twoSidedEmission = twoSidedEmission;
                 mat.model = model;
                 mat.diffuseTexture = std::move(diffuseTexture);
                 mat.name = std::move(name);
                 mat.kt = kt;
                 mat.ior = ior;
                 return mat;
             }),
             py::kw_only(), py::arg("kd") = dm.kd, py::arg("ks") = dm.ks, py::arg("exponent") = dm.exponent,
             py::arg("kr") = dm.kr, py::arg("ke") = dm.ke, py::arg("ka") = dm.ka,
             py::arg("two_sided_emission") = dm.twoSidedEmission, py::arg("model") = dm.model,
             py::arg("diffuse_texture") = dm.diffuseTexture, py::arg("name") = dm.name, py::arg("kt") = dm.kt,
             py::arg("ior") = dm.ior, py::arg("kind") = dm.kind, py::arg("base_color") = dm.baseColor,
             py::arg("metallic") = dm.metallic, py::arg("roughness") = dm.roughness,
             py::arg("transmission") = dm.transmission, py::arg("base_color_texture") = std::string(),
             py::arg("metallic_roughness_texture") = std::string(), py::arg("normal_texture") = std::string(),
             py::arg("normal_scale") = dm.normalScale, py::arg("emissive_texture") = std::string())
        .def_readwrite("name", &pnb::Material::name)
        .def_readwrite("ka", &pnb::Material::ka, "ambient reflectance (times the scene's ambient light)")
        .def_readwrite("kd", &pnb::Material::kd, "diffuse albedo")
        .def_readwrite("ks", &pnb::Material::ks, "specular (Phong lobe) reflectance")
        .def_readwrite("exponent", &pnb::Material::exponent, "Phong exponent n")
        .def_readwrite("kr", &pnb::Material::kr, "mirror reflectance")
        .def_readwrite("ke", &pnb::Material::ke, "emitted radiance: makes the surface an area light")
        .def_readwrite("two_sided_emission", &pnb::Material::twoSidedEmission)
        .def_readwrite("model", &pnb::Material::model)
        .def_readwrite("diffuse_texture", &pnb::Material::diffuseTexture, "image multiplying kd through mesh UVs")
        .def_readwrite("kt", &pnb::Material::kt, "transmission colour: non-zero makes the surface glass")
        .def_readwrite("ior", &pnb::Material::ior, "index of refraction behind the front side (glass)")
        .def_readwrite("kind", &pnb::Material::kind, "the reflection model: Phong or MetalRoughness")
        .def_readwrite("base_color", &pnb::Material::baseColor, "metal-roughness: base colour")
        .def_readwrite("metallic", &pnb::Material::metallic, "metal-roughness: metalness in [0, 1]")
        .def_readwrite("roughness", &pnb::Material::roughness, "metal-roughness: perceptual roughness in [0, 1]")
        .def_readwrite("transmission", &pnb::Material::transmission, "metal-roughness: refracted share in [0, 1]")
        .def_readwrite("normal_scale", &pnb::Material::normalScale, "scales the normal map's X and Y")
        .def_property("base_color_texture", slotPath(&pnb::Material::baseColorTexture),
                      setSlotPath(&pnb::Material::baseColorTexture), "sRGB image multiplying base_color")
        .def_property("normal_texture", slotPath(&pnb::Material::normalTexture),
                      setSlotPath(&pnb::Material::normalTexture), "tangent-space normal map")
        .def_property("emissive_texture", slotPath(&pnb::Material::emissiveTexture),
                      setSlotPath(&pnb::Material::emissiveTexture), "sRGB image multiplying ke")
        .def("__repr__", [](const pnb::Material& mat) {
            return "Material(name=" + std::string(py::repr(py::str(mat.name))) +
                   ", kd=" + std::string(py::repr(py::cast(mat.kd))) + ", ks=" + std::string(py::repr(py::cast(mat.ks))) +
                   ", exponent=" + std::string(py::repr(py::cast(mat.exponent))) +
                   ", kr=" + std::string(py::repr(py::cast(mat.kr))) + ", ke=" + std::string(py::repr(py::cast(mat.ke))) +
                   ", kt=" + std::string(py::repr(py::cast(mat.kt))) + ", ior=" + std::string(py::repr(py::cast(mat.ior))) +
                   ")";
        });

    const pnb::Camera dc;
    py::class_<pnb::Camera>(m, "Camera", "Pinhole or thin-lens camera; `up` maps to the top of the image.")
        .def(py::init([](const pnb::Vec3& eye, const pnb::Vec3& lookAt, const pnb::Vec3& up, float vfov,
                         float aperture, float focusDistance) {
                 return pnb::Camera{eye, lookAt, up, vfov, aperture, focusDistance};
             }),
             py::kw_only(), py::arg("eye") = dc.eye, py::arg("look_at") = dc.lookAt, py::arg("up") = dc.up,
             py::arg("vfov_degrees") = dc.vfovDegrees, py::arg("aperture") = dc.aperture,
             py::arg("focus_distance") = dc.focusDistance)
        .def_readwrite("eye", &pnb::Camera::eye)
        .def_readwrite("look_at", &pnb::Camera::lookAt)
        .def_readwrite("up", &pnb::Camera::up)
        .def_readwrite("vfov_degrees", &pnb::Camera::vfovDegrees)
        .def_readwrite("aperture", &pnb::Camera::aperture, "lens radius; 0 = pinhole")
        .def_readwrite("focus_distance", &pnb::Camera::focusDistance, "0 = distance from eye to look_at")
        .def("validate", [](const pnb::Camera& c) { pnb::validate(c); }, "Raises penumbra.Error for a bad camera.")
        .def("__repr__", [](const pnb::Camera& c) {
            return "Camera(eye=" + std::string(py::repr(py::cast(c.eye))) +
                   ", look_at=" + std::string(py::repr(py::cast(c.lookAt))) +
                   ", up=" + std::string(py::repr(py::cast(c.up))) + ", vfov_degrees=" + std::to_string(c.vfovDegrees) +
                   ", aperture=" + std::to_string(c.aperture) + ", focus_distance=" + std::to_string(c.focusDistance) +
                   ")";
        });

    py::class_<pnb::RenderSettings>(m, "RenderSettings",
                                    "What to render. RenderSettings(width=..., spp=..., ...) takes the same keywords "
                                    "as Renderer.render.")
        .def(py::init([](const py::kwargs& kw) { return settingsWith(pnb::RenderSettings{}, kw); }))
        .def_readwrite("width", &pnb::RenderSettings::width)
        .def_readwrite("height", &pnb::RenderSettings::height)
        .def_readwrite("spp", &pnb::RenderSettings::spp, "camera samples per pixel")
        .def_readwrite("light_samples", &pnb::RenderSettings::lightSamples, "area-light samples per light")
        .def_readwrite("max_depth", &pnb::RenderSettings::maxDepth, "whitted: mirror/refraction bounces; path: path length")
        .def_readwrite("seed", &pnb::RenderSettings::seed)
        .def_readwrite("threads", &pnb::RenderSettings::threads, "0 = all cores")
        .def_readwrite("tile_size", &pnb::RenderSettings::tileSize)
        .def_property(
            "crop", [](const pnb::RenderSettings& s) { return cropTuple(s.crop); },
            [](pnb::RenderSettings& s, const py::object& v) { s.crop = cropFrom(v); },
            "(x0, y0, x1, y1) pixel window of the full frame, or None")
        .def_property(
            "light_selection", [](const pnb::RenderSettings& s) { return s.lightSelection; },
            [](pnb::RenderSettings& s, const py::object& v) { s.lightSelection = selectionFrom(v); })
        .def_readwrite("aovs", &pnb::RenderSettings::aovs, "also accumulate albedo, normal and depth")
        .def_property(
            "integrator", [](const pnb::RenderSettings& s) { return s.integrator; },
            [](pnb::RenderSettings& s, const py::object& v) { s.integrator = integratorFrom(v); },
            "'whitted' (default) or 'path'")
        .def_property(
            "direct_light", [](const pnb::RenderSettings& s) { return s.directLight; },
            [](pnb::RenderSettings& s, const py::object& v) { s.directLight = directLightFrom(v); },
            "'mis', 'light' or 'area' (or the enum): the area-light estimator")
        .def("replace", [](const pnb::RenderSettings& s, const py::kwargs& kw) { return settingsWith(s, kw); },
             "A copy with the given settings changed.")
        .def("validate", [](const pnb::RenderSettings& s) { pnb::validate(s); },
             "Raises penumbra.Error naming a bad setting.")
        .def("__repr__", &settingsRepr);

    py::class_<pnb::Matrix3x4>(m, "Matrix3x4",
                               "Affine map p' = M (p, 1) as a row-major 3x4 matrix; a @ b applies b first.")
        .def(py::init<>())
        .def(py::init(&matrixFrom), py::arg("m"), "From a 3x4 (or 4x4 affine) array-like.")
        .def_static("translate", &pnb::Matrix3x4::translate, py::arg("t"))
        .def_static(
            "scale",
            [](const py::object& s) {
                if (py::isinstance<py::float_>(s) || py::isinstance<py::int_>(s)) {
                    const float v = s.cast<float>();
                    return pnb::Matrix3x4::scale({v, v, v});
                }
                return pnb::Matrix3x4::scale(s.cast<pnb::Vec3>());
            },
            py::arg("s"))
        .def_static("rotate", &pnb::Matrix3x4::rotate, py::arg("degrees"), py::arg("axis"))
        .def("__matmul__", &pnb::Matrix3x4::operator*)
        .def_property_readonly("m",
                               [](const pnb::Matrix3x4& mat) {
                                   py::array_t<float> a({3, 4});
                                   for (int r = 0; r < 3; ++r)
                                       for (int c = 0; c < 4; ++c) a.mutable_at(r, c) = mat.m[r][c];
                                   return a;
                               })
        .def("__array__", [](const py::object& self, const py::args&) { return self.attr("m"); })
        .def("__repr__", [](const py::object& self) { return "Matrix3x4(" + std::string(py::repr(self.attr("m").attr("tolist")())) + ")"; });

    py::class_<pnb::RenderStats>(m, "RenderStats", "Counts and timings of one render call (or all passes of a job).")
        .def_readonly("camera_rays", &pnb::RenderStats::cameraRays)
        .def_readonly("shadow_rays", &pnb::RenderStats::shadowRays)
        .def_readonly("reflection_rays", &pnb::RenderStats::reflectionRays)
        .def_readonly("invalid_rays", &pnb::RenderStats::invalidRays)
        .def_readonly("non_finite_samples", &pnb::RenderStats::nonFiniteSamples)
        .def_readonly("render_seconds", &pnb::RenderStats::renderSeconds)
        .def_readonly("mrays_per_second", &pnb::RenderStats::mraysPerSecond)
        .def_readonly("samples_per_pixel", &pnb::RenderStats::samplesPerPixel)
        .def_readonly("threads", &pnb::RenderStats::threads)
        .def_readonly("transmission_rays", &pnb::RenderStats::transmissionRays)
        .def_readonly("brdf_rays", &pnb::RenderStats::brdfRays)
        .def_readonly("pixels_hit", &pnb::RenderStats::pixelsHit)
        .def_readonly("indirect_rays", &pnb::RenderStats::indirectRays)
        .def_readonly("path_length_sum", &pnb::RenderStats::pathLengthSum,
                      "rays along each camera sample's path, summed (mean = path_length_sum / camera_rays)")
        .def_readonly("path_length_max", &pnb::RenderStats::pathLengthMax)
        .def("__repr__", [](const pnb::RenderStats& s) {
            return "RenderStats(camera_rays=" + std::to_string(s.cameraRays) +
                   ", shadow_rays=" + std::to_string(s.shadowRays) +
                   ", reflection_rays=" + std::to_string(s.reflectionRays) +
                   ", render_seconds=" + std::to_string(s.renderSeconds) +
                   ", samples_per_pixel=" + std::to_string(s.samplesPerPixel) + ", threads=" + std::to_string(s.threads) +
                   ")";
        });
}

}  // namespace pnbpy
