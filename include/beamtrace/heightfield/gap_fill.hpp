// Closing the gaps of sparse sampling in a section's finest level, so that scan lines and
// rings read as a surface: a run of at most `max_gap` empty cells between two occupied cells
// of the same row (then of the same column) takes the lower of the two heights and its
// attribute. A run of at most `max_gap` cells between an occupied cell and the section's edge
// takes that cell's height too (its other end lies in the neighbouring section, so section
// borders show no seam; at the data's own edge this widens it by at most max_gap cells).
// Wider gaps (water, shadows, the edge of the data) stay empty.
#pragma once

#include <cstddef>

#include "beamtrace/heightfield/height_section.hpp"

namespace beamtrace {

/// Fills the finest level of `section` as above (rows first, then columns; call before
/// build_mipmap()); returns the cells filled. max_gap <= 0 fills nothing.
std::size_t fill_gaps(HeightSection& section, int max_gap);

}  // namespace beamtrace
