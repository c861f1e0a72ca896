// The scan pattern table: one line per type (scan_pattern_registry.hpp says how to add one).
#include "beamtrace/sensor/scan_pattern_registry.hpp"

#include <array>
#include <limits>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/name_table.hpp"
#include "beamtrace/sensor/mechanism_presets.hpp"
#include "beamtrace/sensor/rotating_scanner.hpp"
#include "sensor/detail/scan_pattern_types.hpp"

namespace beamtrace {
namespace {

[[nodiscard]] const std::array<ScanPatternEntry, 9>& table() {
    static const std::array<ScanPatternEntry, 9> entries{
        detail::rotating_scanner_entry(), detail::line_scanner_entry(),
        detail::conic_scanner_entry(),    detail::polygon_scanner_entry(),
        detail::risley_scanner_entry(),   detail::fibre_scanner_entry(),
        detail::pinhole_pattern_entry(),  detail::scan_pattern_entry(),
        detail::rays_file_entry(),
    };
    return entries;
}

/// The names of the entries that have `member`.
template <class Member>
std::vector<std::string_view> names_with(Member member) {
    std::vector<std::string_view> names;
    for (const auto& e : table()) {
        if (e.*member != nullptr) {
            names.push_back(e.name);
        }
    }
    return names;
}

}  // namespace

std::optional<std::pair<double, double>> ScannerSettings::preset_range_m() const {
    const SensorDataSheet* d = data_sheet_;
    if (d == nullptr || !(d->range_min_m > 0.0 || d->range_max_m > 0.0)) {
        return std::nullopt;
    }
    return std::pair{d->range_min_m, d->range_max_m > 0.0
                                         ? d->range_max_m
                                         : std::numeric_limits<double>::infinity()};
}

ScannerSpec::ScannerSpec()
    : type_("rotating"), settings_(std::make_unique<SettingsOf<RotatingScanner>>(vlp16())) {}

ScannerSpec::ScannerSpec(std::string type, std::unique_ptr<ScannerSettings> settings)
    : type_(std::move(type)), settings_(std::move(settings)) {
    if (!settings_) {
        throw ConfigError("scanner '" + type_ + "': no settings");
    }
}

ScannerSpec::ScannerSpec(const ScannerSpec& other)
    : type_(other.type_), settings_(other.settings_ ? other.settings_->clone() : nullptr) {}

ScannerSpec& ScannerSpec::operator=(const ScannerSpec& other) {
    if (this != &other) {
        type_ = other.type_;
        settings_ = other.settings_ ? other.settings_->clone() : nullptr;
    }
    return *this;
}

const ScannerSettings& ScannerSpec::settings() const {
    if (!settings_) {
        throw ConfigError("scanner '" + type_ + "': no settings (a moved-from ScannerSpec)");
    }
    return *settings_;
}

std::span<const ScanPatternEntry> scan_pattern_registry() {
    return table();
}

const ScanPatternEntry* find_scan_pattern(std::string_view name) {
    for (const auto& e : table()) {
        if (e.name == name) {
            return &e;
        }
    }
    return nullptr;
}

std::string survey_scanner_types() {
    return join_alternatives(names_with(&ScanPatternEntry::parse));
}

std::string static_scan_pattern_choices() {
    std::string out;
    for (const auto name : names_with(&ScanPatternEntry::static_rays)) {
        out += (out.empty() ? "" : " | ") + std::string(name);
    }
    return out;
}

const ScanPatternEntry& survey_scanner_type(std::string_view name) {
    const ScanPatternEntry* e = find_scan_pattern(name);
    if (e == nullptr || e->parse == nullptr) {
        throw ConfigError("unknown scanner type '" + std::string(name) + "' (expected " +
                          survey_scanner_types() + ")");
    }
    return *e;
}

const ScanPatternEntry& static_scan_pattern(std::string_view name) {
    const ScanPatternEntry* e = find_scan_pattern(name);
    if (e == nullptr || e->static_rays == nullptr) {
        throw ConfigError("unknown pattern '" + std::string(name) + "' (expected " +
                          join_alternatives(names_with(&ScanPatternEntry::static_rays)) + ")");
    }
    return *e;
}

}  // namespace beamtrace
