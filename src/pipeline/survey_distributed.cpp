#include "beamtrace/pipeline/survey_distributed.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <future>
#include <limits>
#include <random>
#include <system_error>

#include "beamtrace/core/cancel.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/io/survey_las.hpp"
#include "core/created_dirs.hpp"
#include "pipeline/detail/survey_outputs.hpp"
#include "pipeline/detail/survey_session.hpp"

namespace beamtrace {

namespace {

using Clock = std::chrono::steady_clock;

/// Runs `step` on every rank, then agree_on_error()s on the outcome.
template <class Step>
void collectively(Communicator& comm, Step&& step) {
    std::exception_ptr error;
    try {
        step();
    } catch (...) {
        error = std::current_exception();
    }
    agree_on_error(comm, error);
}

/// ConfigError for what the ranks cannot write together.
void check_outputs(const SurveySpec& spec, const SinkFacts& facts) {
    for (const std::string& name : spec.outputs) {
        if (name != "las" && name != "preview") {
            throw ConfigError(spec.source.string() + ": output." + name +
                              ": not written by a survey across MPI ranks (points.las and "
                              "trajectory.csv are); turn it off or run on one process");
        }
    }
    if (std::find(spec.outputs.begin(), spec.outputs.end(), "las") == spec.outputs.end()) {
        throw ConfigError(spec.source.string() +
                          ": output.las: a survey across MPI ranks writes points.las; turn it on");
    }
    if (facts.waveform) {
        throw ConfigError(spec.source.string() +
                          ": physics.waveform.keep: waveforms are not written by a survey across "
                          "MPI ranks; turn it off or run on one process");
    }
    if (facts.image) {
        throw ConfigError(spec.source.string() +
                          ": an image scanner's range images are not written by a survey across "
                          "MPI ranks; run it on one process");
    }
}

/// A name no other run picks: rank 0's random token, on every rank.
std::string shared_token(Communicator& comm) {
    std::string token;
    if (comm.rank() == 0) {
        std::random_device device;
        token = std::to_string(device()) + std::to_string(device());
    }
    return comm.broadcast(token, 0);
}

/// Collective: throws OutputError on every rank unless every rank sees the file rank 0 wrote
/// into `dir` (an output directory on a file system the ranks share).
void check_shared_directory(Communicator& comm, const std::filesystem::path& dir,
                            const std::string& token) {
    const std::filesystem::path marker = dir / (".beamtrace-rank0-" + token);
    collectively(comm, [&] {
        if (comm.rank() == 0) {
            open_posix_shared_file(marker, true)->close();
        }
    });
    std::error_code ec;
    std::int64_t blind = std::filesystem::exists(marker, ec)
                             ? std::numeric_limits<std::int64_t>::max()
                             : comm.rank();
    comm.min({&blind, 1});
    if (comm.rank() == 0) {
        std::filesystem::remove(marker, ec);
    }
    if (blind != std::numeric_limits<std::int64_t>::max()) {
        throw OutputError(dir.string() + ": rank " + std::to_string(blind) +
                          " does not see rank 0's files there: the output directory must be on a "
                          "file system all ranks share");
    }
}

/// The sums, minima and maxima of every rank's totals.
LasRecordBlock reduce_totals(Communicator& comm, const LasRecordBlock& mine) {
    std::vector<std::uint64_t> sums{mine.count};
    sums.insert(sums.end(), mine.by_return.begin(), mine.by_return.end());
    comm.sum(sums);
    constexpr auto kNone = std::numeric_limits<std::int64_t>::max();
    std::vector<std::int64_t> mins(6, kNone);
    for (std::size_t k = 0; k < 3 && mine.count > 0; ++k) {
        mins[k] = mine.lo[k];
        mins[3 + k] = -std::int64_t{mine.hi[k]};
    }
    comm.min(mins);
    LasRecordBlock all;
    all.count = static_cast<std::size_t>(sums[0]);
    std::copy(sums.begin() + 1, sums.end(), all.by_return.begin());
    for (std::size_t k = 0; k < 3 && all.count > 0; ++k) {
        all.lo[k] = static_cast<std::int32_t>(mins[k]);
        all.hi[k] = static_cast<std::int32_t>(-mins[3 + k]);
    }
    return all;
}

/// One round's records of this rank: its blocks traced and encoded, back to back.
struct RoundRecords {
    std::vector<LasRecordBlock> blocks;
    std::vector<std::uint8_t> bytes;
    LasRecordBlock totals;      ///< of these records (bytes unused)
    std::uint64_t weather = 0;  ///< of these points, the weather's (BlockPoint::weather)
};

/// The survey's rounds. While the ranks exchange their byte counts and write round r, the pool
/// traces round r + 1 (on a thread of its own): the writing overlaps the tracing, as in a
/// one-process survey. One all_gather per round: the byte counts, or kFailed from a rank whose
/// tracing, progress callback or writing failed (then every rank agree_on_error()s).
class RoundWriter {
  public:
    RoundWriter(const detail::SurveySession& session, const LasWriter& encoder, SharedFile& file,
                Communicator& comm, std::size_t per_rank, ThreadPool& pool)
        : session_(session),
          encoder_(encoder),
          file_(file),
          comm_(comm),
          per_rank_(per_rank),
          pool_(pool) {}

    [[nodiscard]] std::size_t rounds() const {
        const std::size_t step = per_rank_ * static_cast<std::size_t>(comm_.size());
        return (session_.blocks() + step - 1) / step;
    }
    /// Every round; `after(r)` runs on this thread once this rank's round r is traced (the
    /// progress callback; it may throw). Returns the totals of this rank's records.
    LasRecordBlock run_all(std::uint64_t data_start,
                           const std::function<void(std::size_t)>& after) {
        std::future<void> next;
        if (rounds() > 0) {
            next = std::async(std::launch::async, [this] { trace(0, slots_[0]); });
        }
        std::uint64_t written = 0;
        LasRecordBlock totals;
        std::exception_ptr error;
        for (std::size_t r = 0; r < rounds(); ++r) {
            RoundRecords& mine = slots_[r % 2];
            try {
                next.get();
                after(r);
            } catch (...) {
                error = error ? error : std::current_exception();
            }
            if (!error && r + 1 < rounds()) {
                next = std::async(std::launch::async,
                                  [this, r] { trace(r + 1, slots_[(r + 1) % 2]); });
            }
            const auto sizes = comm_.all_gather(error ? kFailed : mine.bytes.size());
            if (std::find(sizes.begin(), sizes.end(), kFailed) != sizes.end()) {
                if (next.valid()) {
                    next.wait();  // its own error, if any, is not needed: one is enough
                }
                agree_on_error(comm_, error);
            }
            std::uint64_t before = 0, all = 0;
            for (std::size_t k = 0; k < sizes.size(); ++k) {
                before += k < static_cast<std::size_t>(comm_.rank()) ? sizes[k] : 0;
                all += sizes[k];
            }
            try {
                file_.write_at(data_start + written + before, mine.bytes);
            } catch (...) {
                error = std::current_exception();  // reported at the next exchange
            }
            las_add_totals(totals, mine.totals);
            weather_ += mine.weather;
            written += all;
        }
        agree_on_error(comm_, error);
        return totals;
    }
    /// This rank's points of the weather (run_all's rounds).
    [[nodiscard]] std::uint64_t weather_points() const { return weather_; }

  private:
    static constexpr std::uint64_t kFailed = std::numeric_limits<std::uint64_t>::max();

    /// This rank's blocks of round r traced and encoded into `out` (on the pool).
    void trace(std::size_t r, RoundRecords& out) {
        const std::size_t first =
            (r * static_cast<std::size_t>(comm_.size()) + static_cast<std::size_t>(comm_.rank())) *
            per_rank_;
        const std::size_t end = std::min(session_.blocks(), first + per_rank_);
        const std::size_t count = end > first ? end - first : 0;
        out.blocks.resize(std::max(out.blocks.size(), count));
        std::atomic<std::uint64_t> weather{0};
        pool_.parallel_for(count, 1, [&](std::size_t b, std::size_t e) {
            std::unique_ptr<detail::BlockWork> w = shelf_.take();
            for (std::size_t k = b; k < e; ++k) {
                session_.run_block(first + k, *w);
                out.blocks[k].clear();
                for (const BlockPoint& p : w->points.points) {
                    encoder_.encode(static_cast<const LasSimplePoint&>(p), out.blocks[k]);
                }
                encode_las_extra_bytes(session_.facts().extra_bytes, w->points.points, encoder_,
                                       out.blocks[k]);
                weather += static_cast<std::uint64_t>(
                    std::count_if(w->points.points.begin(), w->points.points.end(),
                                  [](const BlockPoint& p) { return p.weather != 0; }));
            }
            shelf_.put(std::move(w));
        });
        out.bytes.clear();
        out.totals = LasRecordBlock{};
        out.weather = weather;
        for (std::size_t k = 0; k < count; ++k) {
            const LasRecordBlock& block = out.blocks[k];
            const std::size_t size = block.count * encoder_.header().point_record_length;
            out.bytes.insert(out.bytes.end(), block.bytes.begin(),
                             block.bytes.begin() + static_cast<std::ptrdiff_t>(size));
            las_add_totals(out.totals, block);
        }
    }

    const detail::SurveySession& session_;
    const LasWriter& encoder_;
    SharedFile& file_;
    Communicator& comm_;
    std::size_t per_rank_;
    ThreadPool& pool_;
    detail::WorkShelf shelf_;
    RoundRecords slots_[2];
    std::uint64_t weather_ = 0;
};

/// The ranks write points.las together: no in-memory outputs (SurveyRunConfig::extra_sinks).
void refuse_memory_outputs(const SurveyRunConfig& run) {
    if (!run.write_files || !run.extra_sinks.empty()) {
        throw ConfigError(
            "surveys across processes write files only: no extra sinks, "
            "write_files on");
    }
}

}  // namespace

namespace {

/// Collective: rank 0 makes the output folder (`created` removes it again if the run fails).
void make_output_dir(Communicator& comm, const std::filesystem::path& dir,
                     std::optional<CreatedDirs>& created) {
    collectively(comm, [&] {
        if (comm.rank() == 0) {
            created.emplace(dir);
            std::error_code ec;
            std::filesystem::create_directories(dir, ec);
            if (ec || !std::filesystem::is_directory(dir)) {
                throw OutputError(dir.string() + ": cannot create output directory" +
                                  (ec ? ": " + ec.message() : std::string()));
            }
        }
    });
}

/// Collective: the records of every round into `file`, then the header (rank 0); returns the
/// totals of all ranks' records, and their points of the weather in `weather_points`.
LasRecordBlock write_points(const detail::SurveySession& session, const SurveyRunConfig& run,
                            Communicator& comm, SharedFile& file, ThreadPool& pool,
                            const ProgressFn& progress, std::uint64_t& weather_points) {
    const LasWriter encoder(survey_las_config(session.facts()));
    const std::size_t per_rank = std::max<std::size_t>(
        1, (run.chunk_pulses + detail::kBlockPulses - 1) / detail::kBlockPulses);
    RoundWriter rounds(session, encoder, file, comm, per_rank, pool);
    // The progress callback (it may throw: an interrupt) and the cancel check, after each of
    // this rank's rounds is traced.
    const std::uint64_t pulses = session.pulses();
    const auto report = [&](std::uint64_t done) {
        if (progress) {
            progress(static_cast<std::size_t>(std::min(done, pulses)),
                     static_cast<std::size_t>(pulses));
        }
        throw_if_cancelled(run.cancel, "survey");
    };
    collectively(comm, [&] { report(0); });
    const LasRecordBlock mine =
        rounds.run_all(encoder.header().offset_to_point_data, [&](std::size_t r) {
            report((r + 1) * per_rank * detail::kBlockPulses *
                   static_cast<std::uint64_t>(comm.size()));
        });
    const LasRecordBlock totals = reduce_totals(comm, mine);
    std::uint64_t weather[1] = {rounds.weather_points()};
    comm.sum(weather);
    weather_points = weather[0];
    collectively(comm, [&] {
        if (comm.rank() == 0) {
            file.write_at(0, encoder.header_bytes(totals));
        }
    });
    collectively(comm, [&] { file.close(); });
    return totals;
}

/// Collective: rank 0 writes trajectory.csv and renames `temp` to `final_path`; returns the
/// files (rank 0; none on the others).
std::vector<std::filesystem::path> commit_outputs(const SurveySpec& spec, const SinkFacts& facts,
                                                  Communicator& comm,
                                                  const std::filesystem::path& temp,
                                                  const std::filesystem::path& final_path) {
    std::vector<std::filesystem::path> files;
    collectively(comm, [&] {
        if (comm.rank() != 0) {
            return;
        }
        SurveySpec others = spec;
        others.outputs.clear();  // the sinks that are not switchable: trajectory.csv
        detail::SinkSet sinks = detail::open_survey_sinks(others, facts);
        files = sinks.commit();
        std::error_code ec;
        std::filesystem::rename(temp, final_path, ec);
        if (ec) {
            for (const auto& f : files) {
                std::filesystem::remove(f, ec);
            }
            throw OutputError(final_path.string() + ": cannot rename into place: " + ec.message());
        }
        files.insert(files.begin(), final_path);
    });
    return files;
}

}  // namespace

SurveyResult run_survey_distributed(const SurveySpec& spec, const SurveyRunConfig& run,
                                    Communicator& comm, const ProgressFn& progress) {
    if (run.output_dir.empty()) {
        throw ConfigError("no output directory");
    }
    refuse_memory_outputs(run);
    ThreadPool pool(run.threads);
    std::unique_ptr<detail::SurveySession> session;
    collectively(comm, [&] {
        throw_if_cancelled(run.cancel, "survey");
        session = std::make_unique<detail::SurveySession>(spec, run, pool);
        check_outputs(spec, session->facts());
    });
    SurveyResult result = session->result();
    std::optional<CreatedDirs> created;
    make_output_dir(comm, run.output_dir, created);
    const std::string token = shared_token(comm);
    check_shared_directory(comm, run.output_dir, token);
    const std::filesystem::path temp = run.output_dir / (".points.las." + token + ".tmp");
    const auto t0 = Clock::now();
    try {
        std::unique_ptr<SharedFile> file;
        collectively(comm, [&] { file = comm.open_shared(temp); });
        std::uint64_t weather_points = 0;
        result.points =
            write_points(*session, run, comm, *file, pool, progress, weather_points).count;
        if (spec.physics && spec.physics->weather) {
            result.weather_points = weather_points;  // every rank's
        }
        result.outputs =
            commit_outputs(spec, session->facts(), comm, temp, run.output_dir / "points.las");
    } catch (...) {
        std::error_code ec;
        if (comm.rank() == 0) {
            std::filesystem::remove(temp, ec);
        }
        throw;
    }
    if (created) {
        created->keep();
    }
    result.survey_s = std::chrono::duration<double>(Clock::now() - t0).count();
    if (std::find(spec.outputs.begin(), spec.outputs.end(), "preview") != spec.outputs.end()) {
        result.notes.emplace_back("preview.png: not made by a survey across MPI ranks");
    }
    result.few_points_reasons = session->diagnose(result.points, pool);
    return result;
}

}  // namespace beamtrace
