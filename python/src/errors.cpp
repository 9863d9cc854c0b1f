// penumbra.Error: a RuntimeError subclass with the library's message and a
// `.code` (penumbra.ErrorCode), raised for every pnb::Error.
#include "bindings.h"

namespace pnbpy {

namespace {

// The exception type lives in the module object (its __dict__), created once
// per interpreter at import; this pointer only caches it for the translator.
PyObject* errorType = nullptr;

}  // namespace

py::object errorObject(const pnb::Error& e) {
    py::object type = py::reinterpret_borrow<py::object>(errorType);
    py::object instance = type(py::str(e.what()));
    instance.attr("code") = py::cast(e.code());
    return instance;
}

void bindErrors(py::module_& m) {
    py::enum_<pnb::ErrorCode>(m, "ErrorCode", "What went wrong (the values of the C API's pnb_status codes).")
        .value("InvalidArgument", pnb::ErrorCode::InvalidArgument)
        .value("FileNotFound", pnb::ErrorCode::FileNotFound)
        .value("ParseError", pnb::ErrorCode::ParseError)
        .value("InvalidScene", pnb::ErrorCode::InvalidScene)
        .value("IoError", pnb::ErrorCode::IoError)
        .value("OutOfMemory", pnb::ErrorCode::OutOfMemory)
        .value("Cancelled", pnb::ErrorCode::Cancelled)
        .value("Embree", pnb::ErrorCode::Embree)
        .value("Internal", pnb::ErrorCode::Internal)
        .def_property_readonly("description", [](pnb::ErrorCode c) { return pnb::errorCodeName(c); });

    py::dict ns;
    ns["__doc__"] = "A failure reported by Penumbra. str(e) is the library's message (naming the file and line "
                    "or JSON path where that applies); e.code is the penumbra.ErrorCode.";
    ns["__module__"] = "penumbra";
    ns["code"] = py::cast(pnb::ErrorCode::Internal);
    py::object type = py::reinterpret_borrow<py::object>(reinterpret_cast<PyObject*>(&PyType_Type))(
        "Error", py::make_tuple(py::reinterpret_borrow<py::object>(PyExc_RuntimeError)), ns);
    m.attr("Error") = type;
    errorType = type.ptr();  // kept alive by the module

    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const pnb::Error& e) {
            py::object instance = errorObject(e);
            PyErr_SetObject(errorType, instance.ptr());
        }
    });
}

}  // namespace pnbpy
