// libpenumbra_oiio.so: OpenImageIO behind the table of core/oiio/oiio_api.h.
// The only file of Penumbra that includes OpenImageIO. Encoding goes to memory
// (MemoryFile) so that a full disk never reaches libpng, libjpeg or libtiff;
// decoding reads a descriptor handed over by libpenumbra (pread, into memory)
// or bytes it holds (an image inside a model file), never a path.
#include <sys/stat.h>
#include <unistd.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <exception>
#include <memory>
#include <new>

#include "core/oiio/oiio_api.h"

namespace penumbra::oiio {
namespace {

// The whole content of an open descriptor, read at explicit offsets (its own
// file offset is never moved, so the loader may share it). OpenImageIO 2.4's
// readers accept only their own proxy types (JPEG: memory or file), so every
// decoder reads from memory. False when the file is larger than `limit`.
bool readWhole(int fd, uint64_t limit, std::vector<unsigned char>& out, std::string& error) {
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        error = std::strerror(errno);
        return false;
    }
    if (limit > 0 && uint64_t(st.st_size) > limit) return false;
    out.resize(size_t(st.st_size));
    size_t done = 0;
    while (done < out.size()) {
        ssize_t r = ::pread(fd, out.data() + done, out.size() - done, off_t(done));
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) {
            error = std::strerror(errno);
            return false;
        }
        if (r == 0) break;  // shorter than fstat said: decode what is there
        done += size_t(r);
    }
    out.resize(done);
    return true;
}

// A file in memory that writers may also seek in and read back (libtiff
// rewrites and rereads its directories; IOVecOutput cannot be read).
class MemoryFile final : public OIIO::Filesystem::IOProxy {
public:
    MemoryFile(std::vector<unsigned char>& bytes) : IOProxy("penumbra-memory", Write), bytes_(bytes) {}
    const char* proxytype() const override { return "penumbra-memory"; }
    size_t read(void* buf, size_t size) override {
        size_t n = pread(buf, size, m_pos);
        m_pos += int64_t(n);
        return n;
    }
    size_t write(const void* buf, size_t size) override {
        size_t n = pwrite(buf, size, m_pos);
        m_pos += int64_t(n);
        return n;
    }
    size_t pread(void* buf, size_t size, int64_t offset) override {
        if (offset < 0 || uint64_t(offset) >= bytes_.size()) return 0;
        size_t n = std::min(size, bytes_.size() - size_t(offset));
        std::memcpy(buf, bytes_.data() + offset, n);
        return n;
    }
    size_t pwrite(const void* buf, size_t size, int64_t offset) override {
        if (offset < 0) return 0;
        if (size_t(offset) + size > bytes_.size()) bytes_.resize(size_t(offset) + size);
        std::memcpy(bytes_.data() + offset, buf, size);
        return size;
    }
    size_t size() const override { return bytes_.size(); }

private:
    std::vector<unsigned char>& bytes_;
};

// Reads the encoded header back: a writer that produced a file its own reader
// cannot open, or one of another size, is an error, not an image on disk.
bool verify(const EncodeRequest& rq, std::vector<unsigned char>& bytes, std::string& error) {
    OIIO::Filesystem::IOMemReader reader(bytes.data(), bytes.size());
    auto in = OIIO::ImageInput::create(rq.format);
    OIIO::ImageSpec spec;
    if (!in || !in->set_ioproxy(&reader) || !in->open("penumbra-memory." + rq.format, spec)) {
        error = "the encoded " + rq.format + " file cannot be read back" + (in ? " (" + in->geterror() + ")" : "");
        return false;
    }
    if (spec.width != rq.width || spec.height != rq.height || spec.nchannels != rq.channels) {
        error = "the encoded " + rq.format + " file reads back as " + std::to_string(spec.width) + "x" +
                std::to_string(spec.height) + "x" + std::to_string(spec.nchannels);
        return false;
    }
    return true;
}

bool encode(const EncodeRequest& rq, std::vector<unsigned char>& out, std::string& error) noexcept {
    try {
        out.clear();
        auto writer = OIIO::ImageOutput::create(rq.format);
        if (!writer) {
            error = "no " + rq.format + " writer (" + OIIO::geterror() + ")";
            return false;
        }
        if (!writer->supports("ioproxy")) {
            error = "the " + rq.format + " writer cannot write to memory";
            return false;
        }
        const OIIO::TypeDesc type = rq.type == PixelType::U8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
        OIIO::ImageSpec spec(rq.width, rq.height, rq.channels, type);
        if (!rq.channelNames.empty()) {
            spec.channelnames = rq.channelNames;
            spec.alpha_channel = -1;
        }
        if (rq.fullWidth > 0 && rq.fullHeight > 0) {
            spec.x = rq.dataX;
            spec.y = rq.dataY;
            spec.full_x = spec.full_y = 0;
            spec.full_width = rq.fullWidth;
            spec.full_height = rq.fullHeight;
        }
        for (const Attribute& a : rq.attributes) {
            if (a.kind == Attribute::Kind::Int) spec.attribute(a.name, a.i);
            else if (a.kind == Attribute::Kind::Float) spec.attribute(a.name, a.f);
            else spec.attribute(a.name, a.s);
        }
        MemoryFile memory(out);
        if (!writer->set_ioproxy(&memory)) {
            error = "the " + rq.format + " writer refused the memory output";
            return false;
        }
        // The name only matters to writers that would open a file; with the proxy none does.
        if (!writer->open("penumbra-memory." + rq.format, spec) || !writer->write_image(type, rq.pixels)) {
            error = writer->geterror();
            writer->close();
            return false;
        }
        if (!writer->close()) {
            error = writer->geterror();
            return false;
        }
        if (out.empty()) {
            error = "the " + rq.format + " writer produced no bytes";
            return false;
        }
        return verify(rq, out, error);
    } catch (const std::bad_alloc&) {
        error = "out of memory while encoding";
    } catch (const std::exception& e) {
        error = e.what();
    } catch (...) {
        error = "unknown error while encoding";
    }
    return false;
}

Status decode(const DecodeRequest& rq, Decoded& out, std::string& error) noexcept {
    try {
        // A compressed file is smaller than its pixels, give or take headers:
        // a file beyond the pixel budget (plus 1 MiB) cannot fit it.
        std::vector<unsigned char> file;
        const uint64_t fileLimit = rq.maxBytes > 0 ? rq.maxBytes + (uint64_t(1) << 20) : 0;
        if (rq.bytes && fileLimit > 0 && rq.size > fileLimit) {
            out.fileBytes = rq.size;
            return Status::OverBudget;
        }
        if (!rq.bytes && !readWhole(rq.fd, fileLimit, file, error)) {
            if (!error.empty()) return Status::Failed;
            struct stat st {};
            ::fstat(rq.fd, &st);
            out.fileBytes = uint64_t(st.st_size);
            return Status::OverBudget;
        }
        OIIO::Filesystem::IOMemReader reader(rq.bytes ? rq.bytes : file.data(), rq.bytes ? rq.size : file.size());
        // The values as stored: a PNG's colour is not multiplied by its alpha (glTF's and MTL's alpha is straight).
        OIIO::ImageSpec config;
        config.attribute("oiio:UnassociatedAlpha", 1);
        OIIO::Filesystem::IOProxy* proxy = &reader;  // with a configuration, the reader takes its proxy from there
        config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
        auto in = OIIO::ImageInput::open(rq.name, &config, &reader);
        if (!in) {
            error = OIIO::geterror();
            if (error.empty()) error = "not an image OpenImageIO can read";
            return Status::Failed;
        }
        const OIIO::ImageSpec& spec = in->spec();
        out.width = spec.width;
        out.height = spec.height;
        out.channels = spec.nchannels;
        out.bytesPerChannel = int(spec.format.size());
        out.floatData = spec.format.basetype == OIIO::TypeDesc::FLOAT ||
                        spec.format.basetype == OIIO::TypeDesc::HALF || spec.format.basetype == OIIO::TypeDesc::DOUBLE;
        out.colorSpace = spec.get_string_attribute("oiio:ColorSpace");
        out.channelNames = spec.channelnames;
        out.attributes.clear();
        for (const auto& p : spec.extra_attribs) out.attributes.emplace_back(p.name().string(), p.get_string());
        if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1) {
            error = "unsupported image layout (" + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                    "x" + std::to_string(spec.depth) + ", " + std::to_string(spec.nchannels) + " channels)";
            return Status::Failed;
        }
        out.decodedChannels = rq.maxChannels > 0 ? std::min(spec.nchannels, rq.maxChannels) : spec.nchannels;
        out.type = (!rq.floatPixels && spec.format == OIIO::TypeDesc::UINT8) ? PixelType::U8 : PixelType::F32;
        const uint64_t bytes = uint64_t(spec.width) * uint64_t(spec.height) * uint64_t(out.decodedChannels) *
                               (out.type == PixelType::U8 ? 1u : 4u);
        if (rq.maxBytes > 0 && bytes > rq.maxBytes) return Status::OverBudget;
        if (rq.headerOnly) return Status::Ok;
        out.pixels.resize(size_t(bytes));
        const OIIO::TypeDesc type = out.type == PixelType::U8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
        if (!in->read_image(0, 0, 0, out.decodedChannels, type, out.pixels.data())) {
            error = in->geterror();
            if (error.empty()) error = "its pixels cannot be read";
            out.pixels.clear();
            return Status::Failed;
        }
        // Readers report some damage (a missing tile, a short scanline) only as a pending error.
        if (in->has_error()) {
            error = in->geterror();
            out.pixels.clear();
            return Status::Failed;
        }
        in->close();
        return Status::Ok;
    } catch (const std::bad_alloc&) {
        error = "out of memory while decoding";
    } catch (const std::exception& e) {
        error = e.what();
    } catch (...) {
        error = "unknown error while decoding";
    }
    out.pixels.clear();
    return Status::Failed;
}

constexpr Api kApi{kApiVersion, &encode, &decode};

}  // namespace
}  // namespace penumbra::oiio

extern "C" __attribute__((visibility("default"))) const penumbra::oiio::Api* penumbra_oiio_api() {
    return &penumbra::oiio::kApi;
}
