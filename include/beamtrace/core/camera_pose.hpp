// The one camera convention of beamtrace (docs/camera.md): a position, a yaw and a pitch in
// degrees, read from `X,Y,Z,YAW,PITCH` by every command that takes a camera (`view`, `render`).
//
// Right-handed, z up, and the same roll-pitch-yaw as every other orientation in beamtrace
// (survey and scene files' `rotate_deg`, `scan --orientation`, trajectories): yaw 0 looks along
// +x, positive yaw pans to the right (clockwise seen from above, from +x towards -y: yaw 90
// looks along -y); positive pitch tilts up (-90 looks straight down).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/core/rotation.hpp"
#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

struct CameraPose {
    Vec3d position;          ///< metres (view: the LAS files' units)
    double yaw_deg = 0.0;    ///< 0 looks along +x; positive pans right (clockwise from above)
    double pitch_deg = 0.0;  ///< positive tilts up; -90 looks straight down

    /// The orientation for rpy_matrix (radians): {roll, pitch, yaw}.
    [[nodiscard]] RollPitchYaw orientation(double roll_rad = 0.0) const;
    /// The unit viewing direction: (cos p cos y, -cos p sin y, sin p).
    [[nodiscard]] Vec3d forward() const;
};

/// What a camera text may hold besides `X,Y,Z,YAW,PITCH`.
struct CameraPoseForm {
    bool position_only = false;  ///< also accept `X,Y,Z` alone (yaw and pitch stay 0)
    std::size_t max_extra = 0;   ///< numbers allowed after PITCH (e.g. render's VFOV)
};

struct ParsedCameraPose {
    CameraPose pose;
    bool has_angles = true;     ///< false for the `X,Y,Z` form
    std::vector<double> extra;  ///< the numbers after PITCH
};

/// Parses comma-separated finite numbers (spaces around them allowed) in one of the forms
/// `form` admits; nullopt with `why` (e.g. "field 4 'a' is not a finite number") otherwise.
[[nodiscard]] std::optional<ParsedCameraPose> try_parse_camera_pose(std::string_view text,
                                                                    const CameraPoseForm& form,
                                                                    std::string& why);

/// The same, throwing ConfigError "<what> '<text>': <why>".
[[nodiscard]] ParsedCameraPose parse_camera_pose(std::string_view text, std::string_view what,
                                                 const CameraPoseForm& form = {});

}  // namespace beamtrace
