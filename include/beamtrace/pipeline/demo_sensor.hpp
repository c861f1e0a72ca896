// The demo's default sensor: the view of the embedded demo scene (scene/demo_scene.hpp) that
// `scan --demo` and `render --demo` use.
#pragma once

#include "beamtrace/sensor/image_sensor.hpp"

namespace beamtrace {

/// The demo's default view: a 640 x 320 pinhole 5 m above the ground, 47 m from vehicle 1,
/// looking at it past the occluder.
[[nodiscard]] ImageSensorConfig demo_sensor();

}  // namespace beamtrace
