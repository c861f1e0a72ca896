#include "beamtrace/heightfield/las_ingest.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/heightfield/view_session.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "heightfield/child_peak_rss.hpp"
#include "heightfield/heightfield_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

LasPoint point(double x, double y, double z, std::uint16_t r = 0, std::uint16_t g = 0,
               std::uint16_t b = 0) {
    LasPoint p;
    p.x = x;
    p.y = y;
    p.z = z;
    p.red = r;
    p.green = g;
    p.blue = b;
    p.return_number = 1;
    p.number_of_returns = 1;
    p.intensity = static_cast<std::uint16_t>(z * 100);
    p.classification = 2;
    return p;
}

std::filesystem::path write_las(const std::filesystem::path& path,
                                const std::vector<LasPoint>& points) {
    return test::write_test_las(path, points, 7);
}

ViewSessionConfig small_session(ColorMode color = ColorMode::height) {
    ViewSessionConfig c;
    c.field.cell_size = 1.0;
    c.field.levels = 3;
    c.field.section_cells = 4;  // 16 m sections
    c.field.sections = 2;
    c.field.color = color;
    c.ingest.block_bytes = 100;  // a few points per block: exercises the block loop
    c.threads = 2;
    return c;
}

class ViewIngest : public test::TempDirTest {};

TEST_F(ViewIngest, OnePassOverManyFilesFillsEverySectionWithTheMaxHeightAndItsColour) {
    // Origin is the lower corner of all headers: (0.5, 0.2, 1).
    const auto a = write_las(dir_ / "a.las",
                             {point(0.5, 0.5, 1.0, 65535, 0, 0), point(0.7, 0.2, 3.0, 0, 65535, 0),
                              point(0.9, 0.9, 2.0, 0, 0, 65535)});
    const auto b =
        write_las(dir_ / "b.las", {point(20.5, 17.5, 5.0, 256, 512, 768), point(31.5, 31.5, 4.0)});
    const std::vector<std::filesystem::path> inputs = {a, b};
    ViewSession session(inputs, small_session(ColorMode::rgb));
    const IngestStats stats = session.move_to({16.0, 16.0, 50.0});
    EXPECT_EQ(stats.points_read, 5u);
    EXPECT_EQ(stats.points_inserted, 5u);
    EXPECT_EQ(stats.points_outside_header, 0u);
    const SectionGrid& g = session.grid();
    EXPECT_EQ(g.loaded_sections(), 2);  // the two sections that no file's bounds touch stay free
    EXPECT_EQ(g.window_first_x(), 0);
    EXPECT_FLOAT_EQ(g.height(0, 0, 0), 2.0f);  // 3.0 - origin z 1.0
    EXPECT_EQ(g.attribute(0, 0), pack_rgb8(0, 255, 0));
    EXPECT_FLOAT_EQ(g.height(0, 20, 17), 4.0f);
    EXPECT_EQ(g.attribute(20, 17), pack_rgb8(1, 2, 3));  // 16-bit colours: high bytes
    EXPECT_EQ(g.height(0, 1, 0), kEmptyHeight);
    EXPECT_FLOAT_EQ(g.height(2, 0, 0), 2.0f);  // coarsest level = max of its block
    EXPECT_FLOAT_EQ(g.max_height(), 4.0f);
    // Nothing new to load when the camera stays.
    EXPECT_EQ(session.move_to({16.5, 15.0, 50.0}).points_read, 0u);
}

TEST_F(ViewIngest, PointsOutsideTheHeaderBoundsAreReported) {
    const auto path = write_las(dir_ / "out.las", {point(1, 1, 1), point(5, 5, 2), point(9, 9, 3)});
    // Shrink the header's max x (offset 179) to 6: one point lies outside.
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    const double max_x = 6.0;
    f.seekp(179);
    f.write(reinterpret_cast<const char*>(&max_x), sizeof max_x);
    f.close();
    const std::vector<std::filesystem::path> inputs = {path};
    ViewSession session(inputs, small_session());
    const IngestStats stats = session.move_to({5.0, 5.0, 20.0});
    EXPECT_EQ(stats.points_outside_header, 1u);
    ASSERT_EQ(stats.warnings.size(), 1u);
    EXPECT_NE(stats.warnings[0].find("outside the header bounds"), std::string::npos);
    EXPECT_NE(stats.warnings[0].find(path.string()), std::string::npos);
}

TEST_F(ViewIngest, PointsNotShownAreCountedByWhyTheyAreNot) {
    // Origin (1, 1): 16 m sections; the camera at (17, 17) centres a 2x2 window on sections
    // (0, 0) to (1, 1), all four touching the header's bounds; the budget holds one section (the
    // nearest, slot 0), and (40, 40) lies beyond the window.
    const auto path = write_las(
        dir_ / "three.las", {point(1, 1, 1), point(20, 20, 2), point(21, 22, 2), point(40, 40, 3)});
    ViewSessionConfig config = small_session();
    config.field.memory_budget_bytes = config.field.section_bytes() + config.ingest.block_bytes;
    const std::vector<std::filesystem::path> inputs = {path};
    ViewSession session(inputs, config);
    const IngestStats stats = session.move_to({17.0, 17.0, 50.0});
    EXPECT_EQ(stats.points_read, 4u);
    EXPECT_EQ(stats.points_inserted, 1u);
    const std::string why = session.not_shown_reason();
    EXPECT_NE(why.find("beyond the window of 2x2 sections of 16 units"), std::string::npos) << why;
    EXPECT_NE(why.find("holds 1 of the 4 sections with data"), std::string::npos) << why;
    // A budget that holds the window: only the window is the reason.
    ViewSession all(inputs, small_session());
    EXPECT_EQ(all.move_to({17.0, 17.0, 50.0}).points_inserted, 3u);
    EXPECT_NE(all.not_shown_reason().find("beyond the window"), std::string::npos);
    EXPECT_EQ(all.not_shown_reason().find("memory budget"), std::string::npos);
}

TEST_F(ViewIngest, PointsOnTheLowestHeaderBoundAreShown) {
    // autzen.las: offset 0, scale 0.01; its lowest y (848977.79, the grid's origin) rounds to
    // cell -1 in floor(raw * scale / cell + (offset - origin) / cell).
    const auto path = test::shared_data("las/las/autzen.las");
    BEAMTRACE_REQUIRE_FILE(path);
    for (const double cell : {0.0, 0.5}) {  // from the density (1000 units), and fine
        ViewSessionConfig config;
        config.field.cell_size = cell;
        config.threads = 2;
        const std::vector<std::filesystem::path> inputs = {path};
        ViewSession session(inputs, config);
        const Vec3d lo = session.sources().min(), hi = session.sources().max();
        const IngestStats stats =
            session.move_to({0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), hi.z + 100});
        EXPECT_EQ(stats.points_read, 106u) << cell;
        EXPECT_EQ(stats.points_inserted, 106u) << cell;
        EXPECT_EQ(session.not_shown_reason(), "") << cell;
    }
}

TEST_F(ViewIngest, FilesWithoutPointsGiveAWarningAndAnEmptyView) {
    const auto empty = write_las(dir_ / "empty.las", {});
    const std::vector<std::filesystem::path> inputs = {empty};
    ViewSession session(inputs, small_session());
    ASSERT_EQ(session.sources().warnings().size(), 1u);
    EXPECT_NE(session.sources().warnings()[0].find("no points"), std::string::npos);
    EXPECT_EQ(session.move_to({0, 0, 10}).points_read, 0u);
    ViewCamera cam;
    cam.width = 16;
    cam.height = 9;
    cam.pitch_deg = -90;
    EXPECT_EQ(session.render(cam, {}).hits(), 0u);
}

TEST_F(ViewIngest, DirectoriesAreReadInNameOrder) {
    write_las(dir_ / "b.las", {point(2, 2, 2)});
    write_las(dir_ / "a.las", {point(1, 1, 1)});
    test::write_file(dir_ / "notes.txt", "not a LAS file");
    const std::vector<std::filesystem::path> inputs = {dir_.path()};
    const LasSourceSet set(inputs);
    ASSERT_EQ(set.files().size(), 2u);
    EXPECT_EQ(set.files()[0].path.filename(), "a.las");
    EXPECT_EQ(set.point_count(), 2u);
    const std::vector<std::filesystem::path> none = {dir_ / "nothing"};
    std::filesystem::create_directories(dir_ / "nothing");
    test::expect_input_error([&](const auto&) { return LasSourceSet(none); }, dir_ / "nothing",
                             "no .las files");
}

TEST_F(ViewIngest, BrokenFilesGiveAnInputErrorNamingThem) {
    const auto bad = test::write_file(dir_ / "bad.las", "LASF but far too short");
    const std::vector<std::filesystem::path> inputs = {bad};
    test::expect_input_error([&](const auto&) { return LasSourceSet(inputs); }, bad);
    const std::vector<std::filesystem::path> missing = {dir_ / "missing.las"};
    test::expect_input_error([&](const auto&) { return LasSourceSet(missing); },
                             dir_ / "missing.las", "cannot open");
}

TEST(ViewEdgeFiles, EveryEdgeFileGivesAClearErrorOrAView) {
    const auto edge = test::shared_data("las/edge");
    BEAMTRACE_REQUIRE_FILE(edge);
    int opened = 0, rejected = 0;
    for (const auto& entry : std::filesystem::directory_iterator(edge)) {
        const std::vector<std::filesystem::path> inputs = {entry.path()};
        SCOPED_TRACE(entry.path().string());
        try {
            ViewSessionConfig config;
            config.field.levels = 4;
            config.field.section_cells = 8;
            config.threads = 1;
            ViewSession session(inputs, config);
            const Vec3d c = (session.sources().min() + session.sources().max()) * 0.5;
            static_cast<void>(session.move_to(c));
            ViewCamera cam;
            cam.position = {c.x, c.y, session.sources().max().z + 100};
            cam.pitch_deg = -90;
            cam.width = 32;
            cam.height = 18;
            static_cast<void>(session.render(cam, {}));
            ++opened;
        } catch (const InputError& e) {
            EXPECT_EQ(e.path(), entry.path().string()) << e.what();
            ++rejected;
        }
    }
    EXPECT_GT(opened, 0);
    EXPECT_GT(rejected, 0);  // the LAZ files at least
}

TEST_F(ViewIngest, MemoryBudgetKeepsOnlyTheNearestSectionsResident) {
    // Points spread over all four sections of a 2 x 2 window of 16 m sections.
    std::vector<LasPoint> points;
    for (int y = 0; y < 32; ++y) {
        for (int x = 0; x < 32; ++x) {
            points.push_back(point(x + 0.5, y + 0.5, 1.0 + 0.01 * (x + y)));
        }
    }
    const auto path = write_las(dir_ / "grid.las", points);
    const std::vector<std::filesystem::path> inputs = {path};
    ViewSessionConfig config = small_session();
    const std::size_t each = HeightSection::bytes_for(config.field.layout(), false);
    config.field.memory_budget_bytes = 2 * each + config.ingest.block_bytes;
    ViewSession session(inputs, config);
    static_cast<void>(session.move_to({12.0, 12.0, 30.0}));  // nearest: slot 0, then 1 and 2 (tie)
    const SectionGrid& g = session.grid();
    EXPECT_EQ(g.resident_sections(), 2);
    EXPECT_LE(session.budgeted_bytes(), config.field.memory_budget_bytes);
    EXPECT_NE(g.slot(0), nullptr);
    EXPECT_NE(g.slot(1), nullptr);
    EXPECT_EQ(g.slot(3), nullptr);
    EXPECT_EQ(g.height(0, 20, 20), kEmptyHeight);  // not resident: empty
    EXPECT_NE(g.height(0, 20, 4), kEmptyHeight);
    // Moving to the far corner swaps which sections are resident, within the budget.
    static_cast<void>(session.move_to({20.0, 20.0, 30.0}));
    EXPECT_EQ(g.resident_sections(), 2);
    EXPECT_LE(session.budgeted_bytes(), config.field.memory_budget_bytes);
    EXPECT_NE(g.height(0, 20, 20), kEmptyHeight);
}

#ifndef BEAMTRACE_SANITIZED  // AddressSanitizer's shadow memory and quarantine swamp the RSS
/// One `beamtrace view` run as a child: its peak RSS and the sections it reports loaded.
struct ViewRun {
    std::size_t peak_rss_bytes = 0;
    int sections = -1;
};

ViewRun run_view_cli(const std::filesystem::path& las, const std::filesystem::path& dir,
                     const std::string& budget, int levels, int section_cells) {
    const std::filesystem::path log = dir / "view.log";
    const test::ChildPeak peak = test::run_measuring_peak_rss({BEAMTRACE_CLI_PATH,
                                                               "view",
                                                               las.string(),
                                                               "--cell-size",
                                                               "1",
                                                               "--levels",
                                                               std::to_string(levels),
                                                               "--section-cells",
                                                               std::to_string(section_cells),
                                                               "--sections",
                                                               "4x4",
                                                               "--memory-budget",
                                                               budget,
                                                               "--camera",
                                                               "2048,2048,600,0,-90",
                                                               "--size",
                                                               "64x36",
                                                               "--threads",
                                                               "2",
                                                               "--output",
                                                               (dir / "view.png").string()},
                                                              log);
    const std::string out = test::read_file(log);
    EXPECT_EQ(peak.exit_code, 0) << out;
    EXPECT_TRUE(peak.error.empty()) << peak.error;
    ViewRun run;
    run.peak_rss_bytes = peak.peak_rss_bytes;
    std::smatch m;
    if (std::regex_search(out, m, std::regex("loaded ([0-9]+) sections"))) {
        run.sections = std::stoi(m[1]);
    }
    return run;
}

TEST_F(ViewIngest, MeasuredPeakRssOfTheCliStaysWithinTheMemoryBudget) {
    // The accounting above (budgeted_bytes) is the code's own; here the kernel measures the
    // CLI. One point every 16 m over 4 x 4 km: every section of a 4 x 4 window of 1 km
    // sections (1024^2 cells of 1 m, 6 levels: 5.6 MB each, 89 MB for all 16) has data, so the
    // budget alone decides how many are resident.
    std::vector<LasPoint> points;
    for (int y = 0; y < 256; ++y) {
        for (int x = 0; x < 256; ++x) {
            points.push_back(point(16.0 * x + 8.0, 16.0 * y + 8.0, 1.0 + 0.01 * ((x + y) % 50)));
        }
    }
    const auto las = write_las(dir_ / "wide.las", points);
    // The fixed cost of the process (the program and its libraries, the thread pool, the read
    // buffer, the image): the same file and image with sections of one cell.
    const ViewRun fixed = run_view_cli(las, dir_.path(), "64MB", 1, 1);
    const ViewRun small = run_view_cli(las, dir_.path(), "24MB", 6, 32);
    const ViewRun large = run_view_cli(las, dir_.path(), "120MB", 6, 32);
    const std::size_t each = HeightSection::bytes_for(SectionLayout{32, 6}, false);
    std::printf(
        "[ rss      ] fixed %.1f MB; budget 24 MB: %d sections, peak %.1f MB; budget "
        "120 MB: %d sections, peak %.1f MB (%.2f MB a section)\n",
        static_cast<double>(fixed.peak_rss_bytes) / 1e6, small.sections,
        static_cast<double>(small.peak_rss_bytes) / 1e6, large.sections,
        static_cast<double>(large.peak_rss_bytes) / 1e6, static_cast<double>(each) / 1e6);
    ASSERT_GT(fixed.peak_rss_bytes, 0u);
    EXPECT_LT(fixed.peak_rss_bytes, std::size_t{64} << 20) << "the fixed cost alone";
    // Under budget + the fixed cost + 4 MB of slack (allocator pages, the section pyramid
    // above the sections' levels, stacks of the loader thread).
    const std::size_t slack = std::size_t{4} << 20;
    EXPECT_LE(small.peak_rss_bytes, fixed.peak_rss_bytes + 24'000'000 + slack);
    EXPECT_LE(large.peak_rss_bytes, fixed.peak_rss_bytes + 120'000'000 + slack);
    // And the budget is what limits it: the larger one holds all 16 sections, and the memory
    // they take is there, at least 90 % of their size more than with the small budget.
    EXPECT_EQ(large.sections, 16);
    EXPECT_LT(small.sections, 5);
    EXPECT_GE(large.peak_rss_bytes,
              small.peak_rss_bytes + static_cast<std::size_t>(16 - small.sections) * each * 9 / 10);
}
#endif

TEST_F(ViewIngest, BudgetTooSmallForOneSectionIsAConfigError) {
    const auto path = write_las(dir_ / "one.las", {point(1, 1, 1)});
    const std::vector<std::filesystem::path> inputs = {path};
    ViewSessionConfig config = small_session();
    config.field.memory_budget_bytes = 100;
    EXPECT_THROW(ViewSession(inputs, config), ConfigError);
}

}  // namespace
}  // namespace beamtrace
