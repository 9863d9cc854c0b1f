// Scene (built in code or loaded) and PreparedScene. Meshes come in as numpy
// arrays (or anything the buffer protocol or numpy converts), copied by the
// library in one call: no per-element Python work.
#include "bindings.h"

#include <cstdint>
#include <limits>

namespace pnbpy {

namespace {

[[noreturn]] void invalid(const std::string& message) { throw pnb::Error(pnb::ErrorCode::InvalidArgument, message); }

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<std::uint32_t, py::array::c_style | py::array::forcecast>;

// Rows of `cols` values: an (n, cols) array or a flat one of n * cols values.
std::size_t rowsOf(const py::array& a, py::ssize_t cols, const char* what) {
    if (a.ndim() == 2 && a.shape(1) == cols) return std::size_t(a.shape(0));
    if (a.ndim() == 1 && a.shape(0) % cols == 0) return std::size_t(a.shape(0) / cols);
    std::string shape;
    for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
    invalid(std::string(what) + " must have shape (n, " + std::to_string(cols) + ") or (n*" +
            std::to_string(cols) + ",), got (" + shape + ")");
}

FloatArray floatsFrom(const py::object& obj, const char* what) {
    FloatArray a = FloatArray::ensure(obj);
    if (!a) {
        PyErr_Clear();
        throw py::type_error(std::string(what) + " must be an array of numbers");
    }
    return a;
}

// Integer arrays only: a silent cast would turn 1.5 into 1 and -1 into 4294967295.
IndexArray indicesFrom(const py::object& obj, const char* what) {
    py::array raw = py::array::ensure(obj);
    if (!raw) {
        PyErr_Clear();
        throw py::type_error(std::string(what) + " must be an array of integers");
    }
    const char kind = raw.dtype().kind();
    if (raw.size() > 0 && kind != 'i' && kind != 'u')
        throw py::type_error(std::string(what) + " must be an array of integers, got dtype " +
                             std::string(py::str(raw.dtype())));
    if (raw.size() > 0 && (kind == 'i' || raw.dtype().itemsize() > 4)) {
        using Wide = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;
        const Wide wide = kind == 'u' ? Wide() : Wide::ensure(raw);
        if (kind == 'i') {
            const std::int64_t* p = wide.data();
            for (py::ssize_t i = 0, n = wide.size(); i < n; ++i)
                if (p[i] < 0 || p[i] > std::int64_t(std::numeric_limits<std::uint32_t>::max()))
                    invalid(std::string(what) + "[" + std::to_string(i) + "] = " + std::to_string(p[i]) +
                            " is not a valid index");
        } else {
            const auto u = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>::ensure(raw);
            const std::uint64_t* p = u.data();
            for (py::ssize_t i = 0, n = u.size(); i < n; ++i)
                if (p[i] > std::numeric_limits<std::uint32_t>::max())
                    invalid(std::string(what) + "[" + std::to_string(i) + "] = " + std::to_string(p[i]) +
                            " is not a valid index");
        }
    }
    return IndexArray::ensure(raw);
}

// Checks the arrays, fills a MeshDesc pointing into them and hands it to `add`
// (the arrays must outlive the call).
template <class Add>
void withMeshDesc(const py::object& positions, const py::object& indices, pnb::MaterialId material,
                  const py::object& normals, const py::object& uvs, const py::object& faceMaterials,
                  const std::string& name, const std::string& fn, Add add) {
    // Error messages name the Python method and the argument.
    const std::string P = fn + ": positions", I = fn + ": indices", N = fn + ": normals", U = fn + ": uvs",
                      F = fn + ": face_materials";
    const FloatArray pos = floatsFrom(positions, P.c_str());
    const IndexArray idx = indicesFrom(indices, I.c_str());
    pnb::MeshDesc d;
    d.name = name;
    d.vertexCount = rowsOf(pos, 3, P.c_str());
    d.positions = pos.data();
    d.triangleCount = rowsOf(idx, 3, I.c_str());
    d.indices = idx.data();
    d.material = material;
    FloatArray nrm, uv;
    IndexArray fm;
    if (!normals.is_none()) {
        nrm = floatsFrom(normals, N.c_str());
        if (rowsOf(nrm, 3, N.c_str()) != d.vertexCount)
            invalid(N + " has " + std::to_string(rowsOf(nrm, 3, N.c_str())) + " rows, positions " +
                    std::to_string(d.vertexCount));
        d.normals = nrm.data();
    }
    if (!uvs.is_none()) {
        uv = floatsFrom(uvs, U.c_str());
        if (rowsOf(uv, 2, U.c_str()) != d.vertexCount)
            invalid(U + " has " + std::to_string(rowsOf(uv, 2, U.c_str())) + " rows, positions " +
                    std::to_string(d.vertexCount));
        d.uvs = uv.data();
    }
    if (!faceMaterials.is_none()) {
        fm = indicesFrom(faceMaterials, F.c_str());
        if (std::size_t(fm.size()) != d.triangleCount)
            invalid(F + " has " + std::to_string(fm.size()) + " entries for " +
                    std::to_string(d.triangleCount) + " triangles");
        d.faceMaterials = fm.data();
    }
    add(d);
}

void addMesh(pnb::Scene& scene, const py::object& positions, const py::object& indices, pnb::MaterialId material,
             const py::object& normals, const py::object& uvs, const py::object& faceMaterials,
             const std::string& name) {
    withMeshDesc(positions, indices, material, normals, uvs, faceMaterials, name, "add_mesh",
                 [&](const pnb::MeshDesc& d) { scene.addMesh(d); });
}

void addPrototypeMesh(pnb::Scene& scene, pnb::PrototypeId prototype, const py::object& positions,
                      const py::object& indices, pnb::MaterialId material, const py::object& normals,
                      const py::object& uvs, const py::object& faceMaterials, const std::string& name) {
    withMeshDesc(positions, indices, material, normals, uvs, faceMaterials, name, "add_prototype_mesh",
                 [&](const pnb::MeshDesc& d) { scene.addPrototypeMesh(prototype, d); });
}

py::object optionalCamera(const std::optional<pnb::Camera>& c) { return c ? py::cast(*c) : py::none(); }

}  // namespace

void bindScene(py::module_& m) {
    py::class_<pnb::Scene>(m, "Scene",
                           "A scene description: materials, shapes, meshes, lights, ambient and background light, "
                           "and optionally a camera and settings from a file. A plain value (copy.copy works).")
        .def(py::init<>())
        .def("__copy__", [](const pnb::Scene& s) { return pnb::Scene(s); })
        .def("__deepcopy__", [](const pnb::Scene& s, const py::object&) { return pnb::Scene(s); })
        .def(
            "add_material",
            [](pnb::Scene& s, const py::object& material, const py::kwargs& kw) {
                if (material.is_none()) return s.addMaterial(py::type::of<pnb::Material>()(**kw).cast<pnb::Material>());
                if (kw.size() > 0) throw py::type_error("add_material: pass a Material or keywords, not both");
                return s.addMaterial(material.cast<pnb::Material>());
            },
            py::arg("material") = py::none(),
            "Adds a Material (or Material(**keywords)) and returns its id. Before any material is added, id 0 "
            "names a default grey material.")
        .def("add_sphere", &pnb::Scene::addSphere, py::arg("center"), py::arg("radius"), py::arg("material") = 0)
        .def("add_plane", &pnb::Scene::addPlane, py::arg("point"), py::arg("normal"), py::arg("material") = 0,
             py::arg("two_sided") = true)
        .def(
            "add_box",
            [](pnb::Scene& s, const pnb::Vec3& lo, const pnb::Vec3& hi, pnb::MaterialId material,
               const std::optional<pnb::Matrix3x4>& transform) {
                if (transform) s.addBox(lo, hi, *transform, material);
                else s.addBox(lo, hi, material);
            },
            py::arg("lo"), py::arg("hi"), py::arg("material") = 0, py::arg("transform") = py::none(),
            "Box [lo, hi], in object space when a world-from-object transform (Matrix3x4) is given.")
        .def("add_rectangle", &pnb::Scene::addRectangle, py::arg("corner"), py::arg("edge_a"), py::arg("edge_b"),
             py::arg("material") = 0, "Parallelogram corner + s*edge_a + t*edge_b; front faces cross(edge_a, edge_b).")
        .def("add_disk", &pnb::Scene::addDisk, py::arg("center"), py::arg("normal"), py::arg("radius"),
             py::arg("material") = 0)
        .def("add_mesh", &addMesh, py::arg("positions"), py::arg("indices"), py::arg("material") = 0, py::kw_only(),
             py::arg("normals") = py::none(), py::arg("uvs") = py::none(), py::arg("face_materials") = py::none(),
             py::arg("name") = "",
             "Copies a triangle mesh: positions (n, 3) floats, indices (m, 3) integers (counter-clockwise = "
             "front); optional per-vertex normals (n, 3) and uvs (n, 2), per-triangle face_materials (m,).")
        .def("add_point_light", &pnb::Scene::addPointLight, py::arg("position"), py::arg("intensity"),
             "Isotropic point light of intensity I (W/sr per channel).")
        .def("add_directional_light", &pnb::Scene::addDirectionalLight, py::arg("direction"), py::arg("irradiance"),
             "Light travelling along `direction` with irradiance E on a surface facing it.")
        .def("set_ambient", &pnb::Scene::setAmbient, py::arg("ambient"))
        .def("set_background", &pnb::Scene::setBackground, py::arg("background"))
        .def("set_environment", &pnb::Scene::setEnvironment, py::arg("radiance"), py::arg("scale") = 1.f,
             "Environment light of constant radiance (times scale): lights the scene, seen by rays that leave it.")
        .def("set_environment_image", &pnb::Scene::setEnvironmentImage, py::arg("path"),
             py::arg("rotate_degrees") = 0.f, py::arg("scale") = 1.f,
             "Environment light from a lat-long image (opened now, decoded by prepare), turned about +y.")
        .def("clear_environment", &pnb::Scene::clearEnvironment)
        .def_property_readonly("has_environment", &pnb::Scene::hasEnvironment)
        .def_property("default_light", &pnb::Scene::defaultLight, &pnb::Scene::setDefaultLight,
                      "True (the default): prepare gives a scene with no light at all a white environment "
                      "of radiance 1 and warns. False: such a scene renders black.")
        .def_property(
            "camera", [](const pnb::Scene& s) { return optionalCamera(s.camera()); },
            [](pnb::Scene& s, const pnb::Camera& c) { s.setCamera(c); },
            "The camera the scene file set (or that was assigned), or None.")
        .def("default_camera", &pnb::Scene::defaultCamera, py::arg("aspect"), py::arg("vfov_degrees") = 40.f,
             "camera if set, else one looking along -z that frames the scene.")
        .def("settings", &pnb::Scene::settings, "Default settings with the scene file's render block applied.")
        .def_property_readonly("material_count", &pnb::Scene::materialCount)
        .def_property_readonly("primitive_count", &pnb::Scene::primitiveCount)
        .def_property_readonly("triangle_count", &pnb::Scene::triangleCount)
        .def("add_prototype", &pnb::Scene::addPrototype, py::arg("name") = "",
             "Adds an empty prototype (a named group of meshes drawn only through instances) and returns its id.")
        .def("add_prototype_mesh", &addPrototypeMesh, py::arg("prototype"), py::arg("positions"), py::arg("indices"),
             py::arg("material") = 0, py::kw_only(), py::arg("normals") = py::none(), py::arg("uvs") = py::none(),
             py::arg("face_materials") = py::none(), py::arg("name") = "",
             "Copies a triangle mesh into a prototype (its object space); the arrays as for add_mesh.")
        .def(
            "add_instance",
            [](pnb::Scene& s, pnb::PrototypeId prototype, const std::optional<pnb::Matrix3x4>& transform,
               std::optional<pnb::MaterialId> material) {
                return s.addInstance(prototype, transform ? *transform : pnb::Matrix3x4{}, material);
            },
            py::arg("prototype"), py::arg("transform") = py::none(), py::arg("material") = py::none(),
            "Places a prototype by a world-from-object transform (Matrix3x4, invertible; None = identity) and "
            "returns the instance's index (0, 1, ... in the order placed; Renderer.update's transforms name it). "
            "material, when given, replaces the material of every face.")
        .def_property_readonly("prototype_count", &pnb::Scene::prototypeCount)
        .def_property_readonly("instance_count", &pnb::Scene::instanceCount)
        .def("__repr__", [](const pnb::Scene& s) {
            return "<penumbra.Scene: " + std::to_string(s.materialCount()) + " materials, " +
                   std::to_string(s.primitiveCount()) + " primitives (" + std::to_string(s.triangleCount()) +
                   " triangles)>";
        });

    py::class_<pnb::PreparedScene>(m, "PreparedScene",
                                   "A validated scene with its BVH and light tables; immutable, safe to render from "
                                   "several threads at once. Made by Renderer.prepare.")
        .def_property_readonly("valid", &pnb::PreparedScene::valid)
        .def_property_readonly("primitive_count", &pnb::PreparedScene::primitiveCount)
        .def_property_readonly("triangle_count", &pnb::PreparedScene::triangleCount)
        .def_property_readonly("light_count", &pnb::PreparedScene::lightCount)
        .def_property_readonly("dropped_triangles", &pnb::PreparedScene::droppedTriangles)
        .def_property_readonly("dropped_shapes", &pnb::PreparedScene::droppedShapes)
        .def_property_readonly("build_seconds", &pnb::PreparedScene::buildSeconds)
        .def_property_readonly("default_light_added", &pnb::PreparedScene::defaultLightAdded,
                               "True when the scene had no light and got the default white environment.")
        .def_property_readonly("camera", [](const pnb::PreparedScene& p) { return optionalCamera(p.camera()); })
        .def("default_camera", &pnb::PreparedScene::defaultCamera, py::arg("aspect"), py::arg("vfov_degrees") = 40.f)
        .def("settings", &pnb::PreparedScene::settings)
        .def("__repr__", [](const pnb::PreparedScene& p) {
            if (!p.valid()) return std::string("<penumbra.PreparedScene: empty>");
            return "<penumbra.PreparedScene: " + std::to_string(p.primitiveCount()) + " primitives (" +
                   std::to_string(p.triangleCount()) + " triangles), " + std::to_string(p.lightCount()) + " lights>";
        });
}

}  // namespace pnbpy
