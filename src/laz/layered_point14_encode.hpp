// The encoder of the layered POINT14 item (version 3), LASzip's LASwriteItemCompressed_POINT14_v3:
// the mirror of Point14Decoder (layered_point14.hpp), producing LASzip's bytes for the same
// records. Nine layers; each scanner channel has its own context, and encode() returns the
// channel, which selects the context of the record's other items.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "laz/layered_encode_layer.hpp"

namespace beamtrace::laz {

class Point14Encoder {
  public:
    static constexpr std::size_t kLayers = 9;

    /// `first`: the chunk's first record (30 bytes), written raw by the chunk.
    explicit Point14Encoder(const std::uint8_t* first);
    ~Point14Encoder();
    Point14Encoder(const Point14Encoder&) = delete;
    Point14Encoder& operator=(const Point14Encoder&) = delete;
    Point14Encoder(Point14Encoder&&) = delete;
    Point14Encoder& operator=(Point14Encoder&&) = delete;

    /// Encodes the next record (30 bytes); returns its scanner channel.
    unsigned encode(const std::uint8_t* record);

    /// Ends the layers and appends their bytes (9 spans, empty for an unchanged layer) to
    /// `layers`; the spans live as long as the encoder.
    void finish(std::vector<std::span<const std::uint8_t>>& layers);

    struct Fields;

  private:
    struct Context;
    enum LayerIndex : std::size_t {
        kXy,
        kZ,
        kClassification,
        kFlags,
        kIntensity,
        kScanAngle,
        kUserData,
        kPointSource,
        kGpsTime
    };

    void start_context(unsigned channel, const Fields& from);
    void encode_returns(Context& c, const Fields& p, std::uint32_t changed);
    void encode_xyz(Context& c, const Fields& p, bool gps_change);
    void encode_attributes(Context& c, const Fields& p, std::uint32_t changed);
    static void encode_gps_time(Context& c, ArithmeticEncoder& enc, std::uint64_t time_bits);
    static void encode_gps_difference(Context& c, ArithmeticEncoder& enc, std::int32_t diff);
    static void encode_full_gps_time(Context& c, ArithmeticEncoder& enc, std::uint64_t time_bits);

    std::array<EncodeLayer, kLayers> layers_;
    std::array<std::unique_ptr<Context>, 4> contexts_;
    unsigned current_ = 0;
};

}  // namespace beamtrace::laz
