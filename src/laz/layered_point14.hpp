// The layered POINT14 item (version 3): the 30-byte core record of point formats 6-10.
//
// Nine layers: channel/returns/XY, Z, classification, flags, intensity, scan angle, user data,
// point source ID, GPS time. Each of the four scanner channels has its own context (last point,
// models), started from the point that first switches to it. decode() returns the scanner
// channel, the context every other item of the record uses.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "laz/arithmetic_model.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/layered_layer.hpp"

namespace beamtrace::laz {

class Point14Decoder {
  public:
    static constexpr std::size_t kLayers = 9;
    static constexpr std::size_t kRecordBytes = 30;

    /// `first`: the chunk's first (raw) record; `layers`: the nine layers' bytes in order.
    Point14Decoder(const std::uint8_t* first,
                   std::span<const std::span<const std::uint8_t>> layers);
    ~Point14Decoder();
    Point14Decoder(const Point14Decoder&) = delete;
    Point14Decoder& operator=(const Point14Decoder&) = delete;
    Point14Decoder(Point14Decoder&&) = delete;
    Point14Decoder& operator=(Point14Decoder&&) = delete;

    /// Decodes the next record into `out` (30 bytes); returns its scanner channel.
    unsigned decode(std::uint8_t* out);

  private:
    struct Fields;
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

    void start_context(unsigned channel, const Fields& from, std::uint64_t gps_time);
    void decode_returns(Context& c, std::uint32_t changed);
    void decode_xyz(Context& c, std::uint32_t changed);
    void decode_attributes(Context& c, std::uint32_t changed, unsigned cpr);
    static void decode_gps_time(Context& c, ArithmeticDecoder& dec);
    static void decode_full_gps_time(Context& c, ArithmeticDecoder& dec);
    static std::int32_t decode_gps_multiple(Context& c, ArithmeticDecoder& dec, std::int32_t multi);

    std::array<std::optional<Layer>, kLayers> layers_;
    std::array<std::unique_ptr<Context>, 4> contexts_;
    unsigned current_ = 0;
};

}  // namespace beamtrace::laz
