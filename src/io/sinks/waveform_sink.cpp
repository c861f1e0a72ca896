// waveforms.bin (physics.waveform.keep): the header "BTWAVE01", version, reserved, bin_ns and
// pulse_fwhm_ns, then per pulse its index, time, beam origin and axis, first bin, sample count
// and the samples as float32 (docs/formats.md).
#include <cstring>

#include "beamtrace/io/point_sink.hpp"
#include "io/sinks/byte_file_sink.hpp"

namespace beamtrace {

namespace {

template <typename T>
void append(std::string& out, const T& value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

class WaveformSink final : public detail::ByteFileSink {
  public:
    explicit WaveformSink(const SinkFacts& facts)
        : ByteFileSink(facts.output_dir / "waveforms.bin") {
        std::string header = "BTWAVE01";
        const std::uint32_t version = 1, reserved = 0;
        append(header, version);
        append(header, reserved);
        append(header, facts.waveform->bin_ns);
        append(header, facts.waveform->pulse_fwhm_ns);
        file().write(header);
    }
    void encode(const PointBlock& block, SinkBuffer& out) const override {
        std::string& bytes = static_cast<ByteBuffer&>(out).bytes;
        for (const PulseWaveform& w : block.waveforms) {
            const Vec3d& o = w.origin_m;
            const double pose_record[7] = {w.time_s, o.x, o.y, o.z, w.axis.x, w.axis.y, w.axis.z};
            append(bytes, w.pulse);
            bytes.append(reinterpret_cast<const char*>(pose_record), sizeof pose_record);
            append(bytes, w.first_bin);
            append(bytes, w.count);
            bytes.append(reinterpret_cast<const char*>(block.samples.data() + w.first_sample),
                         4 * std::size_t{w.count});
        }
    }
};

}  // namespace

std::unique_ptr<PointSink> make_waveform_sink(const SinkFacts& facts) {
    return std::make_unique<WaveformSink>(facts);
}

}  // namespace beamtrace
