// Damaged-file tests that look at what a reader returns, not only at whether it crashed: every
// truncation and random byte flips of a valid file, each load either refused with InputError or
// handed, with the damage, to a checker that compares the result with the undamaged original.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <ostream>
#include <random>
#include <sstream>
#include <string>
#include <utility>

#include "beamtrace/core/error.hpp"

namespace beamtrace::test {

/// One byte of a file replaced: the byte at `offset` was `from` and is now `to` (never equal).
struct ByteFlip {
    std::size_t offset = 0;
    std::uint8_t from = 0;
    std::uint8_t to = 0;
};

inline std::ostream& operator<<(std::ostream& os, const ByteFlip& f) {
    return os << "byte " << f.offset << " changed from " << int{f.from} << " to " << int{f.to};
}

/// `load(bytes)`, or nullopt when the reader refuses the bytes with InputError. Any other
/// exception escapes and fails the test.
template <typename Load>
auto load_or_refuse(Load& load, const std::string& bytes) -> std::optional<decltype(load(bytes))> {
    try {
        return load(bytes);
    } catch (const InputError&) {
        return std::nullopt;
    }
}

/// Loads every proper prefix of `bytes` (the file cut short after n bytes). A prefix that loads
/// goes to `check(result, n)`, which must fail the test unless the result is acceptable for a
/// file cut at n. Stops at the first failure, so one bug does not print a thousand.
template <typename Load, typename Check>
void check_every_truncation(const std::string& bytes, Load&& load, Check&& check) {
    for (std::size_t n = 0; n < bytes.size(); ++n) {
        SCOPED_TRACE("file cut to " + std::to_string(n) + " of " + std::to_string(bytes.size()) +
                     " bytes");
        if (auto got = load_or_refuse(load, bytes.substr(0, n))) {
            check(*got, n);
        }
        if (::testing::Test::HasFailure()) {
            return;
        }
    }
}

/// Loads `trials` copies of `bytes`, each with one byte at a random offset replaced by a different
/// random value. A copy that loads goes to `check(result, flip)`, which must fail the test unless
/// the result differs from the original only where the flipped byte can reach. Stops at the
/// first failure.
template <typename Load, typename Check>
void check_random_byte_flips(const std::string& bytes, std::mt19937& rng, int trials, Load&& load,
                             Check&& check) {
    for (int trial = 0; trial < trials; ++trial) {
        ByteFlip flip;
        flip.offset = rng() % bytes.size();
        flip.from = static_cast<std::uint8_t>(bytes[flip.offset]);
        flip.to = static_cast<std::uint8_t>(flip.from ^ (1u + rng() % 255u));  // never the same
        std::string corrupt = bytes;
        corrupt[flip.offset] = static_cast<char>(flip.to);
        std::ostringstream what;
        what << "trial " << trial << ": " << flip;
        SCOPED_TRACE(what.str());
        if (auto got = load_or_refuse(load, corrupt)) {
            check(*got, flip);
        }
        if (::testing::Test::HasFailure()) {
            return;
        }
    }
}

/// For small files: every byte in turn replaced by `per_byte` different random values, each copy
/// loaded and checked as check_random_byte_flips does, so no byte goes untried.
template <typename Load, typename Check>
void check_every_byte_flip(const std::string& bytes, std::mt19937& rng, int per_byte, Load&& load,
                           Check&& check) {
    for (std::size_t offset = 0; offset < bytes.size(); ++offset) {
        for (int k = 0; k < per_byte; ++k) {
            ByteFlip flip;
            flip.offset = offset;
            flip.from = static_cast<std::uint8_t>(bytes[offset]);
            flip.to = static_cast<std::uint8_t>(flip.from ^ (1u + rng() % 255u));
            std::string corrupt = bytes;
            corrupt[offset] = static_cast<char>(flip.to);
            std::ostringstream what;
            what << flip;
            SCOPED_TRACE(what.str());
            if (auto got = load_or_refuse(load, corrupt)) {
                check(*got, flip);
            }
            if (::testing::Test::HasFailure()) {
                return;
            }
        }
    }
}

}  // namespace beamtrace::test
