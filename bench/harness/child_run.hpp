// Running a piece of work in a forked child process, so that what it costs in memory (its peak
// resident set) is its own, not added to what this process already holds. Used by the
// throughput benchmark for the peak RSS of each survey run.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace beamtrace::detail {

/// True when this process has one thread: fork() is then safe (no lock is left held by a thread
/// the child does not have, no thread pool believes it has workers).
[[nodiscard]] bool process_is_single_threaded();

struct ChildRun {
    std::string payload;             ///< what `work` returned
    std::size_t peak_rss_bytes = 0;  ///< the child's peak resident set (getrusage ru_maxrss)
};

/// Runs `work` in a forked child and returns what it returned, with the child's peak RSS. An
/// exception in the child comes back as its message: rethrown as ConfigError for beamtrace
/// errors, std::bad_alloc, or std::runtime_error otherwise; a child killed by a signal is a
/// std::runtime_error. Call it only when process_is_single_threaded().
[[nodiscard]] ChildRun run_in_child(const std::function<std::string()>& work);

}  // namespace beamtrace::detail
