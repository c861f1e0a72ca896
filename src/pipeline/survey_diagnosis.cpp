#include "pipeline/detail/survey_diagnosis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "beamtrace/core/hit_batch.hpp"
#include "pipeline/detail/survey_reference_range.hpp"

namespace beamtrace::detail {
namespace {

/// What the pilot met, traced without range limits.
struct PilotTally {
    std::size_t pulses = 0, in_range = 0, too_near = 0, too_far = 0, box_only = 0, away = 0;
    double nearest_m = std::numeric_limits<double>::infinity(), farthest_m = 0.0;
    Vec3d first_origin, first_direction;
};

}  // namespace

bool ray_meets_box(const Vec3d& o, const Vec3d& d, const Aabb& b) {
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const double inv = 1.0 / d[k];
        double a = (static_cast<double>(b.lo[k]) - o[k]) * inv;
        double c = (static_cast<double>(b.hi[k]) - o[k]) * inv;
        if (a > c) {
            std::swap(a, c);
        }
        t0 = std::max(t0, std::isnan(a) ? t0 : a);
        t1 = std::min(t1, std::isnan(c) ? t1 : c);
    }
    return t0 <= t1;
}

namespace {

PilotTally tally_pilot(const SurveySpec& spec, RayBatch rays, const Backend& backend,
                       const Aabb& box, ThreadPool& pool) {
    PilotTally t;
    t.pulses = rays.size();
    std::fill(rays.tmin.begin(), rays.tmin.end(), 0.0);
    std::fill(rays.tmax.begin(), rays.tmax.end(), std::numeric_limits<double>::infinity());
    HitBatch hits;
    hits.resize(rays.size());
    backend.intersect(rays, 0, rays.size(), hits, pool);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Vec3d o{rays.ox[i], rays.oy[i], rays.oz[i]}, d{rays.dx[i], rays.dy[i], rays.dz[i]};
        if (i == 0) {
            t.first_origin = o;
            t.first_direction = d;
        }
        if (!hits.hit(i)) {
            ++(ray_meets_box(o, d, box) ? t.box_only : t.away);
            continue;
        }
        const double r = hits.t[i];
        t.nearest_m = std::min(t.nearest_m, r);
        t.farthest_m = std::max(t.farthest_m, r);
        ++(r < spec.range_min_m ? t.too_near : r > spec.range_max_m ? t.too_far : t.in_range);
    }
    return t;
}

/// `v` with `decimals` decimals; %g for decimals < 0.
std::string num(double v, int decimals = 0) {
    char buf[64];
    if (decimals < 0) {
        std::snprintf(buf, sizeof buf, "%g", v);
    } else {
        std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    }
    return buf;
}

std::string vec(const Vec3d& v, int decimals) {
    return "(" + num(v.x, decimals) + ", " + num(v.y, decimals) + ", " + num(v.z, decimals) + ")";
}

}  // namespace

std::vector<std::string> diagnose_survey(const SurveySpec& spec, const ScanPattern& pattern,
                                         const Trajectory& trajectory, const Backend& backend,
                                         const Aabb& box, std::uint64_t pulses,
                                         std::uint64_t points, ThreadPool& pool) {
    std::vector<std::string> why;
    if (pulses == 0 ||
        static_cast<double>(points) >= kFewPointsFraction * static_cast<double>(pulses)) {
        return why;
    }
    const PilotTally t =
        tally_pilot(spec, pilot_rays(spec, pattern, trajectory), backend, box, pool);
    why.push_back(std::to_string(points) + " of " + std::to_string(pulses) +
                  " pulses gave points; of " + std::to_string(t.pulses) +
                  " pilot pulses spread over the survey and traced without range limits:");
    if (t.away + t.box_only == t.pulses) {
        why.push_back("none hits the scene (" + std::to_string(t.away) +
                      " do not even point at its bounding box): the scanner looks away from "
                      "it; the first pulse leaves " +
                      vec(t.first_origin, 1) + " along " + vec(t.first_direction, 3) +
                      ": check the mount's boresight_deg (a line scanner looks along its +x; "
                      "boresight_deg: [0, -90, 0] turns it down) and the platform's attitude");
    } else if (t.in_range == 0) {
        why.push_back(std::to_string(t.too_near + t.too_far) + " hit the scene, at " +
                      num(t.nearest_m, 1) + " to " + num(t.farthest_m, 1) +
                      " m, none of them inside the range gate scanner.range_min_m..range_max_m = " +
                      num(spec.range_min_m, 1) + ".." + num(spec.range_max_m, 1) + " m");
    } else if (spec.physics) {
        why.push_back(std::to_string(t.in_range) +
                      " hit the scene within the range gate, so the physics dropped their "
                      "returns: physics.detection_threshold_w (" +
                      num(spec.physics->radiometry.detection_threshold_w, -1) +
                      " W) may be above every echo (raise peak_power_w or lower the "
                      "threshold), or physics.noise.dropout_probability (" +
                      num(spec.physics->noise.dropout_probability, -1) + ") removes them");
    } else {
        why.push_back(std::to_string(t.in_range) +
                      " hit the scene within the range gate: the survey's pulses meet it only "
                      "rarely (a narrow field of view, or most pulses into the sky)");
    }
    return why;
}

std::vector<std::string> diagnose_scan(const RayBatch& rays, std::size_t hits, const Aabb& box) {
    std::vector<std::string> why;
    if (rays.size() == 0 ||
        static_cast<double>(hits) >= kFewPointsFraction * static_cast<double>(rays.size())) {
        return why;
    }
    std::size_t away = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        away += ray_meets_box({rays.ox[i], rays.oy[i], rays.oz[i]},
                              {rays.dx[i], rays.dy[i], rays.dz[i]}, box)
                    ? 0
                    : 1;
    }
    const std::size_t m = rays.size() / 2;
    why.push_back(std::to_string(hits) + " of " + std::to_string(rays.size()) +
                  " rays hit the scene; " + std::to_string(away) +
                  " do not even point at its bounding box " + vec(Vec3d(box.lo), 1) + " to " +
                  vec(Vec3d(box.hi), 1) + "; the middle ray leaves " +
                  vec({rays.ox[m], rays.oy[m], rays.oz[m]}, 2) + " along " +
                  vec({rays.dx[m], rays.dy[m], rays.dz[m]}, 3) +
                  ": check --position and --orientation (roll, pitch, yaw in radians, or with "
                  "units: 0,-90deg,0)");
    return why;
}

}  // namespace beamtrace::detail
