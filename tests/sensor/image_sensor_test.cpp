// The report's sensor code against beamtrace, transcribed here step by step: the pinhole and
// scan models (Appendix A.3 castRaysPinhole, A.4 castRaysScan: meshgrid, column-major (:),
// normalisation, D * (Rx*Ry*Rz)) and the push-broom scan of MovingScanExample.m (B.1), the
// only other sensor in the report's code (the rest of Appendix A is the model, the k-d tree,
// its traversal and raysToImg; B.2 OcclusionExample.m uses castRaysPinhole).
#include "beamtrace/sensor/image_sensor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/rays_file.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

using M3 = double[3][3];

void matlab_R(double roll, double pitch, double yaw, M3 out) {
    const M3 rx = {
        {1, 0, 0}, {0, std::cos(roll), -std::sin(roll)}, {0, std::sin(roll), std::cos(roll)}};
    const M3 ry = {
        {std::cos(pitch), 0, std::sin(pitch)}, {0, 1, 0}, {-std::sin(pitch), 0, std::cos(pitch)}};
    const M3 rz = {
        {std::cos(yaw), -std::sin(yaw), 0}, {std::sin(yaw), std::cos(yaw), 0}, {0, 0, 1}};
    M3 rxy{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                rxy[i][j] += rx[i][k] * ry[k][j];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            out[i][j] = 0;
            for (int k = 0; k < 3; ++k)
                out[i][j] += rxy[i][k] * rz[k][j];
        }
}

/// Matlab's linspace: for n = 1 it returns b. With `centre_single`, beamtrace's one deliberate
/// deviation (linspace_at): a single sample at the centre (a + b) / 2.
std::vector<double> matlab_linspace(double a, double b, int n, bool centre_single = false) {
    if (n == 1) {
        return {centre_single ? 0.5 * (a + b) : b};
    }
    std::vector<double> v(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
        v[static_cast<std::size_t>(i)] = a + (b - a) * i / (n - 1);
    return v;
}

/// castRaysPinhole / castRaysScan as in the report, returning D (n x 3) in Matlab's order.
std::vector<Vec3d> matlab_cast(bool scan, const ImageSensorConfig& c, bool centre_single = false) {
    const int w = c.width, h = c.height;
    std::vector<double> xs, ys;
    if (scan) {
        xs = matlab_linspace(0.5 * c.hfov_rad, -0.5 * c.hfov_rad, w, centre_single);
        ys = matlab_linspace(0.5 * c.vfov_rad, -0.5 * c.vfov_rad, h, centre_single);
    } else {
        xs = matlab_linspace(std::tan(0.5 * c.hfov_rad), -std::tan(0.5 * c.hfov_rad), w,
                             centre_single);
        ys = matlab_linspace(std::tan(0.5 * c.vfov_rad), -std::tan(0.5 * c.vfov_rad), h,
                             centre_single);
    }
    // [x, y] = meshgrid(xs, ys): x(r, k) = xs(k), y(r, k) = ys(r); x(:) runs down columns.
    std::vector<Vec3d> d;
    for (int k = 0; k < w; ++k) {
        for (int r = 0; r < h; ++r) {
            const double x = xs[static_cast<std::size_t>(k)], y = ys[static_cast<std::size_t>(r)];
            Vec3d v = scan
                          ? Vec3d{std::cos(y) * std::cos(x), std::cos(y) * std::sin(x), std::sin(y)}
                          : Vec3d{1.0, x, y};
            if (!scan)
                v = v * (1.0 / std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z));
            d.push_back(v);
        }
    }
    M3 R;
    matlab_R(c.orientation.roll_rad, c.orientation.pitch_rad, c.orientation.yaw_rad, R);
    for (auto& v : d) {  // D * R with D as row vectors
        v = Vec3d{v.x * R[0][0] + v.y * R[1][0] + v.z * R[2][0],
                  v.x * R[0][1] + v.y * R[1][1] + v.z * R[2][1],
                  v.x * R[0][2] + v.y * R[1][2] + v.z * R[2][2]};
    }
    return d;
}

void expect_matches_matlab(bool scan, const ImageSensorConfig& c) {
    const RayBatch rays = scan ? cast_rays_scan(c) : cast_rays_pinhole(c);
    const auto ref = matlab_cast(scan, c);
    ASSERT_EQ(rays.size(), ref.size());
    for (std::size_t i = 0; i < ref.size(); ++i) {
        ASSERT_NEAR(rays.dx[i], ref[i].x, 1e-12) << i;
        ASSERT_NEAR(rays.dy[i], ref[i].y, 1e-12) << i;
        ASSERT_NEAR(rays.dz[i], ref[i].z, 1e-12) << i;
        ASSERT_EQ(rays.origin(i), c.position_m);
        ASSERT_EQ(rays.tmin[i], 0.0);
        ASSERT_TRUE(std::isinf(rays.tmax[i]));
    }
}

TEST(ImageSensor, PinholeMatchesReportFormulas) {
    ImageSensorConfig c;
    c.position_m = {100, 0, 2};
    c.orientation = {0, 0, -std::numbers::pi};  // the occlusion example
    c.width = 50;
    c.height = 20;
    c.hfov_rad = 0.11;
    c.vfov_rad = 0.05;
    expect_matches_matlab(false, c);
    c.orientation = {0.3, -0.7, 2.1};
    c.width = 7;
    c.height = 9;
    c.hfov_rad = 2.5;
    c.vfov_rad = 1.9;
    expect_matches_matlab(false, c);
}

TEST(ImageSensor, ScanMatchesReportFormulasIncluding360Panorama) {
    ImageSensorConfig c;
    c.position_m = {-20, 0, 180};
    c.orientation = {0, 0, 0};
    c.width = 360;
    c.height = 20;
    c.hfov_rad = 2 * std::numbers::pi;
    c.vfov_rad = std::numbers::pi / 9;
    expect_matches_matlab(true, c);
    c.orientation = {-0.2, 0.4, 1.3};
    expect_matches_matlab(true, c);
}

struct MatlabRays {
    std::vector<Vec3d> origins, directions;
};

/// MovingScanExample.m (Appendix B.1), the ray loop line by line: a push-broom line of h
/// pixels cast with castRaysPinhole at each of h steps from pStart to pEnd, the platform
/// pitching by a degree, all aggregated in order into one ray list.
MatlabRays matlab_moving_scan(int h, double z, bool centre_single) {
    const double pi = std::numbers::pi;
    const int w = 1;                                         // w = 1;
    const double roll = 0;                                   // roll = 0;
    const double yaw = pi / 4;                               // yaw = pi/4;
    const std::vector<double> t = matlab_linspace(0, 1, h);  // t = linspace(0,1,h);
    const Vec3d p_start{-50, -50, z}, p_end{50, 50, z};      // pStart, pEnd
    MatlabRays rays;
    for (int i = 0; i < h; ++i) {  // for i=1:h
        const double ti = t[static_cast<std::size_t>(i)];
        // pos = repmat(pStart,h,1) + t'*(pEnd-pStart);
        const Vec3d pos{p_start.x + ti * (p_end.x - p_start.x),
                        p_start.y + ti * (p_end.y - p_start.y),
                        p_start.z + ti * (p_end.z - p_start.z)};
        const double pitch = -pi / 2 + (pi / 180) * std::sin(ti * 4 * pi);
        // tmp = castRaysPinhole(pos(i,:), [roll pitch(i) yaw], w, h, (pi/9)/h, pi/9);
        ImageSensorConfig c;
        c.position_m = pos;
        c.orientation = {roll, pitch, yaw};
        c.width = w;
        c.height = h;
        c.hfov_rad = (pi / 9) / h;
        c.vfov_rad = pi / 9;
        // rays.O((i-1)*h+1:i*h,:) = tmp.O; rays.D((i-1)*h+1:i*h,:) = tmp.D;
        for (const Vec3d& d : matlab_cast(false, c, centre_single)) {
            rays.origins.push_back(pos);
            rays.directions.push_back(d);
        }
    }
    return rays;
}

TEST(ImageSensor, PushBroomExampleMatchesTheReportsMovingScanExample) {
    // examples/pushbroom_rays.cpp (what docs/scan.md and examples/pushbroom.sh run) against
    // the transcription, with beamtrace's single documented deviation: Matlab's
    // linspace(x0, -x0, 1) is -x0, which points the report's one-pixel-wide line half a pixel
    // (hfov / 2) to the right; beamtrace centres it.
    const int h = 40;
    const double z = 370.0;  // the report's flying height
    test::TempDir dir;
    const auto csv = dir / "pushbroom.csv";
    const auto r = test::run_command(std::string(BEAMTRACE_PUSHBROOM_PATH) + " '" + csv.string() +
                                     "' " + std::to_string(h) + " 370");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const RayBatch rays = read_rays_csv(csv);
    const MatlabRays centred = matlab_moving_scan(h, z, true);
    const MatlabRays literal = matlab_moving_scan(h, z, false);
    ASSERT_EQ(rays.size(), static_cast<std::size_t>(h * h));
    ASSERT_EQ(centred.directions.size(), rays.size());
    const double x0 = std::tan(0.5 * (std::numbers::pi / 9) / h);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Vec3d o = rays.origin(i), d = rays.direction(i);
        ASSERT_NEAR(o.x, centred.origins[i].x, 1e-12) << i;
        ASSERT_NEAR(o.y, centred.origins[i].y, 1e-12) << i;
        ASSERT_NEAR(o.z, centred.origins[i].z, 1e-12) << i;
        ASSERT_NEAR(d.x, centred.directions[i].x, 1e-12) << i;
        ASSERT_NEAR(d.y, centred.directions[i].y, 1e-12) << i;
        ASSERT_NEAR(d.z, centred.directions[i].z, 1e-12) << i;
        // The literal Matlab ray of row v: normalize([1, -x0, z_v]) against normalize([1, 0,
        // z_v]), an angle of atan(x0 / sqrt(1 + z_v^2)), and nothing else.
        const double zv =
            std::tan(std::numbers::pi / 18) * (1.0 - 2.0 * static_cast<double>(i % h) / (h - 1));
        const Vec3d m = literal.directions[i];
        const double angle = std::acos(std::min(1.0, d.x * m.x + d.y * m.y + d.z * m.z));
        ASSERT_NEAR(angle, std::atan(x0 / std::sqrt(1.0 + zv * zv)), 1e-7) << i;
    }
}

TEST(ImageSensor, OrderAndAxesConventions) {
    ImageSensorConfig c;
    c.width = 3;
    c.height = 3;
    c.hfov_rad = std::numbers::pi / 2;
    c.vfov_rad = std::numbers::pi / 2;
    const RayBatch r = cast_rays_pinhole(c);
    // Centre pixel looks along +x.
    EXPECT_NEAR(r.dx[ray_index(1, 1, 3)], 1.0, 1e-15);
    // Top-left pixel (u = 0, v = 0) is ray 0 and points left (+y) and up (+z).
    EXPECT_GT(r.dy[0], 0.0);
    EXPECT_GT(r.dz[0], 0.0);
    EXPECT_NEAR(r.dy[0], 1.0 / std::sqrt(3.0), 1e-15);
    // Ray 1 is the next row down in the same column (column-major order).
    EXPECT_NEAR(r.dz[1], 0.0, 1e-15);
    EXPECT_NEAR(r.dy[1], std::sqrt(0.5), 1e-15);
    // Yaw turns left: yaw = +pi/2 makes the optical axis +y.
    c.orientation = {0, 0, std::numbers::pi / 2};
    const RayBatch y = cast_rays_pinhole(c);
    EXPECT_NEAR(y.dy[ray_index(1, 1, 3)], -1.0, 1e-12)
        << "the report's D*R turns +x to -y for yaw +pi/2 (row-vector convention)";
}

TEST(ImageSensor, SingleRowOrColumnIsCentred) {
    ImageSensorConfig c;
    c.width = 1;
    c.height = 5;
    c.hfov_rad = 0.4;
    c.vfov_rad = 0.4;
    const RayBatch r = cast_rays_pinhole(c);
    for (std::size_t i = 0; i < r.size(); ++i) {
        EXPECT_EQ(r.dy[i], 0.0) << "a single column looks straight ahead, not to one edge";
    }
    c.width = 4;
    c.height = 1;
    const RayBatch s = cast_rays_scan(c);
    for (std::size_t i = 0; i < s.size(); ++i) {
        EXPECT_EQ(s.dz[i], 0.0);
    }
    EXPECT_EQ(linspace_at(2.0, 4.0, 1, 0), 3.0);
    EXPECT_EQ(linspace_at(2.0, 4.0, 3, 2), 4.0);
}

TEST(ImageSensor, ImpossibleSettingsListEveryProblem) {
    ImageSensorConfig c;
    c.width = 0;
    c.height = -3;
    c.hfov_rad = 4.0;
    c.vfov_rad = 0.0;
    const auto p = c.validate(false);
    EXPECT_EQ(p.size(), 4u);
    EXPECT_THROW((void)cast_rays_pinhole(c), ConfigError);
    ImageSensorConfig s;
    s.hfov_rad = 2 * std::numbers::pi;  // fine for a scan, not for a pinhole
    EXPECT_TRUE(s.validate(true).empty());
    EXPECT_FALSE(s.validate(false).empty());
    s.position_m.x = std::nan("");
    EXPECT_FALSE(s.validate(true).empty());
}

}  // namespace
}  // namespace beamtrace
