// read_bounded_file: config and trajectory files are regular files within a size limit
// (issue 15, finding 8), refused with little memory otherwise.
#include "text/file_bytes.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "beamtrace/core/error.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

std::string input_error(const std::filesystem::path& path, std::size_t limit) {
    try {
        (void)detail::read_bounded_file(path, "scene file", limit);
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "accepted " << path;
    return {};
}

TEST(ReadBoundedFile, ReadsARegularFileUpToTheLimit) {
    test::TempDir dir;
    test::write_file(dir / "a.yaml", "0123456789");
    EXPECT_EQ(detail::read_bounded_file(dir / "a.yaml", "scene file", 10), "0123456789");
    test::write_file(dir / "empty.yaml", "");
    EXPECT_EQ(detail::read_bounded_file(dir / "empty.yaml", "scene file", 10), "");
}

TEST(ReadBoundedFile, RefusesFilesOverTheLimitNamingFileAndLimit) {
    test::TempDir dir;
    test::write_file(dir / "a.yaml", "0123456789!");
    EXPECT_EQ(input_error(dir / "a.yaml", 10),
              (dir / "a.yaml").string() +
                  ": the scene file is larger than the limit of 10 bytes for scene files");
    test::write_file(dir / "b.yaml", "");
    std::filesystem::resize_file(dir / "b.yaml", std::size_t{65} << 20);
    EXPECT_EQ(input_error(dir / "b.yaml", detail::kMaxConfigFileBytes),
              (dir / "b.yaml").string() +
                  ": the scene file is larger than the limit of 64 MiB for scene files");
}

TEST(ReadBoundedFile, RefusesDevicesFoldersAndMissingFiles) {
    test::TempDir dir;
    EXPECT_EQ(input_error("/dev/zero", 1 << 20), "/dev/zero: the scene file is not a regular file");
    EXPECT_EQ(input_error(dir.path(), 1 << 20),
              dir.path().string() + ": the scene file is not a regular file (a directory)");
    EXPECT_NE(input_error(dir / "none.yaml", 1 << 20).find("cannot open the scene file: "),
              std::string::npos);
}

}  // namespace
}  // namespace beamtrace
