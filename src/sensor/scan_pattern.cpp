#include "beamtrace/sensor/scan_pattern.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

void ScanPattern::generate(std::uint64_t first, std::size_t count, PulseBatch& out) const {
    const std::uint64_t total = pulse_count();
    if (first > total || count > total - first) {
        throw std::out_of_range("scan pattern: pulses [" + std::to_string(first) + ", " +
                                std::to_string(first) + " + " + std::to_string(count) +
                                ") requested, but the pattern has " + std::to_string(total));
    }
    out.resize(count);
    std::fill(out.scanner.begin(), out.scanner.end(), std::uint8_t{0});  // ScannerSet sets it
    if (count > 0) {
        generate_pulses(first, count, out);
    }
}

void throw_if_problems(std::string_view subject, const std::vector<std::string>& problems) {
    if (problems.empty()) {
        return;
    }
    std::string msg(subject);
    msg += ":";
    for (const auto& p : problems) {
        msg += " " + p + ";";
    }
    msg.pop_back();
    throw ConfigError(msg);
}

std::uint64_t whole_count(double x) {
    if (!(x > 0.0)) {
        return 0;
    }
    if (x >= 1.8e19) {
        return std::numeric_limits<std::uint64_t>::max();
    }
    const double nearest = std::round(x);
    const double whole = std::abs(x - nearest) <= 1e-9 * nearest ? nearest : std::floor(x);
    return static_cast<std::uint64_t>(whole);
}

}  // namespace beamtrace
