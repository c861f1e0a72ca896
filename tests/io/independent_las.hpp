// What two independent third-party readers (copc.js and loaders.gl's laz-rs, from the npm
// registry) decode from a LAS file, and checks of it against the points we meant to write.
// The expectations come from the writer's input, never from our own reader.
#pragma once

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/io/las.hpp"
#include "test_support.hpp"

namespace beamtrace::test {

/// One LAS file as the npm readers decode it (tests/tools/lasdump.mjs).
struct IndependentLas {
    nlohmann::json facts;           ///< header, VLRs (bytes in hex), dimension names
    std::vector<std::string> dims;  ///< copc.js's dimensions, in row order
    std::size_t count = 0;          ///< points copc.js decoded
    std::vector<double> copc;       ///< count rows of dims.size() values
    std::vector<double> loadersgl;  ///< rows of X, Y, Z, intensity, classification

    /// copc.js's value of dimension `dim` for point i (the dimension must exist).
    [[nodiscard]] double at(std::size_t i, std::size_t dim) const {
        return copc[i * dims.size() + dim];
    }
    /// Index of a dimension in the rows, or -1.
    [[nodiscard]] int dim(std::string_view name) const {
        const auto it = std::find(dims.begin(), dims.end(), name);
        return it == dims.end() ? -1 : static_cast<int>(it - dims.begin());
    }
    [[nodiscard]] Vec3d header_vec(const char* key) const {
        const auto& a = facts.at(key);
        return {a.at(0).get<double>(), a.at(1).get<double>(), a.at(2).get<double>()};
    }
};

inline std::vector<double> read_f64_file(const std::filesystem::path& path) {
    const std::string bytes = read_file(path);
    std::vector<double> values(bytes.size() / sizeof(double));
    std::memcpy(values.data(), bytes.data(), values.size() * sizeof(double));
    return values;
}

/// Decodes `las` with the npm readers installed in `lasval` (see install_lasval); a test
/// failure and nothing when they cannot.
inline std::optional<IndependentLas> decode_independently(const std::filesystem::path& lasval,
                                                          const std::filesystem::path& las,
                                                          const std::filesystem::path& scratch) {
    const std::filesystem::path out = scratch / (las.stem().string() + "-lasdump");
    const auto r = run_command("cd '" + lasval.string() + "' && node lasdump.mjs '" + las.string() +
                               "' '" + out.string() + "'");
    if (r.exit_code != 0) {
        ADD_FAILURE() << "the npm readers could not decode " << las << ":\n" << r.out;
        return std::nullopt;
    }
    IndependentLas d;
    d.facts = nlohmann::json::parse(read_file(out.string() + ".json"));
    d.dims = d.facts.at("dimensions").get<std::vector<std::string>>();
    d.count = d.facts.at("copcPoints").get<std::size_t>();
    d.copc = read_f64_file(out.string() + ".copc.f64");
    d.loadersgl = read_f64_file(out.string() + ".loadersgl.f64");
    EXPECT_EQ(d.copc.size(), d.count * d.dims.size()) << las;
    EXPECT_EQ(d.loadersgl.size(), d.facts.at("loadersglPoints").get<std::size_t>() * 5) << las;
    for (const char* suffix : {".json", ".copc.f64", ".loadersgl.f64"}) {
        std::filesystem::remove(out.string() + suffix);
    }
    return d;
}

/// What a file must hold besides its points.
struct ExpectedLasHeader {
    int point_format = 6;
    Vec3d scale{0.001, 0.001, 0.001};
    std::optional<Vec3d> offset;  ///< unset: any offset (but X, Y, Z must still match)
};

namespace detail {
using Field = double (*)(const LasPoint&);

/// Checks that the decoded dimension `name` equals `want(p)` for every point (within `tol`);
/// reports the first few differences.
inline void expect_dimension(const IndependentLas& d, std::span<const LasPoint> expected,
                             const char* name, Field want, double tol, const std::string& what) {
    const int k = d.dim(name);
    ASSERT_GE(k, 0) << what << ": copc.js has no dimension " << name;
    std::size_t bad = 0;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const double got = d.at(i, static_cast<std::size_t>(k));
        const double w = want(expected[i]);
        if (!(std::abs(got - w) <= tol) && ++bad <= 3) {
            ADD_FAILURE() << what << ": point " << i << " " << name << " decodes as " << got
                          << ", we wrote " << w;
        }
    }
    EXPECT_EQ(bad, 0u) << what << ": " << name << " differs on " << bad << " points";
}

/// X, Y, Z from both readers within half a scale step of what we wrote (a one-step shift
/// fails), and the header's bounds equal to the decoded points' (to rounding of offset + s k).
inline void expect_coordinates(const IndependentLas& d, std::span<const LasPoint> expected,
                               const std::string& what) {
    const Vec3d scale = d.header_vec("scale");
    const Vec3d hmin = d.header_vec("min"), hmax = d.header_vec("max");
    const std::array<Field, 3> coord = {[](const LasPoint& p) { return p.x; },
                                        [](const LasPoint& p) { return p.y; },
                                        [](const LasPoint& p) { return p.z; }};
    const char* names[3] = {"X", "Y", "Z"};
    for (std::size_t a = 0; a < 3; ++a) {
        const double tol = 0.5 * scale[a] * (1.0 + 1e-6);
        expect_dimension(d, expected, names[a], coord[a], tol, what);
        const auto k = static_cast<std::size_t>(d.dim(names[a]));
        double lo = 1e300, hi = -1e300;
        std::size_t bad = 0;
        for (std::size_t i = 0; i < expected.size(); ++i) {
            bad += std::abs(d.loadersgl[5 * i + a] - coord[a](expected[i])) <= tol ? 0 : 1;
            lo = std::min(lo, d.at(i, k));
            hi = std::max(hi, d.at(i, k));
        }
        EXPECT_EQ(bad, 0u) << what << ": loaders.gl's " << names[a] << " differs on " << bad
                           << " points";
        if (!expected.empty()) {
            EXPECT_NEAR(hmin[a], lo, 1e-6 * scale[a]) << what << ": header min " << names[a];
            EXPECT_NEAR(hmax[a], hi, 1e-6 * scale[a]) << what << ": header max " << names[a];
        }
    }
}
}  // namespace detail

/// Compares every point field and the header that the independent readers decode with the
/// points we wrote: coordinates within half a scale step (the quantisation), everything else
/// exactly (the scan angle to half a 0.006-degree step), header bounds equal to the decoded
/// points' and counts by return equal to the written points'.
inline void expect_decodes_as(const IndependentLas& d, std::span<const LasPoint> expected,
                              const ExpectedLasHeader& header, const std::string& what) {
    ASSERT_EQ(d.count, expected.size()) << what;
    ASSERT_EQ(d.facts.at("pointCount").get<std::size_t>(), expected.size()) << what;
    ASSERT_EQ(d.loadersgl.size(), expected.size() * 5) << what << ": loaders.gl's point count";
    EXPECT_EQ(d.facts.at("version"), nlohmann::json::array({1, 4})) << what;
    EXPECT_EQ(d.facts.at("pointFormat").get<int>(), header.point_format) << what;
    EXPECT_EQ(d.header_vec("scale"), header.scale) << what;
    if (header.offset) {
        EXPECT_EQ(d.header_vec("offset"), *header.offset) << what;
    }
    detail::expect_coordinates(d, expected, what);
    using P = const LasPoint&;
    const std::pair<const char*, detail::Field> exact[] = {
        {"GpsTime", [](P p) { return p.gps_time; }},
        {"Intensity", [](P p) { return double(p.intensity); }},
        {"ReturnNumber", [](P p) { return double(p.return_number); }},
        {"NumberOfReturns", [](P p) { return double(p.number_of_returns); }},
        {"Classification", [](P p) { return double(p.classification); }},
        {"UserData", [](P p) { return double(p.user_data); }},
        {"PointSourceId", [](P p) { return double(p.point_source_id); }},
        {"Synthetic", [](P p) { return double(p.synthetic); }},
        {"KeyPoint", [](P p) { return double(p.key_point); }},
        {"Withheld", [](P p) { return double(p.withheld); }},
        {"Overlap", [](P p) { return double(p.overlap); }},
        {"ScannerChannel", [](P p) { return double(p.scanner_channel); }},
        {"ScanDirectionFlag", [](P p) { return double(p.scan_direction); }},
        {"EdgeOfFlightLine", [](P p) { return double(p.edge_of_flight_line); }}};
    for (const auto& [name, field] : exact) {
        detail::expect_dimension(d, expected, name, field, 0.0, what);
    }
    detail::expect_dimension(
        d, expected, "ScanAngle", [](P p) { return double(p.scan_angle_deg); }, 0.003 + 1e-9, what);
    std::size_t lg_bad = 0;
    std::vector<std::uint64_t> by_return(15, 0);
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const LasPoint& p = expected[i];
        lg_bad += d.loadersgl[5 * i + 3] == p.intensity ? 0 : 1;
        lg_bad += d.loadersgl[5 * i + 4] == p.classification ? 0 : 1;
        if (p.return_number >= 1 && p.return_number <= 15) {
            ++by_return[p.return_number - 1u];
        }
    }
    EXPECT_EQ(lg_bad, 0u) << what << ": loaders.gl's intensity or classification differs";
    EXPECT_EQ(d.facts.at("pointCountByReturn").get<std::vector<std::uint64_t>>(), by_return)
        << what;
    const std::pair<const char*, detail::Field> colours[] = {
        {"Red", [](P p) { return double(p.red); }},
        {"Green", [](P p) { return double(p.green); }},
        {"Blue", [](P p) { return double(p.blue); }},
        {"Infrared", [](P p) { return double(p.nir); }}};
    for (std::size_t c = 0; c < 4; ++c) {
        const bool in_format = c < 3 ? header.point_format >= 7 : header.point_format == 8;
        if (in_format) {
            detail::expect_dimension(d, expected, colours[c].first, colours[c].second, 0.0, what);
        } else {
            EXPECT_LT(d.dim(colours[c].first), 0)
                << what << ": format " << header.point_format << " has " << colours[c].first;
        }
    }
}

}  // namespace beamtrace::test

/// Declares `var`, the folder of the installed npm readers, or skips the test (a failure under
/// BEAMTRACE_REQUIRE_ALL=1) saying why they are missing.
#define BEAMTRACE_REQUIRE_LASVAL(var)                                                        \
    std::filesystem::path var;                                                               \
    do {                                                                                     \
        std::string why_;                                                                    \
        try {                                                                                \
            var = ::beamtrace::test::install_lasval(why_);                                   \
        } catch (const std::filesystem::filesystem_error& e) {                               \
            why_ = std::string("cannot install the npm readers: ") + e.what();               \
        }                                                                                    \
        if (var.empty()) {                                                                   \
            BEAMTRACE_SKIP_OR_FAIL("the independent LAS readers are unavailable: " << why_); \
        }                                                                                    \
    } while (0)
