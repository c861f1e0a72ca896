#include "beamtrace/physics/beam_divergence.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace beamtrace {

std::vector<std::string> BeamConfig::validate() const {
    std::vector<std::string> p;
    if (!(divergence_rad >= 0) || !(divergence_rad < 0.5)) {
        p.emplace_back("beam: divergence_rad must be in [0, 0.5)");
    }
    if (rings < 0 || rings > 20) {
        p.emplace_back("beam: rings must be in [0, 20]");
    }
    if (!(exit_diameter_m >= 0) || !(exit_diameter_m <= 10.0)) {
        p.emplace_back("beam: exit_diameter_m must be in [0, 10]");
    }
    if (edge_samples < 0 || edge_samples > 8) {
        p.emplace_back("beam: edge_samples must be in [0, 8]");
    }
    return p;
}

namespace {

/// A pattern with more than one sub-ray.
bool has_rings(const BeamConfig& config) {
    return (config.divergence_rad > 0 || config.exit_diameter_m > 0) && config.rings > 0;
}

/// Energy of the profile exp(-2 u^2) (normalised to 1) in the annulus lo <= u < hi.
double annulus_energy(double lo, double hi) {
    return std::exp(-2.0 * lo * lo) - (std::isinf(hi) ? 0.0 : std::exp(-2.0 * hi * hi));
}

/// E[u | lo <= u < hi] under the profile: int u^2 e^(-2u^2) du / int u e^(-2u^2) du, with
/// int u^2 e^(-2u^2) du = -u e^(-2u^2) / 4 + sqrt(pi / 8) erf(sqrt(2) u) / 4.
double annulus_mean_radius(double lo, double hi) {
    const auto primitive = [](double u) {
        const double tail = std::isinf(u) ? 0.0 : u * std::exp(-2.0 * u * u);
        return -tail / 4.0 + std::sqrt(std::numbers::pi / 8.0) * std::erf(std::sqrt(2.0) * u) / 4.0;
    };
    return (primitive(hi) - primitive(lo)) / (annulus_energy(lo, hi) / 4.0);
}

/// One cell of the pattern: the annulus [lo, hi) in beam units, the sector of width `width_rad`
/// centred on `azimuth_rad`, and its ring.
struct CellShape {
    double lo = 0.0, hi = 0.0;
    double azimuth_rad = 0.0, width_rad = 0.0;
    int ring = 0;
};

/// The cells of beam_pattern(config), in its order (has_rings(config) must hold).
std::vector<CellShape> cell_shapes(const BeamConfig& config) {
    std::vector<CellShape> out;
    const double d = 1.0 / config.rings;
    for (int k = 0; k <= config.rings; ++k) {
        const double lo = k == 0 ? 0.0 : (k - 0.5) * d;
        const double hi =
            k == config.rings ? std::numeric_limits<double>::infinity() : (k + 0.5) * d;
        const int count = k == 0 ? 1 : 6 * k;
        const double step = 2.0 * std::numbers::pi / count;
        const double phase = (k % 2 == 1) ? step / 2.0 : 0.0;
        for (int j = 0; j < count; ++j) {
            out.push_back({lo, hi, k == 0 ? 0.0 : phase + j * step, step, k});
        }
    }
    return out;
}

/// The radius where the energy outside it is the fraction `f` of the way from e^(-2 lo^2) to
/// e^(-2 hi^2) (equal-energy bands of an annulus).
double band_edge(double lo, double hi, double f) {
    const double e_lo = std::exp(-2.0 * lo * lo);
    const double e_hi = std::isinf(hi) ? 0.0 : std::exp(-2.0 * hi * hi);
    const double e = e_lo - f * (e_lo - e_hi);
    return e > 0 ? std::sqrt(-std::log(e) / 2.0) : std::numeric_limits<double>::infinity();
}

/// Whether the angular intervals [a - wa/2, a + wa/2] and [b - wb/2, b + wb/2] overlap by more
/// than a sliver, modulo 2 pi.
bool sectors_overlap(double a, double wa, double b, double wb) {
    const double two_pi = 2.0 * std::numbers::pi;
    double gap = std::fmod(std::abs(a - b), two_pi);
    gap = std::min(gap, two_pi - gap);
    return gap < (wa + wb) / 2.0 - 1e-9;
}

}  // namespace

std::vector<SubRayOffset> cell_probe_pattern(const BeamConfig& config) {
    std::vector<SubRayOffset> out;
    if (!has_rings(config) || config.edge_samples <= 0) {
        return out;
    }
    const double w = config.divergence_rad / 2.0;
    const int n = config.edge_samples;
    const std::vector<SubRayOffset> cells = beam_pattern(config);
    const std::vector<CellShape> shapes = cell_shapes(config);
    for (std::size_t j = 0; j < shapes.size(); ++j) {
        const CellShape& c = shapes[j];
        const double step = c.width_rad / n;
        const double sinc = std::sin(step / 2.0) / (step / 2.0);
        for (int b = 0; b < n; ++b) {
            const double lo = b == 0 ? c.lo : band_edge(c.lo, c.hi, double(b) / n);
            const double hi = b + 1 == n ? c.hi : band_edge(c.lo, c.hi, double(b + 1) / n);
            const double radius = annulus_mean_radius(lo, hi) * sinc;
            for (int a = 0; a < n; ++a) {
                const double azimuth = c.azimuth_rad - c.width_rad / 2.0 + (a + 0.5) * step;
                out.push_back({radius * w, radius, azimuth, cells[j].weight / (n * n)});
            }
        }
    }
    return out;
}

std::vector<std::vector<std::uint32_t>> cell_neighbours(const BeamConfig& config) {
    if (!has_rings(config)) {
        return {{}};
    }
    const std::vector<CellShape> shapes = cell_shapes(config);
    std::vector<std::vector<std::uint32_t>> out(shapes.size());
    for (std::size_t a = 0; a < shapes.size(); ++a) {
        for (std::size_t b = 0; b < shapes.size(); ++b) {
            const CellShape &p = shapes[a], &q = shapes[b];
            const bool same_ring = p.ring == q.ring && a != b && p.ring > 0 &&
                                   sectors_overlap(p.azimuth_rad, 2 * p.width_rad, q.azimuth_rad,
                                                   2 * q.width_rad - 1e-6);
            const bool next_ring =
                std::abs(p.ring - q.ring) == 1 &&
                (p.ring == 0 || q.ring == 0 ||
                 sectors_overlap(p.azimuth_rad, p.width_rad, q.azimuth_rad, q.width_rad));
            if (same_ring || next_ring) {
                out[a].push_back(static_cast<std::uint32_t>(b));
            }
        }
    }
    return out;
}

std::size_t sub_ray_count(const BeamConfig& config) {
    if (!has_rings(config)) {
        return 1;
    }
    const auto r = static_cast<std::size_t>(config.rings);
    return 1 + 3 * r * (r + 1);
}

std::vector<SubRayOffset> beam_pattern(const BeamConfig& config) {
    std::vector<SubRayOffset> out;
    if (!has_rings(config)) {
        out.push_back({});
        return out;
    }
    const double w = config.divergence_rad / 2.0;  // 1/e^2 half-angle
    const double d = 1.0 / config.rings;           // ring spacing in beam units
    out.reserve(sub_ray_count(config));
    double total = 0.0;
    for (int k = 0; k <= config.rings; ++k) {
        const double lo = k == 0 ? 0.0 : (k - 0.5) * d;
        const double hi =
            k == config.rings ? std::numeric_limits<double>::infinity() : (k + 0.5) * d;
        const int count = k == 0 ? 1 : 6 * k;
        const double share = annulus_energy(lo, hi) / count;
        const double step = 2.0 * std::numbers::pi / count;
        const double phase = (k % 2 == 1) ? step / 2.0 : 0.0;
        // The centroid of a sector of half-angle step / 2: its mean radius times the sinc.
        const double radius =
            k == 0 ? 0.0 : annulus_mean_radius(lo, hi) * std::sin(step / 2.0) / (step / 2.0);
        for (int j = 0; j < count; ++j) {
            out.push_back({radius * w, radius, k == 0 ? 0.0 : phase + j * step, share});
            total += share;
        }
    }
    for (auto& s : out) {
        s.weight /= total;
    }
    return out;
}

double cell_variance(std::span<const SubRayOffset> pattern) {
    double discrete = 0.0;
    for (const auto& s : pattern) {
        discrete += 0.5 * s.weight * s.radius * s.radius;
    }
    return std::max(0.0, 0.25 - discrete);
}

std::vector<Vec3d> beam_frame_origins(const BeamConfig& config,
                                      std::span<const SubRayOffset> pattern) {
    std::vector<Vec3d> out(pattern.size(), Vec3d{0, 0, 0});
    if (!(config.exit_diameter_m > 0)) {
        return out;
    }
    const double half = config.exit_diameter_m / 2.0;
    const bool collimated = !(config.divergence_rad > 0);
    for (std::size_t j = 0; j < pattern.size(); ++j) {
        const double r = half * pattern[j].radius;
        const double c = std::cos(pattern[j].azimuth_rad), s = std::sin(pattern[j].azimuth_rad);
        // Perpendicular to the angular offset (a ruled hyperboloid); along it when collimated.
        out[j] = collimated ? Vec3d{r * c, r * s, 0.0} : Vec3d{-r * s, r * c, 0.0};
    }
    return out;
}

void orthonormal_basis(const Vec3d& n, Vec3d& e1, Vec3d& e2) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    e1 = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    e2 = {b, sign + n.y * n.y * a, -n.y};
}

void sub_ray_directions(const Vec3d& axis, std::span<const SubRayOffset> pattern,
                        std::span<Vec3d> out) {
    assert(out.size() == pattern.size());
    Vec3d e1, e2;
    orthonormal_basis(axis, e1, e2);
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        const SubRayOffset& s = pattern[i];
        const double st = std::sin(s.off_axis_rad), ct = std::cos(s.off_axis_rad);
        out[i] = normalize(axis * ct +
                           (e1 * std::cos(s.azimuth_rad) + e2 * std::sin(s.azimuth_rad)) * st);
    }
}

std::vector<Vec3d> beam_frame_directions(std::span<const SubRayOffset> pattern) {
    std::vector<Vec3d> out;
    out.reserve(pattern.size());
    for (const auto& s : pattern) {
        const double st = std::sin(s.off_axis_rad);
        out.push_back(
            {st * std::cos(s.azimuth_rad), st * std::sin(s.azimuth_rad), std::cos(s.off_axis_rad)});
    }
    return out;
}

namespace {

#if defined(__x86_64__) && defined(__GNUC__)
/// (u b.x + v b.y) + a b.z in the first three lanes.
__attribute__((target("avx2"), always_inline)) inline __m256d direction_avx2(__m256d a, __m256d u,
                                                                             __m256d v,
                                                                             const Vec3d& b) {
    return _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(u, _mm256_set1_pd(b.x)), _mm256_mul_pd(v, _mm256_set1_pd(b.y))),
        _mm256_mul_pd(a, _mm256_set1_pd(b.z)));
}

/// out[i] = e1 * b.x + e2 * b.y + axis * b.z for the beam-frame directions b of frame[0, n), one
/// direction to an AVX2 register (its x, y, z in three lanes; no FMA: each product and sum
/// rounded alone, in that order). Each store but the last writes four doubles: the fourth is the
/// next direction's x, which its own store writes after.
__attribute__((target("avx2"))) void directions_avx2(const Vec3d& axis, const Vec3d& e1,
                                                     const Vec3d& e2, const Vec3d* frame,
                                                     std::size_t n, Vec3d* out) {
    static_assert(sizeof(Vec3d) == 3 * sizeof(double));
    const __m256d a = _mm256_setr_pd(axis.x, axis.y, axis.z, 0.0);
    const __m256d u = _mm256_setr_pd(e1.x, e1.y, e1.z, 0.0);
    const __m256d v = _mm256_setr_pd(e2.x, e2.y, e2.z, 0.0);
    for (std::size_t i = 0; i + 1 < n; ++i) {
        _mm256_storeu_pd(&out[i].x, direction_avx2(a, u, v, frame[i]));
    }
    const __m256d d = direction_avx2(a, u, v, frame[n - 1]);
    _mm_storeu_pd(&out[n - 1].x, _mm256_castpd256_pd128(d));
    _mm_store_sd(&out[n - 1].z, _mm256_extractf128_pd(d, 1));
}
#endif

}  // namespace

void sub_ray_directions(const Vec3d& axis, std::span<const Vec3d> beam_frame,
                        std::span<Vec3d> out) {
    assert(out.size() == beam_frame.size());
    Vec3d e1, e2;
    orthonormal_basis(axis, e1, e2);
#if defined(__x86_64__) && defined(__GNUC__)
    if (beam_frame.size() > 1 && __builtin_cpu_supports("avx2")) {  // a single ray's: below
        directions_avx2(axis, e1, e2, beam_frame.data(), beam_frame.size(), out.data());
        return;
    }
#endif
    for (std::size_t i = 0; i < beam_frame.size(); ++i) {
        const Vec3d& b = beam_frame[i];
        out[i] = e1 * b.x + e2 * b.y + axis * b.z;
    }
}

void sub_ray_origins(const Vec3d& origin, const Vec3d& axis, std::span<const Vec3d> beam_frame,
                     std::span<Vec3d> out) {
    assert(out.size() == beam_frame.size());
    Vec3d e1, e2;
    orthonormal_basis(axis, e1, e2);
    for (std::size_t i = 0; i < beam_frame.size(); ++i) {
        const Vec3d& b = beam_frame[i];
        out[i] = origin + e1 * b.x + e2 * b.y;
    }
}

}  // namespace beamtrace
