#include "core/png_encoder.h"

#include <png.h>

#include <csetjmp>
#include <exception>

namespace penumbra {
namespace {

// libpng reports errors by calling back and must not return to it: the
// handler records the message and jumps back to writePng's setjmp. No C++
// exception may cross libpng's C frames, so the write callback catches its own.
struct Sink {
    std::vector<unsigned char>* out;
    std::string error;
    std::string warning;  // libpng says why before some errors ("Invalid IHDR data")
};

[[noreturn]] void onError(png_structp png, png_const_charp message) {
    static_cast<Sink*>(png_get_error_ptr(png))->error = message ? message : "libpng error";
    png_longjmp(png, 1);
}

void onWarning(png_structp png, png_const_charp message) {
    if (message) static_cast<Sink*>(png_get_error_ptr(png))->warning = message;
}

void onWrite(png_structp png, png_bytep data, size_t size) {
    auto* sink = static_cast<Sink*>(png_get_io_ptr(png));
    bool ok = true;
    try {
        sink->out->insert(sink->out->end(), data, data + size);
    } catch (const std::exception&) {
        ok = false;
    }
    if (!ok) png_error(png, "out of memory");
}

void onFlush(png_structp) {}

// The libpng calls, apart from anything a jump could clobber: only pointers
// set before setjmp live in this frame.
bool writePng(png_structp png, png_infop info, const PngImage& image, png_bytepp rows, png_textp text, int nText) {
    if (setjmp(png_jmpbuf(png)) != 0) return false;
    png_set_write_fn(png, png_get_error_ptr(png), onWrite, onFlush);
    png_set_compression_level(png, image.zlibLevel);
    // Each row by the Sub filter alone: libpng's default tries all five filters per
    // row, which cost more than the deflate, for files within 1.5% of its size
    // on rendered images (docs/ab/fig24_session_fd67303_to_586ab34.txt has the sizes).
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    if (nText > 0) png_set_text(png, info, text, nText);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, info);
    return true;
}

}  // namespace

bool encodePng(const PngImage& image, std::vector<unsigned char>& out, std::string& error) {
    Sink sink{&out, {}};
    std::vector<png_bytep> rows(size_t(image.height));
    const size_t stride = size_t(image.width) * 3;
    for (size_t y = 0; y < rows.size(); ++y) rows[y] = const_cast<png_bytep>(image.rgb + y * stride);
    std::vector<png_text> text(image.text.size());
    for (size_t i = 0; i < text.size(); ++i) {
        text[i] = png_text{};
        text[i].compression = PNG_TEXT_COMPRESSION_NONE;
        text[i].key = const_cast<png_charp>(image.text[i].first.c_str());
        text[i].text = const_cast<png_charp>(image.text[i].second.c_str());
        text[i].text_length = image.text[i].second.size();
    }
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, onError, onWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        error = "libpng: out of memory";
        return false;
    }
    const bool ok = writePng(png, info, image, rows.data(), text.data(), int(text.size()));
    png_destroy_write_struct(&png, &info);
    if (!ok) error = "libpng: " + sink.error + (sink.warning.empty() ? "" : " (" + sink.warning + ")");
    return ok;
}

}  // namespace penumbra
