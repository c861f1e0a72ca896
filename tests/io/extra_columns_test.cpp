// output.extra_bytes in points.csv, points.ply and points.pcd (docs/formats.md): the attributes
// as columns / properties / fields named as the LAS dimensions, read back by parsers written
// here from the format specifications (CSV text, PLY and PCD headers and packed binary records),
// and checked against the geometry of a tilted plane at a known range and incidence and against
// the LAS file's extra bytes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "beamtrace/io/las_extra_bytes.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kTiltDeg = 30.0;
constexpr double kDepthM = 40.0;

Vec3d plane_normal() {
    const double t = kTiltDeg * std::numbers::pi / 180.0;
    return {std::sin(t), 0.0, std::cos(t)};
}

/// A 3 x 3 pinhole looking down from the origin onto a plane tilted by 30 deg, 40 m below
/// (part_id 7), writing every point file with every attribute.
void run(const test::TempDir& dir, bool physics) {
    const Vec3d n = plane_normal();
    test::write_file(dir / "plane.yaml",
                     "materials: [{name: white, reflectance: 1}]\n"
                     "parts: [{plane: {point_m: [0, 0, -40], normal: [" +
                         std::to_string(n.x) + ", 0, " + std::to_string(n.z) +
                         "], size_m: 200}, material: white, part_id: 7}]\n");
    test::run_survey_in(
        "scene: plane.yaml\n"
        "scanner: {type: pinhole, width: 3, height: 3, hfov_deg: 4, vfov_deg: 4}\n"
        "platform: {type: static, position_m: [0, 0, 0], rotate_deg: [0, -90, 0]}\n" +
            std::string(physics ? "physics:\n  atmosphere: {enabled: false}\n"
                                  "  waveform: {pulse_fwhm_ns: 5}\n"
                                : "") +
            "output: {trajectory_rate_hz: 0, csv: true, ply: true, pcd: true, extra_bytes: "
            "[range, incidence_angle, echo_width, beam, object_id]}\n",
        dir, 2, 1 << 16, 1);
}

std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A table of named columns, one row per point (NaN for an empty CSV field).
using Columns = std::map<std::string, std::vector<double>>;

Columns read_csv(const std::filesystem::path& p) {
    std::istringstream in(slurp(p));
    std::string line;
    std::getline(in, line);
    std::vector<std::string> names;
    std::stringstream h(line);
    for (std::string name; std::getline(h, name, ',');) {
        EXPECT_EQ(std::count(names.begin(), names.end(), name), 0) << "column twice: " << name;
        names.push_back(name);
    }
    Columns out;
    while (std::getline(in, line)) {
        line += ',';  // so that a trailing empty field is read too
        std::stringstream r(line);
        std::string field;
        for (const std::string& name : names) {
            std::getline(r, field, ',');
            out[name].push_back(field.empty() ? std::nan("") : std::stod(field));
        }
    }
    return out;
}

/// Reads one little-endian value of PLY/PCD type `type` (as the letter and size, or the PLY name).
double binary_value(const char* at, const std::string& type) {
    const auto get = [&](auto v) {
        std::memcpy(&v, at, sizeof v);
        return static_cast<double>(v);
    };
    if (type == "double" || type == "F8") {
        return get(double{});
    }
    if (type == "float" || type == "F4") {
        return get(float{});
    }
    if (type == "int" || type == "I4") {
        return get(std::int32_t{});
    }
    if (type == "uint" || type == "U4") {
        return get(std::uint32_t{});
    }
    if (type == "ushort" || type == "U2") {
        return get(std::uint16_t{});
    }
    if (type == "uchar" || type == "U1") {
        return get(std::uint8_t{});
    }
    ADD_FAILURE() << "type " << type;
    return 0.0;
}

std::size_t type_bytes(const std::string& type) {
    if (type == "double") {
        return 8;
    }
    if (type == "ushort") {
        return 2;
    }
    if (type == "uchar") {
        return 1;
    }
    return 4;
}

/// The packed records after `header_end` with the given (name, type, bytes) layout.
Columns read_records(const std::string& file, std::size_t header_end, std::size_t count,
                     const std::vector<std::pair<std::string, std::string>>& fields,
                     const std::vector<std::size_t>& sizes) {
    std::size_t record = 0;
    for (const std::size_t s : sizes) {
        record += s;
    }
    EXPECT_EQ(file.size(), header_end + count * record) << "size";
    Columns out;
    for (std::size_t i = 0; i < count && file.size() >= header_end + count * record; ++i) {
        const char* at = file.data() + header_end + i * record;
        for (std::size_t f = 0; f < fields.size(); ++f) {
            out[fields[f].first].push_back(binary_value(at, fields[f].second));
            at += sizes[f];
        }
    }
    return out;
}

Columns read_ply(const std::filesystem::path& p) {
    const std::string file = slurp(p);
    const std::size_t end = file.find("end_header\n");
    EXPECT_NE(end, std::string::npos);
    std::istringstream h(file.substr(0, end));
    std::vector<std::pair<std::string, std::string>> fields;
    std::vector<std::size_t> sizes;
    std::size_t count = 0;
    for (std::string line; std::getline(h, line);) {
        std::istringstream w(line);
        std::string key, a, b;
        w >> key >> a >> b;
        if (key == "format") {
            EXPECT_EQ(a, "binary_little_endian");
        }
        if (key == "element") {
            count = std::stoul(b);
        }
        if (key == "property") {
            fields.emplace_back(b, a);
            sizes.push_back(type_bytes(a));
        }
    }
    return read_records(file, end + 11, count, fields, sizes);
}

Columns read_pcd(const std::filesystem::path& p) {
    const std::string file = slurp(p);
    const std::size_t data = file.find("DATA binary\n");
    EXPECT_NE(data, std::string::npos);
    std::istringstream h(file.substr(0, data));
    std::vector<std::string> names, sizes, types;
    std::size_t count = 0;
    for (std::string line; std::getline(h, line);) {
        std::istringstream w(line);
        std::string key, v;
        w >> key;
        std::vector<std::string> values;
        while (w >> v)
            values.push_back(v);
        if (key == "FIELDS") {
            names = values;
        }
        if (key == "SIZE") {
            sizes = values;
        }
        if (key == "TYPE") {
            types = values;
        }
        if (key == "POINTS") {
            count = std::stoul(values.at(0));
        }
    }
    EXPECT_EQ(names.size(), sizes.size());
    EXPECT_EQ(names.size(), types.size());
    std::vector<std::pair<std::string, std::string>> fields;
    std::vector<std::size_t> bytes;
    for (std::size_t f = 0; f < names.size() && f < sizes.size() && f < types.size(); ++f) {
        fields.emplace_back(names[f], types[f] + sizes[f]);
        bytes.push_back(std::stoul(sizes[f]));
    }
    return read_records(file, data + 12, count, fields, bytes);
}

/// Each file's attributes against the plane's geometry and the LAS file's extra bytes.
void expect_columns(const Columns& c, const std::vector<LasPoint>& las,
                    const std::vector<LasExtraBytesDescriptor>& d, bool physics, double step,
                    const char* file) {
    SCOPED_TRACE(file);
    for (const char* name : {"x", "y", "z", "incidence_angle_deg", "echo_width_ns", "object_id"}) {
        ASSERT_EQ(c.count(name), 1u) << name;
        ASSERT_EQ(c.at(name).size(), 9u) << name;
    }
    const Vec3d n = plane_normal();
    for (std::size_t i = 0; i < 9; ++i) {
        SCOPED_TRACE("point " + std::to_string(i));
        const Vec3d xyz{c.at("x")[i], c.at("y")[i], c.at("z")[i]};
        const double incidence =
            std::acos(std::abs(dot(n, xyz)) / length(xyz)) * 180.0 / std::numbers::pi;
        EXPECT_NEAR(c.at("range_m")[i], length(xyz), 2e-3);
        EXPECT_NEAR(c.at("incidence_angle_deg")[i], incidence, 0.011);
        if (physics) {
            EXPECT_NEAR(c.at("echo_width_ns")[i], 5.0, 0.15);
        } else {
            EXPECT_TRUE(std::isnan(c.at("echo_width_ns")[i])) << "unknown without physics";
        }
        EXPECT_EQ(c.at("beam")[i], static_cast<double>(i % 3));
        EXPECT_EQ(c.at("object_id")[i], 7.0);
        // The LAS file's extra bytes, to its scale (or this file's rounding, if coarser).
        const char* las_names[] = {"range_m", "incidence_angle_deg", "echo_width_ns", "beam",
                                   "object_id"};
        for (std::size_t f = 0; f < 5; ++f) {
            const double v = las_extra_bytes_value(d, f, las[i].extra_bytes);
            if (f == 2 && !physics) {
                continue;
            }
            EXPECT_NEAR(c.at(las_names[f])[i], v, std::max(d[f].scale, step)) << las_names[f];
        }
    }
}

TEST(ExtraColumns, CsvPlyAndPcdCarryTheAttributesNamedAsInLas) {
    for (const bool physics : {true, false}) {
        SCOPED_TRACE(physics ? "physics" : "no physics");
        test::TempDir dir;
        run(dir, physics);
        const std::filesystem::path out = dir / "out";
        LasReader reader(out / "points.las");
        const auto d = las_extra_bytes_descriptors(reader.vlrs());
        ASSERT_EQ(d.size(), 5u);
        const std::vector<LasPoint> las = read_las_points(out / "points.las");
        ASSERT_EQ(las.size(), 9u);
        expect_columns(read_csv(out / "points.csv"), las, d, physics, 0.005, "csv");
        expect_columns(read_ply(out / "points.ply"), las, d, physics, 1e-4, "ply");
        expect_columns(read_pcd(out / "points.pcd"), las, d, physics, 1e-4, "pcd");
        // PLY names its range `range` and PCD `range` / `ring`: the LAS names come on top.
        const std::string ply = slurp(out / "points.ply");
        EXPECT_NE(ply.find("property uint ray\nproperty float range_m\nproperty float "
                           "incidence_angle_deg\nproperty float echo_width_ns\nproperty ushort "
                           "beam\nproperty uint object_id\nend_header\n"),
                  std::string::npos);
        const std::string pcd = slurp(out / "points.pcd");
        EXPECT_NE(pcd.find("range ring range_m incidence_angle_deg echo_width_ns beam "
                           "object_id\nSIZE 8 8 8 2 1 1 1 8 4 2 4 4 4 2 4\nTYPE F F F U U U U F "
                           "F U F F F U U\nCOUNT 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1\n"),
                  std::string::npos);
        const std::string csv = slurp(out / "points.csv");
        EXPECT_EQ(csv.substr(0, csv.find('\n')),
                  std::string("x,y,z,gps_time,range_m,classification,point_source_id,beam,scan_"
                              "angle_deg") +
                      (physics ? ",intensity,return_number,number_of_returns" : "") +
                      ",incidence_angle_deg,echo_width_ns,object_id");
    }
}

}  // namespace
}  // namespace beamtrace
