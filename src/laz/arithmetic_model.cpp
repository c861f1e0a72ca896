#include "laz/arithmetic_model.hpp"

#include <stdexcept>
#include <string>

namespace beamtrace::laz {

ArithmeticModel::ArithmeticModel(std::uint32_t symbols, bool compress)
    : symbols_(symbols), last_symbol_(symbols - 1), compress_(compress) {
    if (symbols < 2 || symbols > kMaxSymbols) {
        throw std::invalid_argument("arithmetic model of " + std::to_string(symbols) +
                                    " symbols (2 to 2048 supported)");
    }
    std::size_t size = 2 * static_cast<std::size_t>(symbols);
    if (!compress && symbols > 16) {
        std::uint32_t table_bits = 3;
        while (symbols > (1U << (table_bits + 2))) {
            ++table_bits;
        }
        table_size_ = 1U << table_bits;
        table_shift_ = kSymbolLengthShift - table_bits;
        size += table_size_ + 2;  // the fill writes up to entry table_size + 1
    }
    data_.assign(size, 0);
}

void ArithmeticModel::init(const std::uint32_t* table) {
    total_count_ = 0;
    update_cycle_ = symbols_;
    std::uint32_t* count = counts();
    for (std::uint32_t k = 0; k < symbols_; ++k) {
        count[k] = table != nullptr ? table[k] : 1;
    }
    update();
    update_cycle_ = (symbols_ + 6) >> 1;
    until_update_ = update_cycle_;
}

void ArithmeticModel::update() {
    std::uint32_t* dist = distribution();
    std::uint32_t* count = counts();
    total_count_ += update_cycle_;
    if (total_count_ > kSymbolMaxCount) {
        total_count_ = 0;
        for (std::uint32_t n = 0; n < symbols_; ++n) {
            count[n] = (count[n] + 1) >> 1;
            total_count_ += count[n];
        }
    }
    const std::uint32_t scale = 0x80000000U / total_count_;
    std::uint32_t sum = 0;
    if (table_size_ == 0) {
        for (std::uint32_t k = 0; k < symbols_; ++k) {
            dist[k] = (scale * sum) >> (31 - kSymbolLengthShift);
            sum += count[k];
        }
    } else {
        std::uint32_t* lookup = table();
        std::uint32_t s = 0;
        for (std::uint32_t k = 0; k < symbols_; ++k) {
            dist[k] = (scale * sum) >> (31 - kSymbolLengthShift);
            sum += count[k];
            const std::uint32_t w = dist[k] >> table_shift_;
            while (s < w) {
                lookup[++s] = k - 1;
            }
        }
        lookup[0] = 0;
        while (s <= table_size_) {
            lookup[++s] = symbols_ - 1;
        }
    }
    update_cycle_ = (5 * update_cycle_) >> 2;
    const std::uint32_t max_cycle = (symbols_ + 6) << 3;
    if (update_cycle_ > max_cycle) {
        update_cycle_ = max_cycle;
    }
    until_update_ = update_cycle_;
}

void ArithmeticBitModel::init() {
    bit0_count_ = 1;
    bit_count_ = 2;
    bit0_prob_ = 1U << (kBitLengthShift - 1);
    update_cycle_ = 4;
    until_update_ = 4;
}

void ArithmeticBitModel::update() {
    bit_count_ += update_cycle_;
    if (bit_count_ > kBitMaxCount) {
        bit_count_ = (bit_count_ + 1) >> 1;
        bit0_count_ = (bit0_count_ + 1) >> 1;
        if (bit0_count_ == bit_count_) {
            ++bit_count_;
        }
    }
    const std::uint32_t scale = 0x80000000U / bit_count_;
    bit0_prob_ = (bit0_count_ * scale) >> (31 - kBitLengthShift);
    update_cycle_ = (5 * update_cycle_) >> 2;
    if (update_cycle_ > 64) {
        update_cycle_ = 64;
    }
    until_update_ = update_cycle_;
}

}  // namespace beamtrace::laz
