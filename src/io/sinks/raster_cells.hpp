// Which cell of a raster a coordinate falls in, for the sinks that bin points (preview.png).
#pragma once

#include <cmath>

namespace beamtrace::detail {

/// floor(d / cell), by a multiplication with per_cell = 1 / cell (a division per coordinate was
/// half of the preview's time). The product is within 2^-52 (relative) of the quotient, so the
/// two have the same floor unless the product lies within 2^-49 of a whole number, where the
/// division decides: always the same cell as dividing.
[[nodiscard]] inline double cells_floor(double d, double cell, double per_cell) {
    const double q = d * per_cell;
    const double f = std::floor(q);
    const double margin = std::abs(q) * 0x1p-49;
    if (q - f > margin && f + 1.0 - q > margin) {
        return f;
    }
    return std::floor(d / cell);  // near a cell's edge, at zero, infinite or NaN
}

}  // namespace beamtrace::detail
