// no_echo.csv (output.no_echo): one row per pulse that gave no point, for gap studies:
// pulse,gps_time,ox,oy,oz,dx,dy,dz — the pulse index, its emission time and its beam's origin
// (world metres, as the points are placed) and unit direction (world), every number in its
// shortest round-trip form (a reader gets the doubles back bit for bit), in pulse order. A survey
// with `scanners:` adds a last column, scanner: the index of the scanner that fired the pulse.
#include <charconv>
#include <string>

#include "beamtrace/io/point_sink.hpp"
#include "io/sinks/byte_file_sink.hpp"

namespace beamtrace {

namespace {

/// Longest row: a 20-digit index and 7 shortest doubles (at most 24 characters each).
constexpr std::size_t kMaxRow = 256;

void append_row(std::string& out, const NoEchoPulse& p, bool scanner) {
    char row[kMaxRow];
    char* c = row;
    char* const end = row + kMaxRow;
    c = std::to_chars(c, end, p.pulse).ptr;
    for (const double v :
         {p.time_s, p.origin_m.x, p.origin_m.y, p.origin_m.z, p.axis.x, p.axis.y, p.axis.z}) {
        *c++ = ',';
        c = std::to_chars(c, end, v + 0.0).ptr;  // + 0.0: never "-0"
    }
    if (scanner) {
        *c++ = ',';
        c = std::to_chars(c, end, unsigned{p.scanner}).ptr;
    }
    *c++ = '\n';
    out.append(row, static_cast<std::size_t>(c - row));
}

class NoEchoSink final : public detail::ByteFileSink {
  public:
    explicit NoEchoSink(const SinkFacts& facts)
        : ByteFileSink(facts.output_dir / "no_echo.csv"), scanner_(facts.scanners > 0) {
        file().write(std::string("pulse,gps_time,ox,oy,oz,dx,dy,dz") +
                     (scanner_ ? ",scanner\n" : "\n"));
    }
    void encode(const PointBlock& block, SinkBuffer& out) const override {
        std::string& bytes = static_cast<ByteBuffer&>(out).bytes;
        for (const NoEchoPulse& p : block.no_echo) {
            append_row(bytes, p, scanner_);
        }
    }

  private:
    bool scanner_;  ///< the scanner column (a survey with `scanners:`)
};

}  // namespace

std::unique_ptr<PointSink> make_no_echo_sink(const SinkFacts& facts) {
    return std::make_unique<NoEchoSink>(facts);
}

}  // namespace beamtrace
