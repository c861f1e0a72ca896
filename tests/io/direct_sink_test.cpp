// DirectSink: large aligned writes (O_DIRECT where the file system has it, the page cache
// elsewhere) give exactly the bytes appended, whatever the sizes of the appends.
#include "io/detail/direct_sink.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "beamtrace/io/atomic_file.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

void expect_round_trip(const std::filesystem::path& dir) {
    std::mt19937 rng(5);
    std::string want;
    const auto path = dir / "out.bin";
    {
        AtomicFile file(path);
        detail::DirectSink sink(file.temp_path(), path);
        // About 21 MB in pieces from 1 byte to 3 MB: several full 8 MiB stages and a tail.
        std::uniform_int_distribution<std::size_t> size(1, 3 << 20);
        while (want.size() < (std::size_t{21} << 20)) {
            std::string piece(size(rng), '\0');
            for (auto& c : piece) {
                c = static_cast<char>(rng());
            }
            sink.append(piece.data(), piece.size());
            want += piece;
            EXPECT_EQ(sink.size(), want.size());
        }
        sink.finish(file.stream());
        file.write("end", 3);  // the stream continues after the data
        want += "end";
        file.commit();
    }
    EXPECT_EQ(test::read_file(path), want);
}

TEST(DirectSink, WritesExactlyTheBytesAppended) {
    test::TempDir dir;
    expect_round_trip(dir.path());
}

TEST(DirectSink, FallsBackWhereDirectIoIsRefused) {
    // tmpfs has no O_DIRECT: the same writes go through the page cache.
    if (!std::filesystem::is_directory("/dev/shm")) {
        BEAMTRACE_SKIP_OR_FAIL("no /dev/shm");
    }
    const auto dir =
        std::filesystem::path("/dev/shm") / ("beamtrace-direct-sink-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    expect_round_trip(dir);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace beamtrace
