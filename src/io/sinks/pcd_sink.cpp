// points.pcd: Point Cloud Library PCD v0.7, binary, fields x y z (F 8, world metres),
// intensity (U 2), return_number, number_of_returns, classification (U 1), gps_time (F 8),
// range (F 4), ring (U 2: the beam); one 43-byte record per point (docs/formats.md).
// output.extra_bytes adds one field per attribute after `ring`, named as in LAS: F 4 for
// measurements, U 2 beam, U 4 object_id (extra_columns.hpp).
#include <cstring>
#include <string>
#include <vector>

#include "beamtrace/io/point_sink.hpp"
#include "io/sinks/counted_file.hpp"
#include "io/sinks/extra_columns.hpp"

namespace beamtrace {

namespace {

constexpr std::size_t kPcdRecordBytes = 3 * 8 + 2 + 3 * 1 + 8 + 4 + 2;
static_assert(kPcdRecordBytes == 43);  // packed, as PCL reads it

template <typename T>
char* put(char* out, const T& value) {
    std::memcpy(out, &value, sizeof value);
    return out + sizeof value;
}

std::string pcd_header(std::size_t count, std::span<const PointAttribute> extra) {
    std::string fields =
        "x y z intensity return_number number_of_returns classification gps_time "
        "range ring";
    std::string sizes = "8 8 8 2 1 1 1 8 4 2", types = "F F F U U U U F F U",
                counts = "1 1 1 1 1 1 1 1 1 1";
    for (const PointAttribute a : extra) {
        fields += " " + detail::extra_column_name(a);
        sizes += " " + std::to_string(detail::extra_column_bytes(a));
        types += detail::extra_column_is_integer(a) ? " U" : " F";
        counts += " 1";
    }
    const std::string n = std::to_string(count);
    return "# .PCD v0.7 - Point Cloud Data file format (beamtrace " BEAMTRACE_VERSION
           ")\n"
           "VERSION 0.7\nFIELDS " +
           fields + "\nSIZE " + sizes + "\nTYPE " + types + "\nCOUNT " + counts + "\nWIDTH " + n +
           "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n + "\nDATA binary\n";
}

class PcdSink final : public PointSink {
  public:
    explicit PcdSink(const SinkFacts& facts)
        : extra_(facts.extra_bytes),
          record_bytes_(kPcdRecordBytes + detail::extra_columns_bytes(extra_)),
          file_(facts.output_dir / "points.pcd") {}

    void encode(const PointBlock& block, SinkBuffer& out) const override {
        std::string& bytes = static_cast<ByteBuffer&>(out).bytes;
        bytes.resize(block.points.size() * record_bytes_);
        char* c = bytes.data();
        for (const BlockPoint& p : block.points) {
            c = put(put(put(c, p.x), p.y), p.z);
            c = put(put(put(put(c, p.intensity), p.return_number), p.number_of_returns),
                    p.classification);
            c = put(put(put(c, p.gps_time), p.range_m), p.channel);
            c = detail::put_extra_columns(extra_, p, c);
        }
    }
    void write(const SinkBuffer& encoded) override {
        const std::string& bytes = static_cast<const ByteBuffer&>(encoded).bytes;
        file_.append(bytes);
        count_ += bytes.size() / record_bytes_;
    }
    std::vector<std::filesystem::path> commit() override {
        file_.commit(pcd_header(count_, extra_));
        return {file_.path()};
    }
    void abort() noexcept override { file_.abort(); }

  private:
    std::vector<PointAttribute> extra_;
    std::size_t record_bytes_;
    detail::CountedFile file_;
    std::size_t count_ = 0;
};

}  // namespace

std::unique_ptr<PointSink> make_pcd_sink(const SinkFacts& facts) {
    return std::make_unique<PcdSink>(facts);
}

}  // namespace beamtrace
