#include "beamtrace/scene/raster_terrain.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "corruption_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

class RasterTerrainTest : public test::TempDirTest {
  protected:
    /// Loading `text` as an .asc must throw InputError naming the file, with `fragment`.
    void expect_asc_error(const std::string& text, const std::string& fragment) const {
        test::expect_input_error(load_esri_ascii_grid, write("broken.asc", text), fragment);
    }
};

// ---- a minimal little-endian TIFF writer for hand-made fixtures ---------------------------

struct TiffEntry {
    std::uint16_t tag = 0;
    std::uint16_t type = 0;  // 2 ASCII, 3 SHORT, 4 LONG, 12 DOUBLE
    std::uint32_t count = 0;
    std::string data;  // little-endian values
};

[[nodiscard]] TiffEntry shorts(std::uint16_t tag, std::vector<std::uint16_t> values) {
    TiffEntry e{tag, 3, static_cast<std::uint32_t>(values.size()), {}};
    for (auto v : values) {
        test::append_bytes(e.data, v);
    }
    return e;
}

[[nodiscard]] TiffEntry longs(std::uint16_t tag, std::uint32_t value) {
    TiffEntry e{tag, 4, 1, {}};
    test::append_bytes(e.data, value);
    return e;
}

[[nodiscard]] TiffEntry doubles(std::uint16_t tag, std::vector<double> values) {
    TiffEntry e{tag, 12, static_cast<std::uint32_t>(values.size()), {}};
    for (auto v : values) {
        test::append_bytes(e.data, v);
    }
    return e;
}

[[nodiscard]] TiffEntry ascii(std::uint16_t tag, const std::string& text) {
    return {tag, 2, static_cast<std::uint32_t>(text.size() + 1), text + '\0'};
}

/// One strip of `pixels` right after the header (or, given `tile` = {width, length}, one tile);
/// `entries` must not hold the strip or tile tags.
[[nodiscard]] std::string make_tiff(std::vector<TiffEntry> entries, std::uint32_t width,
                                    std::uint32_t height, const std::string& pixels,
                                    std::optional<std::array<std::uint32_t, 2>> tile = {}) {
    std::string padded = pixels;
    if (padded.size() % 2 != 0) {
        padded.push_back('\0');
    }
    entries.push_back(longs(256, width));
    entries.push_back(longs(257, height));
    if (tile) {
        entries.push_back(longs(322, (*tile)[0]));
        entries.push_back(longs(323, (*tile)[1]));
        entries.push_back(longs(324, 8));
        entries.push_back(longs(325, static_cast<std::uint32_t>(pixels.size())));
    } else {
        entries.push_back(longs(273, 8));
        entries.push_back(longs(278, height));
        entries.push_back(longs(279, static_cast<std::uint32_t>(pixels.size())));
    }
    std::sort(entries.begin(), entries.end(),
              [](const TiffEntry& a, const TiffEntry& b) { return a.tag < b.tag; });
    std::string out = "II";
    test::append_bytes(out, std::uint16_t{42});
    test::append_bytes(out, std::uint32_t{8 + static_cast<std::uint32_t>(padded.size())});
    out += padded;
    const std::size_t ifd_size = 2 + 12 * entries.size() + 4;
    std::string overflow;
    test::append_bytes(out, static_cast<std::uint16_t>(entries.size()));
    for (const auto& e : entries) {
        test::append_bytes(out, e.tag);
        test::append_bytes(out, e.type);
        test::append_bytes(out, e.count);
        if (e.data.size() <= 4) {
            std::string inline_value = e.data;
            inline_value.resize(4, '\0');
            out += inline_value;
        } else {
            const std::size_t offset = 8 + padded.size() + ifd_size + overflow.size();
            test::append_bytes(out, static_cast<std::uint32_t>(offset));
            overflow += e.data;
            if (overflow.size() % 2 != 0) {
                overflow.push_back('\0');
            }
        }
    }
    test::append_bytes(out, std::uint32_t{0});
    return out + overflow;
}

/// 3 x 2 int16 cells {1, 2, 3; 4, -9999, 6}, 25 m, top-left corner at (1000, 2000).
[[nodiscard]] std::string small_int16_tiff(std::vector<TiffEntry> extra = {}) {
    std::string pixels;
    for (std::int16_t v : std::initializer_list<std::int16_t>{1, 2, 3, 4, -9999, 6}) {
        test::append_bytes(pixels, v);
    }
    std::vector<TiffEntry> entries{shorts(258, {16}),
                                   shorts(259, {1}),
                                   shorts(262, {1}),
                                   shorts(277, {1}),
                                   shorts(339, {2}),
                                   doubles(33550, {25, 25, 0}),
                                   doubles(33922, {0, 0, 0, 1000, 2000, 0}),
                                   ascii(42113, "-9999")};
    for (auto& e : extra) {
        const auto it = std::find_if(entries.begin(), entries.end(),
                                     [&](const TiffEntry& x) { return x.tag == e.tag; });
        if (it != entries.end()) {
            *it = e;
        } else {
            entries.push_back(e);
        }
    }
    return make_tiff(entries, 3, 2, pixels);
}

[[nodiscard]] Vec3f normal(const TriangleMesh& m, const Face& f) {
    return cross(m.vertices[f[1]] - m.vertices[f[0]], m.vertices[f[2]] - m.vertices[f[0]]);
}

// ---- the shared DEM ----------------------------------------------------------------------

TEST(RasterTerrain, AsciiGridAndGeoTiffAreTheSameDem) {
    const auto asc_path = test::shared_mesh("terrain/dem_hd.asc");
    const auto tif_path = test::shared_mesh("terrain/dem_hd.tif");
    BEAMTRACE_REQUIRE_FILE(asc_path);
    BEAMTRACE_REQUIRE_FILE(tif_path);
    const Raster asc = load_raster(asc_path);
    const Raster tif = load_raster(tif_path);
    ASSERT_EQ(asc.cols, 1041);
    ASSERT_EQ(asc.rows, 713);
    EXPECT_EQ(tif.cols, asc.cols);
    EXPECT_EQ(tif.rows, asc.rows);
    EXPECT_NEAR(tif.x0_m, asc.x0_m, 1e-6);
    EXPECT_NEAR(tif.y0_m, asc.y0_m, 1e-6);
    EXPECT_NEAR(tif.cell_x_m, 25.0, 1e-9);
    EXPECT_NEAR(tif.cell_y_m, -25.0, 1e-9);
    EXPECT_NEAR(asc.cell_x_m, 25.0, 1e-9);
    EXPECT_NEAR(asc.cell_y_m, -25.0, 1e-9);
    // Pixel centre of the top-left cell: xllcorner + 12.5, yllcorner + 713 * 25 - 12.5.
    EXPECT_NEAR(asc.x0_m, 465322.625829136115 + 12.5, 1e-6);
    EXPECT_NEAR(asc.y0_m, 5464975.390295740217 + 713 * 25.0 - 12.5, 1e-6);
    ASSERT_EQ(asc.z.size(), tif.z.size());
    float worst = 0.0f;
    for (std::size_t i = 0; i < asc.z.size(); ++i) {
        worst = std::max(worst, std::fabs(asc.z[i] - tif.z[i]));
    }
    EXPECT_LE(worst, 0.005f);
    ASSERT_TRUE(asc.nodata && tif.nodata);
    EXPECT_EQ(*asc.nodata, *tif.nodata);
    EXPECT_EQ(*tif.nodata, -std::numeric_limits<float>::max());
    const auto [lo, hi] = std::minmax_element(tif.z.begin(), tif.z.end());
    EXPECT_NEAR(*lo, 34.0f, 0.5f);  // SOURCES.md: z 34-581 m
    EXPECT_NEAR(*hi, 581.0f, 0.5f);
}

TEST(RasterTerrain, StripTiffSubsetMatchesTheTiledDem) {
    const auto sub_path = test::shared_mesh("terrain/dem_hd_sub.tif");
    const auto tif_path = test::shared_mesh("terrain/dem_hd.tif");
    BEAMTRACE_REQUIRE_FILE(sub_path);
    BEAMTRACE_REQUIRE_FILE(tif_path);
    const Raster sub = load_geotiff(sub_path);
    EXPECT_EQ(sub.cols, 198);
    EXPECT_EQ(sub.rows, 119);
    EXPECT_NEAR(sub.cell_x_m, 25.0, 1e-9);
    const Raster dem = load_geotiff(tif_path);
    const double col0 = (sub.x0_m - dem.x0_m) / dem.cell_x_m;
    const double row0 = (sub.y0_m - dem.y0_m) / dem.cell_y_m;
    ASSERT_NEAR(col0, std::round(col0), 1e-3);
    ASSERT_NEAR(row0, std::round(row0), 1e-3);
    const int c0 = static_cast<int>(std::lround(col0)), r0 = static_cast<int>(std::lround(row0));
    int differing = 0;
    for (int r = 0; r < sub.rows; ++r) {
        for (int c = 0; c < sub.cols; ++c) {
            differing += sub.at(c, r) != dem.at(c0 + c, r0 + r) ? 1 : 0;
        }
    }
    EXPECT_EQ(differing, 0);
}

TEST(RasterTerrain, DemHeightFieldMatchesThePly) {
    const auto tif_path = test::shared_mesh("terrain/dem_hd.tif");
    const auto ply_path = test::shared_mesh("large/dem_hd_heightfield.ply");
    BEAMTRACE_REQUIRE_FILE(tif_path);
    // The PLY's comment: add (465335.125829136, 5464987.890295740) for UTM coordinates.
    const TriangleMesh m =
        raster_to_mesh(load_geotiff(tif_path), {465335.125829136, 5464987.890295740, 0.0});
    EXPECT_EQ(m.triangle_count(), 2u * 1040u * 712u);
    EXPECT_EQ(m.vertices.size(), 1041u * 713u);
    for (std::size_t f = 0; f < m.triangle_count(); f += 9973) {
        EXPECT_GT(normal(m, m.faces[f]).z, 0.0f) << f;
    }
    BEAMTRACE_REQUIRE_FILE(ply_path);
    const TriangleMesh ply = load_ply(ply_path);
    EXPECT_EQ(m.triangle_count(), ply.triangle_count());
    const Aabb a = m.bounds(), b = ply.bounds();
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_NEAR(a.lo[k], b.lo[k], 1e-3) << k;
        EXPECT_NEAR(a.hi[k], b.hi[k], 1e-3) << k;
    }
}

// ---- hand-written grids ------------------------------------------------------------------

TEST_F(RasterTerrainTest, TinyGridGivesExactVerticesAndUpwardFaces) {
    const Raster r = load_raster(write("tiny.asc",
                                       "ncols 3\nNROWS 2\nxllcorner 100\nYllCorner 200\n"
                                       "cellsize 10\n1 2 3\n4 5 6\n"));
    EXPECT_EQ(r.x0_m, 105.0);
    EXPECT_EQ(r.y0_m, 215.0);
    EXPECT_FALSE(r.nodata.has_value());
    const TriangleMesh m = raster_to_mesh(r, {100.0, 200.0, 0.5});
    const std::vector<Vec3f> vertices{{5, 15, 0.5f}, {15, 15, 1.5f}, {25, 15, 2.5f},
                                      {5, 5, 3.5f},  {15, 5, 4.5f},  {25, 5, 5.5f}};
    EXPECT_EQ(m.vertices, vertices);
    const std::vector<Face> faces{{3, 4, 1}, {3, 1, 0}, {4, 5, 2}, {4, 2, 1}};
    EXPECT_EQ(m.faces, faces);
    for (const Face& f : m.faces) {
        EXPECT_GT(normal(m, f).z, 0.0f);
    }
}

TEST_F(RasterTerrainTest, HeaderKeysInAnyOrderWithCentresAndDxDy) {
    const Raster r = load_esri_ascii_grid(
        write("centre.asc",
              "DY 5\nnodata_value -1\nyllcenter 0\r\nxllcenter 0\ndx 2\nnrows 2\nncols 2\n"
              "1 -1\n3 4\n"));
    EXPECT_EQ(r.cell_x_m, 2.0);
    EXPECT_EQ(r.cell_y_m, -5.0);
    EXPECT_EQ(r.x0_m, 0.0);
    EXPECT_EQ(r.y0_m, 5.0);
    ASSERT_TRUE(r.nodata.has_value());
    EXPECT_EQ(*r.nodata, -1.0f);
    EXPECT_FALSE(r.valid(r.at(1, 0)));
    EXPECT_TRUE(r.valid(r.at(0, 1)));
}

TEST_F(RasterTerrainTest, NodataCellRemovesExactlyTheTrianglesTouchingIt) {
    std::string text = "ncols 5\nnrows 4\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
    const std::string full = text + "1 2 3 4 5\n6 7 8 9 10\n11 12 13 14 15\n16 17 18 19 20\n";
    const std::string holed =
        text + "NODATA_value -9999\n1 2 3 4 5\n6 7 -9999 9 10\n11 12 13 14 15\n16 17 18 19 20\n";
    const TriangleMesh a = raster_to_mesh(load_esri_ascii_grid(write("full.asc", full)));
    const TriangleMesh b = raster_to_mesh(load_esri_ascii_grid(write("holed.asc", holed)));
    EXPECT_EQ(a.triangle_count(), 2u * 4u * 3u);
    EXPECT_EQ(b.vertices.size(), a.vertices.size() - 1);
    const Vec3f hole = a.vertices[1 * 5 + 2];  // col 2, row 1
    std::vector<std::array<Vec3f, 3>> kept;
    for (const Face& f : a.faces) {
        const std::array<Vec3f, 3> t{a.vertices[f[0]], a.vertices[f[1]], a.vertices[f[2]]};
        if (t[0] != hole && t[1] != hole && t[2] != hole) {
            kept.push_back(t);
        }
    }
    EXPECT_EQ(kept.size(), a.triangle_count() - 6);  // an interior vertex has six triangles
    ASSERT_EQ(b.triangle_count(), kept.size());
    for (std::size_t i = 0; i < kept.size(); ++i) {
        for (std::size_t c = 0; c < 3; ++c) {
            EXPECT_EQ(b.vertices[b.faces[i][c]], kept[i][c]) << i << " " << c;
        }
    }
}

TEST_F(RasterTerrainTest, NanCellsAndFlippedAxesKeepFacesUp) {
    Raster r;
    r.cols = 3;
    r.rows = 3;
    r.x0_m = 0.0;
    r.y0_m = 0.0;
    r.cell_x_m = 1.0;
    r.cell_y_m = 1.0;  // rows go north
    r.z = {0, 0, 0, 0, std::numeric_limits<float>::quiet_NaN(), 0, 0, 0, 0};
    const TriangleMesh m = raster_to_mesh(r);
    EXPECT_EQ(m.vertices.size(), 8u);
    EXPECT_EQ(m.triangle_count(), 2u);  // the centre touches 6 of the 8 triangles
    for (const Face& f : m.faces) {
        EXPECT_GT(normal(m, f).z, 0.0f);
    }
    r.z.pop_back();
    EXPECT_THROW(static_cast<void>(raster_to_mesh(r)), std::invalid_argument);
}

TEST_F(RasterTerrainTest, BrokenAsciiHeadersNameFileAndLine) {
    expect_asc_error("ncols 2\nnrows two\n", "broken.asc:2: 'nrows' must be a positive integer");
    expect_asc_error("ncols 2\nnrows 1\nbogus 3\n", "broken.asc:3: unknown header key 'bogus'");
    expect_asc_error("ncols 2\nnrows\n", "broken.asc:2: no value for header key 'nrows'");
    expect_asc_error("ncols 2 3\n", "broken.asc:1: unexpected text after the value of 'ncols'");
    expect_asc_error("ncols 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n",
                     "broken.asc:5: the header has no 'nrows'");
    expect_asc_error("ncols 2\nnrows 1\nxllcorner 0\nxllcenter 0\nyllcorner 0\ncellsize 1\n1 2\n",
                     "broken.asc:7: the header needs exactly one of 'xllcorner', 'xllcenter'");
    expect_asc_error("ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\n1 2\n",
                     "broken.asc:5: the header has no positive 'cellsize'");
    const std::string header = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
    expect_asc_error(header + "1 2\n3\n", "expected 4 values (2 rows of 2), found only 3");
    expect_asc_error(header + "1 2\n3 4\n5\n", "broken.asc:8: more than the 4 values");
    expect_asc_error(header + "1 2\n3 x4\n", "broken.asc:7: value 3 'x4' is not a number");
    expect_asc_error(header + "1 2\n3 4e99\n", "broken.asc:7: value 3 '4e99'");
}

// ---- hand-written GeoTIFFs ---------------------------------------------------------------

TEST_F(RasterTerrainTest, Int16GeoTiffWithNodata) {
    const Raster r = load_raster(write("small.TIF", small_int16_tiff()));
    ASSERT_EQ(r.cols, 3);
    ASSERT_EQ(r.rows, 2);
    EXPECT_EQ(r.z, (std::vector<float>{1, 2, 3, 4, -9999, 6}));
    EXPECT_EQ(r.x0_m, 1012.5);
    EXPECT_EQ(r.y0_m, 1987.5);
    EXPECT_EQ(r.cell_x_m, 25.0);
    EXPECT_EQ(r.cell_y_m, -25.0);
    ASSERT_TRUE(r.nodata.has_value());
    EXPECT_EQ(*r.nodata, -9999.0f);
    const TriangleMesh m = raster_to_mesh(r, {1000.0, 2000.0, 0.0});
    EXPECT_EQ(m.vertices.size(), 5u);
    ASSERT_EQ(m.triangle_count(), 1u);  // only the top-left triangle avoids the hole
    EXPECT_EQ(m.vertices[m.faces[0][2]], Vec3f(12.5f, -12.5f, 1.0f));
}

TEST_F(RasterTerrainTest, PixelIsPointShiftsByHalfACell) {
    // GeoKeyDirectory: version 1.1.0, one key: GTRasterTypeGeoKey (1025) = RasterPixelIsPoint.
    const Raster r = load_geotiff(
        write("point.tif", small_int16_tiff({shorts(34735, {1, 1, 0, 1, 1025, 0, 1, 2})})));
    EXPECT_EQ(r.x0_m, 1000.0);
    EXPECT_EQ(r.y0_m, 2000.0);
}

TEST_F(RasterTerrainTest, UnsupportedTiffLayoutsNameTheTagValue) {
    test::expect_input_error(load_geotiff, write("rgb.tif", small_int16_tiff({shorts(277, {3})})),
                             "SamplesPerPixel 3");
    test::expect_input_error(load_geotiff, write("half.tif", small_int16_tiff({shorts(339, {3})})),
                             "SampleFormat 3 with BitsPerSample 16");
    test::expect_input_error(load_geotiff, write("junk.tif", "not a tiff at all"),
                             "cannot open as TIFF");
    test::expect_input_error(load_raster, write("grid.xyz", "1 2 3"), "unknown raster format");
    test::expect_input_error(load_raster, dir_ / "missing.tif", "cannot open");
    test::expect_input_error(load_raster, dir_ / "missing.asc", "");
}

// ---- damaged files: refused, or loaded with only what the damage can reach changed ---------

/// What a damaged raster may load as: `anything` well formed (the damage hit the size or the
/// file's structure), or the original but for the parts named here.
struct RasterAllowance {
    bool anything = false;
    bool all_cells = false;
    std::set<std::size_t> cells;
    bool georeferencing = false;
    bool nodata = false;
};

RasterAllowance allow_anything() {
    RasterAllowance may;
    may.anything = true;
    return may;
}

RasterAllowance allow_cells(std::set<std::size_t> cells) {
    RasterAllowance may;
    may.cells = std::move(cells);
    return may;
}

void expect_within(const Raster& got, const Raster& want, const RasterAllowance& may) {
    ASSERT_EQ(got.z.size(),
              static_cast<std::size_t>(got.cols) * static_cast<std::size_t>(got.rows));
    if (may.anything) {
        return;
    }
    ASSERT_EQ(got.cols, want.cols);
    ASSERT_EQ(got.rows, want.rows);
    if (!may.georeferencing) {
        EXPECT_EQ(got.x0_m, want.x0_m);
        EXPECT_EQ(got.y0_m, want.y0_m);
        EXPECT_EQ(got.cell_x_m, want.cell_x_m);
        EXPECT_EQ(got.cell_y_m, want.cell_y_m);
    }
    if (!may.nodata) {
        EXPECT_EQ(got.nodata, want.nodata);
    }
    for (std::size_t i = 0; i < got.z.size() && !may.all_cells; ++i) {
        EXPECT_TRUE(may.cells.contains(i) || got.z[i] == want.z[i]) << "cell " << i << " changed";
    }
}

/// What a change to tag `tag`'s entry (but its tag number) or data can reach.
RasterAllowance tiff_tag_allowance(std::uint16_t tag) {
    RasterAllowance may;
    may.anything = tag == 256 || tag == 257;  // ImageWidth, ImageLength
    may.georeferencing = tag == 33550 || tag == 33922 || tag == 34264 || tag == 34735;
    may.nodata = tag == 42113;
    may.all_cells = !may.anything && !may.georeferencing && !may.nodata;  // layout tags
    return may;
}

template <typename T>
T le_at(const std::string& bytes, std::size_t offset) {
    T v{};
    std::memcpy(&v, bytes.data() + offset, sizeof v);
    return v;
}

/// What a flip at `offset` of `tiff` (as make_tiff writes it: little endian, one IFD, one strip of
/// int16 samples) can reach, from the file's own IFD: the 8-byte header, the entry count and an
/// entry's tag number anything; the rest of an entry or its out-of-line data that tag's part of
/// the raster; a sample its cell; anything else (the next-IFD offset) nothing.
RasterAllowance tiff_allowance(const std::string& tiff, std::size_t offset) {
    const auto ifd = le_at<std::uint32_t>(tiff, 4);
    const auto entries = le_at<std::uint16_t>(tiff, ifd);
    if (offset < 8 || (offset >= ifd && offset < ifd + 2)) {
        return allow_anything();
    }
    for (std::size_t e = 0; e < entries; ++e) {
        const std::size_t at = ifd + 2 + 12 * e;
        const auto tag = le_at<std::uint16_t>(tiff, at);
        const auto type = le_at<std::uint16_t>(tiff, at + 2);
        const std::size_t size = le_at<std::uint32_t>(tiff, at + 4) * std::size_t{type == 12  ? 8u
                                                                                  : type == 4 ? 4u
                                                                                  : type == 3 ? 2u
                                                                                              : 1u};
        const std::size_t data = size <= 4 ? at + 8 : le_at<std::uint32_t>(tiff, at + 8);
        if (offset >= at && offset < at + 2) {
            return allow_anything();
        }
        if ((offset >= at && offset < at + 12) || (offset >= data && offset < data + size)) {
            return tiff_tag_allowance(tag);
        }
        if (tag == 273) {  // StripOffsets: the samples, 2 bytes each
            const std::size_t strip = le_at<std::uint32_t>(tiff, at + 8);
            if (offset >= strip && offset < strip + 12) {
                return allow_cells({(offset - strip) / 2});
            }
        }
    }
    return {};
}

/// A one-strip int16 TIFF of `pixels` whose header claims `width` x `height` cells.
[[nodiscard]] std::string tiff_claiming(std::uint32_t width, std::uint32_t height,
                                        const std::string& pixels) {
    return make_tiff(
        {shorts(258, {16}), shorts(259, {1}), shorts(262, {1}), shorts(277, {1}), shorts(339, {2})},
        width, height, pixels);
}

TEST_F(RasterTerrainTest, TiffClaimingMoreCellsThanTheFileOrTheLimitIsRefusedUpFront) {
    const std::string pixels(12, '\1');
    // 65536 x 65536 int16 cells (8 GiB, 16 GiB as floats) claimed by a 124-byte file.
    const std::string huge = tiff_claiming(65536, 65536, pixels);
    EXPECT_LT(huge.size(), 200u);
    test::expect_input_error(load_geotiff, write("huge.tif", huge),
                             "ImageWidth x ImageLength = 65536 x 65536 = 4294967296 cells is "
                             "above the limit of 268435456 cells per raster");
    // Under the limit, but 10000 x 10000 uncompressed samples cannot lie in the file (libtiff
    // cuts the single strip into strips of a row, the first of which already runs past the end).
    test::expect_input_error(load_geotiff, write("big.tif", tiff_claiming(10000, 10000, pixels)),
                             "strip 0: its 20000 bytes at byte 8 lie outside the file (146 bytes)");
    // A strip that lies past the end of the file.
    std::string cut = small_int16_tiff();
    const auto ifd = le_at<std::uint32_t>(cut, 4);
    const auto entries = le_at<std::uint16_t>(cut, ifd);
    for (std::size_t e = 0; e < entries; ++e) {
        if (le_at<std::uint16_t>(cut, ifd + 2 + 12 * e) == 273) {
            const std::uint32_t past = static_cast<std::uint32_t>(cut.size()) - 4;
            std::memcpy(cut.data() + ifd + 2 + 12 * e + 8, &past, 4);
        }
    }
    test::expect_input_error(load_geotiff, write("past.tif", cut), "lie outside the file");
    // A tile far larger than the raster: its buffer is not allocated.
    const std::vector<TiffEntry> int16{shorts(258, {16}), shorts(259, {1}), shorts(262, {1}),
                                       shorts(277, {1}), shorts(339, {2})};
    test::expect_input_error(
        load_geotiff, write("tile.tif", make_tiff(int16, 3, 2, pixels, {{65536, 65536}})),
        "TileWidth x TileLength = 65536 x 65536 is larger than the raster (3 x 2) and than "
        "1048576 cells");
    const Raster tiled = load_geotiff(
        write("tiled.tif", make_tiff(int16, 3, 2, std::string(512, '\1'), {{16, 16}})));
    EXPECT_EQ(tiled.z, std::vector<float>(6, 257.0f));
    // The same header over samples the file holds loads.
    EXPECT_EQ(load_geotiff(write("ok.tif", tiff_claiming(3, 2, pixels))).z.size(), 6u);
}

TEST_F(RasterTerrainTest, AsciiGridClaimingMoreCellsThanTheFileOrTheLimitIsRefusedUpFront) {
    // 61 bytes claiming 65536 x 65536 cells.
    const std::string huge = "ncols 65536\nnrows 65536\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n";
    EXPECT_EQ(huge.size(), 61u);
    expect_asc_error(huge,
                     "broken.asc:6: ncols x nrows = 4294967296 cells is above the limit of "
                     "268435456 cells per raster");
    expect_asc_error("ncols 10000\nnrows 10000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n",
                     "ncols x nrows = 100000000 values cannot fit in the 6 bytes after the header");
}

TEST_F(RasterTerrainTest, TruncatedTiffsAreRefused) {
    const std::string tiff = small_int16_tiff();
    const auto path = dir_ / "cut.tif";
    // Every byte of the fixture is header, samples, IFD or tag data: no cut may load.
    test::check_every_truncation(
        tiff, [&](const std::string& bytes) { return load_geotiff(test::write_file(path, bytes)); },
        [](const Raster&, std::size_t) { ADD_FAILURE() << "a truncated TIFF loaded"; });
    // Cut in the GDAL_NODATA text, the last tag data: libtiff drops the tag with only a warning.
    test::expect_input_error(load_geotiff, test::write_file(path, tiff.substr(0, tiff.size() - 1)),
                             "a tag's data runs past the end of the file");
}

TEST_F(RasterTerrainTest, TiffByteFlipsAreRefusedOrChangeOnlyWhatTheyHit) {
    const std::string tiff = small_int16_tiff();
    const auto path = dir_ / "flip.tif";
    const auto load = [&](const std::string& bytes) {
        return load_geotiff(test::write_file(path, bytes));
    };
    const Raster want = load(tiff);
    std::mt19937 rng(11);
    // 2000 flips, about a second: a flipped ImageWidth or ImageLength byte is refused before
    // anything is allocated (the samples must lie in the file), so none allocates gigabytes.
    test::check_random_byte_flips(tiff, rng, 2000, load,
                                  [&](const Raster& got, const test::ByteFlip& flip) {
                                      expect_within(got, want, tiff_allowance(tiff, flip.offset));
                                  });
}

constexpr std::string_view kSmallGrid =
    "ncols 3\nnrows 2\nxllcorner 100\nyllcorner 200\ncellsize 10\nNODATA_value -9999\n"
    "1.5 2 -3\n4 -9999 16.25\n";

TEST_F(RasterTerrainTest, TruncatedAsciiGridsAreRefusedButForAShortenedLastValue) {
    const std::string grid(kSmallGrid);
    const auto path = dir_ / "cut.asc";
    const auto load = [&](const std::string& bytes) {
        return load_esri_ascii_grid(test::write_file(path, bytes));
    };
    const Raster want = load(grid);
    // The format has no length: a cut inside the last value leaves a shorter number, which no
    // reader can tell from a real one ("16.25" cut to "16.2"). Any other cut loses values.
    const std::size_t last = grid.rfind(' ') + 1, end = grid.size() - 1;
    test::check_every_truncation(grid, load, [&](const Raster& got, std::size_t n) {
        ASSERT_GT(n, last) << "a grid missing values loaded";
        RasterAllowance may;
        if (n < end) {
            may.cells = {5};
            ASSERT_EQ(got.z.size(), 6u);
            EXPECT_EQ(got.z[5], std::stof(grid.substr(last, n - last)));
        }
        expect_within(got, want, may);
    });
}

/// What a flip at `offset` of kSmallGrid can reach: a header key anything; the rest of a
/// header line that key's part; a value its cell, the blank after it also the next cell.
RasterAllowance grid_allowance(std::size_t offset) {
    const std::string_view g = kSmallGrid;
    const std::size_t data = g.find("1.5");
    if (offset < data) {
        const std::size_t line = g.rfind('\n', offset - (g[offset] == '\n' ? 1 : 0));
        const std::size_t begin = line == std::string_view::npos ? 0 : line + 1;
        const std::string_view key = g.substr(begin, g.find(' ', begin) - begin);
        if (offset < begin + key.size() || key == "ncols" || key == "nrows") {
            return allow_anything();
        }
        RasterAllowance may;
        (key == "NODATA_value" ? may.nodata : may.georeferencing) = true;
        return may;
    }
    std::size_t cell = 0;
    for (std::size_t i = data; i < offset; ++i) {
        cell += (g[i] == ' ' || g[i] == '\n') ? 1 : 0;
    }
    const bool blank = g[offset] == ' ' || g[offset] == '\n';
    return blank ? allow_cells({cell, cell + 1}) : allow_cells({cell});
}

TEST_F(RasterTerrainTest, AsciiGridByteFlipsAreRefusedOrChangeOnlyWhatTheyHit) {
    const std::string grid(kSmallGrid);
    const auto path = dir_ / "flip.asc";
    const auto load = [&](const std::string& bytes) {
        return load_esri_ascii_grid(test::write_file(path, bytes));
    };
    const Raster want = load(grid);
    std::mt19937 rng(13);
    test::check_every_byte_flip(grid, rng, 4, load,
                                [&](const Raster& got, const test::ByteFlip& flip) {
                                    expect_within(got, want, grid_allowance(flip.offset));
                                });
}

}  // namespace
}  // namespace beamtrace
