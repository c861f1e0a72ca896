// LASzip's integer compressor: codes an integer as the corrector `real - pred`, folded into
// the range of `bits`-bit values (or [0, range) when `range` is set). The corrector's bit
// length k is coded with one of `contexts` symbol models; then, for k >= 1, its position in
// the k-bit interval: with a symbol model per k up to `bits_high` bits, and beyond that the
// high `bits_high` bits by the model and the rest raw. k == 0 (corrector 0 or 1) is one bit.
#pragma once

#include <cstdint>
#include <vector>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_encoder.hpp"
#include "laz/arithmetic_model.hpp"

namespace beamtrace::laz {

class IntegerCompressor {
  public:
    explicit IntegerCompressor(std::uint32_t bits = 16, std::uint32_t contexts = 1,
                               std::uint32_t bits_high = 8, std::uint32_t range = 0);

    /// (Re)creates and resets the models for decoding, or for encoding.
    void init_decompressor() { init_models(false); }
    void init_compressor() { init_models(true); }

    std::int32_t decompress(ArithmeticDecoder& dec, std::int32_t pred, std::uint32_t context = 0);
    void compress(ArithmeticEncoder& enc, std::int32_t pred, std::int32_t real,
                  std::uint32_t context = 0);

    /// The bit length k of the last corrector coded (items use it as a context).
    [[nodiscard]] std::uint32_t k() const { return k_; }

  private:
    void init_models(bool compress);
    std::int32_t read_corrector(ArithmeticDecoder& dec, ArithmeticModel& k_model);
    void write_corrector(ArithmeticEncoder& enc, std::int32_t c, ArithmeticModel& k_model);

    std::uint32_t bits_;
    std::uint32_t contexts_;
    std::uint32_t bits_high_;
    std::uint32_t corr_bits_ = 0;
    std::uint32_t corr_range_ = 0;  ///< 0: the full 32-bit range
    std::int32_t corr_min_ = 0;
    std::int32_t corr_max_ = 0;
    std::uint32_t k_ = 0;
    bool models_compress_ = false;
    std::vector<ArithmeticModel> k_models_;          ///< one per context, corr_bits + 1 symbols
    ArithmeticBitModel corrector0_;                  ///< k == 0
    std::vector<ArithmeticModel> corrector_models_;  ///< entry k - 1 for k = 1..corr_bits
};

}  // namespace beamtrace::laz
