#include "beamtrace/pipeline/demo_sensor.hpp"

#include <cmath>

#include "beamtrace/scene/demo_scene.hpp"

namespace beamtrace {

ImageSensorConfig demo_sensor() {
    ImageSensorConfig c;
    // 45 m east and 14 m south of vehicle 1, 5 m above the ground, looking at it. In the report's
    // convention a sensor-frame +x maps to (cos yaw, -sin yaw) in the ground plane.
    const double x = 45.0, y = -14.0;
    const double z = demo_terrain_height(x, y) + 5.0;
    c.position_m = {x, y, z};
    const double dx = -x, dy = -y, dz = 1.0 - z;
    c.orientation = {0.0, std::atan2(dz, std::hypot(dx, dy)), std::atan2(-dy, dx)};
    c.width = 640;
    c.height = 320;
    c.hfov_rad = 1.0;
    c.vfov_rad = 0.5;
    return c;
}

}  // namespace beamtrace
