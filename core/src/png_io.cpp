// PNG input/output over libpng's classic API (16-bit samples are kept exact: the
// simplified API would apply gamma conversions to 16-bit "linear" data).
#include "ngi/png_io.h"

#include "ngi/asset.h"
#include "ngi/error.h"

#include <png.h>

#include <csetjmp>
#include <cstring>
#include <string>

namespace ngi {
namespace {

struct ErrorSink {
    std::string message;
};

void onPngError(png_structp png, png_const_charp msg)
{
    auto* sink = static_cast<ErrorSink*>(png_get_error_ptr(png));
    if (sink) sink->message = msg;
    png_longjmp(png, 1);
}
void onPngWarning(png_structp, png_const_charp) {}

struct MemoryReader {
    std::span<const uint8_t> bytes;
    size_t at = 0;
};

void readFromMemory(png_structp png, png_bytep out, png_size_t n)
{
    auto* r = static_cast<MemoryReader*>(png_get_io_ptr(png));
    if (r->bytes.size() - r->at < n) png_error(png, "file is truncated");
    std::memcpy(out, r->bytes.data() + r->at, n);
    r->at += n;
}

void writeToMemory(png_structp png, png_bytep data, png_size_t n)
{
    auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
    out->insert(out->end(), data, data + n);
}
void flushMemory(png_structp) {}

// Encodes rows to PNG bytes; returns false with `sink.message` set on a libpng error.
bool encode(const PngImage& image, std::vector<uint8_t>& out, ErrorSink& sink)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, onPngError, onPngWarning);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    const int colorType = image.channels == 1 ? PNG_COLOR_TYPE_GRAY
        : image.channels == 2                 ? PNG_COLOR_TYPE_GRAY_ALPHA
        : image.channels == 3                 ? PNG_COLOR_TYPE_RGB
                                              : PNG_COLOR_TYPE_RGBA;
    const size_t rowBytes = size_t(image.width) * image.channels * (image.bitDepth / 8);
    std::vector<uint8_t> row(rowBytes);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, &out, writeToMemory, flushMemory);
    png_set_IHDR(png, info, image.width, image.height, int(image.bitDepth), colorType, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 6);
    png_write_info(png, info);
    const size_t rowSamples = size_t(image.width) * image.channels;
    for (uint32_t y = 0; y < image.height; ++y) {
        const uint16_t* src = image.samples.data() + y * rowSamples;
        if (image.bitDepth == 16) {
            for (size_t i = 0; i < rowSamples; ++i) {  // PNG stores 16-bit samples big-endian
                row[2 * i] = uint8_t(src[i] >> 8);
                row[2 * i + 1] = uint8_t(src[i] & 0xff);
            }
        } else {
            for (size_t i = 0; i < rowSamples; ++i) row[i] = uint8_t(src[i]);
        }
        png_write_row(png, row.data());
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}

}  // namespace

void writePng(const std::filesystem::path& path, const PngImage& image)
{
    if (image.width == 0 || image.height == 0 || image.channels < 1 || image.channels > 4 ||
        (image.bitDepth != 8 && image.bitDepth != 16) ||
        image.samples.size() != size_t(image.width) * image.height * image.channels)
        throw Error(path.string() + ": inconsistent image for PNG output");
    std::vector<uint8_t> bytes;
    ErrorSink sink;
    if (!encode(image, bytes, sink)) throw Error(path.string() + ": PNG encoding failed (" + sink.message + ")");
    writeFileAtomic(path, bytes);
}

void writePng8(const std::filesystem::path& path, uint32_t width, uint32_t height, uint32_t channels,
               const uint8_t* pixels)
{
    PngImage image;
    image.width = width;
    image.height = height;
    image.channels = channels;
    image.bitDepth = 8;
    image.samples.assign(pixels, pixels + size_t(width) * height * channels);
    writePng(path, image);
}

PngImage readPng(const std::filesystem::path& path)
{
    const std::vector<uint8_t> bytes = readFileBytes(path);
    return readPngFromMemory(bytes, path.string());
}

PngImage readPngFromMemory(std::span<const uint8_t> bytes, const std::string& name)
{
    if (bytes.size() < 8 || png_sig_cmp(bytes.data(), 0, 8) != 0)
        throw Error(name + ": not a PNG file (bad signature)");
    ErrorSink sink;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &sink, onPngError, onPngWarning);
    if (!png) throw Error(name + ": out of memory creating the PNG reader");
    png_infop info = png_create_info_struct(png);
    MemoryReader reader{bytes, 0};
    PngImage image;
    std::vector<uint8_t> pixels;
    std::vector<png_bytep> rows;
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        throw Error(name + ": corrupt PNG (" + sink.message + ")");
    }
    png_set_read_fn(png, &reader, readFromMemory);
    png_set_user_limits(png, 1u << 15, 1u << 15);
    png_read_info(png, info);
    png_set_expand(png);  // palette -> RGB, gray < 8 bit -> 8 bit, tRNS -> alpha
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    image.width = png_get_image_width(png, info);
    image.height = png_get_image_height(png, info);
    image.channels = png_get_channels(png, info);
    image.bitDepth = png_get_bit_depth(png, info);
    const size_t rowBytes = png_get_rowbytes(png, info);
    pixels.resize(rowBytes * image.height);
    rows.resize(image.height);
    for (uint32_t y = 0; y < image.height; ++y) rows[y] = pixels.data() + y * rowBytes;
    png_read_image(png, rows.data());
    png_read_end(png, nullptr);
    png_destroy_read_struct(&png, &info, nullptr);

    const size_t count = size_t(image.width) * image.height * image.channels;
    image.samples.resize(count);
    for (size_t i = 0; i < count; ++i)
        image.samples[i] = image.bitDepth == 16 ? uint16_t(pixels[2 * i] << 8 | pixels[2 * i + 1]) : pixels[i];
    return image;
}

}  // namespace ngi
