// Shared pieces of the point-wise item codecs: a bank of 256 symbol models created on first
// use (LASzip keys some models by the previous value of a byte), the streaming median of five
// that POINT10 version 2 predicts coordinate differences with, and the return-number contexts.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "laz/arithmetic_model.hpp"

namespace beamtrace::laz {

/// 256 models of `symbols` symbols, each created (and initialised) when first used. A fresh
/// bank behaves as if every model had just been initialised, as the format requires at the
/// start of each chunk.
class LazyModelBank {
  public:
    LazyModelBank(std::uint32_t symbols, bool compress) : symbols_(symbols), compress_(compress) {}

    ArithmeticModel& operator[](std::uint8_t key) {
        std::unique_ptr<ArithmeticModel>& m = models_[key];
        if (!m) {
            m = std::make_unique<ArithmeticModel>(symbols_, compress_);
            m->init();
        }
        return *m;
    }

    /// Back to the state of a fresh bank (models already made are re-initialised and kept).
    void reset() {
        for (auto& m : models_) {
            if (m) {
                m->init();
            }
        }
    }

  private:
    std::array<std::unique_ptr<ArithmeticModel>, 256> models_{};
    std::uint32_t symbols_;
    bool compress_;
};

/// The format's running estimate of the median of the last five values (not an exact median:
/// its insertion rule is part of the format).
class StreamingMedian5 {
  public:
    void init() {
        v_ = {0, 0, 0, 0, 0};
        high_ = true;
    }
    [[nodiscard]] std::int32_t get() const { return v_[2]; }

    void add(std::int32_t v) {
        if (high_) {
            add_while_high(v);
        } else {
            add_while_low(v);
        }
    }

  private:
    void add_while_high(std::int32_t v) {
        if (v >= v_[2]) {
            if (v < v_[3]) {
                v_[4] = v_[3];
                v_[3] = v;
            } else {
                v_[4] = v;
            }
            high_ = false;
            return;
        }
        v_[4] = v_[3];
        v_[3] = v_[2];
        if (v < v_[0]) {
            v_[2] = v_[1];
            v_[1] = v_[0];
            v_[0] = v;
        } else if (v < v_[1]) {
            v_[2] = v_[1];
            v_[1] = v;
        } else {
            v_[2] = v;
        }
    }

    void add_while_low(std::int32_t v) {
        if (v <= v_[2]) {
            if (v_[1] < v) {
                v_[0] = v_[1];
                v_[1] = v;
            } else {
                v_[0] = v;
            }
            high_ = true;
            return;
        }
        v_[0] = v_[1];
        v_[1] = v_[2];
        if (v_[4] < v) {
            v_[2] = v_[3];
            v_[3] = v_[4];
            v_[4] = v;
        } else if (v_[3] < v) {
            v_[2] = v_[3];
            v_[3] = v;
        } else {
            v_[2] = v;
        }
    }

    std::array<std::int32_t, 5> v_{0, 0, 0, 0, 0};
    bool high_ = true;
};

/// The context (0-15) of a (number of returns n, return number r) pair, indexed [n][r]; the
/// format also maps the invalid pairs that real files contain.
inline constexpr std::uint8_t kReturnContext[8][8] = {
    {15, 14, 13, 12, 11, 10, 9, 8},  {14, 0, 1, 3, 6, 10, 10, 9},
    {13, 1, 2, 4, 7, 11, 11, 10},    {12, 3, 4, 5, 8, 12, 12, 11},
    {11, 6, 7, 8, 9, 13, 13, 12},    {10, 10, 11, 12, 13, 14, 14, 13},
    {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15}};

/// The level (0-7: how far r is from n) of a (n, r) pair, indexed [n][r].
inline constexpr std::uint8_t kReturnLevel[8][8] = {
    {0, 1, 2, 3, 4, 5, 6, 7}, {1, 0, 1, 2, 3, 4, 5, 6}, {2, 1, 0, 1, 2, 3, 4, 5},
    {3, 2, 1, 0, 1, 2, 3, 4}, {4, 3, 2, 1, 0, 1, 2, 3}, {5, 4, 3, 2, 1, 0, 1, 2},
    {6, 5, 4, 3, 2, 1, 0, 1}, {7, 6, 5, 4, 3, 2, 1, 0}};

}  // namespace beamtrace::laz
