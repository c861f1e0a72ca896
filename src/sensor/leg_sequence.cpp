#include "beamtrace/sensor/leg_sequence.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

namespace {

/// Every problem of the legs' windows and patterns.
std::vector<std::string> leg_problems(const std::vector<SequenceLeg>& legs) {
    std::vector<std::string> p;
    if (legs.empty()) {
        p.emplace_back("at least one leg is needed");
    }
    for (std::size_t l = 0; l < legs.size(); ++l) {
        const SequenceLeg& leg = legs[l];
        const std::string name = "leg " + std::to_string(l);
        if (!(std::isfinite(leg.start_time_s) && std::isfinite(leg.end_time_s) &&
              leg.start_time_s < leg.end_time_s)) {
            p.push_back(name + ": its window must be finite with start < end");
            continue;
        }
        if (l > 0 && leg.start_time_s < legs[l - 1].end_time_s) {
            p.push_back(name + ": starts before leg " + std::to_string(l - 1) + " ends");
        }
        if (leg.pattern && leg.pattern->pulse_count() > 0) {
            const double tol = 1e-9 * std::max(1.0, std::abs(leg.end_time_s));
            if (leg.pattern->start_time_s() < leg.start_time_s - tol ||
                leg.pattern->end_time_s() > leg.end_time_s + tol) {
                p.push_back(name + ": its scanner fires outside the leg's window");
            }
        }
    }
    return p;
}

}  // namespace

std::size_t leg_of_pulse(const std::vector<std::uint64_t>& first_pulses, std::uint64_t i) {
    // The last leg whose first pulse is <= i: legs without pulses share their successor's
    // first pulse, and upper_bound skips past them.
    const auto it = std::upper_bound(first_pulses.begin(), first_pulses.end(), i);
    return static_cast<std::size_t>(it - first_pulses.begin()) - 1;
}

LegSequence::LegSequence(std::vector<SequenceLeg> legs) : legs_(std::move(legs)) {
    throw_if_problems("survey legs", leg_problems(legs_));
    first_pulse_.assign(1, 0);
    for (std::size_t l = 0; l < legs_.size(); ++l) {
        const std::uint64_t n = legs_[l].pattern ? legs_[l].pattern->pulse_count() : 0;
        first_pulse_.push_back(first_pulse_.back() + n);
        if (n > 0) {
            first_active_ = first_active_.value_or(l);
            last_active_ = l;
        }
    }
}

double LegSequence::pulse_rate_hz() const {
    const double span = end_time_s() - start_time_s();
    return pulse_count() > 0 && span > 0 ? static_cast<double>(pulse_count()) / span : 0.0;
}

double LegSequence::start_time_s() const {
    return first_active_ ? legs_[*first_active_].pattern->start_time_s()
                         : legs_.front().start_time_s;
}

double LegSequence::end_time_s() const {
    return last_active_ ? legs_[*last_active_].pattern->end_time_s() : legs_.front().start_time_s;
}

std::size_t LegSequence::leg_of(std::uint64_t i) const {
    return leg_of_pulse(first_pulse_, i);
}

double LegSequence::pulse_time_s(std::uint64_t i) const {
    if (i >= pulse_count()) {
        return end_time_s();
    }
    const std::size_t l = leg_of(i);
    return legs_[l].pattern->pulse_time_s(i - first_pulse_[l]);
}

void LegSequence::generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const {
    PulseBatch part;
    std::size_t done = 0;
    while (done < count) {
        const std::uint64_t i = first + done;
        const std::size_t l = leg_of(i);
        const auto n = static_cast<std::size_t>(
            std::min<std::uint64_t>(count - done, first_pulse_[l + 1] - i));
        legs_[l].pattern->generate(i - first_pulse_[l], n, part);
        const auto at = static_cast<std::ptrdiff_t>(done);
        std::copy(part.time_s.begin(), part.time_s.end(), out.time_s.begin() + at);
        std::copy(part.direction.begin(), part.direction.end(), out.direction.begin() + at);
        std::copy(part.channel.begin(), part.channel.end(), out.channel.begin() + at);
        std::copy(part.scan_angle_deg.begin(), part.scan_angle_deg.end(),
                  out.scan_angle_deg.begin() + at);
        done += n;
    }
}

}  // namespace beamtrace
