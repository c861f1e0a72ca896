// What a part's material pattern is laid on: its analytic sphere or plane, or a solid.
#include "beamtrace/scene/scene.hpp"

namespace beamtrace {

PatternFrame Scene::pattern_frame(const ScenePart& part, std::uint32_t face) const {
    if (part.first_sphere >= 0) {
        // An exact sphere part has one face per sphere, its copies in face order; any other
        // sphere part with an analytic copy has exactly one.
        const std::uint32_t copy =
            part.face_count == part.instance_count ? face - part.first_face : 0;
        const SceneSphere& s = spheres.at(static_cast<std::size_t>(part.first_sphere) + copy);
        return PatternFrame::sphere(s.center_m, s.radius_m, s.attitude);
    }
    if (part.plane >= 0) {
        const ScenePlane& p = planes.at(static_cast<std::size_t>(part.plane));
        // The same axes as the renderer's PlanePatch (build_render_scene): w = normal x u.
        const Vec3d n = normalize(p.normal), u = normalize(p.u_axis);
        return PatternFrame::plane(p.point_m, u, cross(n, u));
    }
    return {};
}

}  // namespace beamtrace
