// readElfDependencies and dependenciesDeepestFirst, which order the image
// module's libraries for loading: the names an ELF object needs, and every
// library of a closure after all the ones it needs.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "core/dependency_order.h"

using namespace penumbra;
namespace fs = std::filesystem;

namespace {

// The file of the loaded object that holds `symbol`.
fs::path objectOf(const void* symbol) {
    Dl_info info{};
    if (::dladdr(symbol, &info) == 0 || !info.dli_fname) return {};
    return fs::path(info.dli_fname);
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
}

// The first n bytes of a file, copied to a temporary one.
fs::path truncatedCopy(const fs::path& from, size_t n, const std::string& name) {
    std::ifstream in(from, std::ios::binary);
    std::string bytes(n, '\0');
    in.read(bytes.data(), std::streamsize(n));
    const fs::path to = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
    std::ofstream(to, std::ios::binary).write(bytes.data(), in.gcount());
    return to;
}

}  // namespace

TEST(DependencyOrder, ReadsTheLibrariesAnObjectNeeds) {
    // The C++ runtime needs the C library and the maths library, and has no search path of its own.
    const fs::path cxx = objectOf(reinterpret_cast<const void*>(&std::terminate));
    ASSERT_FALSE(cxx.empty());
    const std::optional<ElfDependencies> d = readElfDependencies(cxx.string());
    ASSERT_TRUE(d.has_value()) << cxx;
    EXPECT_TRUE(contains(d->needed, "libc.so.6")) << cxx;
    EXPECT_TRUE(contains(d->needed, "libm.so.6")) << cxx;
    EXPECT_FALSE(d->ownSearchPath);
}

TEST(DependencyOrder, WhatIsNoWholeElfObjectGivesNothing) {
    const fs::path cxx = objectOf(reinterpret_cast<const void*>(&std::terminate));
    ASSERT_FALSE(cxx.empty());
    const fs::path text = fs::temp_directory_path() / ("not_elf_" + std::to_string(::getpid()));
    std::ofstream(text) << "not an ELF object\n";
    // Cut in its header, in its program headers, before its dynamic section.
    const fs::path cut[] = {truncatedCopy(cxx, 40, "cut_header"), truncatedCopy(cxx, 100, "cut_phdrs"),
                            truncatedCopy(cxx, 4096, "cut_dynamic")};
    EXPECT_FALSE(readElfDependencies(text.string()).has_value());
    EXPECT_FALSE(readElfDependencies("/nonexistent/libnothing.so").has_value());
    for (const fs::path& p : cut) EXPECT_FALSE(readElfDependencies(p.string()).has_value()) << p;
    EXPECT_TRUE(dependenciesDeepestFirst(text.string()).empty());
    fs::remove(text);
    for (const fs::path& p : cut) fs::remove(p);
}

TEST(DependencyOrder, EveryLibraryComesAfterTheLibrariesItNeeds) {
    // The image module's closure (OpenImageIO's ~260 libraries in Debian's
    // packages), or the C++ runtime's where the module is not built.
    fs::path root = fs::path(PENUMBRA_BINARY_DIR) / "lib" / "libpenumbra_oiio.so";
    if (!fs::exists(root)) root = objectOf(reinterpret_cast<const void*>(&std::terminate));
    const std::vector<std::string> order = dependenciesDeepestFirst(root.string());
    ASSERT_FALSE(order.empty()) << root;
    EXPECT_EQ(std::set<std::string>(order.begin(), order.end()).size(), order.size()) << "a library twice";
    const std::optional<ElfDependencies> direct = readElfDependencies(root.string());
    ASSERT_TRUE(direct.has_value());
    for (const std::string& name : direct->needed) EXPECT_TRUE(contains(order, name)) << name;
    // Where the system folder holds a library, what it needs comes before it.
    const fs::path system = objectOf(reinterpret_cast<const void*>(&::getpid)).parent_path();
    int checked = 0;
    for (size_t i = 0; i < order.size(); ++i) {
        const std::optional<ElfDependencies> d = readElfDependencies((system / order[i]).string());
        if (!d) continue;
        ++checked;
        for (const std::string& name : d->needed) {
            const auto at = std::find(order.begin(), order.end(), name);
            EXPECT_TRUE(at != order.end() && size_t(at - order.begin()) < i) << name << " needed by " << order[i];
        }
    }
    EXPECT_GE(checked, 3);
}

TEST(DependencyOrder, NothingWhereAnObjectCarriesItsOwnSearchPath) {
    // The command-line program of the build tree finds libpenumbra.so through its RUNPATH.
    const fs::path cli = fs::path(PENUMBRA_BINARY_DIR) / "bin" / "penumbra";
    const std::optional<ElfDependencies> d = readElfDependencies(cli.string());
    if (!d || !d->ownSearchPath) GTEST_SKIP() << cli << " has no RUNPATH here";
    EXPECT_TRUE(dependenciesDeepestFirst(cli.string()).empty());
}
