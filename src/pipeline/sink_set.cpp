#include "pipeline/detail/sink_set.hpp"

#include <system_error>

namespace beamtrace::detail {

std::vector<std::filesystem::path> SinkSet::commit() {
    std::vector<std::filesystem::path> files;
    try {
        for (auto& sink : sinks_) {
            for (auto& f : sink->commit()) {
                files.push_back(std::move(f));
            }
            for (auto& n : sink->notes()) {
                notes_.push_back(std::move(n));
            }
            sink.reset();
        }
    } catch (...) {
        abort();
        for (const auto& f : files) {
            std::error_code ignored;
            std::filesystem::remove(f, ignored);
        }
        throw;
    }
    sinks_.clear();
    return files;
}

void SinkSet::abort() noexcept {
    for (auto& sink : sinks_) {
        if (sink) {
            sink->abort();
            sink.reset();
        }
    }
    sinks_.clear();
}

}  // namespace beamtrace::detail
