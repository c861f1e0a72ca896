// points.csv: one row per point (x,y,z,gps_time,range_m,classification,point_source_id,beam,
// scan_angle_deg and, with physics, intensity,return_number,number_of_returns), shortest
// round-trip numbers, streamed.
#include <charconv>
#include <string>

#include "beamtrace/io/point_sink.hpp"
#include "io/sinks/byte_file_sink.hpp"

namespace beamtrace {

namespace {

/// Longest CSV row: 3 doubles, a double time, a float, 3 + 3 integers, a float (to_chars
/// shortest forms, 24 characters at most each).
constexpr std::size_t kMaxCsvRow = 400;

/// Appends one CSV row to `out`.
void append_csv_row(std::string& out, const BlockPoint& p, bool physics) {
    char row[kMaxCsvRow];
    char* c = row;
    char* const end = row + kMaxCsvRow;
    const auto num = [&](double v) {
        c = std::to_chars(c, end, v).ptr;
        *c++ = ',';
    };
    num(p.x);
    num(p.y);
    num(p.z);
    num(p.gps_time);
    c = std::to_chars(c, end, p.range_m).ptr;
    *c++ = ',';
    for (unsigned v :
         {unsigned{p.classification}, unsigned{p.point_source_id}, unsigned{p.channel}}) {
        c = std::to_chars(c, end, v).ptr;
        *c++ = ',';
    }
    c = std::to_chars(c, end, p.scan_angle_deg).ptr;
    if (physics) {
        for (unsigned v :
             {unsigned{p.intensity}, unsigned{p.return_number}, unsigned{p.number_of_returns}}) {
            *c++ = ',';
            c = std::to_chars(c, end, v).ptr;
        }
    }
    *c++ = '\n';
    out.append(row, static_cast<std::size_t>(c - row));
}

class CsvSink final : public detail::ByteFileSink {
  public:
    explicit CsvSink(const SinkFacts& facts)
        : ByteFileSink(facts.output_dir / "points.csv"), physics_(facts.physics) {
        file().write(
            std::string(
                "x,y,z,gps_time,range_m,classification,point_source_id,beam,scan_angle_deg") +
            (physics_ ? ",intensity,return_number,number_of_returns" : "") + "\n");
    }
    void encode(const PointBlock& block, SinkBuffer& out) const override {
        std::string& bytes = static_cast<ByteBuffer&>(out).bytes;
        for (const BlockPoint& p : block.points) {
            append_csv_row(bytes, p, physics_);
        }
    }

  private:
    bool physics_;
};

}  // namespace

std::unique_ptr<PointSink> make_csv_sink(const SinkFacts& facts) {
    return std::make_unique<CsvSink>(facts);
}

}  // namespace beamtrace
