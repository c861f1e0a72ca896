// Reading YAML config files: collects every problem with file, line and key.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "beamtrace/core/angle_text.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/core/vec3.hpp"
#include "text/file_bytes.hpp"
#include "text/quote.hpp"
#include "text/yaml_node_count.hpp"

namespace beamtrace::detail {

class YamlChecker {
  public:
    explicit YamlChecker(std::filesystem::path source) : source_(std::move(source)) {}

    /// The file being read (files it names are relative to its folder).
    [[nodiscard]] const std::filesystem::path& source() const { return source_; }

    void error(const YAML::Node& node, const std::string& key, const std::string& what) {
        std::string where = source_.string();
        if (node.IsDefined() && node.Mark().line >= 0) {
            where += ":" + std::to_string(node.Mark().line + 1);
        }
        errors_.push_back(where + ": " + key + ": " + what);
    }
    [[nodiscard]] const std::vector<std::string>& errors() const { return errors_; }

    /// Reports every key of `map` not in `known` (and every key that is not a name, such as a
    /// list); `owner` (e.g. "a rotating scanner"), when given, says whose keys these are. Keys
    /// are quoted clipped (quote.hpp). Does nothing when `map` is not a map (its parser says so).
    template <typename Names>
    void only_keys_of(const YAML::Node& map, const std::string& key, const Names& known,
                      const std::string& owner = {}) {
        if (!map.IsMap()) {
            return;
        }
        const std::string prefix = key.empty() ? "" : key + ".";
        for (const auto& kv : map) {
            if (!kv.first.IsScalar()) {
                error(
                    kv.first, key.empty() ? "key" : key,
                    "a key must be a name, not a " + std::string(kv.first.IsMap()        ? "map"
                                                                 : kv.first.IsSequence() ? "list"
                                                                                         : "null"));
                continue;
            }
            const std::string& name = kv.first.Scalar();
            bool ok = false;
            for (const auto& k : known) {
                ok = ok || name == std::string_view(k);
            }
            if (!ok) {
                std::string list;
                for (const auto& k : known) {
                    list += (list.empty() ? "" : ", ") + std::string(k);
                }
                error(kv.first, prefix + clip_value(name),
                      "unknown key" + (owner.empty() ? "" : " for " + owner) +
                          " (expected one of: " + list + ")");
            }
        }
    }

    /// only_keys_of for a list of names written in place.
    void only_keys(const YAML::Node& map, const std::string& key,
                   std::initializer_list<const char*> known, const std::string& owner = {}) {
        only_keys_of(map, key, known, owner);
    }

    /// Checks that `path` (named by `node` at `key`) exists, without throwing: a name too
    /// long, a loop of links or a folder that cannot be searched is an error like a missing file.
    /// Names the file by its path when the name as written is short, else quotes it clipped.
    bool existing_file(const YAML::Node& node, const std::string& key,
                       const std::filesystem::path& path) {
        const std::string written = node.IsScalar() ? node.Scalar() : path.string();
        const std::string name =
            written.size() <= kQuoteMaxChars ? path.string() : quote_value(written);
        std::error_code ec;
        const bool exists = std::filesystem::exists(path, ec);
        if (ec) {
            error(node, key, "cannot check the file " + name + ": " + ec.message());
            return false;
        }
        if (!exists) {
            error(node, key, "file not found: " + name);
        }
        return exists;
    }

    /// A finite number. A key whose name ends in `_deg` or `_rad` (before any [index]) is an
    /// angle: its value may carry a unit ("60deg", "1.05rad", core/angle_text.hpp), and a plain
    /// number in degrees that reads as radians (1.5708) is an error. A `wavelength_nm` outside
    /// 200-12 000 nm is an error (micrometres typed into nanometres).
    bool number(const YAML::Node& node, const std::string& key, double& out) {
        if (!node.IsScalar()) {
            error(node, key, "expected a number");
            return false;
        }
        if (const auto unit = angle_unit_of(key)) {
            return angle(node, key, *unit, out);
        }
        if (key.ends_with("wavelength_nm")) {
            return wavelength(node, key, out);
        }
        try {
            const double v = node.as<double>();
            if (!std::isfinite(v)) {
                error(node, key, "expected a finite number");
                return false;
            }
            out = v;
            return true;
        } catch (const YAML::Exception&) {
            error(node, key, "expected a number, got " + quote_value(node.Scalar()));
            return false;
        }
    }

    /// The unit of an angle key (`..._deg`, `..._deg[2]`, `..._rad`), or nullopt.
    static std::optional<AngleUnit> angle_unit_of(std::string_view key) {
        while (key.ends_with("]") && key.find('[') != std::string_view::npos) {
            key = key.substr(0, key.rfind('['));
        }
        if (key.ends_with("_deg")) {
            return AngleUnit::deg;
        }
        if (key.ends_with("_rad")) {
            return AngleUnit::rad;
        }
        return std::nullopt;
    }

    bool angle(const YAML::Node& node, const std::string& key, AngleUnit unit, double& out) {
        const auto a = parse_angle(node.Scalar(), unit);
        if (!a) {
            double v = 0.0;
            const bool non_finite = YAML::convert<double>::decode(node, v) && !std::isfinite(v);
            error(node, key,
                  non_finite ? std::string("expected a finite number")
                             : "expected a number (an angle in " +
                                   std::string(unit == AngleUnit::deg ? "degrees" : "radians") +
                                   "; a unit may follow: 60deg, 1.05rad), got " +
                                   quote_value(node.Scalar()));
            return false;
        }
        if (unit == AngleUnit::deg && !a->explicit_unit) {
            if (const auto pi = radian_lookalike(a->value)) {
                error(node, key, radian_lookalike_message(a->value, *pi));
                return false;
            }
        }
        out = a->value;
        return true;
    }

    bool wavelength(const YAML::Node& node, const std::string& key, double& out) {
        double v = 0.0;
        try {
            v = node.as<double>();
        } catch (const YAML::Exception&) {
            error(node, key, "expected a number, got " + quote_value(node.Scalar()));
            return false;
        }
        if (!(v >= 200.0 && v <= 12000.0)) {
            error(node, key,
                  quote_value(node.Scalar()) +
                      " nm is outside 200-12000 nm, the wavelengths of LiDAR (micrometres? " +
                      "1.064 um is 1064 nm)");
            return false;
        }
        out = v;
        return true;
    }

    bool vec3(const YAML::Node& node, const std::string& key, Vec3d& out) {
        if (!node.IsSequence() || node.size() != 3) {
            error(node, key, "expected three numbers [x, y, z]");
            return false;
        }
        Vec3d v;
        bool ok = true;
        for (std::size_t i = 0; i < 3; ++i) {
            ok = number(node[i], key + "[" + std::to_string(i) + "]", v[i]) && ok;
        }
        if (ok) {
            out = v;
        }
        return ok;
    }

    bool boolean(const YAML::Node& node, const std::string& key, bool& out) {
        try {
            out = node.as<bool>();
            return true;
        } catch (const YAML::Exception&) {
            error(node, key, "expected true or false");
            return false;
        }
    }

    bool integer(const YAML::Node& node, const std::string& key, long lo, long hi, long& out) {
        double v = 0;
        if (!number(node, key, v)) {
            return false;
        }
        if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi)) {
            error(
                node, key,
                "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
            return false;
        }
        out = static_cast<long>(v);
        return true;
    }

    /// Throws ConfigError listing the problems, if there are any: a single problem as its own
    /// line (`file:line: key: what`), so the CLI's one-line message names the file; several
    /// under a count, one line each, the first kMaxListedProblems of them.
    void throw_if_any(const std::string& what) const {
        if (errors_.empty()) {
            return;
        }
        if (errors_.size() == 1) {
            throw ConfigError(errors_.front());
        }
        std::string msg = std::to_string(errors_.size()) + " problem(s) in the " + what + ":";
        for (std::size_t i = 0; i < errors_.size() && i < kMaxListedProblems; ++i) {
            msg += "\n  " + errors_[i];
        }
        if (errors_.size() > kMaxListedProblems) {
            msg += "\n  ... and " + std::to_string(errors_.size() - kMaxListedProblems) + " more";
        }
        throw ConfigError(msg);
    }

    /// The most problems throw_if_any lists.
    static constexpr std::size_t kMaxListedProblems = 50;

  private:
    std::filesystem::path source_;
    std::vector<std::string> errors_;
};

/// Parses YAML text; a syntax error becomes a ConfigError naming `source` and the line, and so
/// does a text of more than kMaxYamlNodes nodes (refused before any node is built).
[[nodiscard]] inline YAML::Node parse_yaml(const std::string& text,
                                           const std::filesystem::path& source) {
    try {
        if (count_yaml_nodes(text, kMaxYamlNodes) > kMaxYamlNodes) {
            throw ConfigError(source.string() + ": more than " + std::to_string(kMaxYamlNodes) +
                              " YAML nodes (values, lists and maps), the limit for a config file");
        }
        return YAML::Load(text);
    } catch (const YAML::Exception& e) {
        const std::string line = e.mark.is_null() ? "" : ":" + std::to_string(e.mark.line + 1);
        throw ConfigError(source.string() + line + ": not valid YAML: " + clip_value(e.msg));
    }
}

/// The whole text of a config file (the `what`, e.g. "scene file"): a regular file of at most
/// kMaxConfigFileBytes; InputError naming it (and the limit) otherwise.
[[nodiscard]] inline std::string read_config_text(const std::filesystem::path& path,
                                                  const std::string& what) {
    return read_bounded_file(path, what, kMaxConfigFileBytes);
}

}  // namespace beamtrace::detail
