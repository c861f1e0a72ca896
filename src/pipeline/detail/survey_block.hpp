// A survey block's working arrays, reused from block to block, and the shelf they wait on.
#pragma once

#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

#include "beamtrace/accel/moving_instances.hpp"
#include "beamtrace/core/hit_batch.hpp"
#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/io/point_sink.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/sensor/scan_pattern.hpp"
#include "pipeline/detail/survey_rays.hpp"

namespace beamtrace::detail {

/// Pulses per block: each block is generated, traced, simulated and encoded by one thread.
/// Blocks start at multiples of it, so results do not depend on the thread count.
inline constexpr std::size_t kBlockPulses = 1024;

/// A block's working arrays (pulses, rays, hits, returns, points). Blocks take one from a
/// WorkShelf and put it back, so a thread keeps reusing the same, cache-warm memory.
struct BlockWork {
    std::uint64_t first = 0;  ///< global index of the block's first pulse
    std::size_t pulse_count = 0;
    PulseBatch pulses;
    SurveyRaySource::Scratch scratch;
    RayBatch rays;
    HitBatch hits;
    std::vector<Vec3d> origin, axis;
    std::vector<float> scan_angle;
    std::vector<PulseReturn> returns;        ///< max_returns per pulse
    std::vector<std::uint8_t> return_count;  ///< returns of each pulse
    PulseResponse response;
    std::vector<std::uint32_t> return_face;  ///< the face of each return (max_returns per pulse)
    /// |cos| of the incidence of the sample that dominated each return (max_returns per pulse)
    std::vector<float> return_cos_incidence;
    // Edge cells (physics/beam_divergence.hpp): the cells of pulse k that probes sample again
    // are edge_cell[edge_start[k], edge_start[k + 1]), cell i of that list has the probe rays
    // [i P, (i + 1) P) of probe_rays (P probes per cell).
    std::vector<std::int64_t> target;  ///< what each sub-ray of one pulse met (part, -1: miss)
    std::vector<std::uint32_t> edges, edge_cell, edge_start;
    RayBatch probe_rays;
    HitBatch probe_hits;
    std::vector<Vec3d> probe_origins, probe_dirs;
    std::vector<std::uint32_t> sample_face;  ///< the face each of a pulse's samples met
    PointBlock points;
    /// Moving parts (scene `motion:`): their top level for the block's time span and the time
    /// of each ray and probe ray (its pulse's).
    MovingFrame moving_frame;
    std::vector<double> ray_time, probe_time;
    ThreadPool this_thread{1};  ///< no workers: the backend traces the block on the caller

    /// Sizes the arrays for `pulse_count` pulses (contents are overwritten by the stages).
    void size_for(std::uint64_t first_pulse, std::size_t pulses_in_block, std::size_t sub_rays,
                  std::size_t max_returns) {
        first = first_pulse;
        pulse_count = pulses_in_block;
        const std::size_t n = pulse_count * sub_rays;
        rays.resize(n);
        if (hits.size() != n) {
            hits.resize(n);
        }
        origin.resize(pulse_count);
        axis.resize(pulse_count);
        scan_angle.resize(pulse_count);
        returns.resize(pulse_count * max_returns);
        return_face.resize(pulse_count * max_returns);
        return_cos_incidence.resize(pulse_count * max_returns);
        return_count.resize(pulse_count);
        points.clear();
    }
};

/// Spare values, last in first out, shared by threads: take() gives the one put back last (its
/// memory warm and already sized), or a new one.
template <class T>
class Shelf {
  public:
    T take() {
        {
            const std::lock_guard lock(mutex_);
            if (!spare_.empty()) {
                T v = std::move(spare_.back());
                spare_.pop_back();
                return v;
            }
        }
        if constexpr (requires { typename T::element_type; }) {
            return std::make_unique<typename T::element_type>();
        } else {
            return T{};
        }
    }
    void put(T v) {
        const std::lock_guard lock(mutex_);
        spare_.push_back(std::move(v));
    }

  private:
    std::mutex mutex_;
    std::vector<T> spare_;
};

/// Spare BlockWork.
using WorkShelf = Shelf<std::unique_ptr<BlockWork>>;

}  // namespace beamtrace::detail
