// The table of point sinks: every output by name, its files, the survey `output:` key that
// switches it on, and its factory. Adding an output = one sink file + one line of the table
// (src/io/sinks/registry.cpp).
#pragma once

#include <memory>
#include <span>
#include <string_view>

#include "beamtrace/io/point_sink.hpp"

namespace beamtrace {

struct SinkEntry {
    std::string_view name;   ///< e.g. "ply"
    std::string_view files;  ///< what it writes, e.g. "points.ply"
    /// The survey file's `output: {<key>: true}` that switches it on; empty: not switchable
    /// (on whenever `applies` says so).
    std::string_view key;
    std::string_view what;  ///< one line for the docs
    /// Whether the run calls for it at all (e.g. images: an image grid), whatever the key says.
    bool (*applies)(const SinkFacts& facts) = nullptr;
    std::unique_ptr<PointSink> (*make)(const SinkFacts& facts) = nullptr;
};

/// Every sink, in the order their files are committed and listed.
[[nodiscard]] std::span<const SinkEntry> point_sinks();
/// The sink named `name`; throws ConfigError naming the known ones otherwise.
[[nodiscard]] const SinkEntry& point_sink(std::string_view name);

}  // namespace beamtrace
