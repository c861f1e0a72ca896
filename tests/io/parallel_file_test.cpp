// ParallelFile: a file of known size written at offsets by several threads at once, renamed into
// place when complete; on a failure, or with no room for it, nothing is left. StagedRange: one
// range of it filled through a small buffer, in blocks that end on multiples of kBlock.
#include "beamtrace/io/parallel_file.hpp"

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

/// Fills [begin, end) of `file` with `bytes`' same range through a StagedRange, `piece` bytes
/// at a time (at most kSlack), checking that every block it writes out ends on a multiple of
/// kBlock of the file.
void fill_staged(const ParallelFile& file, const std::string& bytes, std::size_t begin,
                 std::size_t end, std::size_t piece) {
    StagedRange out(file, begin);
    char* at = out.begin();
    std::size_t block_end = (begin / StagedRange::kBlock + 1) * StagedRange::kBlock;
    for (std::size_t i = begin; i < end; i += piece) {
        ASSERT_EQ(static_cast<std::size_t>(out.limit() - at), block_end - i);
        const std::size_t n = std::min(piece, end - i);
        std::memcpy(at, bytes.data() + i, n);
        at += n;
        if (at >= out.limit()) {
            at = out.flush(at);
            block_end += StagedRange::kBlock;
        }
    }
    out.finish(at);
}

// Three threads fill interleaved ranges of odd sizes and offsets (not page multiples), each
// through a StagedRange in pieces of a record's size: the file holds exactly the bytes, under
// its final name only after commit(), with its blocks reserved up front.
TEST(ParallelFile, ThreadsFillTheirRangesAndCommitRenamesIntoPlace) {
    test::TempDir dir;
    const std::string expected = random_bytes(3 * 1048576 + 4097, 21);
    const fs::path path = dir / "out.bin";
    ParallelFile file(path, expected.size());
    EXPECT_FALSE(fs::exists(path));
    EXPECT_EQ(fs::file_size(file.temp_path()), expected.size());  // reserved up front
    constexpr std::size_t kRange = 3 * StagedRange::kBlock + 12345;
    const std::size_t ranges = (expected.size() + kRange - 1) / kRange;
    std::vector<std::thread> threads;
    for (std::size_t t = 0; t < 3; ++t) {
        threads.emplace_back([&, t] {
            for (std::size_t k = t; k < ranges; k += 3) {
                fill_staged(file, expected, k * kRange, std::min(expected.size(), (k + 1) * kRange),
                            36 + t);
            }
        });
    }
    for (auto& t : threads) {
        t.join();
    }
    EXPECT_FALSE(fs::exists(path));
    file.commit();
    EXPECT_TRUE(test::read_file(path) == expected);
    EXPECT_EQ(test::entry_count(dir.path()), 1u);  // no temporary file left
}

// A range shorter than a block, and pieces of kSlack that jump over a block's end: the bytes
// past the block move to the front of the buffer and follow it in the file.
TEST(ParallelFile, StagedRangeCarriesTheBytesPastEachBlockOver) {
    test::TempDir dir;
    const std::string expected = random_bytes(2 * StagedRange::kBlock + 3 * 4096 + 5, 7);
    ParallelFile file(dir / "out.bin");
    fill_staged(file, expected, 0, 100, 7);
    fill_staged(file, expected, 100, expected.size(), StagedRange::kSlack);
    file.commit();
    EXPECT_TRUE(test::read_file(dir / "out.bin") == expected);
}

// A failure half-way through the writing: the temporary file goes, the file that was at the
// final path before stays as it was.
TEST(ParallelFile, AFailureMidWriteLeavesNoFileAndThePreviousOneUntouched) {
    test::TempDir dir;
    test::write_file(dir / "out.bin", "the previous run's file\n");
    fs::path temp;
    try {
        ParallelFile file(dir / "out.bin", 1 << 20);
        temp = file.temp_path();
        file.write_at(std::string(1 << 19, 'x'), 4096);
        EXPECT_TRUE(fs::exists(temp));
        throw std::runtime_error("encoder failed");
    } catch (const std::runtime_error&) {
    }
    EXPECT_FALSE(temp.empty());
    EXPECT_FALSE(fs::exists(temp));
    EXPECT_EQ(test::read_file(dir / "out.bin"), "the previous run's file\n");
    EXPECT_EQ(test::entry_count(dir.path()), 1u);
}

TEST(ParallelFile, AMissingFolderIsAnOutputErrorNamingThePath) {
    test::TempDir dir;
    try {
        ParallelFile file(dir / "no" / "such" / "out.bin", 100);
        FAIL() << "no error";
    } catch (const OutputError& e) {
        EXPECT_NE(std::string(e.what()).find((dir / "no" / "such" / "out.bin").string()),
                  std::string::npos)
            << e.what();
    }
}

// No room for the file (a file-size limit, as a full disk or a quota would): an OutputError
// when it is created, before anything is written, and no temporary file. In a child process,
// so that the limit binds nothing else.
TEST(ParallelFile, NoRoomIsAnOutputErrorUpFrontAndLeavesNothing) {
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
            ParallelFile file(path, std::size_t{8} << 20);
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
