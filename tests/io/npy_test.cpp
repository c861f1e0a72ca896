#include "beamtrace/io/npy.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

/// Expects reading `path` to fail with an InputError naming it; returns the message.
std::string expect_input_error(const fs::path& path) {
    return test::expect_input_error(read_npy_f32, path);
}

TEST(Npy, RoundTripKeepsShapeAndBits) {
    test::TempDir dir;
    const fs::path path = dir.path() / "a.npy";
    std::vector<float> data = {0.0f,
                               -0.0f,
                               1.5f,
                               -3.25e-7f,
                               std::numeric_limits<float>::infinity(),
                               std::numeric_limits<float>::max(),
                               std::numeric_limits<float>::denorm_min(),
                               42.0f,
                               7.0f,
                               8.0f,
                               9.0f,
                               10.0f};
    write_npy_f32(path, 3, 4, data);
    const NpyArray array = read_npy_f32(path);
    EXPECT_EQ(array.shape, (std::vector<std::size_t>{3, 4}));
    ASSERT_EQ(array.data.size(), data.size());
    EXPECT_EQ(std::memcmp(array.data.data(), data.data(), data.size() * sizeof(float)), 0);
}

TEST(Npy, HeaderBytesAreExact) {
    test::TempDir dir;
    const fs::path path = dir.path() / "h.npy";
    const std::vector<float> data(12, 1.0f);
    write_npy_f32(path, 3, 4, data);
    const std::string bytes = test::read_file(path);

    ASSERT_GE(bytes.size(), 10u);
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
    const std::size_t header_len =
        std::size_t(std::uint8_t(bytes[8])) | (std::size_t(std::uint8_t(bytes[9])) << 8);
    EXPECT_EQ((10 + header_len) % 64, 0u);
    ASSERT_EQ(bytes.size(), 10 + header_len + data.size() * sizeof(float));

    const std::string header = bytes.substr(10, header_len);
    const std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (3, 4), }";
    EXPECT_EQ(header.substr(0, dict.size()), dict);
    EXPECT_EQ(header.back(), '\n');
    EXPECT_EQ(header.find_first_not_of(' ', dict.size()), header_len - 1);
    EXPECT_EQ(header_len, 118u);  // 10 + 118 = 128: the dict is too long for 64 bytes
}

TEST(Npy, EmptyArrayIsValid) {
    test::TempDir dir;
    const fs::path path = dir.path() / "empty.npy";
    write_npy_f32(path, 0, 5, {});
    const NpyArray array = read_npy_f32(path);
    EXPECT_EQ(array.shape, (std::vector<std::size_t>{0, 5}));
    EXPECT_TRUE(array.data.empty());
}

TEST(Npy, SizeMismatchIsAnOutputError) {
    test::TempDir dir;
    const std::vector<float> data(5);
    EXPECT_THROW(write_npy_f32(dir.path() / "x.npy", 2, 3, data), OutputError);
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(Npy, ReadsOtherShapesAndVersion2) {
    test::TempDir dir;
    const fs::path path = dir.path() / "v2.npy";
    std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (2,), }";
    dict += "   \n";
    std::string bytes("\x93NUMPY\x02\x00", 8);
    bytes += static_cast<char>(dict.size());
    bytes += std::string(3, '\0');
    bytes += dict;
    const float values[2] = {1.0f, -2.0f};
    bytes.append(reinterpret_cast<const char*>(values), sizeof values);
    test::write_file(path, bytes);
    const NpyArray array = read_npy_f32(path);
    EXPECT_EQ(array.shape, (std::vector<std::size_t>{2}));
    EXPECT_EQ(array.data, (std::vector<float>{1.0f, -2.0f}));
}

TEST(Npy, BrokenFilesAreInputErrorsNamingTheFile) {
    test::TempDir dir;
    const fs::path good = dir.path() / "good.npy";
    write_npy_f32(good, 2, 2, std::vector<float>{1, 2, 3, 4});
    const std::string bytes = test::read_file(good);

    const fs::path missing = dir.path() / "missing.npy";
    expect_input_error(missing);

    const fs::path magic = dir.path() / "magic.npy";
    test::write_file(magic, "PK\x03\x04 not numpy at all");
    EXPECT_NE(expect_input_error(magic).find("magic"), std::string::npos);

    const fs::path truncated = dir.path() / "truncated.npy";
    test::write_file(truncated, bytes.substr(0, bytes.size() - 1));
    EXPECT_NE(expect_input_error(truncated).find("bytes"), std::string::npos);

    const fs::path f8 = dir.path() / "f8.npy";
    std::string wrong_type = bytes;
    wrong_type.replace(wrong_type.find("<f4"), 3, "<f8");
    test::write_file(f8, wrong_type);
    EXPECT_NE(expect_input_error(f8).find("'<f8'"), std::string::npos);

    const fs::path fortran = dir.path() / "fortran.npy";
    std::string fortran_order = bytes;
    fortran_order.replace(fortran_order.find("False"), 5, "True ");
    test::write_file(fortran, fortran_order);
    EXPECT_NE(expect_input_error(fortran).find("Fortran"), std::string::npos);

    const fs::path short_header = dir.path() / "short_header.npy";
    test::write_file(short_header, bytes.substr(0, 40));
    expect_input_error(short_header);
}

}  // namespace
}  // namespace beamtrace
