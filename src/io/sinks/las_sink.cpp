// points.las: LAS 1.4 (formats 6-8), coordinates quantised to 1 mm around the scene, the
// scene's CRS in an OGC WKT VLR when it has one, the provenance (version, seed, survey file) in a
// VLR, the extra bytes of output.extra_bytes with their Extra Bytes VLR. Records are encoded on
// the pool threads (or the survey's writer thread of its own). points.laz: the same file,
// LASzip-compressed.
#include <algorithm>
#include <span>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_crs.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "beamtrace/io/point_sink.hpp"
#include "beamtrace/io/survey_las.hpp"
#include "io/sinks/wave_packet_stream.hpp"

namespace beamtrace {

namespace {

/// Longest VLR payload recorded (a VLR holds less than 64 KiB).
constexpr std::size_t kMaxProvenance = 60000;

struct LasBuffer final : SinkBuffer {
    /// Mutable: write() completes the wave packet offsets, which only it knows.
    mutable LasRecordBlock block;
    std::string packets;  ///< the block's wave packets (formats 9, 10)
    void clear() override {
        block.clear();
        packets.clear();
    }
};

/// The wave packets of formats 9 and 10 (none for the others).
std::unique_ptr<detail::WavePacketStream> wave_packets(const SinkFacts& facts) {
    if (!facts.waveform || !las_format_has_wave_packet(facts.las_point_format)) {
        return nullptr;
    }
    return std::make_unique<detail::WavePacketStream>(facts.output_dir / "points.las",
                                                      *facts.waveform);
}

LasWriterConfig las_config(const SinkFacts& facts, const detail::WavePacketStream* waves,
                           LasCompression compression) {
    LasWriterConfig las = las_config_for_extent(facts.lo_m, facts.hi_m, 0.001);
    las.compression = compression;
    las.point_format = facts.las_point_format;
    if (!facts.crs_wkt.empty()) {
        las.vlrs.push_back(las_wkt_vlr(facts.crs_wkt));
    }
    LasVlr vlr;
    vlr.user_id = "beamtrace";
    vlr.record_id = 1;
    vlr.description = "survey file";
    const std::string& record = facts.provenance;
    vlr.data.assign(record.begin(),
                    record.begin() + static_cast<std::ptrdiff_t>(
                                         std::min<std::size_t>(record.size(), kMaxProvenance)));
    las.vlrs.push_back(std::move(vlr));
    if (!facts.extra_bytes.empty()) {
        std::vector<LasExtraBytesDescriptor> fields;
        for (const PointAttribute a : facts.extra_bytes) {
            fields.push_back(point_attribute_descriptor(a));
        }
        las.extra_bytes_per_point = static_cast<std::uint16_t>(las_extra_bytes_size(fields));
        las.vlrs.push_back(las_extra_bytes_vlr(fields));
    }
    if (waves != nullptr) {
        las.waveform_storage = facts.waveform->storage;
        for (auto& d : waves->vlrs()) {
            las.vlrs.push_back(std::move(d));
        }
    }
    return las;
}

class LasSink final : public PointSink {
  public:
    explicit LasSink(const SinkFacts& facts)
        : extra_(facts.extra_bytes),
          waves_(wave_packets(facts)),
          writer_(
              std::make_unique<LasWriter>(facts.output_dir / "points.las",
                                          las_config(facts, waves_.get(), LasCompression::none))) {}
    /// points.laz: no wave packets (the survey refuses `laz` with kept waveforms).
    LasSink(const SinkFacts& facts, LasCompression compression)
        : extra_(facts.extra_bytes),
          writer_(std::make_unique<LasWriter>(facts.output_dir / "points.laz",
                                              las_config(facts, nullptr, compression))) {}

    [[nodiscard]] std::unique_ptr<SinkBuffer> make_buffer() const override {
        return std::make_unique<LasBuffer>();
    }
    void encode(const PointBlock& block, SinkBuffer& out) const override {
        LasRecordBlock& las = static_cast<LasBuffer&>(out).block;
        // Room for the whole block at once (kept from block to block).
        const std::size_t most = block.points.size() * writer_->header().point_record_length;
        if (las.bytes.size() < most) {
            las.bytes.resize(most);
        }
        if (waves_) {
            waves_->encode(block, *writer_, las, static_cast<LasBuffer&>(out).packets);
        } else {
            writer_->encode_points(std::span<const BlockPoint>(block.points), las);
        }
        encode_las_extra_bytes(extra_, block.points, *writer_, las);
    }
    void write(const SinkBuffer& encoded) override {
        const auto& buffer = static_cast<const LasBuffer&>(encoded);
        if (waves_) {
            waves_->write(*writer_, buffer.block, buffer.packets);
        }
        writer_->write_block(buffer.block);
    }
    std::vector<std::filesystem::path> commit() override {
        if (waves_) {
            return waves_->commit(*writer_);
        }
        writer_->close();
        return {writer_->path()};
    }
    void abort() noexcept override {
        writer_.reset();
        waves_.reset();
    }

  private:
    std::vector<PointAttribute> extra_;
    std::unique_ptr<detail::WavePacketStream> waves_;
    std::unique_ptr<LasWriter> writer_;
};

}  // namespace

void encode_las_extra_bytes(std::span<const PointAttribute> attributes,
                            std::span<const BlockPoint> points, const LasWriter& writer,
                            LasRecordBlock& records) {
    if (attributes.empty()) {
        return;
    }
    const std::size_t length = writer.header().point_record_length;
    const std::size_t field = las_point_record_size(writer.header().point_format);
    std::uint8_t* r = records.bytes.data() + (records.count - points.size()) * length + field;
    for (const BlockPoint& p : points) {
        encode_point_attributes(
            attributes,
            {p.range_m, p.incidence_deg, p.echo_width_ns, p.channel, p.point_source_id,
             p.instance_id, Vec3d(p.velocity_mps), p.weather},
            r);
        r += length;
    }
}

LasWriterConfig survey_las_config(const SinkFacts& facts) {
    return las_config(facts, nullptr, LasCompression::none);
}

std::unique_ptr<PointSink> make_las_sink(const SinkFacts& facts) {
    return std::make_unique<LasSink>(facts);
}

std::unique_ptr<PointSink> make_laz_sink(const SinkFacts& facts) {
    if (las_format_has_wave_packet(facts.las_point_format)) {
        throw ConfigError("points.laz: point format " + std::to_string(facts.las_point_format) +
                          " (wave packets) is written as points.las only; turn output.laz off");
    }
    return std::make_unique<LasSink>(facts, LasCompression::laz);
}

}  // namespace beamtrace
