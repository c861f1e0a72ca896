#include "beamtrace/heightfield/gap_fill.hpp"

namespace beamtrace {

namespace {

/// Fills the runs of at most max_gap empty cells along one line of the finest level: cell k of
/// the line is (x0 + k * dx, y0 + k * dy).
std::size_t fill_line(HeightSection& s, int x0, int y0, int dx, int dy, int max_gap) {
    const int n = s.layout().finest_cells();
    std::size_t filled = 0;
    int last = -1;  // the last occupied cell of the line
    for (int k = 0; k < n; ++k) {
        const int x = x0 + k * dx, y = y0 + k * dy;
        if (s.height(0, x, y) == kEmptyHeight) {
            continue;
        }
        const int gap = k - last - 1;
        if (last >= 0 && gap > 0 && gap <= max_gap) {
            const int lx = x0 + last * dx, ly = y0 + last * dy;
            const bool left_lower = s.height(0, lx, ly) <= s.height(0, x, y);
            const float z = left_lower ? s.height(0, lx, ly) : s.height(0, x, y);
            const auto attribute = left_lower ? s.attribute(lx, ly) : s.attribute(x, y);
            for (int j = last + 1; j < k; ++j) {
                s.insert(x0 + j * dx, y0 + j * dy, z, attribute);
            }
            filled += static_cast<std::size_t>(gap);
        }
        if (last < 0 && k > 0 && k <= max_gap) {
            // A run at the section's first edge: its other end is in the next section over, so
            // it takes this side's height (else every section border would show as a seam).
            for (int j = 0; j < k; ++j) {
                s.insert(x0 + j * dx, y0 + j * dy, s.height(0, x, y), s.attribute(x, y));
            }
            filled += static_cast<std::size_t>(k);
        }
        last = k;
    }
    if (last >= 0 && n - 1 - last > 0 && n - 1 - last <= max_gap) {  // the same at the far edge
        const int lx = x0 + last * dx, ly = y0 + last * dy;
        for (int j = last + 1; j < n; ++j) {
            s.insert(x0 + j * dx, y0 + j * dy, s.height(0, lx, ly), s.attribute(lx, ly));
        }
        filled += static_cast<std::size_t>(n - 1 - last);
    }
    return filled;
}

}  // namespace

std::size_t fill_gaps(HeightSection& section, int max_gap) {
    if (max_gap <= 0) {
        return 0;
    }
    const int n = section.layout().finest_cells();
    std::size_t filled = 0;
    for (int y = 0; y < n; ++y) {
        filled += fill_line(section, 0, y, 1, 0, max_gap);
    }
    for (int x = 0; x < n; ++x) {
        filled += fill_line(section, x, 0, 0, 1, max_gap);
    }
    return filled;
}

}  // namespace beamtrace
