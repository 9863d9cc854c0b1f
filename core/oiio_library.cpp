#include "core/oiio_library.h"

#include <dlfcn.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"

namespace penumbra {
namespace fs = std::filesystem;
namespace {

constexpr const char* kModuleName = "libpenumbra_oiio.so";

struct Loaded {
    const oiio::Api* api = nullptr;
    std::string error;
};

// Candidates in order: beside the object holding this code (libpenumbra.so in
// the build tree and after install), then ../lib and ../<libdir> from it (an
// executable in bin/ that links the module objects), then the linker's path.
std::vector<std::string> candidates() {
    std::vector<std::string> out;
    Dl_info info{};
    if (::dladdr(reinterpret_cast<const void*>(&oiioLibrary), &info) != 0 && info.dli_fname) {
        std::error_code ec;
        fs::path self = fs::canonical(fs::path(info.dli_fname), ec);
        if (ec) self = fs::path(info.dli_fname);
        const fs::path dir = self.parent_path();
        out.push_back((dir / kModuleName).string());
        out.push_back((dir.parent_path() / "lib" / kModuleName).string());
#ifdef PENUMBRA_INSTALL_LIBDIR
        out.push_back((dir.parent_path() / PENUMBRA_INSTALL_LIBDIR / kModuleName).string());
#endif
    }
    out.emplace_back(kModuleName);
    return out;
}

Loaded load() {
    Loaded result;
    std::string tried;
    for (const std::string& name : candidates()) {
        if (name.find('/') != std::string::npos) {
            std::error_code ec;
            if (!fs::exists(name, ec)) continue;
        }
        if (!tried.empty()) tried += ", ";
        tried += name;
        // Never closed: OpenImageIO registers exit handlers and threads, so it stays for the process.
        void* handle = ::dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* e = ::dlerror();
            tried += std::string(" (") + (e ? e : "dlopen failed") + ")";
            continue;
        }
        auto entry = reinterpret_cast<const oiio::Api* (*)()>(::dlsym(handle, oiio::kEntryPoint));
        const oiio::Api* api = entry ? entry() : nullptr;
        if (!api || api->version != oiio::kApiVersion || !api->encode || !api->decode) {
            tried += " (not the image module of this Penumbra build)";
            continue;
        }
        result.api = api;
        return result;
    }
    result.error = std::string("cannot load the image module ") + kModuleName +
                   (tried.empty() ? std::string(": not found") : ": tried " + tried);
    return result;
}

}  // namespace

const oiio::Api& oiioLibrary() {
    // The one process-wide value in the library: which module was loaded.
    // It is immutable once set, like the dynamic linker's own state.
    static const Loaded loaded = load();
    if (!loaded.api) throw Error(ErrorCode::IoError, loaded.error);
    return *loaded.api;
}

}  // namespace penumbra
