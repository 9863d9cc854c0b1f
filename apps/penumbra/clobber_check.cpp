#include "clobber_check.h"

#include <sys/stat.h>

#include <optional>
#include <penumbra/penumbra.hpp>
#include <system_error>
#include <utility>

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;

// (st_dev, st_ino) of what `p` names, symlinks followed; empty when it does not exist.
std::optional<std::pair<dev_t, ino_t>> identity(const fs::path& p) {
    struct stat st {};
    if (::stat(p.c_str(), &st) != 0) return std::nullopt;
    return std::pair{st.st_dev, st.st_ino};
}

}  // namespace

void refuseOverwrite(const OutputFile& output, const fs::path& input, const std::string& inputRole) {
    const auto out = identity(output.path), in = identity(input);
    if (out && in && *out == *in)
        throw pnb::Error(pnb::ErrorCode::InvalidArgument,
                         output.option + " " + output.path.string() + ": is " + inputRole + " (" + input.string() +
                             "); refusing to overwrite an input");
}

void refuseSameOutput(const OutputFile& a, const OutputFile& b) {
    const auto ia = identity(a.path), ib = identity(b.path);
    std::error_code ec1, ec2;
    const bool same = (ia && ib) ? *ia == *ib
                                 : fs::weakly_canonical(a.path, ec1) == fs::weakly_canonical(b.path, ec2) && !ec1 && !ec2;
    if (same)
        throw pnb::Error(pnb::ErrorCode::InvalidArgument, b.option + " " + b.path.string() + ": is also the " +
                                                              a.option + " file; each output needs a file of its own");
}

}  // namespace penumbra::cli
