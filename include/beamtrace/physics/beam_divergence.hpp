// Beam divergence: a pulse is a Gaussian beam sampled by sub-rays on concentric rings.
//
// Beam units: u = off-axis angle / (divergence / 2), so the 1/e^2 radius is u = 1 and the far-
// field profile exp(-2 u^2) has variance 1/4 per axis. `divergence_rad` is the FULL angle at
// the 1/e^2 intensity points (how data sheets quote it).
// Cells: with d = 1 / rings, the centre sub-ray stands for the disc u < d/2, ring k (k = 1..rings)
// for the annulus [(k - 1/2) d, (k + 1/2) d] (the outermost for [(rings - 1/2) d, inf): the
// Gaussian tail beyond the last ring, 1.1 % of the energy for rings = 1, 4.4 % for 2, 6.6 % for
// 3, belongs to it), cut into max(1, 6k) equal sectors; sector j of ring k is centred on azimuth
// 2 pi j / (6k), rotated by half a step on odd rings (a hexagonal-like packing). rings = 2 gives
// 1 + 6 + 12 = 19 sub-rays. Each sub-ray has its cell's energy as weight (exact in closed form;
// the weights sum to 1) and points at its cell's centroid: radius u_j = E[u | annulus] *
// sin(s/2) / (s/2) with s = 2 pi / (6k). The pattern's per-axis variance V_d =
// 1/2 sum_j w_j u_j^2 then falls short of the beam's 1/4 by exactly the mean within-cell
// variance (law of total variance; the 6k-fold symmetry makes each ring's sum isotropic):
// cell_variance = 1/4 - V_d, the spread every sub-ray's echo gets (pulse.hpp).
// Exit beam: a Gaussian beam of waist diameter D0 = exit_diameter_m has the 1/e^2 radius
// W(R) = sqrt((D0/2)^2 + (R theta/2)^2) at range R (theta the divergence). Its envelope is a
// hyperboloid ruled by straight lines: sub-ray j, angular offset phi_j = u_j theta/2 (cos a,
// sin a), starts at (D0/theta) rot90(phi_j) = (D0/2) u_j (-sin a, cos a) in the exit pupil,
// so at range R it lies at radius u_j W(R) exactly (theta = 0: a collimated beam, parallel
// sub-rays from (D0/2) u_j (cos a, sin a)). D0 = 0 (the default): every sub-ray starts at the
// sensor's origin.
// rings = 0, or no divergence and no exit diameter, is a single ray of weight 1.
// Edge cells (targets smaller than a cell). A sub-ray stands for its whole cell, so a wire or a
// branch that one sub-ray meets would count as filling the cell. Where a cell's sub-ray sees
// another target than a neighbouring cell's (a hit against a miss, or another part), the cell
// is sampled again by edge_samples^2 probe rays: its annulus cut into edge_samples bands of
// equal energy, each cut into edge_samples equal sectors, a probe at each sub-cell's centroid
// (cell_probe_pattern). The cell's energy is then shared equally by its sub-ray and its probes,
// so a target receives the fraction of the cell it covers, to 1 / (edge_samples^2 + 1).
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

struct BeamConfig {
    double divergence_rad = 0.0;   ///< full angle at 1/e^2; 0: an ideal ray (one sub-ray)
    int rings = 2;                 ///< rings around the centre: 1 + 3 r (r + 1) sub-rays
    double exit_diameter_m = 0.0;  ///< 1/e^2 diameter at the exit pupil (the waist); 0: a point
    /// Probe rays per axis of an edge cell (edge_samples^2 probes); 0: a sub-ray always fills
    /// its cell.
    int edge_samples = 3;

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// One sub-ray of the pattern, in the beam frame.
struct SubRayOffset {
    double off_axis_rad = 0.0;  ///< angle from the beam axis: radius * divergence / 2
    double radius = 0.0;        ///< off-axis position in beam units (the 1/e^2 radius is 1)
    double azimuth_rad = 0.0;   ///< around the axis, from the frame's first basis vector
    double weight = 1.0;        ///< share of the pulse energy; all weights sum to 1
};

/// The sub-ray pattern of `config` (1 entry when divergence_rad is 0). Deterministic.
[[nodiscard]] std::vector<SubRayOffset> beam_pattern(const BeamConfig& config);

/// The probes of every cell of beam_pattern(config): cell j's edge_samples^2 probes are entries
/// [j P, (j + 1) P) with P = edge_samples^2, each with its sub-cell's energy as weight (the
/// weights of a cell's probes sum to its own). Empty for a single ray or edge_samples 0.
[[nodiscard]] std::vector<SubRayOffset> cell_probe_pattern(const BeamConfig& config);

/// The neighbours of every cell of beam_pattern(config): cells of one ring next to each other,
/// and cells of adjacent rings whose sectors overlap. Empty lists for a single ray.
[[nodiscard]] std::vector<std::vector<std::uint32_t>> cell_neighbours(const BeamConfig& config);

/// Number of sub-rays beam_pattern returns: 1 + 3 rings (rings + 1), or 1 without divergence
/// and exit diameter.
[[nodiscard]] std::size_t sub_ray_count(const BeamConfig& config);

/// The per-axis variance (beam units) of the footprint each sub-ray's cell stands for:
/// 1/4 - 1/2 sum_j w_j radius_j^2, at least 0 (1/4 for a single ray).
[[nodiscard]] double cell_variance(std::span<const SubRayOffset> pattern);

/// The footprint's 1/e^2 radius at range `range_m`: sqrt((D0/2)^2 + (range theta/2)^2) [m].
/// (Inline: every sample of every pulse asks it, for its echo's width.)
[[nodiscard]] inline double footprint_radius_m(const BeamConfig& config, double range_m) {
    if (config.exit_diameter_m == 0) {
        return std::abs(range_m * config.divergence_rad / 2.0);  // hypot(0, y) is |y|, exactly
    }
    return std::hypot(config.exit_diameter_m / 2.0, range_m * config.divergence_rad / 2.0);
}

/// The sub-rays' start offsets in the beam frame (x, y along e1, e2 of orthonormal_basis, z = 0)
/// [m]: all zero when exit_diameter_m is 0.
[[nodiscard]] std::vector<Vec3d> beam_frame_origins(const BeamConfig& config,
                                                    std::span<const SubRayOffset> pattern);

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

/// The world start points of the sub-rays: `origin` plus the beam-frame offsets
/// (beam_frame_origins) rotated into the frame of the unit `axis`.
void sub_ray_origins(const Vec3d& origin, const Vec3d& axis, std::span<const Vec3d> beam_frame,
                     std::span<Vec3d> out);

}  // namespace beamtrace
