// The point-wise item decoders of version 1 (LASzip 1.0-1.x, and WAVEPACKET13 in every
// point-wise file): POINT10, GPSTIME11, RGB12, BYTE and WAVEPACKET13. Made once per chunk,
// init() with the chunk's first (raw) record item, then decode() each further item. We write
// version 2, so the only version-1 encoder is WAVEPACKET13's (LASzip writes that item as
// version 1 in version-2 files too).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_encoder.hpp"
#include "laz/arithmetic_model.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/item_bytes.hpp"
#include "laz/item_models.hpp"

namespace beamtrace::laz {

/// POINT10 v1: x and y against the median of the last three differences, z against the last
/// z, then a mask of the other fields that changed and those fields.
class Point10DecoderV1 {
  public:
    Point10DecoderV1();
    void init(const std::uint8_t* item);
    void decode(ArithmeticDecoder& dec, std::uint8_t* item);

  private:
    void decode_changed(ArithmeticDecoder& dec, std::uint32_t kz);

    IntegerCompressor dx_;
    IntegerCompressor dy_;
    IntegerCompressor z_;
    IntegerCompressor intensity_;
    IntegerCompressor scan_angle_;
    IntegerCompressor point_source_;
    ArithmeticModel changed_;
    LazyModelBank flags_;
    LazyModelBank classification_;
    LazyModelBank user_data_;
    Point10 last_;
    std::array<std::int32_t, 3> last_dx_{};
    std::array<std::int32_t, 3> last_dy_{};
    std::size_t slot_ = 0;
};

/// GPSTIME11 v1: one sequence; the difference to the last time against a multiple of the
/// last difference.
class Gpstime11DecoderV1 {
  public:
    Gpstime11DecoderV1();
    void init(const std::uint8_t* item);
    void decode(ArithmeticDecoder& dec, std::uint8_t* item);

  private:
    void decode_multiplied(ArithmeticDecoder& dec, std::uint32_t multi);

    ArithmeticModel multi_;
    ArithmeticModel zero_diff_;
    IntegerCompressor ic_;
    std::uint64_t time_ = 0;
    std::int32_t diff_ = 0;
    std::int32_t extreme_ = 0;
};

/// RGB12 v1: a mask of the changed colour bytes, each against its previous value.
class Rgb12DecoderV1 {
  public:
    Rgb12DecoderV1();
    void init(const std::uint8_t* item);
    void decode(ArithmeticDecoder& dec, std::uint8_t* item);

  private:
    ArithmeticModel used_;
    IntegerCompressor ic_;
    std::array<std::uint8_t, 6> last_{};
};

/// BYTE v1: each byte against the previous record's, one context per byte position.
class ByteDecoderV1 {
  public:
    explicit ByteDecoderV1(std::size_t count);
    void init(const std::uint8_t* item);
    void decode(ArithmeticDecoder& dec, std::uint8_t* item);

  private:
    IntegerCompressor ic_;
    std::vector<std::uint8_t> last_;
};

/// WAVEPACKET13 v1 (29 bytes: descriptor index, offset, size, return point, x(t), y(t), z(t)).
class Wavepacket13CodecV1 {
  public:
    explicit Wavepacket13CodecV1(bool compress);
    void init(const std::uint8_t* item);
    void decode(ArithmeticDecoder& dec, std::uint8_t* item);
    void encode(ArithmeticEncoder& enc, const std::uint8_t* item);

  private:
    ArithmeticModel index_;
    std::array<ArithmeticModel, 4> offset_kind_;
    IntegerCompressor offset_diff_;
    IntegerCompressor packet_size_;
    IntegerCompressor return_point_;
    IntegerCompressor xyz_;
    std::uint64_t offset_ = 0;
    std::uint32_t size_ = 0;
    std::array<std::int32_t, 4> point_xyz_{};  ///< return point, x, y, z (their bits)
    std::int32_t last_offset_diff_ = 0;
    std::uint32_t last_kind_ = 0;
    bool compress_;
};

}  // namespace beamtrace::laz
