// ngi offline: texture decoding for the mesh readers (see texture_io.h). Every decoder checks
// the size its header declares against the limits before it allocates or decodes a pixel.
#include "texture_io.h"

#include "ngi/error.h"
#include "ngi/png_io.h"

#include <cstdio>  // jpeglib.h needs FILE
#include <jerror.h>
#include <jpeglib.h>
#if NGI_HAVE_WEBP
#include <webp/decode.h>
#endif

#include <csetjmp>
#include <cstring>
#include <new>

namespace ngi::mesh_io {
namespace {

[[noreturn]] void textureFail(const std::string& meshName, const std::string& imageName, const std::string& problem)
{
    throw Error(meshName + ": texture " + imageName + ": " + problem);
}

void checkSize(uint64_t width, uint64_t height, const std::string& meshName, const std::string& imageName)
{
    if (width == 0 || height == 0)
        textureFail(meshName, imageName,
                    "the image is empty (" + std::to_string(width) + " x " + std::to_string(height) + ")");
    if (width > kMaxTextureSide || height > kMaxTextureSide || width * height > kMaxTexturePixels)
        textureFail(meshName, imageName,
                    "the image is " + std::to_string(width) + " x " + std::to_string(height) +
                        " pixels, beyond the limit of " + std::to_string(kMaxTextureSide) + " per side and " +
                        std::to_string(kMaxTexturePixels) + " pixels");
}

bool startsWith(std::span<const uint8_t> bytes, const char* signature, size_t offset = 0)
{
    const size_t n = std::strlen(signature);
    return bytes.size() >= offset + n && std::memcmp(bytes.data() + offset, signature, n) == 0;
}

uint32_t bigEndian32(const uint8_t* p)
{
    return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3];
}

// ---------------------------------------------------------------- PNG

TextureImage decodePng(std::span<const uint8_t> bytes, const std::string& meshName, const std::string& imageName)
{
    // The IHDR chunk comes first (PNG 1.2, 5.6): width and height at bytes 16 and 20.
    if (bytes.size() >= 24 && startsWith(bytes, "IHDR", 12))
        checkSize(bigEndian32(bytes.data() + 16), bigEndian32(bytes.data() + 20), meshName, imageName);
    const PngImage png = readPngFromMemory(bytes, meshName + ": texture " + imageName);
    checkSize(png.width, png.height, meshName, imageName);
    TextureImage image;
    image.name = imageName;
    image.width = png.width;
    image.height = png.height;
    const size_t pixels = size_t(png.width) * png.height;
    image.rgba.resize(pixels * 4);
    const uint32_t channels = png.channels;
    const bool colour = channels >= 3, alpha = channels == 2 || channels == 4;
    for (size_t i = 0; i < pixels; ++i) {
        const uint16_t* in = png.samples.data() + i * channels;
        uint8_t* out = image.rgba.data() + i * 4;
        auto to8 = [&](uint16_t v) { return uint8_t(png.bitDepth == 16 ? (uint32_t(v) + 128) / 257 : v); };
        out[0] = to8(in[0]);
        out[1] = to8(in[colour ? 1 : 0]);
        out[2] = to8(in[colour ? 2 : 0]);
        out[3] = alpha ? to8(in[channels - 1]) : 255;
    }
    return image;
}

// ---------------------------------------------------------------- JPEG

// libjpeg reports errors through error_exit, which by default prints and calls exit(): ours
// keeps the message and longjmps back to the decoder. Warnings (a truncated file is one:
// libjpeg pads it with grey) are errors too, except bytes between markers, which libjpeg
// skips without losing anything.
struct JpegErrors {
    jpeg_error_mgr manager;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX] = {};
};

void onJpegError(j_common_ptr info)
{
    auto* errors = reinterpret_cast<JpegErrors*>(info->err);
    (*info->err->format_message)(info, errors->message);
    std::longjmp(errors->jump, 1);
}

void onJpegMessage(j_common_ptr info, int level)
{
    if (level < 0 && info->err->msg_code != JWRN_EXTRANEOUS_DATA) onJpegError(info);
}

// Owns a decompressor; it lives in the frame that calls setjmp, so a longjmp back to that
// frame skips no destructor.
struct JpegDecompressor {
    jpeg_decompress_struct info{};
    JpegErrors errors;
    volatile bool created = false;  // read after a longjmp
    ~JpegDecompressor()
    {
        if (created) jpeg_destroy_decompress(&info);
    }
};

void decodeJpegInto(std::span<const uint8_t> bytes, const std::string& meshName, const std::string& imageName,
                    TextureImage& image)
{
    JpegDecompressor jpeg;
    jpeg.info.err = jpeg_std_error(&jpeg.errors.manager);
    jpeg.errors.manager.error_exit = onJpegError;
    jpeg.errors.manager.emit_message = onJpegMessage;
    if (setjmp(jpeg.errors.jump))
        textureFail(meshName, imageName, std::string("corrupt JPEG (") + jpeg.errors.message + ")");
    jpeg_create_decompress(&jpeg.info);
    jpeg.created = true;
    jpeg_mem_src(&jpeg.info, bytes.data(), static_cast<unsigned long>(bytes.size()));
    jpeg_read_header(&jpeg.info, TRUE);
    checkSize(jpeg.info.image_width, jpeg.info.image_height, meshName, imageName);
    jpeg.info.out_color_space = JCS_EXT_RGBA;  // grey and YCbCr to RGBA (CMYK: an error)
    jpeg_start_decompress(&jpeg.info);
    image.width = jpeg.info.output_width;
    image.height = jpeg.info.output_height;
    image.rgba.resize(size_t(image.width) * image.height * 4);
    while (jpeg.info.output_scanline < jpeg.info.output_height) {
        JSAMPROW row = image.rgba.data() + size_t(jpeg.info.output_scanline) * image.width * 4;
        jpeg_read_scanlines(&jpeg.info, &row, 1);
    }
    jpeg_finish_decompress(&jpeg.info);
}

// ---------------------------------------------------------------- WebP

TextureImage decodeWebp(std::span<const uint8_t> bytes, const std::string& meshName, const std::string& imageName)
{
#if NGI_HAVE_WEBP
    int width = 0, height = 0;
    if (!WebPGetInfo(bytes.data(), bytes.size(), &width, &height))
        textureFail(meshName, imageName, "corrupt WebP (no valid header)");
    checkSize(uint64_t(width), uint64_t(height), meshName, imageName);
    TextureImage image;
    image.name = imageName;
    image.width = uint32_t(width);
    image.height = uint32_t(height);
    image.rgba.resize(size_t(width) * size_t(height) * 4);
    if (!WebPDecodeRGBAInto(bytes.data(), bytes.size(), image.rgba.data(), image.rgba.size(), width * 4))
        textureFail(meshName, imageName, "corrupt or truncated WebP");
    return image;
#else
    (void)bytes;
    textureFail(meshName, imageName, "unsupported image format (WebP: this build of ngi has no libwebp)");
#endif
}

// What an unsupported image looks like, for the message.
std::string formatGuess(std::span<const uint8_t> bytes)
{
    if (startsWith(bytes, "BM")) return " (it looks like BMP)";
    if (startsWith(bytes, "GIF8")) return " (it looks like GIF)";
    if (startsWith(bytes, "\xABKTX")) return " (it looks like KTX)";
    if (startsWith(bytes, "DDS ")) return " (it looks like DDS)";
    if (startsWith(bytes, "8BPS")) return " (it looks like PSD)";
    if (startsWith(bytes, "II*") || startsWith(bytes, "MM")) return " (it looks like TIFF)";
    return "";
}

}  // namespace

TextureImage decodeTexture(std::span<const uint8_t> bytes, const std::string& meshName, const std::string& imageName)
{
    try {
        if (bytes.empty()) textureFail(meshName, imageName, "the image file is empty");
        if (startsWith(bytes, "\x89PNG\r\n\x1a\n")) return decodePng(bytes, meshName, imageName);
        if (bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) {
            TextureImage image;
            image.name = imageName;
            decodeJpegInto(bytes, meshName, imageName, image);
            return image;
        }
        if (startsWith(bytes, "RIFF") && startsWith(bytes, "WEBP", 8)) return decodeWebp(bytes, meshName, imageName);
        textureFail(meshName, imageName,
                    "unsupported image format" + formatGuess(bytes) + ": expected PNG, JPEG or WebP");
    } catch (const std::bad_alloc&) {
        textureFail(meshName, imageName, "out of memory decoding the image");
    }
}

}  // namespace ngi::mesh_io
