#include "harness/throughput_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <thread>

#include <unistd.h>

#include "beamtrace/accel/backend_registry.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/core/memory_usage.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "beamtrace/sensor/scan_pattern.hpp"
#include "harness/child_run.hpp"
#include "harness/embree_limit.hpp"

namespace beamtrace {
namespace {

using Clock = std::chrono::steady_clock;

/// Most rays a survey may hold for the trace measurements (80 bytes each with their hits).
constexpr std::uint64_t kMaxBenchRays = 50'000'000;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string machine_description() {
    std::ifstream in("/proc/cpuinfo");
    std::string line, model = "unknown CPU";
    while (std::getline(in, line)) {
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            if (colon != std::string::npos) {
                model = line.substr(colon + 2);
            }
            break;
        }
    }
    return model + ", " + std::to_string(std::max(1u, std::thread::hardware_concurrency())) +
           " hardware threads";
}

std::size_t count_hits(const std::vector<std::uint32_t>& face) {
    return static_cast<std::size_t>(
        std::count_if(face.begin(), face.end(), [](std::uint32_t f) { return f != kNoFace; }));
}

/// Best rays/s of `repeats` timed runs, each repeating `trace` for at least `min_time_s`.
template <class Trace>
double best_rate(std::size_t rays, std::size_t repeats, double min_time_s, Trace&& trace) {
    double best = 0.0;
    for (std::size_t r = 0; r < repeats; ++r) {
        std::size_t runs = 0;
        const auto t0 = Clock::now();
        double elapsed = 0.0;
        do {
            trace();
            ++runs;
            elapsed = seconds_since(t0);
        } while (elapsed < min_time_s);
        best = std::max(best, static_cast<double>(rays * runs) / elapsed);
    }
    return best;
}

/// Hit counts of two tracers on the same rays may differ only by rays aimed exactly at the
/// silhouette of the scene (a handful); anything more is a bug.
void check_hits(const std::string& survey, const std::string& what, std::size_t expected,
                std::size_t got, std::size_t rays) {
    const std::size_t allowed = std::max<std::size_t>(4, rays / 100000);
    const std::size_t diff = expected > got ? expected - got : got - expected;
    if (diff > allowed) {
        throw std::runtime_error("bench check failed: " + survey + ": " + what + " hit " +
                                 std::to_string(got) + " rays, the reference " +
                                 std::to_string(expected));
    }
}

std::string fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

std::string millions(double v) {
    return fixed(v / 1e6, 2) + " M";
}

}  // namespace

std::vector<std::string> ThroughputBenchConfig::validate() const {
    std::vector<std::string> p;
    if (surveys.empty()) {
        p.emplace_back("no survey files");
    }
    for (unsigned t : threads) {
        if (t == 0 || t > 1024) {
            p.push_back("threads: " + std::to_string(t) + " is not in 1..1024");
        }
    }
    if (repeats == 0 || repeats > 100) {
        p.push_back("repeats: " + std::to_string(repeats) + " is not in 1..100");
    }
    if (!(min_time_s >= 0.0 && min_time_s <= 60.0)) {
        p.emplace_back("min_time_s must be in [0, 60]");
    }
    for (BackendKind b : backends) {
        const BackendEntry& e = backend_entry(b);
        if (!e.usable()) {
            p.push_back("backend " + std::string(e.name) + ": this build has no " +
                        std::string(e.summary));
        }
    }
    return p;
}

double ThreadFigures::limit_rays_per_s() const {
    double best = 0.0;
    for (const auto& f : trace) {
        if (f.limit) {
            best = std::max(best, f.rays_per_s);
        }
    }
    return best;
}

namespace {

/// One tracer of the benchmark: a name and a call that traces the survey's rays on a pool.
struct Tracer {
    std::string name;
    bool limit = false;
    std::function<std::size_t(ThreadPool&)> trace;  ///< returns the hit count
    bool watertight = true;  ///< false: its hit count is reported, not checked
};

/// A survey run end to end into `dir`; throws when the LAS file does not hold its points.
SurveyResult run_checked(const SurveySpec& spec, const SurveyRunConfig& run,
                         const std::string& name) {
    std::filesystem::remove_all(run.output_dir);
    const SurveyResult sr = run_survey(spec, run);
    const LasReader las(run.output_dir / "points.las");
    if (las.header().point_count != sr.points) {
        throw std::runtime_error("bench check failed: " + name + ": the LAS file holds " +
                                 std::to_string(las.header().point_count) +
                                 " points, the survey wrote " + std::to_string(sr.points));
    }
    return sr;
}

/// The survey end to end once with each of `backends` but the default one, keeping each one's
/// best run in fig.other_backends (one entry per backend, in their order).
void time_other_backends(const SurveySpec& spec, SurveyRunConfig run, const std::string& name,
                         const std::vector<BackendKind>& backends, ThreadFigures& fig) {
    std::size_t slot = 0;
    for (BackendKind kind : backends) {
        if (kind == default_backend_kind()) {
            continue;
        }
        if (fig.other_backends.size() <= slot) {
            fig.other_backends.push_back({std::string(to_string(kind))});
        }
        BackendSurveyFigure& f = fig.other_backends[slot++];
        run.backend = kind;
        const SurveyResult sr = run_checked(spec, run, name);
        if (f.survey_s == 0.0 || sr.survey_s < f.survey_s) {
            f.survey_s = sr.survey_s;
            f.pulses_per_s = static_cast<double>(sr.pulses) / sr.survey_s;
            f.points_per_s = static_cast<double>(sr.points) / sr.survey_s;
        }
    }
}

/// What a memory run gives: the survey's counts, its survey-stage time and the peak RSS.
struct MemoryRun {
    std::uint64_t pulses = 0, points = 0;
    double survey_s = 0.0;
    std::size_t peak_rss_bytes = 0;
};

/// The survey in this process: the peak RSS counts from what the process holds after freeing
/// what it can.
MemoryRun memory_run_here(const SurveySpec& spec, const SurveyRunConfig& run,
                          const std::string& name) {
    trim_free_memory();
    reset_peak_rss();
    const SurveyResult sr = run_checked(spec, run, name);
    return {sr.pulses, sr.points, sr.survey_s, peak_rss_bytes()};
}

/// The survey in a forked child: its peak RSS is the child's.
MemoryRun memory_run_in_child(const SurveySpec& spec, const SurveyRunConfig& run,
                              const std::string& name) {
    detail::ChildRun child;
    try {
        child = detail::run_in_child([&] {
            const SurveyResult sr = run_checked(spec, run, name);
            MemoryRun m{sr.pulses, sr.points, sr.survey_s, 0};
            return std::string(reinterpret_cast<const char*>(&m), sizeof m);
        });
    } catch (...) {
        // The child's own Interrupted comes back as another error (or the child dies by the
        // signal): the token of this process says what happened.
        throw_if_cancelled(run.cancel, "bench");
        throw;
    }
    MemoryRun m;
    if (child.payload.size() != sizeof m) {
        throw std::runtime_error("bench: " + name + ": the memory run's child sent " +
                                 std::to_string(child.payload.size()) + " bytes");
    }
    std::memcpy(&m, child.payload.data(), sizeof m);
    m.peak_rss_bytes = child.peak_rss_bytes;
    return m;
}

}  // namespace

ThroughputReport run_throughput_bench(const ThroughputBenchConfig& config,
                                      const std::function<void(const std::string&)>& log) {
    throw_if_problems("bench settings", config.validate());
    const auto say = [&](const std::string& s) {  // before each step
        throw_if_cancelled(config.cancel, "bench");
        if (log) {
            log(s);
        }
    };
    std::vector<unsigned> threads = config.threads;
    if (threads.empty()) {
        threads.push_back(1);
        const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
        if (hw > 1) {
            threads.push_back(hw);
        }
    }
    std::vector<BackendKind> backends = config.backends;
    if (backends.empty()) {  // the default backend, and our BVH beside it
        backends.push_back(default_backend_kind());
        if (default_backend_kind() != BackendKind::bvh) {
            backends.push_back(BackendKind::bvh);
        }
    }
    const std::filesystem::path scratch =
        config.scratch_dir.empty()
            ? std::filesystem::temp_directory_path() /
                  ("beamtrace-bench-" + std::to_string(::getpid()))  // one per process
            : config.scratch_dir;

    // Every survey file is parsed first: a typo fails before minutes of benchmarking.
    std::vector<SurveySpec> specs;
    for (const auto& path : config.surveys) {
        specs.push_back(load_survey_spec(path));
        // The trace measurements hold all of a survey's rays (80 bytes each with their hits).
        const SurveySpec& spec = specs.back();
        std::uint64_t pulses = spec.make_pattern()->pulse_count();
        if (config.max_pulses > 0) {
            pulses = std::min(pulses, config.max_pulses);
        }
        const std::uint64_t rays =
            pulses * (spec.physics ? PulseSimulator(*spec.physics).sub_ray_count() : 1);
        if (rays > kMaxBenchRays) {
            throw ConfigError(path.string() + ": " + std::to_string(rays) + " rays would take " +
                              std::to_string(rays * 80 / 1000000) +
                              " MB for the trace measurements (at most " +
                              std::to_string(kMaxBenchRays) + " rays); use --pulses");
        }
    }

    // Our own scratch folder goes when the benchmark ends, also on an error.
    struct RemoveScratch {
        std::filesystem::path dir;
        ~RemoveScratch() {
            std::error_code ignored;
            if (!dir.empty()) {
                std::filesystem::remove_all(dir, ignored);
            }
        }
    } const remove_scratch{config.scratch_dir.empty() ? scratch : std::filesystem::path()};

    // Refused before anything runs: the Embree limit loop is handed triangles only.
    for (const SurveySpec& spec : specs) {
        if (spec.scene_file.empty()) {
            continue;
        }
        for (const PartSpec& part : load_scene_spec(spec.scene_file).parts) {
            if (part.exact_sphere) {
                throw ConfigError(spec.source.string() + ": part '" + part.name +
                                  "' is an exact sphere, and the Embree limit loop traces "
                                  "triangles only; give its spheres subdivisions to bench it");
            }
        }
    }

    ThroughputReport report;
    report.machine = machine_description();
    report.backend = std::string(to_string(default_backend_kind()));
    const auto run_config = [&](const SurveyBenchResult& res) {
        SurveyRunConfig run;
        run.output_dir = scratch / res.name;
        run.seed = config.seed;
        run.max_pulses = config.max_pulses;
        run.cancel = config.cancel;
        return run;
    };

    // 1. Memory: every survey end to end once per thread count (the default backend, as
    //    `beamtrace survey`), before anything else runs. Each run is a child process of its own
    //    when this process has one thread (as the CLI has here), so its peak RSS is the survey's
    //    alone; otherwise it runs here, after freeing what it can.
    report.memory_isolated = detail::process_is_single_threaded();
    for (const SurveySpec& spec : specs) {
        SurveyBenchResult& res = report.surveys.emplace_back();
        res.name = spec.source.stem().string();
        res.runs.resize(threads.size());
        SurveyRunConfig run = run_config(res);
        for (std::size_t ti = 0; ti < threads.size(); ++ti) {
            ThreadFigures& fig = res.runs[ti];
            fig.threads = threads[ti];
            run.threads = fig.threads;
            say(res.name + ", " + std::to_string(fig.threads) + " thread(s): end to end, memory");
            const auto t0 = Clock::now();
            const MemoryRun m = report.memory_isolated ? memory_run_in_child(spec, run, res.name)
                                                       : memory_run_here(spec, run, res.name);
            fig.peak_rss_bytes = m.peak_rss_bytes;
            fig.load_build_s = seconds_since(t0) - m.survey_s;
            if (ti > 0 && m.points != res.points) {
                throw std::runtime_error("bench check failed: " + res.name + ": " +
                                         std::to_string(m.points) + " points with " +
                                         std::to_string(fig.threads) + " threads, " +
                                         std::to_string(res.points) + " before");
            }
            res.pulses = m.pulses;
            res.points = m.points;
        }
    }

    for (std::size_t si = 0; si < specs.size(); ++si) {
        const SurveySpec& spec = specs[si];
        SurveyBenchResult& res = report.surveys[si];
        SurveyRunConfig run = run_config(res);

        // 2. The tracers, on the survey's own rays, each checked before it is timed.
        say(res.name + ": loading the scene and generating the rays");
        const Scene scene =
            spec.scene_file.empty() ? make_demo_scene() : load_scene_file(spec.scene_file);
        res.triangles = scene.geometry.triangle_count();
        res.stored_triangles = scene.geometry.stored_triangle_count();
        ThreadPool build_pool(threads.back());
        const RayBatch rays = survey_rays(spec, config.seed, config.max_pulses, build_pool);
        res.rays = rays.size();
        std::vector<Tracer> tracers;
#ifdef BEAMTRACE_HAVE_EMBREE
        std::optional<TriangleMesh> flat;
        if (!scene.geometry.is_single_mesh()) {
            flat = scene.geometry.flatten();
        }
        const EmbreeLimit limit(flat ? *flat : scene.geometry.meshes[0], threads.back());
        std::vector<std::uint32_t> face;
        for (EmbreeCall call :
             {EmbreeCall::single, EmbreeCall::packet16, EmbreeCall::packet16_coherent}) {
            tracers.push_back({"Embree " + std::string(to_string(call)), true,
                               [&limit, &rays, &face, call](ThreadPool& pool) {
                                   limit.trace(rays, call, face, pool);
                                   return count_hits(face);
                               },
                               call != EmbreeCall::packet16_coherent});
        }
#endif
        std::vector<std::unique_ptr<Backend>> built;
        HitBatch hits;
        hits.resize(rays.size());
        for (BackendKind kind : backends) {
            built.push_back(make_backend(kind, scene.geometry, build_pool));
            const Backend* backend = built.back().get();
            tracers.push_back({"our " + std::string(to_string(kind)), false,
                               [backend, &rays, &hits](ThreadPool& pool) {
                                   backend->intersect(rays, 0, rays.size(), hits, pool);
                                   return count_hits(hits.face);
                               }});
        }
        std::vector<std::uint64_t> missed(tracers.size(), 0);
        for (std::size_t k = 0; k < tracers.size(); ++k) {
            const std::size_t n = tracers[k].trace(build_pool);
            if (k == 0) {
                res.hits = n;
            }
            if (tracers[k].watertight) {
                check_hits(res.name, tracers[k].name, res.hits, n, rays.size());
            } else {
                missed[k] = res.hits > n ? res.hits - n : 0;
            }
        }
        if (!spec.physics) {  // one point per hit
            check_hits(res.name, "the survey", res.hits, res.points, rays.size());
        }
        for (ThreadFigures& fig : res.runs) {
            fig.trace.resize(tracers.size());
            for (std::size_t k = 0; k < tracers.size(); ++k) {
                fig.trace[k] = {tracers[k].name, tracers[k].limit, 0.0, missed[k]};
            }
        }

        // 3. Timing, in rounds: every figure once per round, so load from other processes
        //    spreads over all of them; each is the best of its rounds.
        for (std::size_t r = 0; r < config.repeats; ++r) {
            for (ThreadFigures& fig : res.runs) {
                say(res.name + ", " + std::to_string(fig.threads) + " thread(s): round " +
                    std::to_string(r + 1) + " of " + std::to_string(config.repeats));
                ThreadPool pool(fig.threads);
                run.threads = fig.threads;
                const SurveyResult sr = run_checked(spec, run, res.name);
                if (fig.survey_s == 0.0 || sr.survey_s < fig.survey_s) {
                    fig.survey_s = sr.survey_s;
                    fig.survey_pulses_per_s = static_cast<double>(sr.pulses) / sr.survey_s;
                    fig.survey_points_per_s = static_cast<double>(sr.points) / sr.survey_s;
                }
                time_other_backends(spec, run, res.name, backends, fig);
                run.backend = default_backend_kind();
                for (std::size_t k = 0; k < tracers.size(); ++k) {
                    throw_if_cancelled(config.cancel, "bench");
                    const double rate = best_rate(rays.size(), 1, config.min_time_s,
                                                  [&] { (void)tracers[k].trace(pool); });
                    fig.trace[k].rays_per_s = std::max(fig.trace[k].rays_per_s, rate);
                }
            }
        }
        std::filesystem::remove_all(run.output_dir);
    }
    return report;
}

std::string format_throughput_report(const ThroughputReport& report) {
    std::string out = "Machine: " + report.machine + ". End-to-end surveys use the " +
                      report.backend + " backend; every figure is the best of the timed runs.\n";
    out += report.memory_isolated
               ? "Peak RSS: each end-to-end run in a child process of its own (the survey's "
                 "alone).\n"
               : "Peak RSS: measured in this process, on top of what it already held.\n";
    for (const auto& s : report.surveys) {
        out += "\n### " + s.name + ": " + std::to_string(s.triangles) + " triangles";
        if (s.stored_triangles != s.triangles) {
            out += " (" + std::to_string(s.stored_triangles) + " stored)";
        }
        out += ", " + std::to_string(s.pulses) + " pulses, " + std::to_string(s.rays) + " rays, " +
               std::to_string(s.hits) + " hits, " + std::to_string(s.points) + " points\n\n";
        out +=
            "| threads | tracer | rays/s | of rtcIntersect1 | of the fastest Embree call |\n"
            "|---|---|---|---|---|\n";
        const auto ratio = [](double x, double of) {
            return of > 0 ? fixed(x / of, 2) : std::string("-");
        };
        for (const auto& f : s.runs) {
            const double limit = f.limit_rays_per_s();
            const double single = f.trace.empty() || !f.trace.front().limit
                                      ? 0.0
                                      : f.trace.front().rays_per_s;  // rtcIntersect1 comes first
            for (const auto& tr : f.trace) {
                const std::string missed =
                    tr.missed_hits > 0 ? " (missed " + std::to_string(tr.missed_hits) + " hits)"
                                       : std::string();
                out += "| " + std::to_string(f.threads) + " | " + tr.tracer + missed + " | " +
                       millions(tr.rays_per_s) + " | " + ratio(tr.rays_per_s, single) + " | " +
                       ratio(tr.rays_per_s, limit) + " |\n";
            }
            // Rays per second of the survey: its pulses/s times the rays of a pulse.
            const double survey_rays_per_s =
                f.survey_pulses_per_s * static_cast<double>(s.rays) /
                static_cast<double>(std::max<std::uint64_t>(1, s.pulses));
            out += "| " + std::to_string(f.threads) + " | **survey end to end** (LAS written) | " +
                   millions(f.survey_pulses_per_s) + " pulses/s, " +
                   millions(f.survey_points_per_s) + " points/s | " +
                   ratio(survey_rays_per_s, single) + " | " + ratio(survey_rays_per_s, limit) +
                   " |\n";
            for (const BackendSurveyFigure& o : f.other_backends) {
                const double rays_per_s = o.pulses_per_s * static_cast<double>(s.rays) /
                                          static_cast<double>(std::max<std::uint64_t>(1, s.pulses));
                out += "| " + std::to_string(f.threads) + " | **survey end to end, " + o.backend +
                       "** | " + millions(o.pulses_per_s) + " pulses/s, " +
                       millions(o.points_per_s) + " points/s | " + ratio(rays_per_s, single) +
                       " | " + ratio(rays_per_s, limit) + " |\n";
            }
        }
        out += "\n| threads | scene load + build | survey stage | peak RSS |\n|---|---|---|---|\n";
        for (const auto& f : s.runs) {
            out += "| " + std::to_string(f.threads) + " | " + fixed(f.load_build_s, 3) + " s | " +
                   fixed(f.survey_s, 3) + " s | " +
                   fixed(static_cast<double>(f.peak_rss_bytes) / 1e6, 1) + " MB |\n";
        }
        if (s.runs.size() > 1) {
            const ThreadFigures& a = s.runs.front();
            const ThreadFigures& b = s.runs.back();
            out += "\nScaling " + std::to_string(a.threads) + " -> " + std::to_string(b.threads) +
                   " threads:";
            for (std::size_t k = 0; k < a.trace.size() && k < b.trace.size(); ++k) {
                out += " " + a.trace[k].tracer + " " +
                       fixed(b.trace[k].rays_per_s / a.trace[k].rays_per_s, 2) + "x;";
            }
            out += " survey " + fixed(b.survey_pulses_per_s / a.survey_pulses_per_s, 2) + "x\n";
        }
    }
    return out;
}

}  // namespace beamtrace
