// The compiled part of the `penumbra` Python package (penumbra._penumbra).
// It binds only the public C++ API, <penumbra/penumbra.hpp>.
#include "bindings.h"

PYBIND11_MODULE(_penumbra, m) {
    m.doc() = "Penumbra's C++ API (namespace pnb) for Python; import it as `penumbra`.";
    m.def("version", &pnb::version, "Version of the library actually loaded.");
    pnbpy::bindErrors(m);
    pnbpy::bindValues(m);
    pnbpy::bindScene(m);
    pnbpy::bindFramebuffer(m);
    pnbpy::bindRenderer(m);
}
