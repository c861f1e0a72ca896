#include "beamtrace/core/atomic_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <iterator>
#include <stdexcept>
#include <string>

#include "beamtrace/core/error.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

using test::entry_count;

TEST(AtomicFile, CommitPublishesTheContentAndLeavesNoTempFile) {
    test::TempDir dir;
    const fs::path target = dir.path() / "out.bin";
    {
        AtomicFile out(target);
        out.write("hello ", 6);
        out.write(std::string_view("world"));
        EXPECT_FALSE(fs::exists(target));
        EXPECT_TRUE(fs::exists(out.temp_path()));
        out.commit();
        EXPECT_TRUE(out.committed());
        EXPECT_EQ(out.stream(), nullptr);
    }
    EXPECT_EQ(test::read_file(target), "hello world");
    EXPECT_EQ(entry_count(dir.path()), 1u);
}

TEST(AtomicFile, TempFileIsHiddenNextToTheTarget) {
    test::TempDir dir;
    AtomicFile out(dir.path() / "image.png");
    EXPECT_EQ(out.temp_path().parent_path(), dir.path());
    EXPECT_EQ(out.temp_path().filename().string(),
              ".image.png." + std::to_string(::getpid()) + ".tmp");
    EXPECT_EQ(out.path(), dir.path() / "image.png");
}

TEST(AtomicFile, WithoutCommitNothingAppearsAndTheTempFileIsRemoved) {
    test::TempDir dir;
    const fs::path target = dir.path() / "out.bin";
    fs::path temp;
    {
        AtomicFile out(target);
        temp = out.temp_path();
        out.write("partial", 7);
    }
    EXPECT_FALSE(fs::exists(target));
    EXPECT_FALSE(fs::exists(temp));
    EXPECT_EQ(entry_count(dir.path()), 0u);
}

TEST(AtomicFile, AnExceptionWhileWritingKeepsThePreviousFile) {
    test::TempDir dir;
    const fs::path target = dir.path() / "out.txt";
    {
        AtomicFile first(target);
        first.write(std::string_view("old"));
        first.commit();
    }
    EXPECT_THROW(
        {
            AtomicFile out(target);
            out.write(std::string_view("new but incomplete"));
            throw std::runtime_error("simulated failure");
        },
        std::runtime_error);
    EXPECT_EQ(test::read_file(target), "old");
    EXPECT_EQ(entry_count(dir.path()), 1u);
}

TEST(AtomicFile, CommitReplacesAnExistingFile) {
    test::TempDir dir;
    const fs::path target = dir.path() / "out.txt";
    test::write_file(target, "previous content that is longer");
    AtomicFile out(target, /*fsync_on_commit=*/true);
    out.write(std::string_view("new"));
    out.commit();
    EXPECT_EQ(test::read_file(target), "new");
}

TEST(AtomicFile, TwoWritersOfTheSameTargetUseDistinctTempFiles) {
    test::TempDir dir;
    const fs::path target = dir.path() / "out.txt";
    AtomicFile a(target);
    AtomicFile b(target);
    EXPECT_NE(a.temp_path(), b.temp_path());
    a.write(std::string_view("a"));
    b.write(std::string_view("b"));
    a.commit();
    b.commit();
    EXPECT_EQ(test::read_file(target), "b");
    EXPECT_EQ(entry_count(dir.path()), 1u);
}

TEST(AtomicFile, MissingFolderIsAnOutputErrorNamingThePath) {
    test::TempDir dir;
    const fs::path target = dir.path() / "no" / "such" / "folder" / "out.txt";
    try {
        AtomicFile out(target);
        FAIL() << "expected OutputError";
    } catch (const OutputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(target.string()), std::string::npos) << message;
        EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
    }
}

TEST(AtomicFile, RenameFailureIsAnOutputErrorAndRemovesTheTempFile) {
    test::TempDir dir;
    const fs::path target = dir.path() / "taken";
    fs::create_directories(target / "child");  // a non-empty folder cannot be replaced
    fs::path temp;
    try {
        AtomicFile out(target);
        temp = out.temp_path();
        out.write(std::string_view("data"));
        out.commit();
        FAIL() << "expected OutputError";
    } catch (const OutputError& e) {
        EXPECT_NE(std::string(e.what()).find(target.string()), std::string::npos) << e.what();
    }
    EXPECT_FALSE(temp.empty());
    EXPECT_FALSE(fs::exists(temp));
    EXPECT_TRUE(fs::is_directory(target / "child"));
}

TEST(AtomicFile, WriteAfterCommitThrows) {
    test::TempDir dir;
    AtomicFile out(dir.path() / "out.txt");
    out.commit();
    EXPECT_THROW(out.write("x", 1), OutputError);
    EXPECT_THROW(out.commit(), OutputError);
}

TEST(AtomicFile, EmptyFileIsFine) {
    test::TempDir dir;
    const fs::path target = dir.path() / "empty";
    AtomicFile out(target);
    out.write(nullptr, 0);
    out.commit();
    EXPECT_TRUE(fs::exists(target));
    EXPECT_EQ(fs::file_size(target), 0u);
}

TEST(AtomicFile, LargeWritesArriveIntact) {
    test::TempDir dir;
    const fs::path target = dir.path() / "big.bin";
    std::string block(3 << 20, '\0');
    for (std::size_t i = 0; i < block.size(); ++i) {
        block[i] = static_cast<char>(i * 7 + i / 251);
    }
    AtomicFile out(target);
    out.write(block.data(), 10);
    out.write(block.data() + 10, block.size() - 10);
    out.commit();
    EXPECT_EQ(test::read_file(target), block);
}

}  // namespace
}  // namespace beamtrace
