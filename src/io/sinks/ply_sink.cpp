// points.ply: binary little-endian PLY (write_points_ply's layout, byte for byte), streamed:
// the records go to a temporary body file, the header with the final count is written at commit.
// output.extra_bytes adds one property per attribute after `ray`, named as in LAS
// (extra_columns.hpp).
#include <vector>

#include "beamtrace/io/point_cloud_ply.hpp"
#include "beamtrace/io/point_sink.hpp"
#include "io/sinks/counted_file.hpp"
#include "io/sinks/extra_columns.hpp"

namespace beamtrace {

namespace {

/// points_ply_header with a property line per attribute before end_header.
std::string ply_header(std::size_t count, std::string_view comment,
                       std::span<const PointAttribute> extra) {
    std::string header = points_ply_header(count, comment);
    const std::string end = "end_header\n";
    header.resize(header.size() - end.size());
    for (const PointAttribute a : extra) {
        const char* type = detail::extra_column_ply_type(a);
        header += std::string("property ") + type + " " + detail::extra_column_name(a) + "\n";
    }
    return header + end;
}

class PlySink final : public PointSink {
  public:
    explicit PlySink(const SinkFacts& facts)
        : comment_(facts.comment),
          extra_(facts.extra_bytes),
          record_bytes_(kPlyRecordBytes + detail::extra_columns_bytes(extra_)),
          file_(facts.output_dir / "points.ply") {}

    void encode(const PointBlock& block, SinkBuffer& out) const override {
        std::string& bytes = static_cast<ByteBuffer&>(out).bytes;
        bytes.resize(block.points.size() * record_bytes_);
        char* p = bytes.data();
        for (const BlockPoint& b : block.points) {
            const PointRecord r{b.x,       b.y,    b.z,
                                b.range_m, b.face, static_cast<std::uint32_t>(b.pulse)};
            p = encode_ply_records(std::span(&r, 1), p);
            p = detail::put_extra_columns(extra_, b, p);
        }
    }
    void write(const SinkBuffer& encoded) override {
        const std::string& bytes = static_cast<const ByteBuffer&>(encoded).bytes;
        file_.append(bytes);
        count_ += bytes.size() / record_bytes_;
    }
    std::vector<std::filesystem::path> commit() override {
        file_.commit(ply_header(count_, comment_, extra_));
        return {file_.path()};
    }
    void abort() noexcept override { file_.abort(); }

  private:
    std::string comment_;
    std::vector<PointAttribute> extra_;
    std::size_t record_bytes_;
    detail::CountedFile file_;
    std::size_t count_ = 0;
};

}  // namespace

std::unique_ptr<PointSink> make_ply_sink(const SinkFacts& facts) {
    return std::make_unique<PlySink>(facts);
}

}  // namespace beamtrace
