#include "beamtrace/io/png_writer.hpp"

#include <gtest/gtest.h>
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

/// What an independent libpng reader sees in a file.
struct DecodedPng {
    png_uint_32 width = 0;
    png_uint_32 height = 0;
    int bit_depth = 0;
    int color_type = 0;
    std::vector<std::uint8_t> bytes;  ///< rows as stored (16-bit samples big-endian)
    std::string software;             ///< tEXt "Software", if any
};

// Plain C-style decoding: nothing with a destructor lives in this frame across setjmp.
bool decode_png(std::FILE* file, DecodedPng* out) {
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    if (png == nullptr) {
        return false;
    }
    png_infop info = png_create_info_struct(png);
    if (info == nullptr || setjmp(png_jmpbuf(png)) != 0) {
        png_destroy_read_struct(&png, &info, nullptr);
        return false;
    }
    png_init_io(png, file);
    png_read_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
    out->width = png_get_image_width(png, info);
    out->height = png_get_image_height(png, info);
    out->bit_depth = png_get_bit_depth(png, info);
    out->color_type = png_get_color_type(png, info);
    const std::size_t row_bytes = png_get_rowbytes(png, info);
    png_bytepp rows = png_get_rows(png, info);
    out->bytes.resize(row_bytes * out->height);
    for (png_uint_32 y = 0; y < out->height; ++y) {
        std::memcpy(out->bytes.data() + y * row_bytes, rows[y], row_bytes);
    }
    png_textp text = nullptr;
    const int text_count = png_get_text(png, info, &text, nullptr);
    for (int i = 0; i < text_count; ++i) {
        if (std::strcmp(text[i].key, "Software") == 0) {
            out->software = text[i].text;
        }
    }
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
}

DecodedPng read_png(const fs::path& path) {
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (file == nullptr) {
        ADD_FAILURE() << "cannot open " << path;
        return {};
    }
    DecodedPng decoded;
    const bool ok = decode_png(file, &decoded);
    std::fclose(file);
    EXPECT_TRUE(ok) << "libpng could not read " << path;
    return decoded;
}

TEST(PngWriter, Rgb8RoundTripsPixelForPixel) {
    test::TempDir dir;
    const fs::path path = dir.path() / "rgb.png";
    constexpr int kWidth = 7;
    constexpr int kHeight = 5;
    std::vector<std::uint8_t> rgb(std::size_t{kWidth} * kHeight * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i) {
        rgb[i] = static_cast<std::uint8_t>(i * 37 + 11);
    }
    write_png_rgb8(path, kWidth, kHeight, rgb);

    const DecodedPng png = read_png(path);
    EXPECT_EQ(png.width, png_uint_32{kWidth});
    EXPECT_EQ(png.height, png_uint_32{kHeight});
    EXPECT_EQ(png.bit_depth, 8);
    EXPECT_EQ(png.color_type, PNG_COLOR_TYPE_RGB);
    EXPECT_EQ(png.bytes, rgb);
    EXPECT_EQ(png.software.rfind("beamtrace ", 0), 0u) << png.software;
}

TEST(PngWriter, TopRowComesFirst) {
    test::TempDir dir;
    const fs::path path = dir.path() / "rows.png";
    // Row 0 red, row 1 blue.
    const std::vector<std::uint8_t> rgb = {255, 0, 0, 255, 0, 0, 0, 0, 255, 0, 0, 255};
    write_png_rgb8(path, 2, 2, rgb);
    const DecodedPng png = read_png(path);
    ASSERT_EQ(png.bytes.size(), 12u);
    EXPECT_EQ(png.bytes[0], 255);
    EXPECT_EQ(png.bytes[8], 255);
}

// Rows made while the file is written (as preview.png's strips are): each row asked for once, in
// order, before it is compressed; the file's bytes are those of the finished image.
TEST(PngWriter, RowsMadeWhileWrittenGiveTheFinishedImagesBytes) {
    test::TempDir dir;
    constexpr int kWidth = 37;
    constexpr int kHeight = 29;
    const auto pixel = [](std::size_t i) { return static_cast<std::uint8_t>((i * i) % 251); };
    std::vector<std::uint8_t> whole(std::size_t{kWidth} * kHeight * 3);
    for (std::size_t i = 0; i < whole.size(); ++i) {
        whole[i] = pixel(i);
    }
    write_png_rgb8(dir.path() / "whole.png", kWidth, kHeight, whole);

    std::vector<std::uint8_t> rgb(whole.size(), 0);  // each row made when it is asked for
    std::vector<int> asked;
    write_png_rgb8_rows(dir.path() / "rows.png", kWidth, kHeight, rgb, [&](int y) {
        asked.push_back(y);
        const std::size_t row = std::size_t{kWidth} * 3;
        for (std::size_t i = static_cast<std::size_t>(y) * row; i < (y + 1) * row; ++i) {
            rgb[i] = pixel(i);
        }
    });
    ASSERT_EQ(asked.size(), std::size_t{kHeight});
    for (int y = 0; y < kHeight; ++y) {
        EXPECT_EQ(asked[static_cast<std::size_t>(y)], y);
    }
    EXPECT_EQ(test::read_file(dir.path() / "rows.png"), test::read_file(dir.path() / "whole.png"));
    EXPECT_EQ(read_png(dir.path() / "rows.png").bytes, whole);
}

TEST(PngWriter, Gray16RoundTripsWithBigEndianSamples) {
    test::TempDir dir;
    const fs::path path = dir.path() / "gray.png";
    constexpr int kWidth = 4;
    constexpr int kHeight = 3;
    std::vector<std::uint16_t> gray(std::size_t{kWidth} * kHeight);
    for (std::size_t i = 0; i < gray.size(); ++i) {
        gray[i] = static_cast<std::uint16_t>(i * 5000 + 1);
    }
    gray.back() = 0xffff;
    write_png_gray16(path, kWidth, kHeight, gray);

    const DecodedPng png = read_png(path);
    EXPECT_EQ(png.width, png_uint_32{kWidth});
    EXPECT_EQ(png.height, png_uint_32{kHeight});
    EXPECT_EQ(png.bit_depth, 16);
    EXPECT_EQ(png.color_type, PNG_COLOR_TYPE_GRAY);
    ASSERT_EQ(png.bytes.size(), gray.size() * 2);
    for (std::size_t i = 0; i < gray.size(); ++i) {
        const auto value =
            static_cast<std::uint16_t>((png.bytes[2 * i] << 8) | png.bytes[2 * i + 1]);
        EXPECT_EQ(value, gray[i]) << "sample " << i;
    }
}

TEST(PngWriter, SizeMismatchIsAnOutputErrorAndWritesNothing) {
    test::TempDir dir;
    const fs::path path = dir.path() / "bad.png";
    const std::vector<std::uint8_t> rgb(10);
    try {
        write_png_rgb8(path, 2, 2, rgb);
        FAIL() << "expected OutputError";
    } catch (const OutputError& e) {
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
    EXPECT_THROW(write_png_gray16(path, 0, 1, {}), OutputError);
    EXPECT_THROW(write_png_gray16(path, -1, -1, std::vector<std::uint16_t>(1)), OutputError);
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(PngWriter, LibpngErrorsBecomeOutputErrorsAndLeaveNoFile) {
    test::TempDir dir;
    const fs::path path = dir.path() / "too_wide.png";
    // libpng refuses images wider than its default user limit of 1 000 000 pixels.
    constexpr int kWidth = 1'000'001;
    const std::vector<std::uint16_t> gray(kWidth);
    try {
        write_png_gray16(path, kWidth, 1, gray);
        FAIL() << "expected OutputError";
    } catch (const OutputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(path.string()), std::string::npos) << message;
        EXPECT_NE(message.find("libpng"), std::string::npos) << message;
    }
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(PngWriter, MissingFolderIsAnOutputError) {
    test::TempDir dir;
    const std::vector<std::uint8_t> rgb(3);
    EXPECT_THROW(write_png_rgb8(dir.path() / "missing" / "x.png", 1, 1, rgb), OutputError);
}

}  // namespace
}  // namespace beamtrace
