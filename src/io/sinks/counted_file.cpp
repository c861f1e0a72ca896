#include "io/sinks/counted_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"

namespace beamtrace::detail {

namespace {
constexpr std::size_t kCopyBytes = std::size_t{1} << 20;
}

CountedFile::CountedFile(std::filesystem::path path)
    : path_(std::move(path)),
      body_(std::make_unique<AtomicFile>(path_.parent_path() /
                                         (path_.filename().string() + ".body"))) {}

void CountedFile::commit(std::string_view header) {
    if (!body_) {
        throw OutputError(path_.string() + ": commit after abort or commit");
    }
    if (std::fflush(body_->stream()) != 0 || std::ferror(body_->stream()) != 0) {
        throw OutputError(path_.string() + ": write failed: " + std::strerror(errno));
    }
    std::FILE* in = std::fopen(body_->temp_path().c_str(), "rb");
    if (in == nullptr) {
        throw OutputError(path_.string() + ": cannot read back " + body_->temp_path().string() +
                          ": " + std::strerror(errno));
    }
    const std::unique_ptr<std::FILE, int (*)(std::FILE*)> closer(in, &std::fclose);
    AtomicFile out(path_);
    out.write(header);
    std::vector<char> chunk(kCopyBytes);
    for (;;) {
        const std::size_t n = std::fread(chunk.data(), 1, chunk.size(), in);
        out.write(chunk.data(), n);
        if (n < chunk.size()) {
            break;
        }
    }
    if (std::ferror(in) != 0) {
        throw OutputError(path_.string() + ": cannot read back " + body_->temp_path().string());
    }
    out.commit();
    body_.reset();
}

}  // namespace beamtrace::detail
