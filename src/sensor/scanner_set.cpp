#include "beamtrace/sensor/scanner_set.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

namespace {

/// The first j in [0, n) with pred(j) (n when none); pred must be false then true.
template <class Pred>
std::uint64_t first_where(std::uint64_t n, Pred pred) {
    std::uint64_t lo = 0, hi = n;
    while (lo < hi) {
        const std::uint64_t mid = lo + (hi - lo) / 2;
        if (pred(mid)) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    return lo;
}

}  // namespace

ScannerSet::ScannerSet(std::vector<std::unique_ptr<ScanPattern>> scanners)
    : scanners_(std::move(scanners)) {
    if (scanners_.empty() || scanners_.size() > 255) {
        throw ConfigError("scanners: expected 1 to 255 scanners, got " +
                          std::to_string(scanners_.size()));
    }
    for (const auto& s : scanners_) {
        if (!s) {
            throw ConfigError("scanners: a scanner without a pattern");
        }
        total_ += s->pulse_count();
    }
}

double ScannerSet::pulse_rate_hz() const {
    const double span = end_time_s() - start_time_s();
    return total_ > 0 && span > 0 ? static_cast<double>(total_) / span : 0.0;
}

double ScannerSet::start_time_s() const {
    double t = std::numeric_limits<double>::infinity();
    for (const auto& s : scanners_) {
        if (s->pulse_count() > 0) {
            t = std::min(t, s->start_time_s());
        }
    }
    return total_ > 0 ? t : scanners_.front()->start_time_s();
}

double ScannerSet::end_time_s() const {
    double t = -std::numeric_limits<double>::infinity();
    for (const auto& s : scanners_) {
        if (s->pulse_count() > 0) {
            t = std::max(t, s->end_time_s());
        }
    }
    return total_ > 0 ? t : scanners_.front()->start_time_s();
}

std::uint64_t ScannerSet::rank(std::size_t s, std::uint64_t i) const {
    const double t = scanners_[s]->pulse_time_s(i);
    std::uint64_t r = i;
    for (std::size_t o = 0; o < scanners_.size(); ++o) {
        if (o == s) {
            continue;
        }
        // The other scanner's pulses before (t, s): earlier times, and equal times of a
        // scanner with a smaller index.
        const ScanPattern& p = *scanners_[o];
        r += first_where(p.pulse_count(), [&](std::uint64_t j) {
            const double tj = p.pulse_time_s(j);
            return o < s ? tj > t : tj >= t;
        });
    }
    return r;
}

std::vector<std::uint64_t> ScannerSet::split(std::uint64_t g) const {
    std::vector<std::uint64_t> counts(scanners_.size());
    for (std::size_t s = 0; s < scanners_.size(); ++s) {
        // rank(s, i) grows with i: the pulses of s among the first g are those of rank < g.
        counts[s] = first_where(scanners_[s]->pulse_count(),
                                [&](std::uint64_t i) { return rank(s, i) >= g; });
    }
    return counts;
}

double ScannerSet::pulse_time_s(std::uint64_t i) const {
    if (i >= total_) {
        return end_time_s();
    }
    // The pulse of rank i is the earliest (time, scanner) among the scanners' next pulses.
    const std::vector<std::uint64_t> at = split(i);
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t s = 0; s < scanners_.size(); ++s) {
        if (at[s] < scanners_[s]->pulse_count()) {
            best = std::min(best, scanners_[s]->pulse_time_s(at[s]));
        }
    }
    return best;
}

void ScannerSet::generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const {
    const std::vector<std::uint64_t> a = split(first), b = split(first + count);
    std::vector<PulseBatch> parts(scanners_.size());
    std::uint64_t total = 0;
    for (std::size_t s = 0; s < scanners_.size(); ++s) {
        scanners_[s]->generate(a[s], static_cast<std::size_t>(b[s] - a[s]), parts[s]);
        total += b[s] - a[s];
    }
    if (total != count) {  // only when a pattern's pulse_time_s() decreases somewhere
        throw std::logic_error("ScannerSet: a scanner's pulse times are not in order");
    }
    // Merge by (time, scanner index): each part is in its scanner's order already.
    std::vector<std::size_t> head(scanners_.size(), 0);
    for (std::size_t k = 0; k < count; ++k) {
        std::size_t pick = scanners_.size();
        for (std::size_t s = 0; s < scanners_.size(); ++s) {
            if (head[s] < parts[s].size() &&
                (pick == scanners_.size() ||
                 parts[s].time_s[head[s]] < parts[pick].time_s[head[pick]])) {
                pick = s;
            }
        }
        const PulseBatch& p = parts[pick];
        const std::size_t j = head[pick]++;
        out.time_s[k] = p.time_s[j];
        out.direction[k] = p.direction[j];
        out.channel[k] = p.channel[j];
        out.scan_angle_deg[k] = p.scan_angle_deg[j];
        out.scanner[k] = static_cast<std::uint8_t>(pick);
    }
}

}  // namespace beamtrace
