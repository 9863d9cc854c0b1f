#include "core/image_encoder_process.h"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <exception>
#include <type_traits>

#include "core/oiio_library.h"

namespace penumbra {
namespace {

using Bytes = std::vector<unsigned char>;

// Messages are a 64-bit length and that many bytes; values inside are in the
// host's representation (both ends are one build on one machine).
class Writer {
public:
    template <class T>
    void put(T v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const auto* b = reinterpret_cast<const unsigned char*>(&v);
        bytes.insert(bytes.end(), b, b + sizeof(T));
    }
    void putBytes(const void* data, uint64_t n) {
        put(n);
        const auto* b = static_cast<const unsigned char*>(data);
        bytes.insert(bytes.end(), b, b + n);
    }
    void putString(const std::string& s) { putBytes(s.data(), s.size()); }
    Bytes bytes;
};

class Reader {
public:
    explicit Reader(const Bytes& b) : data_(b) {}
    template <class T>
    bool get(T& v) {
        if (data_.size() - at_ < sizeof(T)) return false;
        std::memcpy(&v, data_.data() + at_, sizeof(T));
        at_ += sizeof(T);
        return true;
    }
    // A view of the next n bytes (valid while the message lives).
    bool getBytes(const unsigned char*& p, uint64_t& n) {
        if (!get(n) || data_.size() - at_ < n) return false;
        p = data_.data() + at_;
        at_ += size_t(n);
        return true;
    }
    bool getString(std::string& s) {
        const unsigned char* p = nullptr;
        uint64_t n = 0;
        if (!getBytes(p, n)) return false;
        s.assign(reinterpret_cast<const char*>(p), size_t(n));
        return true;
    }
    bool atEnd() const { return at_ == data_.size(); }

private:
    const Bytes& data_;
    size_t at_ = 0;
};

bool sendAll(int fd, const void* data, size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    while (n > 0) {
        const ssize_t w = ::send(fd, p, n, MSG_NOSIGNAL);  // a closed peer is an error, not SIGPIPE
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= size_t(w);
    }
    return true;
}

bool receiveAll(int fd, void* data, size_t n) {
    auto* p = static_cast<unsigned char*>(data);
    while (n > 0) {
        const ssize_t r = ::recv(fd, p, n, 0);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return false;  // 0: the peer closed its end
        p += r;
        n -= size_t(r);
    }
    return true;
}

bool sendMessage(int fd, const Bytes& m) {
    const uint64_t n = m.size();
    return sendAll(fd, &n, sizeof n) && sendAll(fd, m.data(), m.size());
}

// Messages larger than this are a broken stream, not an image (16 GiB).
constexpr uint64_t kMaxMessage = uint64_t(1) << 34;
// Images of more pixel bytes than this are not sent to the helper (256 MiB: 8K x 8K RGB floats is 768 MiB).
constexpr uint64_t kMaxHelperPixelBytes = uint64_t(256) << 20;

bool receiveMessage(int fd, Bytes& m) {
    uint64_t n = 0;
    if (!receiveAll(fd, &n, sizeof n) || n > kMaxMessage) return false;
    m.resize(size_t(n));
    return receiveAll(fd, m.data(), m.size());
}

uint64_t pixelBytes(const oiio::EncodeRequest& rq) {
    return uint64_t(rq.width) * uint64_t(rq.height) * uint64_t(rq.channels) *
           (rq.type == oiio::PixelType::U8 ? 1u : sizeof(float));
}

// The request without its pixels, which sendRequest sends from where they
// lie (no copy of an image in the parent), ending with the pixels' length.
Bytes requestHeader(const oiio::EncodeRequest& rq) {
    Writer w;
    w.putString(rq.format);
    for (const int v :
         {rq.width, rq.height, rq.channels, int(rq.type), rq.dataX, rq.dataY, rq.fullWidth, rq.fullHeight})
        w.put(int32_t(v));
    w.put(uint32_t(rq.channelNames.size()));
    for (const std::string& s : rq.channelNames) w.putString(s);
    w.put(uint32_t(rq.attributes.size()));
    for (const oiio::Attribute& a : rq.attributes) {
        w.putString(a.name);
        w.put(int32_t(a.kind));
        w.put(int32_t(a.i));
        w.put(a.f);
        w.putString(a.s);
    }
    w.put(pixelBytes(rq));
    return std::move(w.bytes);
}

bool sendRequest(int fd, const oiio::EncodeRequest& rq) {
    const Bytes header = requestHeader(rq);
    const uint64_t n = header.size() + pixelBytes(rq);
    return sendAll(fd, &n, sizeof n) && sendAll(fd, header.data(), header.size()) &&
           sendAll(fd, rq.pixels, size_t(pixelBytes(rq)));
}

// The request in `m`; rq.pixels points into m.
bool parseRequest(const Bytes& m, oiio::EncodeRequest& rq) {
    Reader r(m);
    int32_t v[8];
    if (!r.getString(rq.format)) return false;
    for (int32_t& x : v)
        if (!r.get(x)) return false;
    rq.width = v[0];
    rq.height = v[1];
    rq.channels = v[2];
    rq.type = oiio::PixelType(v[3]);
    rq.dataX = v[4];
    rq.dataY = v[5];
    rq.fullWidth = v[6];
    rq.fullHeight = v[7];
    uint32_t count = 0;
    if (!r.get(count)) return false;
    rq.channelNames.resize(count);
    for (std::string& s : rq.channelNames)
        if (!r.getString(s)) return false;
    if (!r.get(count)) return false;
    rq.attributes.resize(count);
    for (oiio::Attribute& a : rq.attributes) {
        int32_t kind = 0, i = 0;
        if (!r.getString(a.name) || !r.get(kind) || !r.get(i) || !r.get(a.f) || !r.getString(a.s)) return false;
        a.kind = oiio::Attribute::Kind(kind);
        a.i = i;
    }
    const unsigned char* pixels = nullptr;
    uint64_t n = 0;
    if (!r.getBytes(pixels, n) || n != pixelBytes(rq) || !r.atEnd()) return false;
    rq.pixels = pixels;
    return true;
}

// The helper: loads the module, then answers requests until the parent closes
// its end (or dies: PR_SET_PDEATHSIG). It ends with _exit, so nothing the
// parent's image of the process holds (stdio buffers, static destructors) runs twice.
[[noreturn]] void serve(int fd) {
    try {
        std::signal(SIGINT, SIG_IGN);  // an interrupt is the parent's to handle: it closes the socket
        std::signal(SIGTERM, SIG_DFL);
        const oiio::Api* api = nullptr;
        std::string loadError;
        try {
            api = &oiioLibrary();
        } catch (const std::exception& e) {
            loadError = e.what();
        }
        Bytes message;
        while (receiveMessage(fd, message)) {
            oiio::EncodeRequest rq;
            if (!parseRequest(message, rq)) ::_exit(2);
            Bytes out;
            std::string error;
            bool ok = false;
            if (api) {
                ok = api->encode(rq, out, error);
            } else {
                error = loadError;
            }
            Writer w;
            w.put(uint8_t(ok ? 1 : 0));
            if (ok) {
                w.putBytes(out.data(), out.size());
            } else {
                w.putString(error);
            }
            if (!sendMessage(fd, w.bytes)) break;
        }
        ::_exit(0);
    } catch (...) {
        ::_exit(1);  // the parent sees the socket close and encodes in-process
    }
}

}  // namespace

std::unique_ptr<ImageEncoderProcess> ImageEncoderProcess::start() {
    int sv[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) return nullptr;
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(sv[0]);
        ::close(sv[1]);
        return nullptr;
    }
    if (pid == 0) {
        ::close(sv[0]);
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != parent) ::_exit(0);  // the parent died before the line above
        // The helper reads and writes nothing but the socket: it must not hold the
        // parent's stdin or stdout open (a reader of the parent's output waits for
        // every writer to close it). stderr stays, for what a library reports.
        if (const int null = ::open("/dev/null", O_RDWR | O_CLOEXEC); null >= 0) {
            ::dup2(null, STDIN_FILENO);
            ::dup2(null, STDOUT_FILENO);
            if (null > STDERR_FILENO) ::close(null);
        }
        serve(sv[1]);
    }
    ::close(sv[1]);
    return std::unique_ptr<ImageEncoderProcess>(new ImageEncoderProcess(sv[0], pid));
}

ImageEncoderProcess::~ImageEncoderProcess() { stop(); }

void ImageEncoderProcess::stop() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    if (pid_ > 0) {
        ::kill(pid_, SIGKILL);
        while (::waitpid(pid_, nullptr, 0) < 0 && errno == EINTR) {
        }
    }
    pid_ = -1;
}

std::optional<bool> ImageEncoderProcess::encode(const oiio::EncodeRequest& request, Bytes& out, std::string& error) {
    if (fd_ < 0) return std::nullopt;
    Bytes reply;
    // A large image is encoded in-process: copying it to the helper would hold it twice, and the
    // module's load is then small next to the render that made it.
    if (pixelBytes(request) > kMaxHelperPixelBytes) return std::nullopt;
    if (!sendRequest(fd_, request) || !receiveMessage(fd_, reply)) {
        stop();
        return std::nullopt;
    }
    Reader r(reply);
    uint8_t ok = 0;
    const unsigned char* p = nullptr;
    uint64_t n = 0;
    if (!r.get(ok)) {
        stop();
        return std::nullopt;
    }
    if (ok) {
        if (!r.getBytes(p, n)) {
            stop();
            return std::nullopt;
        }
        out.assign(p, p + n);
        return true;
    }
    if (!r.getString(error)) {
        stop();
        return std::nullopt;
    }
    return false;
}

}  // namespace penumbra
