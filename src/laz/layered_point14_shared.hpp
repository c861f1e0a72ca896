// The parts of the layered POINT14 format (version 3) that its encoder needs as the decoder
// does: the GPS time codes, the (number of returns, return number) contexts and the running
// median of the X and Y differences; the decoder (layered_point14.cpp) and the encoder share them.
#pragma once

#include <array>
#include <cstdint>
#include <initializer_list>
#include <memory>

#include "laz/arithmetic_model.hpp"
#include "laz/integer_compressor.hpp"

namespace beamtrace::laz::point14 {

/// GPS time codes: multiples of the last difference from kGpsMultiMinus to kGpsMulti, then a
/// full 64-bit time, then a switch to one of the other three time sequences.
inline constexpr std::int32_t kGpsMulti = 500;
inline constexpr std::int32_t kGpsMultiMinus = -10;
inline constexpr std::uint32_t kGpsCodeFull = kGpsMulti - kGpsMultiMinus + 1;
inline constexpr std::uint32_t kGpsSymbols = kGpsMulti - kGpsMultiMinus + 5;

/// The format's grouping of (number of returns, return number) into six XY contexts.
inline constexpr std::uint8_t kReturnMap6[16][16] = {
    {0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5},
    {1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3},
    {2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3},
    {3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5},
};

/// The Z context: how deep the return lies in its pulse, |n - r|, at most 7.
[[nodiscard]] inline unsigned return_level(unsigned n, unsigned r) {
    const unsigned d = n > r ? n - r : r - n;
    return d < 7 ? d : 7;
}

/// A running median of the last five values (the predictor of the X and Y differences). Each
/// value drops the largest or the smallest of the five, switching sides whenever a value lands
/// on the other side of the median: the format's rule, which an encoder must match exactly.
class Median5 {
  public:
    [[nodiscard]] std::int32_t get() const { return v_[2]; }
    void add(std::int32_t x) {
        std::size_t i = 0;
        if (drop_high_) {
            i = 4;
            while (i > 0 && x < v_[i - 1]) {
                v_[i] = v_[i - 1];
                --i;
            }
            drop_high_ = i <= 2;
        } else {
            while (i < 4 && v_[i + 1] < x) {
                v_[i] = v_[i + 1];
                ++i;
            }
            drop_high_ = i <= 1;
        }
        v_[i] = x;
    }

  private:
    std::array<std::int32_t, 5> v_{};
    bool drop_high_ = true;
};

/// A lazily created 'symbols'-symbol model (the format creates them on first use), for the
/// encoder (`compress`) or the decoder.
inline ArithmeticModel& lazy_model(std::unique_ptr<ArithmeticModel>& slot, std::uint32_t symbols,
                                   bool compress) {
    if (!slot) {
        slot = std::make_unique<ArithmeticModel>(symbols, compress);
        slot->init();
    }
    return *slot;
}

/// A scanner channel's predictors and the models that code its next point: the same in the
/// decoder and the encoder, each initialising them for its side (`compress` for the encoder).
struct ChannelModels {
    explicit ChannelModels(bool compress_side) : compress(compress_side) {
        for (ArithmeticModel& m : changed_values) {
            m.init();
        }
        scanner_channel.init();
        return_number_gps_same.init();
        gps_multi.init();
        gps_0diff.init();
        for (IntegerCompressor* ic :
             {&dx, &dy, &dz, &intensity_ic, &scan_angle_ic, &point_source_ic, &gps_ic}) {
            compress ? ic->init_compressor() : ic->init_decompressor();
        }
    }

    /// The lazily created model in `slot`, for this side.
    ArithmeticModel& lazy(std::unique_ptr<ArithmeticModel>& slot, std::uint32_t symbols) const {
        return lazy_model(slot, symbols, compress);
    }

    bool compress;
    std::array<std::uint16_t, 8> last_intensity{};
    std::array<Median5, 12> x_median{};
    std::array<Median5, 12> y_median{};
    std::array<std::int32_t, 8> last_z{};

    // GPS time: four sequences of times and their last differences.
    std::array<std::uint64_t, 4> gps{};
    std::array<std::int32_t, 4> gps_diff{};
    std::array<std::int32_t, 4> gps_extreme{};
    unsigned gps_last = 0, gps_next = 0;

    std::array<ArithmeticModel, 8> changed_values{
        ArithmeticModel(128, compress), ArithmeticModel(128, compress),
        ArithmeticModel(128, compress), ArithmeticModel(128, compress),
        ArithmeticModel(128, compress), ArithmeticModel(128, compress),
        ArithmeticModel(128, compress), ArithmeticModel(128, compress)};
    ArithmeticModel scanner_channel{3, compress};
    std::array<std::unique_ptr<ArithmeticModel>, 16> number_of_returns_models;
    std::array<std::unique_ptr<ArithmeticModel>, 16> return_number_models;
    ArithmeticModel return_number_gps_same{13, compress};
    IntegerCompressor dx{32, 2};
    IntegerCompressor dy{32, 22};
    IntegerCompressor dz{32, 20};
    std::array<std::unique_ptr<ArithmeticModel>, 64> classification_models;
    std::array<std::unique_ptr<ArithmeticModel>, 64> flags_models;
    std::array<std::unique_ptr<ArithmeticModel>, 64> user_data_models;
    IntegerCompressor intensity_ic{16, 4};
    IntegerCompressor scan_angle_ic{16, 2};
    IntegerCompressor point_source_ic{16};
    ArithmeticModel gps_multi{kGpsSymbols, compress};
    ArithmeticModel gps_0diff{5, compress};
    IntegerCompressor gps_ic{32, 9};
};

}  // namespace beamtrace::laz::point14
