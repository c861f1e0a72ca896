// A sink whose output is one file of bytes appended block by block (points.csv, waveforms.bin):
// the encoded blocks go to an AtomicFile, renamed into place at commit().
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include "beamtrace/core/atomic_file.hpp"
#include "beamtrace/io/point_sink.hpp"

namespace beamtrace::detail {

class ByteFileSink : public PointSink {
  public:
    explicit ByteFileSink(const std::filesystem::path& path)
        : file_(std::make_unique<AtomicFile>(path)) {}

    void write(const SinkBuffer& encoded) override {
        file_->write(static_cast<const ByteBuffer&>(encoded).bytes);
    }
    std::vector<std::filesystem::path> commit() override {
        file_->commit();
        return {file_->path()};
    }
    void abort() noexcept override { file_.reset(); }

  protected:
    /// The file, for a header written when the sink opens.
    [[nodiscard]] AtomicFile& file() { return *file_; }

  private:
    std::unique_ptr<AtomicFile> file_;
};

}  // namespace beamtrace::detail
