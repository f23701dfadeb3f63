// Small appearance inputs the mesh reader tests build in code: PNG and JPEG bytes, headers
// that lie about their size, base64 and GLB containers, and a scratch directory per test.
#pragma once

#include "ngi/error.h"
#include "ngi/png_io.h"

#include <gtest/gtest.h>
#include <jpeglib.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace appearance_fixtures {

namespace fs = std::filesystem;

// A directory of the running test's own, removed after it.
class ScratchDirectory : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() /
            ("ngi_appearance_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path write(const std::string& name, const std::string& bytes) const
    {
        const fs::path path = dir_ / name;
        fs::create_directories(path.parent_path());
        std::ofstream(path, std::ios::binary) << bytes;
        return path;
    }
    fs::path dir_;
};

inline std::string readBytes(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// An 8-bit RGBA PNG's bytes (through core's writer and a scratch file).
inline std::string pngBytes(const fs::path& scratch, uint32_t width, uint32_t height, const std::vector<uint8_t>& rgba)
{
    ngi::writePng8(scratch, width, height, 4, rgba.data());
    std::string bytes = readBytes(scratch);
    fs::remove(scratch);
    return bytes;
}

// A 16-bit RGB PNG's bytes.
inline std::string png16Bytes(const fs::path& scratch, uint32_t width, uint32_t height,
                              const std::vector<uint16_t>& rgb)
{
    ngi::PngImage image;
    image.width = width, image.height = height, image.channels = 3, image.bitDepth = 16;
    image.samples = rgb;
    ngi::writePng(scratch, image);
    std::string bytes = readBytes(scratch);
    fs::remove(scratch);
    return bytes;
}

// A baseline RGB JPEG (quality 100) of `rgb`, width * height * 3 bytes.
inline std::string jpegBytes(uint32_t width, uint32_t height, const std::vector<uint8_t>& rgb)
{
    jpeg_compress_struct info{};
    jpeg_error_mgr errors{};
    info.err = jpeg_std_error(&errors);
    jpeg_create_compress(&info);
    unsigned char* out = nullptr;
    unsigned long size = 0;
    jpeg_mem_dest(&info, &out, &size);
    info.image_width = width, info.image_height = height, info.input_components = 3, info.in_color_space = JCS_RGB;
    jpeg_set_defaults(&info);
    jpeg_set_quality(&info, 100, TRUE);
    jpeg_start_compress(&info, TRUE);
    while (info.next_scanline < height) {
        JSAMPROW row = const_cast<uint8_t*>(rgb.data()) + size_t(info.next_scanline) * width * 3;
        jpeg_write_scanlines(&info, &row, 1);
    }
    jpeg_finish_compress(&info);
    std::string bytes(reinterpret_cast<const char*>(out), size);
    jpeg_destroy_compress(&info);
    std::free(out);
    return bytes;
}

inline std::string bigEndian32(uint32_t v) { return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; }

// A PNG signature and an IHDR chunk claiming width x height RGBA, and nothing after it.
inline std::string pngHeaderOnly(uint32_t width, uint32_t height)
{
    return std::string("\x89PNG\r\n\x1a\n", 8) + bigEndian32(13) + "IHDR" + bigEndian32(width) + bigEndian32(height) +
        std::string("\x08\x06\x00\x00\x00", 5) + bigEndian32(0);
}

// A real JPEG whose SOF0 header is patched to claim width x height.
inline std::string jpegClaiming(uint16_t width, uint16_t height)
{
    std::string bytes = jpegBytes(8, 8, std::vector<uint8_t>(8 * 8 * 3, 128));
    for (size_t i = 2; i + 9 < bytes.size(); ++i)
        if (uint8_t(bytes[i]) == 0xFF && uint8_t(bytes[i + 1]) == 0xC0) {  // SOF0: length, precision, height, width
            bytes[i + 5] = char(height >> 8), bytes[i + 6] = char(height & 0xFF);
            bytes[i + 7] = char(width >> 8), bytes[i + 8] = char(width & 0xFF);
            break;
        }
    return bytes;
}

inline std::string base64(const std::string& bytes)
{
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        const size_t n = std::min<size_t>(3, bytes.size() - i);
        uint32_t v = 0;
        for (size_t k = 0; k < 3; ++k) v = v << 8 | (k < n ? uint8_t(bytes[i + k]) : 0u);
        for (size_t k = 0; k < 4; ++k) out += k <= n ? table[(v >> (18 - 6 * k)) & 63] : '=';
    }
    return out;
}

template <typename T> std::string raw(std::initializer_list<T> values)
{
    std::string out;
    for (T v : values) out.append(reinterpret_cast<const char*>(&v), sizeof v);
    return out;
}

inline std::string u32(uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); }

inline std::string glb(std::string json, std::string bin)
{
    while (json.size() % 4) json += ' ';
    while (bin.size() % 4) bin += '\0';
    return "glTF" + u32(2) + u32(uint32_t(12 + 8 + json.size() + 8 + bin.size())) + u32(uint32_t(json.size())) +
        "JSON" + json + u32(uint32_t(bin.size())) + std::string("BIN\0", 4) + bin;
}

// The ngi::Error message of `read`, which must start with `name` followed by ": ".
template <typename Read> std::string errorOf(const std::string& name, Read read)
{
    try {
        read();
    } catch (const ngi::Error& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(name + ": ", 0), 0u) << "does not start with " << name << ": " << message;
        return message;
    }
    ADD_FAILURE() << name << " was read without an error";
    return "";
}

// sRGB-encoded [0, 1] to linear (IEC 61966-2-1), the reference for the readers' conversion.
inline double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

#define EXPECT_CONTAINS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

}  // namespace appearance_fixtures
