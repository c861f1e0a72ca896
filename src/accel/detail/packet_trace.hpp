// Nearest hits of coherent rays in packets of 8 (AVX2) or 16 (AVX-512) lanes over one mesh's BVH
// (packet_trace.cpp): one walk of the tree per packet with a mask of the lanes still in each node,
// and the watertight test in lanes with the scalar test's float arithmetic, operation for
// operation (packet_trace.cpp is compiled with -ffp-contract=off, so no product is fused into
// an FMA). The hits equal the single-ray walk's bit for bit: per lane, the nearest hit is the
// least (t, face) among the faces whose test passes within the lane's limit, whatever the order
// in which nodes are met, and a lane enters a node on the same slab test as a single ray does.
// A coherent packet (directions within 0.032 rad, one sign per moving axis) walks the tree as one
// frustum instead (interval culling, packet_kernel.inl): a node is skipped only if every lane's
// slab test would fail, and at a leaf the lanes whose own slab test enters it test its faces,
// as in the lane-by-lane walk, so the hits are the same.
#pragma once

#include <cstddef>

#include "beamtrace/accel/bvh.hpp"
#include "beamtrace/core/hit_batch.hpp"
#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace::detail {

/// The widest packet this CPU can trace: 16 (AVX-512F/DQ), 8 (AVX2) or 1 (neither, or a build
/// for another architecture).
[[nodiscard]] int widest_packet_lanes();

/// The packet width `config` asks for on this CPU (1: single rays).
[[nodiscard]] int packet_lanes(const BvhTraceConfig& config);

/// Nearest hits of rays [begin, end) into `hits`, as the single-ray walk gives them, in packets
/// of `lanes` (8 or 16, at most widest_packet_lanes(); else one ray at a time). Rays are grouped
/// by the watertight test's axis order and the signs of their other two direction components
/// (so that interval culling bounds every axis), 1024 at a time, and a packet is made of
/// neighbouring directions of a group (sorted by elevation, then azimuth: a spinning scanner's fan
/// of beams gives packets of one beam's consecutive firings, which meet the ground side by side);
/// with `only_coherent` a packet whose directions spread wider than `max_spread_rad` is traced ray
/// by ray. The order changes no result: each ray's hit is its single-ray walk's.
void intersect_packets(const Bvh& bvh, const TriangleMesh& mesh, const RayBatch& rays,
                       std::size_t begin, std::size_t end, HitBatch& hits, int lanes,
                       bool only_coherent, double max_spread_rad);

/// intersect_packets for rays in beams of `rays_per_beam` (rays [begin + k * rays_per_beam,
/// begin + (k + 1) * rays_per_beam): a pulse's sub-rays, from one origin in a narrow cone): the
/// same hits, bit for bit. Without the stage's sort, as many whole beams as 128 rays hold walk
/// the tree as one frustum (packets of `lanes` sharing one walk; each lane tests the faces of the
/// leaves its own slab test enters) where their rays share the watertight axis order; lanes
/// moving up and down an axis (a beam about a plane of it) are bounded on it by their own near
/// and far distances. Beams of one ray or of more than 128 are traced as intersect_packets.
void intersect_beams(const Bvh& bvh, const TriangleMesh& mesh, const RayBatch& rays,
                     std::size_t begin, std::size_t end, std::size_t rays_per_beam, HitBatch& hits,
                     int lanes, bool only_coherent, double max_spread_rad);

}  // namespace beamtrace::detail
