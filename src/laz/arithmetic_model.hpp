// The adaptive models of LASzip's range coder (the coder of A. Said's FastAC, as LASzip uses
// it): a multi-symbol model and a binary model. Their counts, update cycles and rescaling are
// the format's: an encoder and a decoder stay in step only if both update exactly this way.
#pragma once

#include <cstdint>
#include <vector>

namespace beamtrace::laz {

/// Interval lengths below this renormalise the coder (shift out one byte).
inline constexpr std::uint32_t kMinLength = 0x01000000U;
/// The coder's initial interval length.
inline constexpr std::uint32_t kMaxLength = 0xFFFFFFFFU;
/// Bits of the interval length dropped before the product with a bit probability.
inline constexpr std::uint32_t kBitLengthShift = 13;
inline constexpr std::uint32_t kBitMaxCount = 1U << kBitLengthShift;
/// Bits of the interval length dropped before the product with a symbol distribution.
inline constexpr std::uint32_t kSymbolLengthShift = 15;
inline constexpr std::uint32_t kSymbolMaxCount = 1U << kSymbolLengthShift;
/// The largest alphabet a symbol model supports.
inline constexpr std::uint32_t kMaxSymbols = 1U << 11;

/// An adaptive model of `symbols` symbols (2 to 2048). A decoding model of more than 16
/// symbols keeps a look-up table that narrows the search. All state lies in one flat array.
class ArithmeticModel {
  public:
    /// `compress`: whether the model encodes (no decoder table). Throws std::invalid_argument
    /// for an alphabet outside 2..2048.
    ArithmeticModel(std::uint32_t symbols, bool compress);

    /// Resets the counts to `table` (one count per symbol) or to all ones.
    void init(const std::uint32_t* table = nullptr);

    [[nodiscard]] std::uint32_t symbols() const { return symbols_; }

  private:
    friend class ArithmeticEncoder;
    friend class ArithmeticDecoder;

    /// Rescales the counts and recomputes the distribution (and the decoder table).
    void update();

    std::uint32_t* distribution() { return data_.data(); }
    std::uint32_t* counts() { return data_.data() + symbols_; }
    std::uint32_t* table() { return data_.data() + 2 * symbols_; }

    std::vector<std::uint32_t> data_;  ///< distribution, counts, then the decoder table
    std::uint32_t symbols_ = 0;
    std::uint32_t last_symbol_ = 0;
    std::uint32_t table_size_ = 0;  ///< 0: no decoder table
    std::uint32_t table_shift_ = 0;
    std::uint32_t total_count_ = 0;
    std::uint32_t update_cycle_ = 0;
    std::uint32_t until_update_ = 0;
    bool compress_ = false;
};

/// An adaptive model of one bit.
class ArithmeticBitModel {
  public:
    ArithmeticBitModel() { init(); }

    /// Resets to equal probabilities and frequent updates.
    void init();

  private:
    friend class ArithmeticEncoder;
    friend class ArithmeticDecoder;

    void update();

    std::uint32_t update_cycle_ = 0;
    std::uint32_t until_update_ = 0;
    std::uint32_t bit0_prob_ = 0;
    std::uint32_t bit0_count_ = 0;
    std::uint32_t bit_count_ = 0;
};

}  // namespace beamtrace::laz
