#include "core/dependency_order.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <link.h>
#include <unistd.h>

#include <bit>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <set>

namespace penumbra {
namespace fs = std::filesystem;
namespace {

using Ehdr = ElfW(Ehdr);
using Phdr = ElfW(Phdr);
using Dyn = ElfW(Dyn);

class File {
public:
    explicit File(const std::string& path) : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC)) {}
    ~File() {
        if (fd_ >= 0) ::close(fd_);
    }
    File(const File&) = delete;
    File& operator=(const File&) = delete;
    bool ok() const { return fd_ >= 0; }
    // Exactly n bytes at offset, or false.
    bool read(uint64_t offset, void* out, size_t n) const {
        auto* p = static_cast<char*>(out);
        while (n > 0) {
            const ssize_t got = ::pread(fd_, p, n, off_t(offset));
            if (got <= 0) return false;
            p += got;
            n -= size_t(got);
            offset += uint64_t(got);
        }
        return true;
    }

private:
    int fd_;
};

constexpr unsigned char kClass = sizeof(void*) == 8 ? ELFCLASS64 : ELFCLASS32;
constexpr unsigned char kData = std::endian::native == std::endian::little ? ELFDATA2LSB : ELFDATA2MSB;

// The folders a needed name is looked for in: LD_LIBRARY_PATH's, then the
// C library's folder and its twin under / or /usr (Debian's multiarch folders).
std::vector<fs::path> searchFolders() {
    std::vector<fs::path> out;
    if (const char* env = std::getenv("LD_LIBRARY_PATH")) {
        std::string list = env;
        for (size_t start = 0; start <= list.size();) {
            const size_t end = std::min(list.find(':', start), list.size());
            if (end > start) out.emplace_back(list.substr(start, end - start));
            start = end + 1;
        }
    }
    Dl_info info{};
    if (::dladdr(reinterpret_cast<const void*>(&::getpid), &info) != 0 && info.dli_fname) {
        const std::string dir = fs::path(info.dli_fname).parent_path().string();
        out.emplace_back(dir);
        if (dir.rfind("/usr/", 0) == 0)
            out.emplace_back(dir.substr(4));
        else if (dir.rfind("/", 0) == 0)
            out.emplace_back("/usr" + dir);
    }
    return out;
}

struct Walk {
    std::vector<fs::path> folders;
    std::set<std::string> visited;
    std::vector<std::string> order;
    bool ownSearchPath = false;

    std::optional<fs::path> find(const std::string& name) const {
        for (const fs::path& dir : folders) {
            std::error_code ec;
            const fs::path p = dir / name;
            if (fs::is_regular_file(p, ec)) return p;
        }
        return std::nullopt;
    }

    // Appends what the object at path needs (not yet visited), deepest first.
    void visit(const fs::path& path, int depth) {
        if (depth > 64 || ownSearchPath) return;  // no real chain is that deep
        const std::optional<ElfDependencies> deps = readElfDependencies(path.string());
        if (!deps) return;
        if (deps->ownSearchPath) {
            ownSearchPath = true;
            return;
        }
        for (const std::string& name : deps->needed) {
            if (!visited.insert(name).second) continue;
            if (const std::optional<fs::path> p = find(name)) visit(*p, depth + 1);
            order.push_back(name);
        }
    }
};

}  // namespace

std::optional<ElfDependencies> readElfDependencies(const std::string& path) {
    const File f(path);
    if (!f.ok()) return std::nullopt;
    Ehdr eh{};
    if (!f.read(0, &eh, sizeof eh) || std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 || eh.e_ident[EI_CLASS] != kClass ||
        eh.e_ident[EI_DATA] != kData || eh.e_phentsize != sizeof(Phdr) || eh.e_phnum == 0 || eh.e_phnum > 512)
        return std::nullopt;
    std::vector<Phdr> ph(eh.e_phnum);
    if (!f.read(eh.e_phoff, ph.data(), ph.size() * sizeof(Phdr))) return std::nullopt;
    const Phdr* dynamic = nullptr;
    for (const Phdr& p : ph)
        if (p.p_type == PT_DYNAMIC) dynamic = &p;
    if (!dynamic || dynamic->p_filesz > (1u << 20)) return std::nullopt;
    std::vector<Dyn> dyn(dynamic->p_filesz / sizeof(Dyn));
    if (!f.read(dynamic->p_offset, dyn.data(), dyn.size() * sizeof(Dyn))) return std::nullopt;
    uint64_t strtab = 0, strsz = 0;
    std::vector<uint64_t> needed;
    ElfDependencies out;
    for (const Dyn& d : dyn) {
        if (d.d_tag == DT_NULL) break;
        if (d.d_tag == DT_STRTAB) strtab = d.d_un.d_ptr;
        if (d.d_tag == DT_STRSZ) strsz = d.d_un.d_val;
        if (d.d_tag == DT_NEEDED) needed.push_back(d.d_un.d_val);
        if (d.d_tag == DT_RPATH || d.d_tag == DT_RUNPATH) out.ownSearchPath = true;
    }
    // The string table's address in memory, as a place in the file.
    std::optional<uint64_t> strOffset;
    for (const Phdr& p : ph)
        if (p.p_type == PT_LOAD && strtab >= p.p_vaddr && strtab - p.p_vaddr < p.p_filesz)
            strOffset = p.p_offset + (strtab - p.p_vaddr);
    if (!needed.empty() && !strOffset) return std::nullopt;
    for (const uint64_t at : needed) {
        if (at >= strsz) return std::nullopt;
        char name[256];  // longer names are no library's
        const size_t n = size_t(std::min<uint64_t>(sizeof name, strsz - at));
        if (!f.read(*strOffset + at, name, n)) return std::nullopt;
        const void* end = std::memchr(name, '\0', n);
        if (!end) return std::nullopt;
        out.needed.emplace_back(name, size_t(static_cast<const char*>(end) - name));
    }
    return out;
}

std::vector<std::string> dependenciesDeepestFirst(const std::string& path) {
    Walk walk;
    walk.folders = searchFolders();
    walk.visit(path, 0);
    if (walk.ownSearchPath) return {};
    return walk.order;
}

}  // namespace penumbra
