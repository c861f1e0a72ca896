// DirectSink: large aligned writes (O_DIRECT where the file system has it, the page cache
// elsewhere) give exactly the bytes appended, whatever the sizes of the appends; and the path
// that ran is the one the file system allows. Which file systems take O_DIRECT is asked of the
// kernel here (a probe file opened with O_DIRECT), not assumed: tmpfs takes it since Linux 6.6,
// ramfs never does, so the fallback is checked on a ramfs mounted in a private mount namespace.
#include "io/detail/direct_sink.hpp"

#include <fcntl.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <future>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/core/atomic_file.hpp"
#include "beamtrace/core/error.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr std::size_t kPage = 4096;

/// True when the file system of `dir` accepts O_DIRECT: a file there opens with it and takes an
/// aligned 4 KiB write. Independent of DirectSink, so the sink's report can be checked against it.
bool accepts_o_direct(const std::filesystem::path& dir) {
    const auto probe = dir / ("o-direct-probe-" + std::to_string(::getpid()));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_DIRECT, 0600);
    bool ok = false;
    if (fd >= 0) {
        void* block = std::aligned_alloc(kPage, kPage);
        std::memset(block, 7, kPage);
        ok = ::pwrite(fd, block, kPage, 0) == static_cast<ssize_t>(kPage);
        std::free(block);
        ::close(fd);
    }
    std::error_code ec;
    std::filesystem::remove(probe, ec);
    return ok;
}

/// Pages of `path` in the page cache (mincore of a mapping, which faults nothing in): writes
/// that bypassed the cache leave none behind, buffered writes leave them all.
std::size_t cached_pages(const std::filesystem::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    const auto size = static_cast<std::size_t>(std::filesystem::file_size(path));
    void* map = ::mmap(nullptr, size, PROT_READ, MAP_SHARED, fd, 0);
    ::close(fd);
    if (map == MAP_FAILED) {
        ADD_FAILURE() << "cannot map " << path;
        return 0;
    }
    std::vector<unsigned char> resident((size + kPage - 1) / kPage);
    std::size_t count = 0;
    if (::mincore(map, size, resident.data()) == 0) {
        for (const unsigned char r : resident) {
            count += r & 1u;
        }
    } else {
        ADD_FAILURE() << "mincore failed on " << path;
    }
    ::munmap(map, size);
    return count;
}

struct WriteReport {
    bool bytes_ok = false;  ///< the file holds exactly the bytes appended, then "end"
    bool direct = false;    ///< DirectSink::direct() after the writes
    std::uint64_t direct_bytes = 0;
    std::uint64_t spilled_bytes = 0;  ///< whole stages through the page cache: the disk was behind
    std::uint64_t data_bytes = 0;     ///< bytes appended to the sink
    std::size_t cached_pages = 0;     ///< pages of the file in the page cache before it is read
    std::size_t file_pages = 0;
};

/// About 21 MB in pieces from 1 byte to 3 MB (many full stages and a partly filled last one)
/// through a DirectSink into `dir`/out.bin, then "end" through the stream. No gtest assertions:
/// it also runs in a forked child.
WriteReport write_through_sink(const std::filesystem::path& dir) {
    std::mt19937 rng(5);
    std::string want;
    const auto path = dir / "out.bin";
    WriteReport report;
    bool sizes_ok = true;
    {
        AtomicFile file(path);
        detail::DirectSink sink(file.temp_path(), path);
        std::uniform_int_distribution<std::size_t> size(1, 3 << 20);
        while (want.size() < (std::size_t{21} << 20)) {
            std::string piece(size(rng), '\0');
            for (auto& c : piece) {
                c = static_cast<char>(rng());
            }
            sink.append(piece.data(), piece.size());
            want += piece;
            sizes_ok = sizes_ok && sink.size() == want.size();
        }
        sink.finish(file.stream());
        report.direct = sink.direct();
        report.direct_bytes = sink.direct_bytes();
        report.spilled_bytes = sink.spilled_bytes();
        report.data_bytes = want.size();
        file.write("end", 3);  // the stream continues after the data
        want += "end";
        file.commit();
    }
    report.cached_pages = cached_pages(path);
    report.file_pages = (want.size() + kPage - 1) / kPage;
    std::ifstream in(path, std::ios::binary);
    const std::string got{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    report.bytes_ok = sizes_ok && got == want;
    return report;
}

/// The data's whole stages: what goes through the O_DIRECT descriptor when it is used (the last,
/// partly filled stage goes through the stream).
std::uint64_t aligned(std::uint64_t bytes) {
    return bytes / detail::DirectSink::kStageBytes * detail::DirectSink::kStageBytes;
}

/// Pages of the last, partly filled stage and "end", written through the page cache.
constexpr std::size_t kBufferedPages = detail::DirectSink::kStageBytes / kPage + 2;

TEST(DirectSink, TakesTheDirectPathWhereTheFileSystemAcceptsIt) {
    // /tmp (the temporary folders) and the build tree: ext4 here, which takes O_DIRECT.
    const test::TempDir tmp;
    const std::filesystem::path build = std::filesystem::path(BEAMTRACE_CLI_PATH).parent_path();
    const auto in_build = build / ("direct-sink-test-" + std::to_string(::getpid()));
    std::filesystem::create_directories(in_build);
    int checked = 0;
    for (const std::filesystem::path& dir : {tmp.path(), in_build}) {
        if (!accepts_o_direct(dir)) {
            std::printf("[ o_direct ] %s refuses O_DIRECT\n", dir.c_str());
            continue;
        }
        const WriteReport r = write_through_sink(dir);
        EXPECT_TRUE(r.bytes_ok) << dir;
        EXPECT_TRUE(r.direct) << dir << " takes O_DIRECT but the sink went through the cache";
        // Whole stages directly, but those the disk was too slow for; the first one at least.
        EXPECT_EQ(r.direct_bytes + r.spilled_bytes, aligned(r.data_bytes)) << dir;
        EXPECT_GE(r.direct_bytes, detail::DirectSink::kStageBytes) << dir;
        // Measured, not reported: the direct data bypassed the page cache (the cache holds at
        // most the spilled stages, the last stage and "end").
        EXPECT_LE(r.cached_pages, r.spilled_bytes / kPage + kBufferedPages)
            << dir << ": " << r.cached_pages << " of " << r.file_pages << " pages cached";
        std::printf(
            "[ o_direct ] %s: %s path, %llu of %llu bytes direct (%llu spilled), %zu of %zu "
            "pages cached\n",
            dir.c_str(), r.direct ? "direct" : "buffered",
            static_cast<unsigned long long>(r.direct_bytes),
            static_cast<unsigned long long>(r.data_bytes),
            static_cast<unsigned long long>(r.spilled_bytes), r.cached_pages, r.file_pages);
        ++checked;
    }
    std::filesystem::remove_all(in_build);
    if (checked == 0) {
        BEAMTRACE_SKIP_OR_FAIL("neither /tmp nor the build tree takes O_DIRECT");
    }
}

TEST(DirectSink, FollowsTheKernelOnTmpfs) {
    // tmpfs took no O_DIRECT before Linux 6.6 and takes it since: the sink must do what the
    // kernel allows either way, with the same bytes.
    if (!std::filesystem::is_directory("/dev/shm")) {
        BEAMTRACE_SKIP_OR_FAIL("no /dev/shm");
    }
    const auto dir =
        std::filesystem::path("/dev/shm") / ("beamtrace-direct-sink-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const bool accepts = accepts_o_direct(dir);
    const WriteReport r = write_through_sink(dir);
    std::filesystem::remove_all(dir);
    EXPECT_TRUE(r.bytes_ok);
    EXPECT_EQ(r.direct, accepts);
    EXPECT_EQ(r.direct_bytes + (accepts ? r.spilled_bytes : 0u),
              accepts ? aligned(r.data_bytes) : 0u);
    std::printf("[ o_direct ] /dev/shm (tmpfs) %s O_DIRECT: %s path\n",
                accepts ? "takes" : "refuses", r.direct ? "direct" : "buffered");
}

TEST(DirectSink, StagesTheDiskIsTooSlowForGoThroughThePageCacheWithTheSameBytes) {
    // 64 MiB appended while the disk takes no write (the writing thread held before its first
    // write until every append is done): once every stage is queued, stages go through the page
    // cache on the appending thread instead of waiting, and finish() spills what is still
    // queued. The file is the same either way.
    const test::TempDir tmp;
    if (!accepts_o_direct(tmp.path())) {
        BEAMTRACE_SKIP_OR_FAIL("/tmp refuses O_DIRECT");
    }
    std::string piece(detail::DirectSink::kStageBytes / 3 + 123, '\0');
    std::mt19937 rng(11);
    for (auto& c : piece) {
        c = static_cast<char>(rng());
    }
    const auto path = tmp.path() / "fast.bin";
    std::uint64_t spilled = 0, direct = 0;
    std::size_t pieces = 0;
    {
        AtomicFile file(path);
        std::promise<void> appended;
        std::shared_future<void> disk = appended.get_future().share();
        detail::DirectSink sink(file.temp_path(), path, [disk] { disk.wait(); });
        for (; sink.size() < (std::uint64_t{64} << 20); ++pieces) {
            sink.append(piece.data(), piece.size());
        }
        appended.set_value();
        sink.finish(file.stream());
        spilled = sink.spilled_bytes();
        direct = sink.direct_bytes();
        file.commit();
    }
    const std::uint64_t total = pieces * piece.size();
    // At most the kStages stages held (one filled, the rest queued or being written) went direct.
    EXPECT_GE(spilled,
              aligned(total) - detail::DirectSink::kStages * detail::DirectSink::kStageBytes);
    EXPECT_GT(spilled, 0u);
    EXPECT_EQ(direct + spilled, aligned(total));
    ASSERT_EQ(std::filesystem::file_size(path), total);
    std::ifstream in(path, std::ios::binary);
    std::string got(piece.size(), '\0');
    for (std::size_t k = 0; k < pieces; ++k) {
        in.read(got.data(), static_cast<std::streamsize>(got.size()));
        ASSERT_EQ(got, piece) << "piece " << k << " of " << pieces;
    }
    std::printf("[ o_direct ] tight loop: %llu bytes direct, %llu spilled of %llu\n",
                static_cast<unsigned long long>(direct), static_cast<unsigned long long>(spilled),
                static_cast<unsigned long long>(total));
}

/// Makes this (single-threaded, forked) process the root of a new mount namespace: as root with
/// CLONE_NEWNS alone, otherwise in a new user namespace too. Mounts made there vanish with it.
bool enter_private_mount_namespace() {
    if (::unshare(CLONE_NEWNS) != 0) {
        const std::string uid = "0 " + std::to_string(::getuid()) + " 1";
        const std::string gid = "0 " + std::to_string(::getgid()) + " 1";
        if (::unshare(CLONE_NEWUSER | CLONE_NEWNS) != 0) {
            return false;
        }
        const auto put = [](const char* file, const std::string& text) {
            std::FILE* f = std::fopen(file, "w");
            const bool ok = f != nullptr && std::fputs(text.c_str(), f) >= 0;
            return f != nullptr && std::fclose(f) == 0 && ok;
        };
        if (!put("/proc/self/setgroups", "deny") || !put("/proc/self/uid_map", uid) ||
            !put("/proc/self/gid_map", gid)) {
            return false;
        }
    }
    // Private: the ramfs must not propagate to the parent's namespace.
    return ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) == 0;
}

enum ChildResult : int {
    kFellBack = 0,
    kNoNamespace = 10,
    kNoRamfs = 11,
    kRamfsTookODirect = 12,
    kWentDirect = 20,
    kWrongBytes = 21,
    kThrew = 22,
};

TEST(DirectSink, FallsBackWhereDirectIoIsRefused) {
    // ramfs has no direct I/O at all (open with O_DIRECT fails with EINVAL): mounted in a
    // private mount namespace of a forked child, which writes there and reports by exit code.
    test::TempDir dir;
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        int result = kFellBack;
        try {
            if (!enter_private_mount_namespace()) {
                result = kNoNamespace;
            } else if (::mount("none", dir.path().c_str(), "ramfs", 0, nullptr) != 0) {
                result = kNoRamfs;
            } else if (accepts_o_direct(dir.path())) {
                result = kRamfsTookODirect;
            } else {
                const WriteReport r = write_through_sink(dir.path());
                result = !r.bytes_ok                       ? kWrongBytes
                         : r.direct || r.direct_bytes != 0 ? kWentDirect
                                                           : kFellBack;
            }
        } catch (...) {
            result = kThrew;
        }
        ::_exit(result);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status)) << "child killed by signal " << WTERMSIG(status);
    const int result = WEXITSTATUS(status);
    if (result == kNoNamespace || result == kNoRamfs) {
        BEAMTRACE_SKIP_OR_FAIL(
            "cannot mount a ramfs in a private mount namespace (needs root or "
            "unprivileged user namespaces)");
    }
    EXPECT_NE(result, kRamfsTookODirect) << "ramfs took O_DIRECT: no refusing file system here";
    EXPECT_NE(result, kWentDirect) << "the sink claims the direct path on ramfs";
    EXPECT_NE(result, kWrongBytes) << "the buffered fallback wrote other bytes";
    EXPECT_NE(result, kThrew) << "the write through the fallback threw";
    EXPECT_EQ(result, kFellBack);
    std::printf("[ o_direct ] ramfs refuses O_DIRECT: buffered path, same bytes\n");
}

enum WriteErrorResult : int {
    kThrewEfbig = 0,
    kNoError = 30,
    kOtherError = 31,
    kNoLimit = 32,
};

TEST(DirectSink, AWriteThatFailsBehindTheAppendsIsThrownByTheNextAppendOrFinish) {
    // The stages are written on the sink's own thread: a failure there (a file-size limit, in a
    // forked child with SIGXFSZ ignored, so the write fails with EFBIG) must still reach the
    // caller as an OutputError naming the file, from append() or finish(), never be lost.
    test::TempDir dir;
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        int result = kNoError;
        const rlimit limit{3 * detail::DirectSink::kStageBytes,
                           3 * detail::DirectSink::kStageBytes};
        if (std::signal(SIGXFSZ, SIG_IGN) == SIG_ERR || ::setrlimit(RLIMIT_FSIZE, &limit) != 0) {
            ::_exit(kNoLimit);
        }
        try {
            const auto path = dir.path() / "big.bin";
            AtomicFile file(path);
            detail::DirectSink sink(file.temp_path(), path);
            const std::string piece(100000, 'x');
            for (std::size_t n = 0; n < 10 * detail::DirectSink::kStageBytes; n += piece.size()) {
                sink.append(piece.data(), piece.size());
            }
            sink.finish(file.stream());
        } catch (const OutputError& e) {
            const std::string what = e.what();
            result = what.find("big.bin: write failed: ") != std::string::npos &&
                             what.find(std::strerror(EFBIG)) != std::string::npos
                         ? kThrewEfbig
                         : kOtherError;
            if (result != kThrewEfbig) {
                std::fprintf(stderr, "error: %s\n", what.c_str());
            }
        } catch (...) {
            result = kOtherError;
        }
        ::_exit(result);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status)) << "child killed by signal " << WTERMSIG(status);
    const int result = WEXITSTATUS(status);
    if (result == kNoLimit) {
        BEAMTRACE_SKIP_OR_FAIL("cannot set a file-size limit");
    }
    EXPECT_NE(result, kNoError) << "10 stages written past a 3-stage file-size limit";
    EXPECT_EQ(result, kThrewEfbig);
    // The temporary file went with the AtomicFile: nothing is left.
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace beamtrace
