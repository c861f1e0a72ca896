// Height-field views of raw LAS files: ingest rate (points/s) and frame time at 1920x1080 for the
// section shapes of the thesis's Table 4.1 (16x16/8, 32x32/8, 64x64/8) on autzen_trim.las.
// Results are checked (hierarchical == brute-force reference, most pixels hit) before timing.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "beamtrace/heightfield/las_sources.hpp"
#include "beamtrace/heightfield/view_session.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/io/las_writer.hpp"

namespace bt = beamtrace;

namespace {

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "benchmark check failed: %s\n", what.c_str());
    std::exit(1);
}

std::filesystem::path autzen_trim() {
    return std::filesystem::path(BEAMTRACE_SHARED_DATA_DIR) / "las/las/autzen_trim.las";
}

/// autzen_trim.las tiled 8 x 8 times (7 M points, 250 MB, point format 7), written once into
/// the temporary folder: the ingest benchmark's large input.
const std::filesystem::path& tiled_autzen() {
    static const std::filesystem::path path = [] {
        const auto out = std::filesystem::temp_directory_path() / "beamtrace-bench-autzen-8x8.las";
        if (std::filesystem::exists(out)) {
            return out;
        }
        const std::vector<bt::LasPoint> points = bt::read_las_points(autzen_trim());
        bt::LasReader reader(autzen_trim());
        const bt::LasHeader& h = reader.header();
        const double w = h.max.x - h.min.x, d = h.max.y - h.min.y;
        bt::LasWriterConfig config =
            bt::las_config_for_extent(h.min, {h.min.x + 8 * w, h.min.y + 8 * d, h.max.z}, 0.01);
        config.point_format = 7;
        bt::LasWriter writer(out, config);
        std::vector<bt::LasPoint> tile = points;
        for (int j = 0; j < 8; ++j) {
            for (int i = 0; i < 8; ++i) {
                for (std::size_t k = 0; k < points.size(); ++k) {
                    tile[k].x = points[k].x + i * w;
                    tile[k].y = points[k].y + j * d;
                    tile[k].return_number = std::max<std::uint8_t>(1, points[k].return_number);
                    tile[k].number_of_returns =
                        std::max(tile[k].return_number, points[k].number_of_returns);
                }
                writer.write(tile);
            }
        }
        writer.close();
        return out;
    }();
    return path;
}

bt::ViewSessionConfig session_config(int section_cells, int levels, double cell_size) {
    bt::ViewSessionConfig c;
    c.field.cell_size = cell_size;
    c.field.section_cells = section_cells;
    c.field.levels = levels;
    c.field.sections = 4;
    c.field.memory_budget_bytes = std::uint64_t{3} << 30;
    c.field.color = bt::ColorMode::rgb;
    c.threads = std::thread::hardware_concurrency();
    return c;
}

/// Ingest: every point of the file into a 4x4 window of 16x16/7 sections covering it all.
void BM_ViewIngest(benchmark::State& state, int which) {
    const std::filesystem::path path = which == 0 ? autzen_trim() : tiled_autzen();
    if (!std::filesystem::exists(path)) {
        state.SkipWithError("missing input");
        return;
    }
    const std::vector<std::filesystem::path> inputs = {path};
    const double cell = which == 0 ? 1.0 : 4.0;
    std::uint64_t points = 0;
    for (auto _ : state) {
        state.PauseTiming();
        auto session = std::make_unique<bt::ViewSession>(inputs, session_config(16, 7, cell));
        const bt::Vec3d c = (session->sources().min() + session->sources().max()) * 0.5;
        state.ResumeTiming();
        const bt::IngestStats s = session->move_to(c);
        if (s.points_read != session->sources().point_count() || s.points_inserted == 0) {
            fail("ingest read " + std::to_string(s.points_read) + " points");
        }
        points += s.points_read;
        state.PauseTiming();
        session.reset();
        state.ResumeTiming();
    }
    state.counters["points/s"] =
        benchmark::Counter(static_cast<double>(points), benchmark::Counter::kIsRate);
}

/// A view over autzen_trim: 150 ft above its highest point, looking 30 degrees down.
bt::ViewCamera frame_camera(const bt::ViewSession& s, int width, int height) {
    bt::ViewCamera cam;
    const bt::Vec3d lo = s.sources().min(), hi = s.sources().max();
    cam.position = {lo.x + 0.2 * (hi.x - lo.x), lo.y + 0.2 * (hi.y - lo.y), hi.z + 150.0};
    cam.yaw_deg = -25.0;  // towards +x, +y (docs/camera.md)
    cam.pitch_deg = -30.0;
    cam.hfov_deg = 70.0;
    cam.width = width;
    cam.height = height;
    return cam;
}

/// Checks, before timing, that the hierarchy agrees with the brute-force reference on a small
/// image of the benchmark's view and that most pixels hit.
void check_against_reference(bt::ViewSession& session, const bt::RenderOptions& options,
                             const std::string& what) {
    const bt::ViewCamera small = frame_camera(session, 192, 108);
    const bt::ViewImage a = session.render(small, options);
    const bt::ViewImage b =
        bt::render_view_reference(session.grid(), small, options, session.pool());
    if (a.rgb != b.rgb || a.depth != b.depth) {
        fail("hierarchical and reference views differ" + what);
    }
    if (a.hits() < a.depth.size() / 2) {
        fail("fewer than half the pixels hit" + what);
    }
}

/// Loads the benchmark's 1920x1080 view, checks it against the reference, then times frames
/// rendered into one reused image (as a viewer would).
void time_frames(benchmark::State& state, bt::ViewSession& session, const std::string& what,
                 int simd_lanes = 0) {
    const bt::ViewCamera cam = frame_camera(session, 1920, 1080);
    static_cast<void>(session.move_to(cam.position));
    bt::RenderOptions options;
    options.fog_distance = 3000.0;
    options.simd_lanes = simd_lanes;
    check_against_reference(session, options, what);
    bt::ViewImage img;
    // The process's CPU time (every thread's) over the loop's wall time: about the threads the
    // frames ran on. Under 2 at threads:0 on 2 cores, something else took a core: with the
    // kernel's autogroups a nice'd process of another session still gets its group's full share.
    const std::clock_t cpu0 = std::clock();
    const auto wall0 = std::chrono::steady_clock::now();
    for (auto _ : state) {
        session.render(cam, options, img);
        benchmark::DoNotOptimize(img.rgb.data());
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    const double cpu = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    state.counters["cores"] = wall > 0.0 ? cpu / wall : 0.0;
    state.counters["fps"] =
        benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
    state.counters["resident_MB"] = static_cast<double>(session.budgeted_bytes()) / 1e6;
}

void BM_ViewFrame(benchmark::State& state) {
    if (!std::filesystem::exists(autzen_trim())) {
        state.SkipWithError("missing autzen_trim.las");
        return;
    }
    const std::vector<std::filesystem::path> inputs = {autzen_trim()};
    const auto cells = static_cast<int>(state.range(0));
    const auto levels = static_cast<int>(state.range(1));
    bt::ViewSessionConfig config = session_config(cells, levels, 1.0);
    if (state.range(2) > 0) {
        config.threads = static_cast<unsigned>(state.range(2));
    }
    bt::ViewSession session(inputs, config);
    time_frames(state, session, "", static_cast<int>(state.range(3)));
}

/// A fly-through of 16 poses across the 8 x 8 tiled autzen (7 M points, so every section load is
/// a 250 MB pass over the file) at 960x540, 8/7 sections at 2 ft (1024 ft; the 4 x 4 window moves
/// by a column about every other frame), a budget of 20 sections (the window and one column
/// more). prefetch:1 loads the next pose's sections on the loader thread while the current
/// frame renders; prefetch:0 loads them when the frame is due. The frames are the same (checked
/// before timing).
void BM_ViewPath(benchmark::State& state) {
    const std::filesystem::path& path = tiled_autzen();
    const std::vector<std::filesystem::path> inputs = {path};
    const bool prefetch = state.range(0) != 0;
    bt::ViewSessionConfig config = session_config(8, 7, 2.0);
    config.field.memory_budget_bytes =
        config.ingest.block_bytes + 20 * config.field.section_bytes();
    std::vector<bt::ViewCamera> cams;
    {
        const bt::LasSourceSet sources(inputs);
        const bt::Vec3d lo = sources.min(), hi = sources.max();
        for (int i = 0; i < 16; ++i) {
            bt::ViewCamera cam;
            const double f = 0.1 + 0.8 * i / 15.0;
            cam.position = {lo.x + f * (hi.x - lo.x), lo.y + 0.5 * (hi.y - lo.y), hi.z + 150.0};
            cam.yaw_deg = -10.0;
            cam.pitch_deg = -35.0;
            cam.hfov_deg = 70.0;
            cam.width = 960;
            cam.height = 540;
            cams.push_back(cam);
        }
    }
    const auto run_path = [&](bool with_prefetch, std::vector<bt::ViewImage>* frames) {
        bt::ViewSession session(inputs, config);
        bt::ViewImage img;
        int prefetched = 0;
        for (std::size_t i = 0; i < cams.size(); ++i) {
            prefetched += session.move_to(cams[i].position).sections_prefetched;
            if (with_prefetch && i + 1 < cams.size()) {
                session.prefetch(cams[i + 1].position);
            }
            session.render(cams[i], {}, img);
            if (frames != nullptr) {
                frames->push_back(img);
            }
        }
        if (session.peak_budgeted_bytes() > config.field.memory_budget_bytes) {
            fail("path went over the memory budget");
        }
        return prefetched;
    };
    {
        std::vector<bt::ViewImage> a, b;
        static_cast<void>(run_path(false, &a));
        const int prefetched = run_path(true, &b);
        for (std::size_t i = 0; i < a.size(); ++i) {
            if (a[i].rgb != b[i].rgb || a[i].depth != b[i].depth) {
                fail("prefetched frame " + std::to_string(i) + " differs");
            }
        }
        if (prefetched == 0) {
            fail("nothing was prefetched");
        }
        state.counters["prefetched_sections"] = prefetched;
    }
    for (auto _ : state) {
        benchmark::DoNotOptimize(run_path(prefetch, nullptr));
    }
    state.counters["frames/s"] = benchmark::Counter(
        static_cast<double>(state.iterations() * cams.size()), benchmark::Counter::kIsRate);
}

/// The cost of height stacks: the BM_ViewFrame view at 32/8 with up to 3 intervals per cell.
void BM_ViewFrameStacks(benchmark::State& state) {
    if (!std::filesystem::exists(autzen_trim())) {
        state.SkipWithError("missing autzen_trim.las");
        return;
    }
    const std::vector<std::filesystem::path> inputs = {autzen_trim()};
    bt::ViewSessionConfig config = session_config(32, 8, 1.0);
    config.field.height_stacks = static_cast<int>(state.range(0));
    bt::ViewSession session(inputs, config);
    time_frames(state, session, " with stacks");
}

}  // namespace

BENCHMARK_CAPTURE(BM_ViewIngest, autzen_trim, 0)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ViewIngest, autzen_8x8_tiled, 1)->Unit(benchmark::kMillisecond)->UseRealTime();
// threads:0 = every core; threads:1 makes the CPU time the whole work of a frame (comparable
// between runs on a loaded machine). lanes: rays traced together in SIMD lanes (0 = the most
// the CPU has: 8 with AVX-512, 4 with AVX2; 4 and 1 are the baselines of the same run;
// threads:1/lanes:4 is the AVX2 kernel's whole frame in CPU time).
BENCHMARK(BM_ViewFrame)
    ->Args({16, 8, 0, 0})
    ->Args({32, 8, 0, 0})
    ->Args({64, 8, 0, 0})
    ->Args({32, 8, 1, 0})
    ->Args({32, 8, 0, 4})
    ->Args({32, 8, 0, 1})
    ->Args({32, 8, 1, 4})
    ->ArgNames({"cells", "levels", "threads", "lanes"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ViewPath)
    ->Arg(0)
    ->Arg(1)
    ->ArgName("prefetch")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ViewFrameStacks)
    ->Arg(3)
    ->ArgName("stacks")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
