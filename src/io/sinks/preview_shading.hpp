// preview.png's pixels: a height's jet colour darkened by hill shading, one raster row at a time,
// in AVX2 lanes where the CPU has them (the same bytes as the scalar formula on every CPU).
#pragma once

#include <cstdint>

namespace beamtrace::detail {

/// The heights a row of the preview reads: the row, the rows above and below it (clamped at the
/// raster's edges: the row itself there), `width` pixels each; `empty` marks a pixel without a
/// point (an empty neighbour counts as the pixel's own height).
struct PreviewRows {
    const float* up = nullptr;
    const float* row = nullptr;
    const float* down = nullptr;
    int width = 0;
    float empty = 0.0f;
};

/// How heights become colours: jet over [z_lo, z_lo + span] (blue low; 0.5 where span is 0),
/// slopes from differences over two pixels of `cell_m`.
struct PreviewShading {
    double z_lo = 0.0, span = 0.0, cell_m = 1.0;
};

/// Pixels [x0, x1) of `rows.row` as RGB into out[3 * (x - x0) ...]; empty pixels are left as they
/// are. Each channel is round(jet * shade) where jet = round(255 * trapezoid(t)), rounded as
/// std::lround() rounds, t the height's place in the span, shade the hill shading from the
/// north-west (1 on flat ground, 0.35 facing away).
void shade_preview_row(const PreviewRows& rows, const PreviewShading& shading, int x0, int x1,
                       std::uint8_t* out);

/// The same, always by the scalar code (for tests of the lanes).
void shade_preview_row_scalar(const PreviewRows& rows, const PreviewShading& shading, int x0,
                              int x1, std::uint8_t* out);

}  // namespace beamtrace::detail
