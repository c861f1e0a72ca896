// The point-wise item codecs of version 2 (LASzip 2): POINT10, GPSTIME11, RGB12 and BYTE.
// A codec is made once per chunk, init() with the chunk's first (raw) record item, then codes
// each further item against the previous one. The decoders and the encoders mirror each other
// step by step; their state must evolve identically.
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

/// POINT10 v2: which fields changed (a 6-bit mask), the changed fields, then x and y against
/// the running medians of their differences and z against the last z of the return level.
class Point10CodecV2 {
  public:
    explicit Point10CodecV2(bool compress);
    void init(const std::uint8_t* item);
    void decode(ArithmeticDecoder& dec, std::uint8_t* item);
    void encode(ArithmeticEncoder& enc, const std::uint8_t* item);

  private:
    ArithmeticModel changed_;
    IntegerCompressor intensity_;
    std::array<ArithmeticModel, 2> scan_angle_;
    IntegerCompressor point_source_;
    LazyModelBank flags_;
    LazyModelBank classification_;
    LazyModelBank user_data_;
    IntegerCompressor dx_;
    IntegerCompressor dy_;
    IntegerCompressor z_;
    Point10 last_;
    std::array<StreamingMedian5, 16> x_median_;
    std::array<StreamingMedian5, 16> y_median_;
    std::array<std::uint16_t, 16> last_intensity_{};
    std::array<std::int32_t, 8> last_height_{};
    bool compress_;
};

/// GPSTIME11 v2: the 64-bit time as an integer, in up to four interleaved sequences, each
/// predicted from its last difference times a coded multiplier.
class Gpstime11CodecV2 {
  public:
    explicit Gpstime11CodecV2(bool compress);
    void init(const std::uint8_t* item);
    void decode(ArithmeticDecoder& dec, std::uint8_t* item);
    void encode(ArithmeticEncoder& enc, const std::uint8_t* item);

  private:
    bool decode_step(ArithmeticDecoder& dec);
    void decode_multiplied(ArithmeticDecoder& dec, std::uint32_t multi);
    void decode_new_sequence(ArithmeticDecoder& dec);
    bool encode_step(ArithmeticEncoder& enc, std::uint64_t time);
    void encode_multiplied(ArithmeticEncoder& enc, std::int32_t diff);
    bool switch_sequence(ArithmeticEncoder& enc, ArithmeticModel& m, std::uint32_t base,
                         std::uint64_t time);
    void encode_new_sequence(ArithmeticEncoder& enc, ArithmeticModel& m, std::uint32_t symbol,
                             std::uint64_t time);
    void count_extreme(std::int32_t diff);

    ArithmeticModel multi_;
    ArithmeticModel zero_diff_;
    IntegerCompressor ic_;
    std::uint32_t last_ = 0;
    std::uint32_t next_ = 0;
    std::array<std::uint64_t, 4> time_{};
    std::array<std::int32_t, 4> diff_{};
    std::array<std::int32_t, 4> extreme_{};
    bool compress_;
};

/// RGB12 v2: which colour bytes changed, then each changed byte against a prediction from red's
/// change.
class Rgb12CodecV2 {
  public:
    explicit Rgb12CodecV2(bool compress);
    void init(const std::uint8_t* item);
    void decode(ArithmeticDecoder& dec, std::uint8_t* item);
    void encode(ArithmeticEncoder& enc, const std::uint8_t* item);

  private:
    ArithmeticModel used_;
    std::array<ArithmeticModel, 6> diff_;
    std::array<std::uint16_t, 3> last_{};
};

/// BYTE v2: each byte as its difference to the previous record's, one model per byte.
class ByteCodecV2 {
  public:
    ByteCodecV2(std::size_t count, bool compress);
    void init(const std::uint8_t* item);
    void decode(ArithmeticDecoder& dec, std::uint8_t* item);
    void encode(ArithmeticEncoder& enc, const std::uint8_t* item);

  private:
    std::vector<ArithmeticModel> models_;
    std::vector<std::uint8_t> last_;
};

}  // namespace beamtrace::laz
