// The table of scan pattern types, in the spirit of pbrt-v4's Camera::Create: a survey file's
// `scanner: {type: NAME, ...}` names an entry, whose own parse reads and validates its own keys
// (an unknown key is an error naming the type) into its own config struct; `beamtrace scan
// --pattern NAME` uses the entries that cast the rays of a sensor standing still. Each entry's
// keys, units and defaults are documented in docs/survey.md, one section per type.
//
// Adding a scan mechanism (a conic/Palmer scanner, a rotating polygon, Risley prisms, a fibre
// array, ...) = one new file + one registry line:
//   1. src/sensor/<name>_scanner.cpp (+ include/beamtrace/sensor/<name>_scanner.hpp): its config
//      struct with documented defaults and validate(), its ScanPattern (with `using Config =
//      <its config>;`), and `ScanPatternEntry <name>_scanner_entry()` returning its name, a
//      one-line summary, its own YAML keys and its parse function (read the keys with the
//      YamlChecker as `scanner.<key>`, then report every validate() problem under `scanner`;
//      return std::make_unique<SettingsOf<ItsPattern>>(config));
//   2. declare that function in src/sensor/detail/scan_pattern_types.hpp and add one line to
//      the table in src/sensor/scan_pattern_registry.cpp;
//   3. a section in docs/survey.md with every key, its unit and default, and a test that the
//      type accepts exactly its keys (tests/sensor/scan_pattern_registry_test.cpp iterates the
//      table, so the generic checks cover it already).
// Nothing in the pipeline changes: survey files, SurveySpec::make_pattern() and the error
// messages listing the types all come from the table.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/sensor/image_sensor.hpp"
#include "beamtrace/sensor/scan_pattern.hpp"

namespace YAML {
class Node;
}

namespace beamtrace {

namespace detail {
class YamlChecker;
}
struct SensorDataSheet;  // sensor/mechanism_presets.hpp

/// One scanner type's settings behind one interface (what a registry entry's parse returns).
class ScannerSettings {
  public:
    virtual ~ScannerSettings() = default;
    ScannerSettings() = default;
    ScannerSettings(const ScannerSettings&) = default;
    ScannerSettings& operator=(const ScannerSettings&) = default;
    ScannerSettings(ScannerSettings&&) = default;
    ScannerSettings& operator=(ScannerSettings&&) = default;

    [[nodiscard]] virtual std::unique_ptr<ScannerSettings> clone() const = 0;
    /// Every problem with these settings; empty when valid.
    [[nodiscard]] virtual std::vector<std::string> validate() const = 0;
    /// The pattern; throws ConfigError listing every problem.
    [[nodiscard]] virtual std::unique_ptr<ScanPattern> make_pattern() const = 0;
    /// The range limits [min, max] in metres that a sensor preset's data sheet gives, the
    /// survey's defaults for range_min_m and range_max_m; nullopt: none.
    /// Default: the data sheet's limits (a maximum of +infinity when it gives none); nullopt
    /// without a data sheet or limits.
    [[nodiscard]] virtual std::optional<std::pair<double, double>> preset_range_m() const;
    /// These settings firing from `start_time_s` for `duration_s` (a survey leg, LegSequence),
    /// with the same data sheet; nullptr for a type without a duration (an image pattern counts
    /// frames).
    [[nodiscard]] virtual std::unique_ptr<ScannerSettings> with_timing(double start_time_s,
                                                                       double duration_s) const {
        static_cast<void>(start_time_s);
        static_cast<void>(duration_s);
        return nullptr;
    }

    /// The data sheet of the sensor preset these settings started from (a mechanism's
    /// `preset`, sensor/mechanism_presets.hpp), or nullptr. Its divergence and wavelength are
    /// the defaults of a survey's physics block.
    [[nodiscard]] const SensorDataSheet* data_sheet() const { return data_sheet_; }
    void set_data_sheet(const SensorDataSheet* sheet) { data_sheet_ = sheet; }

  private:
    const SensorDataSheet* data_sheet_ = nullptr;  ///< static data, never owned
};

/// The settings of a `Pattern` type: its `Pattern::Config`, from which it is constructed.
template <class Pattern>
class SettingsOf final : public ScannerSettings {
  public:
    using Config = typename Pattern::Config;
    explicit SettingsOf(Config c) : config(std::move(c)) {}

    [[nodiscard]] std::unique_ptr<ScannerSettings> clone() const override {
        return std::make_unique<SettingsOf>(*this);
    }
    [[nodiscard]] std::vector<std::string> validate() const override { return config.validate(); }
    [[nodiscard]] std::unique_ptr<ScanPattern> make_pattern() const override {
        return std::make_unique<Pattern>(config);
    }
    /// Config::preset_range_m() when the config has one, else the data sheet's.
    [[nodiscard]] std::optional<std::pair<double, double>> preset_range_m() const override {
        if constexpr (requires(const Config& c) { c.preset_range_m(); }) {
            return config.preset_range_m();
        } else {
            return ScannerSettings::preset_range_m();
        }
    }
    [[nodiscard]] std::unique_ptr<ScannerSettings> with_timing(double start_time_s,
                                                               double duration_s) const override {
        if constexpr (requires(Config & c) {
                          c.start_time_s = 0.0;
                          c.duration_s = 0.0;
                      }) {
            Config c = config;
            c.start_time_s = start_time_s;
            c.duration_s = duration_s;
            auto timed = std::make_unique<SettingsOf>(std::move(c));
            timed->set_data_sheet(data_sheet());
            return timed;
        } else {
            static_cast<void>(start_time_s);
            static_cast<void>(duration_s);
            return nullptr;
        }
    }

    Config config;
};

/// A survey's scanner: the registry type name and that type's settings. A value (copies are
/// deep), so a SurveySpec stays copyable.
class ScannerSpec {
  public:
    /// A rotating VLP-16 (vlp16()), one revolution.
    ScannerSpec();
    ScannerSpec(std::string type, std::unique_ptr<ScannerSettings> settings);
    ScannerSpec(const ScannerSpec& other);
    ScannerSpec& operator=(const ScannerSpec& other);
    ScannerSpec(ScannerSpec&&) noexcept = default;
    ScannerSpec& operator=(ScannerSpec&&) noexcept = default;
    ~ScannerSpec() = default;

    /// The registry name ("rotating", "line", "pinhole", "scan", ...).
    [[nodiscard]] const std::string& type() const { return type_; }
    /// Throws ConfigError for a moved-from spec.
    [[nodiscard]] const ScannerSettings& settings() const;
    /// The config when the settings are those of `Pattern`, else nullptr.
    template <class Pattern>
    [[nodiscard]] const typename Pattern::Config* config() const {
        const auto* s = dynamic_cast<const SettingsOf<Pattern>*>(settings_.get());
        return s != nullptr ? &s->config : nullptr;
    }
    [[nodiscard]] std::unique_ptr<ScanPattern> make_pattern() const {
        return settings().make_pattern();
    }

  private:
    std::string type_;
    std::unique_ptr<ScannerSettings> settings_;
};

/// What `beamtrace scan` knows of a sensor standing still.
struct StaticScanInput {
    ImageSensorConfig sensor;         ///< position, orientation, image size and fields of view
    std::filesystem::path rays_file;  ///< for a pattern that reads its rays from a file
};

/// The rays of a static scan, and their image grid when they form an image.
struct StaticRays {
    RayBatch rays;
    std::optional<ImageGrid> grid;
};

struct ScanPatternEntry {
    using ParseFn = std::unique_ptr<ScannerSettings> (*)(detail::YamlChecker&, const YAML::Node&);
    using StaticRaysFn = StaticRays (*)(const StaticScanInput&);
    using StaticCheckFn = std::vector<std::string> (*)(const StaticScanInput&);

    std::string_view name;
    std::string_view summary;
    /// Its own keys in a survey's `scanner:` block (besides type, range_min_m, range_max_m).
    std::span<const std::string_view> keys;
    /// Survey files: reads the keys of the node (errors `scanner.<key>: what`) and reports
    /// every validate() problem (`scanner: what`). nullptr: not a survey scanner.
    ParseFn parse = nullptr;
    /// `beamtrace scan`: the rays (throws InputError/ConfigError). nullptr: not offered there.
    StaticRaysFn static_rays = nullptr;
    /// `beamtrace scan`: the problems of the input for this pattern (nullptr: none to check).
    StaticCheckFn check_static = nullptr;
    bool reads_rays_file = false;  ///< its rays come from StaticScanInput::rays_file
};

/// Every scan pattern type, in the order of help texts and docs/survey.md.
[[nodiscard]] std::span<const ScanPatternEntry> scan_pattern_registry();
/// The entry named `name`, or nullptr.
[[nodiscard]] const ScanPatternEntry* find_scan_pattern(std::string_view name);
/// The survey scanner type `name`; throws ConfigError "unknown scanner type 'x' (expected
/// rotating, line, conic, polygon, risley, fibre, pinhole or scan)".
[[nodiscard]] const ScanPatternEntry& survey_scanner_type(std::string_view name);
/// The `beamtrace scan` pattern `name`; throws ConfigError "unknown pattern 'x' (expected
/// pinhole, scan or rays)".
[[nodiscard]] const ScanPatternEntry& static_scan_pattern(std::string_view name);
/// "rotating, line, conic, polygon, risley, fibre, pinhole or scan": the survey scanner types.
[[nodiscard]] std::string survey_scanner_types();
/// "pinhole | scan | rays": the patterns of `beamtrace scan`, for its help text.
[[nodiscard]] std::string static_scan_pattern_choices();

}  // namespace beamtrace
