// The head of a survey file for the tests of its physics block: a static VLP-16 on the demo scene.
#pragma once

#include <string>

namespace beamtrace::test {

inline const std::string kPhysicsSurveyHead = R"(scene: demo
scanner: {type: rotating, preset: vlp16}
platform: {type: static, position_m: [0, 0, 2]}
)";

}  // namespace beamtrace::test
