// Per-pixel ray casting of the resident height-field sections: the hierarchical maximum-mipmap
// traversal of Dick, Krueger & Westermann (2009), and a brute-force reference.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "beamtrace/heightfield/color_mode.hpp"
#include "beamtrace/heightfield/section_grid.hpp"
#include "beamtrace/heightfield/view_camera.hpp"

namespace beamtrace {

class ThreadPool;

struct RenderOptions {
    /// Lambert shading from height-map normals (central differences of the finest level; the
    /// sides of cell columns use their face normals), with a fixed sun and 35 % ambient light.
    bool shading = true;
    /// Distance fog: colours fade to the sky by 1 - exp(-distance / fog_distance); 0 = off.
    double fog_distance = 0.0;
    Rgb8 sky = {150, 180, 220};  ///< colour of rays that hit nothing
    /// Eye-dome lighting strength (heightfield/eye_dome.hpp): darkens pixels behind nearer
    /// neighbours, outlining columns, crowns and walls; 0 = off, 1 = a clear outline.
    double eye_dome = 0.0;
    int tile_pixels = 16;  ///< square tiles handed to the threads
    /// Rays traced together in SIMD lanes: 0 = the most this CPU has (8 with AVX-512, 4 with
    /// AVX2, else 1); 1 = one ray at a time; 4 or 8 = at most that many. The image is the same
    /// bit for bit whatever the lanes; height stacks are traced one ray at a time.
    int simd_lanes = 0;
};

/// An RGB image with the distance along each pixel's ray to its hit (+inf for a miss).
struct ViewImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;  ///< width * height * 3, row-major, top row first
    std::vector<float> depth;       ///< width * height
    /// Rays per kernel call of the traversal that rendered the image: 1 (one ray at a time), 4
    /// (AVX2) or 8 (AVX-512). RenderOptions::simd_lanes is only an upper bound (height stacks
    /// and CPUs without the instruction set get fewer), so tests and benchmarks read what ran.
    int kernel_lanes = 0;
    [[nodiscard]] std::size_t hits() const;
};

/// Renders the loaded sections of `grid` from `camera` with the hierarchical traversal (all ray
/// directions; descend a level on a potential hit, climb when leaving the parent's 2x2 block),
/// reading the sections in place. Tiles are spread over `pool`; the image does not depend on
/// the number of threads. Throws ConfigError on a bad camera.
[[nodiscard]] ViewImage render_view(const SectionGrid& grid, const ViewCamera& camera,
                                    const RenderOptions& options, ThreadPool& pool);

/// The same into `image`, reusing its buffers (no allocation when the size is unchanged): for
/// frame loops.
void render_view(const SectionGrid& grid, const ViewCamera& camera, const RenderOptions& options,
                 ThreadPool& pool, ViewImage& image);

/// The same image by stepping through every finest cell along each ray (no hierarchy): the
/// oracle of the tests. Same setup, hit test and shading as render_view.
[[nodiscard]] ViewImage render_view_reference(const SectionGrid& grid, const ViewCamera& camera,
                                              const RenderOptions& options, ThreadPool& pool);

}  // namespace beamtrace
