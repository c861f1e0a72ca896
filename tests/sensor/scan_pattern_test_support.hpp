// What every scan mechanism's tests share: all of a pattern's pulses at once, and the check
// that generate() gives the same pulses bit for bit however the survey is cut into chunks.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <initializer_list>

#include "beamtrace/sensor/scan_pattern.hpp"

namespace beamtrace::test {

/// Every pulse of `pattern`, generated in one call.
inline PulseBatch all_pulses(const ScanPattern& pattern) {
    PulseBatch out;
    pattern.generate(0, static_cast<std::size_t>(pattern.pulse_count()), out);
    return out;
}

/// generate() over chunks of each size in `chunks` equals all_pulses(), bit for bit.
inline void expect_chunking_does_not_matter(const ScanPattern& pattern,
                                            std::initializer_list<std::size_t> chunks) {
    const PulseBatch whole = all_pulses(pattern);
    for (const std::size_t chunk : chunks) {
        PulseBatch part;
        for (std::uint64_t first = 0; first < pattern.pulse_count(); first += chunk) {
            const auto n = static_cast<std::size_t>(
                std::min<std::uint64_t>(chunk, pattern.pulse_count() - first));
            pattern.generate(first, n, part);
            for (std::size_t j = 0; j < n; ++j) {
                const auto i = static_cast<std::size_t>(first + j);
                ASSERT_EQ(part.time_s[j], whole.time_s[i]) << "chunk " << chunk << ", pulse " << i;
                ASSERT_EQ(part.direction[j], whole.direction[i]) << "chunk " << chunk;
                ASSERT_EQ(part.channel[j], whole.channel[i]) << "chunk " << chunk;
                ASSERT_EQ(part.scan_angle_deg[j], whole.scan_angle_deg[i]) << "chunk " << chunk;
            }
        }
    }
}

}  // namespace beamtrace::test
