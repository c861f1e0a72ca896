// Progress reporting from long library calls: the library reports, the caller draws.
#pragma once

#include <cstddef>
#include <functional>

namespace beamtrace {

/// Called with (work done, total work), never concurrently. A first call with done == 0 marks
/// the start of the long stage (after loading and building), so that rates count from there.
using ProgressFn = std::function<void(std::size_t done, std::size_t total)>;

}  // namespace beamtrace
