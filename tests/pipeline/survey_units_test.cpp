// Units in survey files: angle keys take "60deg" / "1.05rad", radians typed into a degree key
// and micrometres typed into a nanometre key are refused with file, line and key.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/survey.hpp"

namespace beamtrace {
namespace {

const std::string kBase =
    "scene: demo\n"
    "scanner: {type: rotating, preset: vlp16, duration_s: 0.01}\n"
    "platform: {type: static, position_m: [0, 0, 2]}\n";

std::string error_of(const std::string& yaml) {
    try {
        (void)parse_survey_spec(yaml, "s.yaml");
    } catch (const ConfigError& e) {
        return e.what();
    }
    ADD_FAILURE() << "accepted: " << yaml;
    return {};
}

TEST(SurveyUnits, AngleKeysTakeAnExplicitUnit) {
    const SurveySpec deg =
        parse_survey_spec(kBase + "mount: {boresight_deg: [0, -90, 0]}\n", "s.yaml");
    const SurveySpec rad = parse_survey_spec(
        kBase + "mount: {boresight_deg: [0, -1.5707963267948966rad, 0]}\n", "s.yaml");
    const SurveySpec both =
        parse_survey_spec(kBase + "mount: {boresight_deg: [0deg, '-90 deg', 0rad]}\n", "s.yaml");
    const Quat a = deg.mount.sensor_to_platform.attitude;
    for (const SurveySpec* s : {&rad, &both}) {
        const Quat b = s->mount.sensor_to_platform.attitude;
        EXPECT_NEAR(a.w, b.w, 1e-15);
        EXPECT_NEAR(a.y, b.y, 1e-15);
    }
    EXPECT_GT(std::abs(a.y), 0.7);  // a quarter turn: -90 degrees, not -90 radians
}

TEST(SurveyUnits, RadiansInADegreeKeyAreRefusedWithTheFixes) {
    const std::string msg = error_of(kBase + "mount: {boresight_deg: [0, -1.5708, 0]}\n");
    EXPECT_EQ(msg.rfind("s.yaml:4: mount.boresight_deg[1]: -1.5708 looks like -\xCF\x80/2", 0), 0u)
        << msg;
    EXPECT_NE(msg.find("write -90 (degrees)"), std::string::npos) << msg;
    // Written with its unit, the small angle is taken as it stands.
    const SurveySpec kept =
        parse_survey_spec(kBase + "mount: {boresight_deg: [0, -1.5708deg, 0]}\n", "s.yaml");
    EXPECT_GT(kept.mount.sensor_to_platform.attitude.w, 0.9998);
    // Scanner and platform angle keys alike.
    EXPECT_NE(error_of("scene: demo\nscanner: {type: line, pulse_rate_hz: 1000, scan_rate_hz: "
                       "10, scan_angle_max_deg: 0.7854, duration_s: 0.1}\nplatform: {type: "
                       "static, position_m: [0, 0, 100]}\n")
                  .find("scanner.scan_angle_max_deg: 0.7854 looks like \xCF\x80/4"),
              std::string::npos);
    EXPECT_NE(error_of("scene: demo\nscanner: {type: rotating, preset: vlp16, duration_s: "
                       "0.01}\nplatform: {type: static, position_m: [0, 0, 2], rotate_deg: [0, "
                       "0, 3.1416]}\n")
                  .find("platform.rotate_deg[2]: 3.1416 looks like \xCF\x80"),
              std::string::npos);
    EXPECT_NE(error_of(kBase + "mount: {boresight_deg: [0, 90 degrees, 0]}\n")
                  .find("expected a number (an angle in degrees; a unit may follow"),
              std::string::npos);
}

TEST(SurveyUnits, MicrometresInTheWavelengthAreRefused) {
    const std::string msg = error_of(kBase + "physics: {wavelength_nm: 1.064}\n");
    EXPECT_NE(msg.find("physics.wavelength_nm: '1.064' nm is outside 200-12000 nm"),
              std::string::npos)
        << msg;
    EXPECT_NO_THROW((void)parse_survey_spec(kBase + "physics: {wavelength_nm: 1550}\n", "s.yaml"));
}

}  // namespace
}  // namespace beamtrace
