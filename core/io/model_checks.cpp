#include "core/io/model_checks.h"

#include "core/io/fbx_checks.h"
#include "core/io/nesting_checks.h"
#include "core/io/off_checks.h"
#include "core/io/ply_checks.h"
#include "core/io/stl_checks.h"
#include "core/io/xml_checks.h"

namespace penumbra {

std::optional<std::string> modelFileProblem(const std::string& format, const std::string& bytes) {
    if (format == "ply") return plyHeaderProblem(bytes);
    if (format == "stl") return stlTextProblem(bytes);
    if (format == "off") return offHeaderProblem(bytes);
    if (format == "fbx") return fbxProblem(bytes);
    if (format == "x") return xFileNestingProblem(bytes);
    if (format == "ac" || format == "acc" || format == "ac3d") return ac3dNestingProblem(bytes);
    if (format == "dae") return xmlModelProblem(bytes, true);
    if (format == "xml" || format == "amf" || format == "xgl" || format == "x3d" || format == "irr" || format == "irrmesh")
        return xmlModelProblem(bytes, false);
    return std::nullopt;
}

}  // namespace penumbra
