// Progress reporting from long library calls: the library reports, the caller draws.
#pragma once

#include <cstddef>
#include <functional>

namespace beamtrace {

/// Called with (work done, total work) from the calling thread, never concurrently.
using ProgressFn = std::function<void(std::size_t done, std::size_t total)>;

}  // namespace beamtrace
