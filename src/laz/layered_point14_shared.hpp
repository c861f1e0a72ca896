// The parts of the layered POINT14 format (version 3) that its encoder needs as the decoder
// does: the GPS time codes, the (number of returns, return number) contexts and the running
// median of the X and Y differences; the decoder (layered_point14.cpp) and the encoder share them.
#pragma once

#include <array>
#include <cstdint>

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

}  // namespace beamtrace::laz::point14
