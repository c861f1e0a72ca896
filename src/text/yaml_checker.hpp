// Reading YAML config files: collects every problem with file, line and key.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/vec3.hpp"
#include "text/file_bytes.hpp"
#include "text/quote.hpp"
#include "text/yaml_node_count.hpp"

namespace beamtrace::detail {

class YamlChecker {
  public:
    explicit YamlChecker(std::filesystem::path source) : source_(std::move(source)) {}

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

    bool number(const YAML::Node& node, const std::string& key, double& out) {
        if (!node.IsScalar()) {
            error(node, key, "expected a number");
            return false;
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
