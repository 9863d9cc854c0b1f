// The order in which to load a shared library's dependencies so that the
// dynamic loader's symbol lookups stay short.
//
// One dlopen of the image module loads OpenImageIO's ~260 libraries and binds
// ~155 000 symbols, each found by searching the loaded libraries in
// breadth-first order from the module. A library deep in that order that
// binds many of its own symbols pays a search across all the libraries ahead
// of it for each: OpenVDB alone binds 57 000 of its own. Loaded one by one
// beforehand, deepest first, each library is the first of its own search
// order and its dependencies come right after it: the module's load took
// 0.09 s instead of 0.16 s of CPU on the development machine, and its
// helper process competes that much less with the render.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace penumbra {

/// What the dynamic section of an ELF shared object (of this process's ELF
/// class) names: its needed libraries, in order, and whether it carries its
/// own search path (DT_RPATH or DT_RUNPATH). nullopt where the file is not
/// such an object or cannot be read.
struct ElfDependencies {
    std::vector<std::string> needed;
    bool ownSearchPath = false;
};
std::optional<ElfDependencies> readElfDependencies(const std::string& path);

/// The names of the libraries the shared object at `path` needs, directly or
/// not, each after every library it needs (deepest first), without the
/// object itself. Files are looked for in LD_LIBRARY_PATH and then in the
/// system library folders (that of the C library, under / and /usr); a name
/// found in none is left out with what it alone needs. Empty where `path`
/// cannot be read or any of the files carries its own search path: a name
/// loaded by itself could then resolve to another file than the object's
/// own load would take.
std::vector<std::string> dependenciesDeepestFirst(const std::string& path);

}  // namespace penumbra
