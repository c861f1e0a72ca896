// This process's resident memory, for reports and benchmarks (Linux /proc; 0 where unknown).
#pragma once

#include <cstddef>

namespace beamtrace {

/// Current resident set size in bytes (VmRSS).
[[nodiscard]] std::size_t current_rss_bytes();
/// Highest resident set size since the process started or since the last successful
/// reset_peak_rss() (VmHWM).
[[nodiscard]] std::size_t peak_rss_bytes();
/// Returns the heap's free memory to the system where the C library can (glibc's malloc_trim),
/// so a peak measured next is not inflated by what earlier work freed.
void trim_free_memory();
/// Resets the peak to the current RSS (writes 5 to /proc/self/clear_refs); false when the
/// kernel does not allow it, in which case peak_rss_bytes() keeps counting from the start.
bool reset_peak_rss();

}  // namespace beamtrace
