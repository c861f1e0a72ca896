#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define BEAMTRACE_SCAN_ANGLE_AVX2 1
#endif

#include "pipeline/detail/survey_rays.hpp"

namespace beamtrace {
namespace detail {

namespace {

/// The unit vector to the right of travel: the axis the LAS scan angle is measured about.
Vec3d right_of(const Vec3d& forward) {
    const Vec3d right = cross(forward, Vec3d{0, 0, 1});
    return length(right) < 1e-9 ? Vec3d{1, 0, 0}  // travelling vertically: the world x axis
                                : normalize(right);
}

/// atan(u) for u in [0, 1]: u P(u^2), P of degree 7 fitted to atan by least squares on 400
/// Chebyshev nodes; at most 4.1e-8 rad off (2.3e-6 degrees, 0.04 % of a LAS scan angle step, as
/// close as atan2f), a third of its cost.
constexpr double kAtanUnit[] = {0.9999994368431484,   -0.3333010667768892, 0.1994850898576502,
                                -0.13915802260682877, 0.09656256470426208, -0.05606317672858324,
                                0.021946611032240992, -0.00407330946436799};

double atan_unit(double u) {
    const auto& c = kAtanUnit;
    // Estrin's scheme: a shorter dependency chain than Horner's.
    const double s = u * u, s2 = s * s, s4 = s2 * s2;
    const double p01 = c[0] + c[1] * s, p23 = c[2] + c[3] * s;
    const double p45 = c[4] + c[5] * s, p67 = c[6] + c[7] * s;
    return u * ((p01 + p23 * s2) + (p45 + p67 * s2) * s4);
}

/// The LAS scan angle about `right`, degrees: atan2(dir . right, -dir.z), clamped to +/-90
/// (beams at or above the horizontal).
float scan_angle_about(const Vec3d& dir, const Vec3d& right) {
    const double y = dot(dir, right), x = -dir.z;
    if (!(x > 0.0)) {
        return y == 0.0 && x == 0.0 ? 0.0f : (std::signbit(y) ? -90.0f : 90.0f);
    }
    const double ay = std::fabs(y);
    double a = ay <= x ? atan_unit(ay / x) : std::numbers::pi / 2 - atan_unit(x / ay);
    a *= 180.0 / std::numbers::pi;
    return static_cast<float>(std::signbit(y) ? -a : a);
}

#if defined(__SSE2__)
/// scan_angle_about() of two directions at once, the same operations lane by lane: both sides
/// of each choice computed, one selected by mask.
__m128d scan_angle_pair(__m128d dx, __m128d dy, __m128d dz, const Vec3d& right) {
    const __m128d sign = _mm_set1_pd(-0.0);
    const auto select = [](__m128d mask, __m128d a, __m128d b) {
        return _mm_or_pd(_mm_and_pd(mask, a), _mm_andnot_pd(mask, b));
    };
    const __m128d y = _mm_add_pd(
        _mm_add_pd(_mm_mul_pd(dx, _mm_set1_pd(right.x)), _mm_mul_pd(dy, _mm_set1_pd(right.y))),
        _mm_mul_pd(dz, _mm_set1_pd(right.z)));  // dot()
    const __m128d x = _mm_xor_pd(dz, sign);
    const __m128d ay = _mm_andnot_pd(sign, y);
    // ay / x where ay <= x, else x / ay; then atan_unit().
    const __m128d u = _mm_div_pd(_mm_min_pd(x, ay), _mm_max_pd(ay, x));
    const auto c = [](double v) { return _mm_set1_pd(v); };
    const __m128d s = _mm_mul_pd(u, u), s2 = _mm_mul_pd(s, s), s4 = _mm_mul_pd(s2, s2);
    const __m128d p01 = _mm_add_pd(c(kAtanUnit[0]), _mm_mul_pd(c(kAtanUnit[1]), s));
    const __m128d p23 = _mm_add_pd(c(kAtanUnit[2]), _mm_mul_pd(c(kAtanUnit[3]), s));
    const __m128d p45 = _mm_add_pd(c(kAtanUnit[4]), _mm_mul_pd(c(kAtanUnit[5]), s));
    const __m128d p67 = _mm_add_pd(c(kAtanUnit[6]), _mm_mul_pd(c(kAtanUnit[7]), s));
    const __m128d p =
        _mm_mul_pd(u, _mm_add_pd(_mm_add_pd(p01, _mm_mul_pd(p23, s2)),
                                 _mm_mul_pd(_mm_add_pd(p45, _mm_mul_pd(p67, s2)), s4)));
    const __m128d a =
        _mm_mul_pd(select(_mm_cmple_pd(ay, x), p, _mm_sub_pd(c(std::numbers::pi / 2), p)),
                   c(180.0 / std::numbers::pi));
    const __m128d y_sign = _mm_and_pd(y, sign);
    // At or above the horizontal: +/-90 by the sign of y, +0 where y and x are both 0.
    const __m128d level = _mm_andnot_pd(
        _mm_and_pd(_mm_cmpeq_pd(y, _mm_setzero_pd()), _mm_cmpeq_pd(x, _mm_setzero_pd())),
        _mm_or_pd(c(90.0), y_sign));
    return select(_mm_cmpgt_pd(x, _mm_setzero_pd()), _mm_or_pd(a, y_sign), level);
}
#endif

#if BEAMTRACE_SCAN_ANGLE_AVX2
/// scan_angle_pair() four lanes wide (AVX2, no FMA: the same operations lane by lane, so the
/// same floats).
__attribute__((target("avx2"), always_inline)) inline __m256d scan_angle_quad(__m256d dx,
                                                                              __m256d dy,
                                                                              __m256d dz,
                                                                              const Vec3d& right) {
    const __m256d sign = _mm256_set1_pd(-0.0);
    const __m256d y = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, _mm256_set1_pd(right.x)),
                                                  _mm256_mul_pd(dy, _mm256_set1_pd(right.y))),
                                    _mm256_mul_pd(dz, _mm256_set1_pd(right.z)));  // dot()
    const __m256d x = _mm256_xor_pd(dz, sign);
    const __m256d ay = _mm256_andnot_pd(sign, y);
    const __m256d u = _mm256_div_pd(_mm256_min_pd(x, ay), _mm256_max_pd(ay, x));
    const __m256d s = _mm256_mul_pd(u, u), s2 = _mm256_mul_pd(s, s), s4 = _mm256_mul_pd(s2, s2);
    const __m256d p01 =
        _mm256_add_pd(_mm256_set1_pd(kAtanUnit[0]), _mm256_mul_pd(_mm256_set1_pd(kAtanUnit[1]), s));
    const __m256d p23 =
        _mm256_add_pd(_mm256_set1_pd(kAtanUnit[2]), _mm256_mul_pd(_mm256_set1_pd(kAtanUnit[3]), s));
    const __m256d p45 =
        _mm256_add_pd(_mm256_set1_pd(kAtanUnit[4]), _mm256_mul_pd(_mm256_set1_pd(kAtanUnit[5]), s));
    const __m256d p67 =
        _mm256_add_pd(_mm256_set1_pd(kAtanUnit[6]), _mm256_mul_pd(_mm256_set1_pd(kAtanUnit[7]), s));
    const __m256d p = _mm256_mul_pd(
        u, _mm256_add_pd(_mm256_add_pd(p01, _mm256_mul_pd(p23, s2)),
                         _mm256_mul_pd(_mm256_add_pd(p45, _mm256_mul_pd(p67, s2)), s4)));
    const __m256d zero = _mm256_setzero_pd();
    const __m256d a =
        _mm256_mul_pd(_mm256_blendv_pd(_mm256_sub_pd(_mm256_set1_pd(std::numbers::pi / 2), p), p,
                                       _mm256_cmp_pd(ay, x, _CMP_LE_OS)),
                      _mm256_set1_pd(180.0 / std::numbers::pi));
    const __m256d y_sign = _mm256_and_pd(y, sign);
    const __m256d level = _mm256_andnot_pd(
        _mm256_and_pd(_mm256_cmp_pd(y, zero, _CMP_EQ_OQ), _mm256_cmp_pd(x, zero, _CMP_EQ_OQ)),
        _mm256_or_pd(_mm256_set1_pd(90.0), y_sign));
    return _mm256_blendv_pd(level, _mm256_or_pd(a, y_sign), _mm256_cmp_pd(x, zero, _CMP_GT_OS));
}

/// The scan angles of directions [b, e) four at a time while four are left; returns the first
/// one not done.
__attribute__((target("avx2"))) std::size_t scan_angles_quads(const double* dx, const double* dy,
                                                              const double* dz, std::size_t b,
                                                              std::size_t e, const Vec3d& right,
                                                              float* out) {
    std::size_t i = b;
    for (; i + 4 <= e; i += 4) {
        _mm_storeu_ps(out + i, _mm256_cvtpd_ps(scan_angle_quad(_mm256_loadu_pd(dx + i),
                                                               _mm256_loadu_pd(dy + i),
                                                               _mm256_loadu_pd(dz + i), right)));
    }
    return i;
}
#endif

/// scan_angle_about() of the directions of rays ray_offset + i, i in [b, e), into out[i]: the
/// same floats, four (AVX2) or two at a time (a tenth of the rays' generation one at a time).
void scan_angles_about(const RayBatch& rays, std::size_t b, std::size_t e, std::size_t ray_offset,
                       const Vec3d& right, float* out) {
    const double* dx = rays.dx.data() + ray_offset;
    const double* dy = rays.dy.data() + ray_offset;
    const double* dz = rays.dz.data() + ray_offset;
    std::size_t i = b;
#if BEAMTRACE_SCAN_ANGLE_AVX2
    if (__builtin_cpu_supports("avx2")) {
        i = scan_angles_quads(dx, dy, dz, b, e, right, out);
    }
#endif
#if defined(__SSE2__)
    for (; i + 2 <= e; i += 2) {
        const __m128 f = _mm_cvtpd_ps(scan_angle_pair(_mm_loadu_pd(dx + i), _mm_loadu_pd(dy + i),
                                                      _mm_loadu_pd(dz + i), right));
        _mm_storel_pi(reinterpret_cast<__m64*>(out + i), f);
    }
#endif
    for (; i < e; ++i) {
        out[i] = scan_angle_about({dx[i], dy[i], dz[i]}, right);
    }
}

}  // namespace

float las_scan_angle_deg(const Vec3d& dir, const Vec3d& forward) {
    return scan_angle_about(dir, right_of(forward));
}

void las_scan_angles_deg(const RayBatch& rays, std::size_t first, std::size_t count,
                         const Vec3d& forward, float* out) {
    scan_angles_about(rays, 0, count, first, right_of(forward), out);
}

namespace {

/// What depends on the platform's attitude alone, kept while the attitude stays the same (a
/// straight leg, a tripod): the sensor's attitude, the lever arm in the world and the scan
/// angle's axis. Reused only for bit-identical attitudes, so nothing depends on it.
struct AttitudeFrame {
    bool valid = false;
    Quat platform_attitude, sensor_attitude;
    Mat3 sensor_rotation;  // sensor_attitude as a matrix: 15 flops a direction instead of 30
    Vec3d lever_world, right;

    /// True when the frame changed (the first time, or another attitude).
    bool update(const Quat& q, const Pose& mount) {
        if (valid && q.w == platform_attitude.w && q.x == platform_attitude.x &&
            q.y == platform_attitude.y && q.z == platform_attitude.z) {
            return false;
        }
        valid = true;
        platform_attitude = q;
        sensor_attitude = q * mount.attitude;
        sensor_rotation = sensor_attitude.to_matrix();
        lever_world = q.rotate(mount.position_m);
        right = right_of(q.rotate({1, 0, 0}));
        return true;
    }
};

/// One scanner's mount (true and as measured), range gate and attitude cache: one per entry of
/// `scanners:`, or the survey's one scanner.
struct ScannerFrame {
    Pose mount, mount_measured;
    double range_min_m = 0.0, range_max_m = 0.0;
    AttitudeFrame frame;
};

std::vector<ScannerFrame> scanner_frames(const SurveySpec& spec, const GeoreferencingConfig* geo) {
    std::vector<ScannerFrame> out;
    const auto add = [&](const Mount& m, double lo, double hi) {
        ScannerFrame& f = out.emplace_back();
        f.mount = m.sensor_to_platform;
        f.mount_measured = geo != nullptr ? measured_mount(*geo, f.mount) : f.mount;
        f.range_min_m = lo;
        f.range_max_m = hi;
    };
    if (spec.scanners.empty()) {
        add(spec.mount, spec.range_min_m, spec.range_max_m);
    }
    for (const SurveyScanner& s : spec.scanners) {
        add(s.mount, s.range_min_m, s.range_max_m);
    }
    return out;
}

/// The pulse's origin, beam axis and LAS scan angle (about `right`) into its slots.
void store_beam(const Vec3d& o, const Vec3d& d, const Vec3d& right, Vec3d& origin, Vec3d& axis,
                float& scan_angle) {
    // Field by field: a Vec3d copied whole here was read back from the stack as 16 bytes right
    // after being stored as 8-byte halves, which stalls store forwarding (a third of the
    // generator's time).
    const double ox = o.x, oy = o.y, oz = o.z;
    const double dx = d.x, dy = d.y, dz = d.z;
    origin.x = ox;
    origin.y = oy;
    origin.z = oz;
    axis.x = dx;
    axis.y = dy;
    axis.z = dz;
    scan_angle = scan_angle_about({dx, dy, dz}, right);
}

/// The batch's arrays and range gate, and the pulses' platform poses and sensor directions: what
/// generate() reads and writes for each pulse without physics, in locals (the stores of doubles
/// may alias any double in memory, which was loaded again for every pulse).
struct BeamArrays {
    double *ox, *oy, *oz, *dx, *dy, *dz, *tmin, *tmax;
    const Pose* platforms;
    const Vec3d* directions;
    double range_min_m, range_max_m;
};

/// Ray i of `a`: the platform's pose times the mount (`frame`), term by term.
void beam_at(const BeamArrays& a, const AttitudeFrame& frame, std::size_t i) {
    const Vec3d o = a.platforms[i].position_m + frame.lever_world;
    const Vec3d dir = frame.sensor_rotation * a.directions[i];
    a.ox[i] = o.x;
    a.oy[i] = o.y;
    a.oz[i] = o.z;
    a.dx[i] = dir.x;
    a.dy[i] = dir.y;
    a.dz[i] = dir.z;
    a.tmin[i] = a.range_min_m;
    a.tmax[i] = a.range_max_m;
}

#if BEAMTRACE_SCAN_ANGLE_AVX2
static_assert(sizeof(Vec3d) == 24 && sizeof(Pose) == 56 && offsetof(Pose, attitude) == 24 &&
              offsetof(Quat, w) == 0 && offsetof(Quat, z) == 24);

/// The four lanes of `q` equal those of p->attitude (==: NaN never equal), as a mask.
__attribute__((target("avx2"), always_inline)) inline __m256d same_attitude(const Pose* p,
                                                                            __m256d q) {
    return _mm256_cmp_pd(_mm256_loadu_pd(&p->attitude.w), q, _CMP_EQ_OQ);
}

/// True when the attitudes of the four poses from p all equal q, as AttitudeFrame::update
/// compares them.
__attribute__((target("avx2"), always_inline)) inline bool same_attitudes(const Pose* p,
                                                                          __m256d q) {
    const __m256d m01 = _mm256_and_pd(same_attitude(p, q), same_attitude(p + 1, q));
    const __m256d m23 = _mm256_and_pd(same_attitude(p + 2, q), same_attitude(p + 3, q));
    return _mm256_movemask_pd(_mm256_and_pd(m01, m23)) == 0xF;
}

/// A row of a matrix, each element in every lane.
struct RowQuad {
    __m256d c0, c1, c2;
};

/// The row times (x, y, z), lane by lane: Mat3 * Vec3d's sums in its order.
__attribute__((target("avx2"), always_inline)) inline __m256d row_times(const RowQuad& r, __m256d x,
                                                                        __m256d y, __m256d z) {
    return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(r.c0, x), _mm256_mul_pd(r.c1, y)),
                         _mm256_mul_pd(r.c2, z));
}

/// Row r of m in lanes.
__attribute__((target("avx2"), always_inline)) inline RowQuad row_quad(const Mat3& m, int r) {
    return {_mm256_set1_pd(m.m[r][0]), _mm256_set1_pd(m.m[r][1]), _mm256_set1_pd(m.m[r][2])};
}

/// beam_at() of rays [b, e) four at a time while four are left whose platform attitude is the
/// frame's (AVX2, no FMA: the same operations lane by lane, so the same doubles); returns the
/// first ray not done. Everything the loop reads besides the pulses is in locals (a store of
/// doubles may alias `a` and `frame`, whose members were loaded again for every four rays).
__attribute__((target("avx2"))) std::size_t beam_quads(const BeamArrays& arrays,
                                                       const AttitudeFrame& frame, std::size_t b,
                                                       std::size_t e) {
    const BeamArrays a = arrays;
    const Quat& q = frame.platform_attitude;
    const __m256d att = _mm256_setr_pd(q.w, q.x, q.y, q.z);
    const RowQuad m0 = row_quad(frame.sensor_rotation, 0), m1 = row_quad(frame.sensor_rotation, 1),
                  m2 = row_quad(frame.sensor_rotation, 2);
    const __m256d lx = _mm256_set1_pd(frame.lever_world.x),
                  ly = _mm256_set1_pd(frame.lever_world.y),
                  lz = _mm256_set1_pd(frame.lever_world.z);
    const __m256d tmin = _mm256_set1_pd(a.range_min_m), tmax = _mm256_set1_pd(a.range_max_m);
    std::size_t i = b;
    for (; i + 4 <= e && same_attitudes(a.platforms + i, att); i += 4) {
        // The four positions: rows (x, y, z, attitude w) transposed.
        const double* p = &a.platforms[i].position_m.x;
        const __m256d r0 = _mm256_loadu_pd(p), r1 = _mm256_loadu_pd(p + 7);
        const __m256d r2 = _mm256_loadu_pd(p + 14), r3 = _mm256_loadu_pd(p + 21);
        const __m256d xz01 = _mm256_unpacklo_pd(r0, r1), y01 = _mm256_unpackhi_pd(r0, r1);
        const __m256d xz23 = _mm256_unpacklo_pd(r2, r3), y23 = _mm256_unpackhi_pd(r2, r3);
        _mm256_storeu_pd(a.ox + i, _mm256_add_pd(_mm256_permute2f128_pd(xz01, xz23, 0x20), lx));
        _mm256_storeu_pd(a.oy + i, _mm256_add_pd(_mm256_permute2f128_pd(y01, y23, 0x20), ly));
        _mm256_storeu_pd(a.oz + i, _mm256_add_pd(_mm256_permute2f128_pd(xz01, xz23, 0x31), lz));
        // The four directions: (x, y) pairs unpacked, z one by one.
        const double* d = &a.directions[i].x;
        const __m256d xy02 = _mm256_loadu2_m128d(d + 6, d),
                      xy13 = _mm256_loadu2_m128d(d + 9, d + 3);
        const __m256d dx = _mm256_unpacklo_pd(xy02, xy13), dy = _mm256_unpackhi_pd(xy02, xy13);
        const __m256d dz = _mm256_setr_pd(d[2], d[5], d[8], d[11]);
        _mm256_storeu_pd(a.dx + i, row_times(m0, dx, dy, dz));
        _mm256_storeu_pd(a.dy + i, row_times(m1, dx, dy, dz));
        _mm256_storeu_pd(a.dz + i, row_times(m2, dx, dy, dz));
        _mm256_storeu_pd(a.tmin + i, tmin);
        _mm256_storeu_pd(a.tmax + i, tmax);
    }
    return i;
}
#endif

/// The rays of n pulses from the survey's one mount (beam_at), four at a time where `lanes` and
/// the CPU allow; then scan_angles(b, e, right) of each run [b, e) of pulses with the same scan
/// angle axis.
template <class ScanAngles>
void generate_beams(const BeamArrays& a, const Pose& mount, std::size_t n, bool lanes,
                    ScanAngles&& scan_angles) {
    AttitudeFrame frame;
    std::size_t run = 0;
    Vec3d run_right;
#if BEAMTRACE_SCAN_ANGLE_AVX2
    lanes = lanes && __builtin_cpu_supports("avx2");
#else
    (void)lanes;  // one pulse at a time
#endif
    for (std::size_t i = 0; i < n; ++i) {
#if BEAMTRACE_SCAN_ANGLE_AVX2
        if (lanes && frame.valid && (i = beam_quads(a, frame, i, n)) == n) {
            break;
        }
#endif
        if (frame.update(a.platforms[i].attitude, mount)) {
            scan_angles(run, i, run_right);
            run = i;
            run_right = frame.right;
        }
        beam_at(a, frame, i);
    }
    scan_angles(run, n, run_right);
}

}  // namespace

void SurveyRaySource::generate(const PulseBatch& pulses, std::uint64_t first, RayBatch& rays,
                               std::size_t ray_offset, Vec3d* origin, Vec3d* axis,
                               float* scan_angle, Scratch& scratch) const {
    scratch.platform.resize(pulses.time_s.size());
    trajectory->poses_at(pulses.time_s, scratch.platform);
    if (sim) {
        generate_physics(pulses, first, rays, ray_offset, origin, axis, scan_angle, scratch);
        return;
    }
    if (!spec->scanners.empty()) {
        generate_scanners(pulses, rays, ray_offset, origin, axis, scan_angle, scratch);
        return;
    }
    const BeamArrays a{rays.ox.data() + ray_offset,
                       rays.oy.data() + ray_offset,
                       rays.oz.data() + ray_offset,
                       rays.dx.data() + ray_offset,
                       rays.dy.data() + ray_offset,
                       rays.dz.data() + ray_offset,
                       rays.tmin.data() + ray_offset,
                       rays.tmax.data() + ray_offset,
                       scratch.platform.data(),
                       pulses.direction.data(),
                       spec->range_min_m,
                       spec->range_max_m};
    const std::size_t n = pulses.time_s.size();
    generate_beams(a, spec->mount.sensor_to_platform, n, lanes,
                   [&](std::size_t b, std::size_t e, const Vec3d& right) {
                       scan_angles_about(rays, b, e, ray_offset, right, scan_angle);
                   });
    if (origin != nullptr) {  // the beams are the rays: copied for callers that want them apart
        for (std::size_t i = 0; i < n; ++i) {
            origin[i] = {a.ox[i], a.oy[i], a.oz[i]};
            axis[i] = {a.dx[i], a.dy[i], a.dz[i]};
        }
    }
}

void SurveyRaySource::generate_scanners(const PulseBatch& pulses, RayBatch& rays,
                                        std::size_t ray_offset, Vec3d* origin, Vec3d* axis,
                                        float* scan_angle, Scratch& scratch) const {
    std::vector<ScannerFrame> frames = scanner_frames(*spec, nullptr);
    for (std::size_t i = 0; i < pulses.time_s.size(); ++i) {
        const Pose& platform = scratch.platform[i];
        ScannerFrame& f = frames[pulses.scanner[i]];
        f.frame.update(platform.attitude, f.mount);
        const Vec3d o = platform.position_m + f.frame.lever_world;
        const Vec3d d = f.frame.sensor_rotation * pulses.direction[i];
        if (origin != nullptr) {
            store_beam(o, d, f.frame.right, origin[i], axis[i], scan_angle[i]);
        } else {
            scan_angle[i] = scan_angle_about(d, f.frame.right);
        }
        rays.set(ray_offset + i, o, d, f.range_min_m, f.range_max_m);
    }
}

void SurveyRaySource::generate_physics(const PulseBatch& pulses, std::uint64_t first,
                                       RayBatch& rays, std::size_t ray_offset, Vec3d* origin,
                                       Vec3d* axis, float* scan_angle, Scratch& scratch) const {
    const std::size_t n_sub = sub_rays();
    std::vector<Vec3d>& dirs = scratch.dirs;
    dirs.resize(n_sub);
    // The rays leave the TRUE pose; the point is placed with the MEASURED one (georeferencing).
    const GeoreferencingConfig& geo = sim->config().noise.georeferencing;
    const bool measured_differs = !geo.none();
    std::vector<ScannerFrame> frames = scanner_frames(*spec, &geo);
    const bool several = !spec->scanners.empty();
    if (measured_differs) {
        scratch.errors.resize(pulses.time_s.size());
        platform_errors(geo, seed, first, pulses.time_s, scratch.errors, scratch.georeferencing);
    }
    for (std::size_t i = 0; i < pulses.time_s.size(); ++i) {
        const Pose& platform = scratch.platform[i];
        ScannerFrame& f = frames[several ? pulses.scanner[i] : 0];
        f.frame.update(platform.attitude, f.mount);
        const Vec3d o = platform.position_m + f.frame.lever_world;
        const Vec3d d = f.frame.sensor_rotation * pulses.direction[i];
        if (measured_differs) {
            const Pose measured = measured_platform_pose(platform, scratch.errors[i]);
            const Pose sensor = measured * f.mount_measured;
            store_beam(sensor.position_m, sensor.attitude.to_matrix() * pulses.direction[i],
                       right_of(measured.attitude.rotate({1, 0, 0})), origin[i], axis[i],
                       scan_angle[i]);
        } else {
            store_beam(o, d, f.frame.right, origin[i], axis[i], scan_angle[i]);
        }
        scratch.origins.resize(n_sub);
        sim->sub_rays(seed, first + i, o, d, scratch.origins, dirs);
        for (std::size_t j = 0; j < n_sub; ++j) {
            rays.set(ray_offset + i * n_sub + j, scratch.origins[j], dirs[j], f.range_min_m,
                     f.range_max_m);
        }
    }
}

}  // namespace detail

}  // namespace beamtrace
