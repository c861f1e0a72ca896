// Beam divergence: a pulse is a cone sampled by sub-rays on concentric rings.
//
// Ring k (k = 0..rings) holds max(1, 6k) sub-rays at the off-axis angle theta_k = k * d with
// d = (divergence / 2) / rings, so the outermost ring lies on the beam's half-angle: rings = 2
// gives 1 + 6 + 12 = 19 sub-rays. Sub-ray j of ring k sits at azimuth 2 pi j / (6k), rotated by
// half a step on odd rings (a hexagonal-like packing). `divergence_rad` is the FULL angle at
// the 1/e^2 intensity points of a Gaussian beam (how data sheets quote it), so the far-field
// profile is I(theta) ~ exp(-2 theta^2 / w^2) with w = divergence / 2.
// Weights: each ring stands for the annulus [theta_k - d/2, theta_k + d/2] (the centre: a disc of
// radius d/2); its share of the Gaussian profile integrated over that annulus (small-angle,
// exact in closed form) is split evenly between its sub-rays; the weights are normalised to
// sum to 1 (the energy beyond the outer annulus, about 1 % for rings >= 1, is folded in).
// rings = 0 (or divergence 0) is a single ray of weight 1.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

struct BeamConfig {
    double divergence_rad = 0.0;  ///< full angle at 1/e^2; 0: an ideal ray (one sub-ray)
    int rings = 2;                ///< rings around the centre: 1 + 3 r (r + 1) sub-rays

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// One sub-ray of the pattern, in the beam frame.
struct SubRayOffset {
    double off_axis_rad = 0.0;  ///< angle from the beam axis
    double azimuth_rad = 0.0;   ///< around the axis, from the frame's first basis vector
    double weight = 1.0;        ///< share of the pulse energy; all weights sum to 1
};

/// The sub-ray pattern of `config` (1 entry when divergence_rad is 0). Deterministic.
[[nodiscard]] std::vector<SubRayOffset> beam_pattern(const BeamConfig& config);

/// Number of sub-rays beam_pattern returns: 1 + 3 rings (rings + 1), or 1 without divergence.
[[nodiscard]] std::size_t sub_ray_count(const BeamConfig& config);

/// A right-handed orthonormal basis (e1, e2) perpendicular to the unit vector `axis`,
/// continuous except near axis = -z (Duff et al., JCGT 2017). Deterministic.
void orthonormal_basis(const Vec3d& axis, Vec3d& e1, Vec3d& e2);

/// Writes the unit direction of every pattern entry around the unit `axis` into `out`
/// (out.size() must equal pattern.size()).
void sub_ray_directions(const Vec3d& axis, std::span<const SubRayOffset> pattern,
                        std::span<Vec3d> out);

/// The pattern's unit directions in the beam frame (x, y along the basis vectors e1, e2 of
/// orthonormal_basis, z along the axis): precompute once, then rotate per pulse cheaply.
[[nodiscard]] std::vector<Vec3d> beam_frame_directions(std::span<const SubRayOffset> pattern);

/// Like sub_ray_directions, from precomputed beam_frame_directions (no trigonometry).
void sub_ray_directions(const Vec3d& axis, std::span<const Vec3d> beam_frame, std::span<Vec3d> out);

}  // namespace beamtrace
