#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <mutex>
#include <numbers>
#include <optional>
#include <system_error>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/atomic_file.hpp"
#include "beamtrace/io/colormap.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "beamtrace/io/npy.hpp"
#include "beamtrace/io/png_writer.hpp"
#include "beamtrace/io/point_cloud_ply.hpp"
#include "beamtrace/physics/material_library.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "pipeline/detail/ordered_blocks.hpp"
#include "pipeline/detail/survey_rays.hpp"

namespace beamtrace {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Longest CSV row: 3 doubles, a double time, a float, 3 + 3 integers, a float (to_chars
/// shortest forms, 24 characters at most each).
constexpr std::size_t kMaxCsvRow = 400;

/// Appends one CSV row to `out`.
void append_csv_row(std::string& out, const LasSimplePoint& p, float range_m, std::uint16_t beam,
                    bool physics) {
    char row[kMaxCsvRow];
    char* c = row;
    char* const end = row + kMaxCsvRow;
    const auto num = [&](double v) {
        c = std::to_chars(c, end, v).ptr;
        *c++ = ',';
    };
    num(p.x);
    num(p.y);
    num(p.z);
    num(p.gps_time);
    c = std::to_chars(c, end, range_m).ptr;
    *c++ = ',';
    for (unsigned v : {unsigned{p.classification}, unsigned{p.point_source_id}, unsigned{beam}}) {
        c = std::to_chars(c, end, v).ptr;
        *c++ = ',';
    }
    c = std::to_chars(c, end, p.scan_angle_deg).ptr;
    if (physics) {
        for (unsigned v :
             {unsigned{p.intensity}, unsigned{p.return_number}, unsigned{p.number_of_returns}}) {
            *c++ = ',';
            c = std::to_chars(c, end, v).ptr;
        }
    }
    *c++ = '\n';
    out.append(row, static_cast<std::size_t>(c - row));
}

/// A block's working arrays (pulses, rays, hits, returns...). Blocks take one from a WorkShelf
/// and put it back, so a thread keeps reusing the same, cache-warm memory.
struct BlockWork {
    PulseBatch pulses;
    detail::SurveyRaySource::Scratch scratch;
    RayBatch rays;
    HitBatch hits;
    std::vector<Vec3d> origin, axis;
    std::vector<float> scan_angle;
    std::vector<PulseReturn> returns;
    std::vector<std::uint8_t> return_count;
    std::vector<SubRayHit> sub;
    PulseResponse response;
    ThreadPool this_thread{1};  ///< no workers: the backend traces the block on the caller

    /// Sizes the arrays for `pulses` pulses (contents are overwritten by the stages).
    void size_for(std::size_t pulse_count, std::size_t sub_rays, std::size_t max_returns) {
        const std::size_t n = pulse_count * sub_rays;
        rays.resize(n);
        if (hits.size() != n) {
            hits.resize(n);
        }
        origin.resize(pulse_count);
        axis.resize(pulse_count);
        scan_angle.resize(pulse_count);
        returns.resize(pulse_count * max_returns);
        return_count.resize(pulse_count);
        sub.resize(sub_rays);
    }
};

/// Spare BlockWork, last in first out.
class WorkShelf {
  public:
    std::unique_ptr<BlockWork> take() {
        const std::lock_guard lock(mutex_);
        if (spare_.empty()) {
            return std::make_unique<BlockWork>();
        }
        auto w = std::move(spare_.back());
        spare_.pop_back();
        return w;
    }
    void put(std::unique_ptr<BlockWork> w) {
        const std::lock_guard lock(mutex_);
        spare_.push_back(std::move(w));
    }

  private:
    std::mutex mutex_;
    std::vector<std::unique_ptr<BlockWork>> spare_;
};

/// Pulses per block: each block is generated, traced, simulated and encoded by one thread.
constexpr std::size_t kBlockPulses = 1024;

}  // namespace

std::unique_ptr<ScanPattern> SurveySpec::make_pattern() const {
    return scanner.make_pattern();
}

std::unique_ptr<Trajectory> SurveySpec::make_trajectory() const {
    switch (platform) {
        case PlatformKind::fixed:
            return std::make_unique<StaticPlatform>(fixed_pose);
        case PlatformKind::legs:
            return std::make_unique<LinearLegs>(legs);
        case PlatformKind::trajectory:
            return std::make_unique<SampledTrajectory>(read_trajectory_csv(trajectory_file));
    }
    throw ConfigError("unknown platform kind");
}

RayBatch survey_rays(const SurveySpec& spec, std::uint64_t seed, std::uint64_t max_pulses,
                     ThreadPool& pool) {
    const auto pattern = spec.make_pattern();
    const auto trajectory = spec.make_trajectory();
    std::optional<PulseSimulator> sim;
    if (spec.physics) {
        sim.emplace(*spec.physics);
    }
    const detail::SurveyRaySource source{&spec, trajectory.get(), sim ? &*sim : nullptr, seed};
    const std::uint64_t pulses =
        max_pulses > 0 ? std::min(pattern->pulse_count(), max_pulses) : pattern->pulse_count();
    const std::size_t sub_rays = source.sub_rays();
    RayBatch rays;
    rays.resize(static_cast<std::size_t>(pulses) * sub_rays);
    std::vector<Vec3d> origin(static_cast<std::size_t>(pulses)), axis(origin.size());
    std::vector<float> scan_angle(origin.size());
    pool.parallel_for(origin.size(), kBlockPulses, [&](std::size_t b, std::size_t e) {
        PulseBatch batch;
        detail::SurveyRaySource::Scratch scratch;
        pattern->generate(b, e - b, batch);
        source.generate(batch, b, rays, b * sub_rays, origin.data() + b, axis.data() + b,
                        scan_angle.data() + b, scratch);
    });
    return rays;
}

SurveyResult run_survey(const SurveySpec& spec, const SurveyRunConfig& run,
                        const ProgressFn& progress) {
    if (run.output_dir.empty()) {
        throw ConfigError("no output directory");
    }
    SurveyResult result;
    ThreadPool pool(run.threads);

    // Inputs first: nothing is written before the scene, pattern and trajectory are all valid.
    const Scene scene =
        spec.scene_file.empty() ? make_demo_scene() : load_scene_file(spec.scene_file);
    const auto pattern = spec.make_pattern();
    const auto trajectory = spec.make_trajectory();
    if (pattern->pulse_count() > 0 &&
        !trajectory->covers(pattern->start_time_s(), pattern->end_time_s())) {
        throw ConfigError(spec.source.string() + ": the scanner fires from " +
                          std::to_string(pattern->start_time_s()) + " s to " +
                          std::to_string(pattern->end_time_s()) +
                          " s but the platform moves only from " +
                          std::to_string(trajectory->start_time_s()) + " s to " +
                          std::to_string(trajectory->end_time_s()) + " s");
    }
    // Physics (optional): each pulse is sub_rays rays; their hits become the pulse's returns.
    std::optional<PulseSimulator> sim;
    std::vector<Material> materials;
    if (spec.physics) {
        sim.emplace(*spec.physics);
        for (const auto& m : scene.materials) {
            Material pm;
            pm.name = m.name;
            pm.reflectance = m.reflectance;
            pm.specular_weight = m.specular_weight;
            pm.specular_exponent = m.specular_exponent;
            if (!m.library.empty()) {
                const auto lib =
                    library_material(m.library, spec.physics->radiometry.wavelength_nm);
                if (!lib) {
                    throw ConfigError(spec.scene_file.string() + ": material '" + m.name +
                                      "': unknown library material '" + m.library +
                                      "' (known: " + material_library_names() + ")");
                }
                pm = *lib;
                pm.name = m.name;
            }
            materials.push_back(pm);
        }
    }
    const std::size_t sub_rays = sim ? sim->sub_ray_count() : 1;
    const std::size_t max_returns =
        sim ? static_cast<std::size_t>(sim->config().max_returns) : std::size_t{1};

    result.triangles = scene.triangle_count();
    result.spheres = scene.sphere_count();
    result.pulses = run.max_pulses > 0 ? std::min(pattern->pulse_count(), run.max_pulses)
                                       : pattern->pulse_count();

    auto t0 = Clock::now();
    const auto backend = make_backend(run.backend, scene.geometry, pool);
    result.build_s = seconds_since(t0);

    std::error_code ec;
    std::filesystem::create_directories(run.output_dir, ec);
    if (ec || !std::filesystem::is_directory(run.output_dir)) {
        throw OutputError(run.output_dir.string() + ": cannot create output directory" +
                          (ec ? ": " + ec.message() : std::string()));
    }

    // LAS: coordinates quantised to 1 mm around the scene; the survey file goes into a VLR.
    const Aabb bounds = scene.geometry.bounds();
    LasWriterConfig las = las_config_for_extent(Vec3d(bounds.lo) + scene.origin_m,
                                                Vec3d(bounds.hi) + scene.origin_m, 0.001);
    las.point_format = spec.point_format;
    LasVlr vlr;
    vlr.user_id = "beamtrace";
    vlr.record_id = 1;
    vlr.description = "survey file";
    const std::string record = "# beamtrace " BEAMTRACE_VERSION " survey, seed " +
                               std::to_string(run.seed) + "\n" + spec.text;
    vlr.data.assign(
        record.begin(),
        record.begin() + static_cast<std::ptrdiff_t>(std::min<std::size_t>(record.size(), 60000)));
    las.vlrs.push_back(std::move(vlr));
    const auto las_path = run.output_dir / "points.las";
    LasWriter writer(las_path, las);
    std::vector<PointRecord> ply_points;
    std::unique_ptr<AtomicFile> csv;
    if (spec.write_csv) {
        csv = std::make_unique<AtomicFile>(run.output_dir / "points.csv");
        csv->write(
            std::string(
                "x,y,z,gps_time,range_m,classification,point_source_id,beam,scan_angle_deg") +
            (spec.physics ? ",intensity,return_number,number_of_returns" : "") + "\n");
    }

    // Image scanners firing one frame also get the report's range image and a label image.
    const std::optional<ImageGrid> grid = pattern->image_grid();
    const bool images = grid.has_value();
    const int img_w = grid ? grid->width : 0, img_h = grid ? grid->height : 0;
    std::vector<float> range_img(
        images ? static_cast<std::size_t>(img_w) * static_cast<std::size_t>(img_h) : 0, 0.0f);
    std::vector<std::uint16_t> label_img(range_img.size(), 0);

    t0 = Clock::now();
    // At most chunk_pulses (rounded up to whole blocks) in flight between the oldest block not
    // yet written and the newest one taken.
    const std::size_t window =
        (std::max<std::size_t>(1, run.chunk_pulses) + kBlockPulses - 1) / kBlockPulses;
    // Optional waveforms.bin (physics.waveform.keep): every pulse's sampled echo power.
    const bool keep_waves = sim && sim->config().keep_waveform;
    std::unique_ptr<AtomicFile> waves;
    if (keep_waves) {
        waves = std::make_unique<AtomicFile>(run.output_dir / "waveforms.bin");
        waves->write("BTWAVE01", 8);
        const std::uint32_t version = 1, reserved = 0;
        const double bin_ns = sim->config().waveform.bin_ns;
        const double fwhm_ns = sim->config().waveform.pulse_fwhm_ns;
        waves->write(&version, 4);
        waves->write(&reserved, 4);
        waves->write(&bin_ns, 8);
        waves->write(&fwhm_ns, 8);
    }
    WorkShelf shelf;
    const detail::SurveyRaySource source{&spec, trajectory.get(), sim ? &*sim : nullptr, run.seed};
    const bool physics = sim.has_value();
    // Every block goes through all stages on one pool thread (pose and rays, trace, physics,
    // points, LAS/CSV encoding) into its own output; one writer thread writes the outputs in
    // block order meanwhile. Blocks start at multiples of kBlockPulses, so neither they nor the
    // ray packets inside them depend on the thread count or the window.
    const std::size_t blocks =
        static_cast<std::size_t>((result.pulses + kBlockPulses - 1) / kBlockPulses);
    const std::size_t progress_every = std::max<std::size_t>(1, window / 4);
    detail::OrderedBlocks ordered(blocks, window, [&](std::size_t k, detail::BlockOutput& out) {
        writer.write_block(out.las);
        if (csv) {
            csv->write(out.csv);
        }
        if (waves) {
            waves->write(out.waves);
        }
        if (spec.write_ply) {
            ply_points.insert(ply_points.end(), out.ply.begin(), out.ply.end());
        }
        if (progress && ((k + 1) % progress_every == 0 || k + 1 == blocks)) {
            progress(static_cast<std::size_t>(
                         std::min<std::uint64_t>((k + 1) * kBlockPulses, result.pulses)),
                     static_cast<std::size_t>(result.pulses));
        }
    });
    const auto process = [&](std::size_t block_index, detail::BlockOutput& block) {
        const std::uint64_t first = std::uint64_t{block_index} * kBlockPulses;
        const auto n_pulses =
            static_cast<std::size_t>(std::min<std::uint64_t>(kBlockPulses, result.pulses - first));
        std::unique_ptr<BlockWork> work = shelf.take();
        BlockWork& w = *work;
        w.size_for(n_pulses, sub_rays, max_returns);
        const PulseBatch& pulses = w.pulses;
        pattern->generate(first, n_pulses, w.pulses);
        source.generate(pulses, first, w.rays, 0, w.origin.data(), w.axis.data(),
                        w.scan_angle.data(), w.scratch);
        backend->intersect(w.rays, 0, n_pulses * sub_rays, w.hits, w.this_thread);
        if (sim) {
            for (std::size_t k = 0; k < n_pulses; ++k) {
                for (std::size_t j = 0; j < sub_rays; ++j) {
                    const std::size_t h = k * sub_rays + j;
                    if (!w.hits.hit(h)) {
                        w.sub[j] = SubRayHit{};
                        continue;
                    }
                    const Vec3d d{w.rays.dx[h], w.rays.dy[h], w.rays.dz[h]};
                    const double t = w.hits.t[h];
                    const ScenePart& part = scene.parts[scene.part_of_face(w.hits.face[h])];
                    const Vec3d at = w.origin[k] + d * t;
                    w.sub[j] = make_sub_ray_hit(materials[part.material], t, at,
                                                scene.geometry.normal_at(w.hits.face[h], at), d);
                }
                sim->simulate(run.seed, first + k, w.sub, w.response);
                if (keep_waves) {
                    // index, time, beam origin (world), beam axis, first bin, count, samples
                    const std::uint64_t index = first + k;
                    const Vec3d o = w.origin[k] + scene.origin_m;
                    const double pose_record[7] = {pulses.time_s[k], o.x,         o.y,        o.z,
                                                   w.axis[k].x,      w.axis[k].y, w.axis[k].z};
                    const std::int64_t first_bin = w.response.waveform.first_bin;
                    const auto& samples = w.response.waveform.samples_w;
                    const auto count = static_cast<std::uint32_t>(samples.size());
                    block.waves.append(reinterpret_cast<const char*>(&index), 8);
                    block.waves.append(reinterpret_cast<const char*>(pose_record),
                                       sizeof pose_record);
                    block.waves.append(reinterpret_cast<const char*>(&first_bin), 8);
                    block.waves.append(reinterpret_cast<const char*>(&count), 4);
                    const std::size_t at = block.waves.size();  // samples as float32
                    block.waves.resize(at + 4 * std::size_t{count});
                    for (std::size_t q = 0; q < samples.size(); ++q) {
                        const auto f = static_cast<float>(samples[q]);
                        std::memcpy(block.waves.data() + at + 4 * q, &f, 4);
                    }
                }
                const std::size_t n = std::min(w.response.returns.size(), max_returns);
                std::copy_n(w.response.returns.begin(), n,
                            w.returns.begin() + static_cast<std::ptrdiff_t>(k * max_returns));
                w.return_count[k] = static_cast<std::uint8_t>(n);
            }
        }
        // Room for every return of the block at once (kept from block to block).
        const std::size_t most = n_pulses * max_returns * writer.header().point_record_length;
        if (block.las.bytes.size() < most) {
            block.las.bytes.resize(most);
        }
        LasSimplePoint p;
        for (std::size_t k = 0; k < n_pulses; ++k) {
            const std::size_t n = sim ? w.return_count[k] : (w.hits.hit(k) ? 1 : 0);
            for (std::size_t r = 0; r < n; ++r) {
                const PulseReturn* ret = sim ? &w.returns[k * max_returns + r] : nullptr;
                const std::size_t h = sim ? k * sub_rays + ret->sub_ray : k;
                const double t = sim ? ret->range_m : double{w.hits.t[k]};
                const ScenePart& part = scene.parts[scene.part_of_face(w.hits.face[h])];
                if (images && r == 0) {
                    // Pulse index u * h + v is pixel (row v, column u).
                    const std::uint64_t index = first + k;
                    const auto u =
                        static_cast<std::size_t>(index / static_cast<std::uint64_t>(img_h));
                    const auto v =
                        static_cast<std::size_t>(index % static_cast<std::uint64_t>(img_h));
                    range_img[v * static_cast<std::size_t>(img_w) + u] = static_cast<float>(t);
                    label_img[v * static_cast<std::size_t>(img_w) + u] = part.label;
                }
                const Vec3d xyz = w.origin[k] + w.axis[k] * t + scene.origin_m;
                p.x = xyz.x;
                p.y = xyz.y;
                p.z = xyz.z;
                p.gps_time = pulses.time_s[k];
                p.scan_angle_deg = w.scan_angle[k];
                p.return_number = ret ? ret->return_number : 1;
                p.number_of_returns = ret ? ret->number_of_returns : 1;
                p.intensity = ret ? ret->intensity : 0;
                p.classification = part.label;
                p.point_source_id = part.part_id;
                p.user_data = static_cast<std::uint8_t>(pulses.channel[k] & 0xFFu);  // beam / row
                writer.encode(p, block.las);
                if (csv) {
                    append_csv_row(block.csv, p, static_cast<float>(t), pulses.channel[k], physics);
                }
                if (spec.write_ply) {
                    block.ply.push_back({p.x, p.y, p.z, static_cast<float>(t), w.hits.face[h],
                                         static_cast<std::uint32_t>(first + k)});
                }
            }
        }
        shelf.put(std::move(work));
    };
    pool.parallel_for(blocks, 1, [&](std::size_t kb, std::size_t ke) {
        for (std::size_t k = kb; k < ke; ++k) {
            detail::BlockOutput* out = ordered.acquire(k);
            if (out == nullptr) {
                return;  // the writer failed, or another block did: finish() or parallel_for says
            }
            try {
                process(k, *out);
            } catch (...) {
                ordered.abort();
                throw;
            }
            ordered.publish(k);
        }
    });
    ordered.finish();
    writer.close();
    result.points = writer.point_count();
    result.outputs.push_back(las_path);
    if (waves) {
        waves->commit();
        result.outputs.push_back(run.output_dir / "waveforms.bin");
    }
    if (csv) {
        csv->commit();
        result.outputs.push_back(run.output_dir / "points.csv");
    }
    if (images) {
        // The three files at once (PNG compression is most of it: 40 ms of a 110 ms panorama
        // survey when written one after the other).
        pool.parallel_for(3, 1, [&](std::size_t kb, std::size_t ke) {
            for (std::size_t k = kb; k < ke; ++k) {
                if (k == 0) {
                    write_png_rgb8(run.output_dir / "range.png", img_w, img_h,
                                   range_image_rgb(range_img, img_w, img_h));
                } else if (k == 1) {
                    write_png_gray16(run.output_dir / "labels.png", img_w, img_h, label_img);
                } else {
                    write_npy_f32(run.output_dir / "range.npy", static_cast<std::size_t>(img_h),
                                  static_cast<std::size_t>(img_w), range_img);
                }
            }
        });
        for (const char* f : {"range.npy", "range.png", "labels.png"}) {
            result.outputs.push_back(run.output_dir / f);
        }
    }
    if (spec.write_ply) {
        write_points_ply(run.output_dir / "points.ply", ply_points,
                         "beamtrace survey " + spec.source.filename().string());
        result.outputs.push_back(run.output_dir / "points.ply");
    }
    if (spec.trajectory_rate_hz > 0 && result.pulses > 0) {
        // The platform over the survey window, in world coordinates.
        std::vector<TrajectorySample> samples;
        const double start = pattern->start_time_s(), end = pattern->end_time_s();
        const auto n =
            static_cast<std::size_t>(std::floor((end - start) * spec.trajectory_rate_hz));
        for (std::size_t k = 0; k <= n + 1; ++k) {
            const double time =
                std::min(end, start + static_cast<double>(k) / spec.trajectory_rate_hz);
            if (!samples.empty() && time <= samples.back().time_s) {
                break;
            }
            const Pose pose = trajectory->pose_at(time);
            samples.push_back({time, pose.position_m + scene.origin_m, to_rpy(pose.attitude)});
        }
        if (samples.size() == 1) {
            samples.push_back({samples[0].time_s + 1.0 / spec.trajectory_rate_hz,
                               samples[0].position_m, samples[0].attitude});
        }
        write_trajectory_csv(run.output_dir / "trajectory.csv", SampledTrajectory(samples),
                             spec.trajectory_rate_hz);
        result.outputs.push_back(run.output_dir / "trajectory.csv");
    }
    result.survey_s = seconds_since(t0);
    return result;
}

}  // namespace beamtrace
