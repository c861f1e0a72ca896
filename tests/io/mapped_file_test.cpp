// MappedFile: a file of known size filled in place by several threads through a shared mapping,
// renamed into place when complete; on a failure, or with no room for it, nothing is left.
#include "beamtrace/io/mapped_file.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

std::string random_bytes(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::string s(n, '\0');
    for (char& c : s) {
        c = static_cast<char>(rng() & 0xff);
    }
    return s;
}

// Three threads fill interleaved pieces of odd sizes (not page multiples): the file holds
// exactly the bytes, under its final name only after commit(). The same through the buffer of
// file systems that cannot map files.
TEST(MappedFile, ThreadsFillTheirRangesAndCommitRenamesIntoPlace) {
    test::TempDir dir;
    const std::string expected = random_bytes(3 * 1048576 + 4097, 21);
    for (const bool buffered : {false, true}) {
        const fs::path path = dir / (buffered ? "buffered.bin" : "mapped.bin");
        MappedFile file(path, expected.size(), buffered);
        EXPECT_EQ(file.mapped(), !buffered);
        ASSERT_EQ(file.bytes().size(), expected.size());
        EXPECT_EQ(file.bytes()[12345], 0);
        EXPECT_FALSE(fs::exists(path));
        EXPECT_EQ(fs::file_size(file.temp_path()), expected.size());  // reserved up front
        constexpr std::size_t kPiece = 65536 + 37;
        const std::size_t pieces = (expected.size() + kPiece - 1) / kPiece;
        std::vector<std::thread> threads;
        for (std::size_t t = 0; t < 3; ++t) {
            threads.emplace_back([&, t] {
                for (std::size_t k = t; k < pieces; k += 3) {
                    const std::size_t n = std::min(kPiece, expected.size() - k * kPiece);
                    // The fault-in hint before a piece, and over written neighbours and past
                    // the end after it, changes no byte.
                    file.prefault(k * kPiece, n);
                    std::memcpy(file.bytes().data() + k * kPiece, expected.data() + k * kPiece, n);
                    file.prefault(k * kPiece > 5000 ? k * kPiece - 5000 : 0, n + 10000);
                }
            });
        }
        for (auto& t : threads) {
            t.join();
        }
        file.prefault(expected.size() + 1, 4096);
        EXPECT_FALSE(fs::exists(path));
        file.commit();
        file.prefault(0, expected.size());  // after commit: nothing mapped, nothing happens
        EXPECT_TRUE(file.bytes().empty());
        EXPECT_TRUE(test::read_file(path) == expected) << "buffered " << buffered;
        EXPECT_THROW(file.commit(), OutputError);
    }
    EXPECT_EQ(test::entry_count(dir.path()), 2u);  // no temporary file left
}

TEST(MappedFile, AnEmptyFileNeedsNoMapping) {
    test::TempDir dir;
    MappedFile file(dir / "empty", 0);
    EXPECT_TRUE(file.bytes().empty());
    file.commit();
    EXPECT_EQ(test::read_file(dir / "empty"), "");
    EXPECT_EQ(test::entry_count(dir.path()), 1u);
}

// A failure half-way through the writing: the temporary file goes, the file that was at the
// final path before stays as it was.
TEST(MappedFile, AFailureMidWriteLeavesNoFileAndThePreviousOneUntouched) {
    test::TempDir dir;
    test::write_file(dir / "out.bin", "the previous run's file\n");
    for (const bool buffered : {false, true}) {
        fs::path temp;
        try {
            MappedFile file(dir / "out.bin", 1 << 20, buffered);
            temp = file.temp_path();
            std::memset(file.bytes().data(), 'x', 1 << 19);
            EXPECT_TRUE(fs::exists(temp));
            throw std::runtime_error("encoder failed");
        } catch (const std::runtime_error&) {
        }
        EXPECT_FALSE(temp.empty());
        EXPECT_FALSE(fs::exists(temp));
        EXPECT_EQ(test::read_file(dir / "out.bin"), "the previous run's file\n");
        EXPECT_EQ(test::entry_count(dir.path()), 1u);
    }
}

TEST(MappedFile, AMissingFolderIsAnOutputErrorNamingThePath) {
    test::TempDir dir;
    try {
        MappedFile file(dir / "no" / "such" / "out.bin", 100);
        FAIL() << "no error";
    } catch (const OutputError& e) {
        EXPECT_NE(std::string(e.what()).find((dir / "no" / "such" / "out.bin").string()),
                  std::string::npos)
            << e.what();
    }
}

// No room for the file (a file-size limit, as a full disk or a quota would): an OutputError
// when it is created, never a SIGBUS on a store, and no temporary file. In a child process, so
// that the limit binds nothing else.
TEST(MappedFile, NoRoomIsAnOutputErrorUpFrontAndLeavesNothing) {
    test::TempDir dir;
    const fs::path path = dir / "big.bin";
    const fs::path message =
        dir.path().parent_path() / (dir.path().filename().string() + ".message");
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        std::signal(SIGXFSZ, SIG_IGN);  // exceeding the limit fails with EFBIG instead
        const rlimit limit{65536, 65536};
        ::setrlimit(RLIMIT_FSIZE, &limit);
        int code = 1;
        try {
            MappedFile file(path, std::size_t{8} << 20);
        } catch (const OutputError& e) {
            test::write_file(message, e.what());
            code = 0;
        } catch (...) {
            code = 2;
        }
        ::_exit(code);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << WTERMSIG(status);
    ASSERT_EQ(WEXITSTATUS(status), 0);
    const std::string what = test::read_file(message);
    fs::remove(message);
    EXPECT_NE(what.find(path.string() + ": cannot reserve 8388608 bytes: "), std::string::npos)
        << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
    EXPECT_EQ(test::entry_count(dir.path()), 0u);
}

}  // namespace
}  // namespace beamtrace
