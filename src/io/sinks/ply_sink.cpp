// points.ply: binary little-endian PLY (write_points_ply's layout, byte for byte), streamed:
// the records go to a temporary body file, the header with the final count is written at commit.
#include "beamtrace/io/point_cloud_ply.hpp"
#include "beamtrace/io/point_sink.hpp"
#include "io/sinks/counted_file.hpp"

namespace beamtrace {

namespace {

class PlySink final : public PointSink {
  public:
    explicit PlySink(const SinkFacts& facts)
        : comment_(facts.comment), file_(facts.output_dir / "points.ply") {}

    void encode(const PointBlock& block, SinkBuffer& out) const override {
        std::string& bytes = static_cast<ByteBuffer&>(out).bytes;
        bytes.resize(block.points.size() * kPlyRecordBytes);
        char* p = bytes.data();
        for (const BlockPoint& b : block.points) {
            const PointRecord r{b.x,       b.y,    b.z,
                                b.range_m, b.face, static_cast<std::uint32_t>(b.pulse)};
            p = encode_ply_records(std::span(&r, 1), p);
        }
    }
    void write(const SinkBuffer& encoded) override {
        const std::string& bytes = static_cast<const ByteBuffer&>(encoded).bytes;
        file_.append(bytes);
        count_ += bytes.size() / kPlyRecordBytes;
    }
    std::vector<std::filesystem::path> commit() override {
        file_.commit(points_ply_header(count_, comment_));
        return {file_.path()};
    }
    void abort() noexcept override { file_.abort(); }

  private:
    std::string comment_;
    detail::CountedFile file_;
    std::size_t count_ = 0;
};

}  // namespace

std::unique_ptr<PointSink> make_ply_sink(const SinkFacts& facts) {
    return std::make_unique<PlySink>(facts);
}

}  // namespace beamtrace
