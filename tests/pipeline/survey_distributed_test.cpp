// run_survey_distributed: ranks as threads (thread_communicator.hpp) write one points.las that
// equals run_survey's byte for byte, for 1-3 ranks and 1-2 threads per rank; errors on any rank
// stop every rank and leave nothing; outputs the ranks cannot write together are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/pipeline/survey_distributed.hpp"
#include "pipeline/thread_communicator.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

/// The first 40 blocks of each survey: at 8 blocks per rank and round, 2 to 5 rounds.
constexpr std::uint64_t kPulses = 40 * 1024;

/// Example survey `name` (scene: demo), writing points.las and trajectory.csv only.
SurveySpec example(const std::string& name) {
    SurveySpec spec =
        load_survey_spec(fs::path(BEAMTRACE_EXAMPLES_DIR) / "surveys" / (name + ".yaml"));
    spec.outputs = {"las"};
    return spec;
}

/// Runs `spec` on `ranks` thread ranks with `threads` threads each into `dir`; returns the
/// message of every rank's error ("" for none), by rank.
std::vector<std::string> run_ranks(const SurveySpec& spec, const fs::path& dir, int ranks,
                                   unsigned threads, std::size_t chunk_pulses,
                                   const ProgressFn& progress_of_rank1 = {}) {
    std::vector<std::string> errors(static_cast<std::size_t>(ranks));
    test::ThreadWorld world(ranks);
    world.run([&](Communicator& comm) {
        SurveyRunConfig run;
        run.output_dir = dir;
        run.threads = threads;
        run.chunk_pulses = chunk_pulses;
        run.seed = 7;
        run.max_pulses = kPulses;
        try {
            (void)run_survey_distributed(spec, run, comm,
                                         comm.rank() == 1 ? progress_of_rank1 : ProgressFn{});
        } catch (const std::exception& e) {
            errors[static_cast<std::size_t>(comm.rank())] = e.what();
        }
    });
    return errors;
}

std::string single_process_las(const SurveySpec& spec, const fs::path& dir) {
    SurveyRunConfig run;
    run.output_dir = dir;
    run.threads = 2;
    run.seed = 7;
    run.max_pulses = kPulses;
    (void)run_survey(spec, run);
    return test::read_file(dir / "points.las");
}

TEST(SurveyDistributed, OneLasFileIdenticalToOneProcessForAnyRanksAndThreads) {
    for (const std::string name : {"car_hdl64", "airborne_line_physics"}) {
        SurveySpec spec = example(name);
        test::TempDir dir;
        const std::string expected = single_process_las(spec, dir / "single");
        const std::string trajectory = test::read_file(dir / "single" / "trajectory.csv");
        for (const int ranks : {1, 2, 3}) {
            for (const unsigned threads : {1u, 2u}) {
                SCOPED_TRACE(name + ": " + std::to_string(ranks) + " ranks x " +
                             std::to_string(threads) + " threads");
                const fs::path out = dir / (std::to_string(ranks) + "x" + std::to_string(threads));
                // 8 blocks per rank and round: many rounds, the last ones partly empty.
                const auto errors = run_ranks(spec, out, ranks, threads, 8 * 1024);
                for (const auto& e : errors) {
                    EXPECT_EQ(e, "");
                }
                EXPECT_TRUE(test::read_file(out / "points.las") == expected);
                EXPECT_EQ(test::read_file(out / "trajectory.csv"), trajectory);
                std::vector<std::string> files;
                for (const auto& f : fs::directory_iterator(out)) {
                    files.push_back(f.path().filename().string());
                }
                std::sort(files.begin(), files.end());
                EXPECT_EQ(files, (std::vector<std::string>{"points.las", "trajectory.csv"}));
            }
        }
    }
}

TEST(SurveyDistributed, ExtraBytesIdenticalToOneProcess) {
    SurveySpec spec = example("airborne_line_physics");
    spec.extra_bytes = {PointAttribute::range, PointAttribute::incidence_angle,
                        PointAttribute::echo_width, PointAttribute::beam,
                        PointAttribute::object_id};
    test::TempDir dir;
    const std::string expected = single_process_las(spec, dir / "single");
    const auto errors = run_ranks(spec, dir / "ranks", 2, 1, 8 * 1024);
    for (const auto& e : errors) {
        EXPECT_EQ(e, "");
    }
    const std::string got = test::read_file(dir / "ranks" / "points.las");
    EXPECT_TRUE(got == expected);
    // The records carry the extra bytes, and not as zeros.
    LasReader reader(dir / "ranks" / "points.las");
    EXPECT_EQ(reader.header().point_record_length, 30 + 14);
    std::vector<LasPoint> points(64);
    ASSERT_EQ(reader.read(points), 64u);
    EXPECT_NE(points[0].extra_bytes, std::vector<std::uint8_t>(14, 0));
}

// The summary's count of the weather's points is every rank's, not the rank's own: each rank
// reports the one-process run's count, and the ranks' file is that run's.
TEST(SurveyDistributed, WeatherPointsAreCountedOverEveryRank) {
    // The airborne flight with sub-rays in heavy rain (the weather examples' range camera is a
    // scanner the ranks refuse).
    SurveySpec spec = example("airborne_line_physics");
    ASSERT_TRUE(spec.physics.has_value());
    WeatherConfig weather;
    PrecipitationConfig rain;
    rain.rate_mm_h = 25.0;
    weather.precipitation = rain;
    spec.physics->weather = weather;
    constexpr std::uint64_t kWeatherPulses = 16 * 1024;
    test::TempDir dir;
    SurveyRunConfig one;
    one.output_dir = dir / "single";
    one.seed = 7;
    one.max_pulses = kWeatherPulses;
    const SurveyResult single = run_survey(spec, one);
    ASSERT_TRUE(single.weather_points.has_value());
    ASSERT_GT(*single.weather_points, 0u);
    ASSERT_LT(*single.weather_points, single.points);
    for (const int ranks : {2, 3}) {
        std::vector<std::optional<std::uint64_t>> counts(static_cast<std::size_t>(ranks));
        test::ThreadWorld world(ranks);
        world.run([&](Communicator& comm) {
            SurveyRunConfig run;
            run.output_dir = dir / std::to_string(ranks);
            run.seed = 7;
            run.threads = 1;
            run.chunk_pulses = 4 * 1024;  // several rounds
            run.max_pulses = kWeatherPulses;
            counts[static_cast<std::size_t>(comm.rank())] =
                run_survey_distributed(spec, run, comm).weather_points;
        });
        EXPECT_EQ(test::read_file(dir / std::to_string(ranks) / "points.las"),
                  test::read_file(dir / "single" / "points.las"));
        for (const auto& c : counts) {
            EXPECT_EQ(c, single.weather_points) << ranks << " ranks";
        }
    }
    // Without weather: no count.
    const SurveySpec clear = example("airborne_line_physics");
    test::ThreadWorld world(2);
    world.run([&](Communicator& comm) {
        SurveyRunConfig run;
        run.output_dir = dir / "clear";
        run.seed = 7;
        run.max_pulses = kWeatherPulses;
        EXPECT_FALSE(run_survey_distributed(clear, run, comm).weather_points.has_value());
    });
}

TEST(SurveyDistributed, AFailingRankStopsEveryRankAndLeavesNothing) {
    const SurveySpec spec = example("car_hdl64");
    test::TempDir dir;
    // Rank 1 fails after its second round.
    std::atomic<int> calls{0};
    const auto fail = [&](std::size_t, std::size_t) {
        if (++calls == 3) {
            throw OutputError("disk full (test)");
        }
    };
    const auto errors = run_ranks(spec, dir / "out", 3, 1, 4 * 1024, fail);
    EXPECT_EQ(errors[1], "disk full (test)");
    EXPECT_EQ(errors[0], "rank 1: disk full (test)");
    EXPECT_EQ(errors[2], "rank 1: disk full (test)");
    EXPECT_FALSE(fs::exists(dir / "out")) << "the folder the run made is removed with its files";
}

TEST(SurveyDistributed, OneRanksErrorReachesEveryRankWithItsKindAndMessage) {
    // Rank 2 alone fails (a file only its node cannot read); the others learn it at once.
    std::vector<std::string> kinds(3), messages(3);
    test::ThreadWorld world(3);
    world.run([&](Communicator& comm) {
        const auto r = static_cast<std::size_t>(comm.rank());
        agree_on_error(comm, nullptr);  // nobody failed: everyone goes on
        std::exception_ptr error;
        if (comm.rank() == 2) {
            error = std::make_exception_ptr(ConfigError("bad.yaml:3: scanner.preset: unknown"));
        }
        try {
            agree_on_error(comm, error);
            kinds[r] = "none";
        } catch (const ConfigError& e) {
            kinds[r] = "config";
            messages[r] = e.what();
        } catch (const std::exception& e) {
            kinds[r] = "other";
            messages[r] = e.what();
        }
    });
    for (std::size_t r = 0; r < 3; ++r) {
        EXPECT_EQ(kinds[r], "config") << r;
        EXPECT_EQ(messages[r], "bad.yaml:3: scanner.preset: unknown") << r;
    }
}

TEST(SurveyDistributed, OutputsTheRanksCannotWriteTogetherAreRefusedOnEveryRank) {
    SurveySpec spec = example("car_hdl64");
    spec.outputs = {"las", "csv"};
    test::TempDir dir;
    const auto errors = run_ranks(spec, dir / "out", 2, 1, 4 * 1024);
    for (const auto& e : errors) {
        EXPECT_NE(e.find("output.csv: not written by a survey across MPI ranks"), std::string::npos)
            << e;
    }
    EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(SurveyDistributed, HeaderOfRecordsPlacedApartEqualsTheWritersOwn) {
    // LasWriter's encoder and header_bytes: the same file as LasWriter writes itself.
    test::TempDir dir;
    LasWriterConfig config;
    config.creation_day_of_year = 100;
    config.creation_year = 2026;
    LasVlr vlr;
    vlr.user_id = "beamtrace";
    vlr.record_id = 1;
    vlr.description = "test";
    vlr.data = {'a', 'b'};
    config.vlrs.push_back(vlr);
    std::vector<LasPoint> points(5);
    for (std::size_t i = 0; i < points.size(); ++i) {
        points[i].x = 1.0 + double(i);
        points[i].y = -2.0 * double(i);
        points[i].z = 0.5;
        points[i].return_number = static_cast<std::uint8_t>(1 + i % 2);
        points[i].number_of_returns = 2;
    }
    {
        LasWriter writer(dir / "a.las", config);
        writer.write(points);
        writer.close();
    }
    const LasWriter encoder(config);
    LasRecordBlock records, totals;
    for (const auto& p : points) {
        encoder.encode(p, records);
    }
    las_add_totals(totals, records);
    std::vector<std::uint8_t> bytes = encoder.header_bytes(totals);
    bytes.insert(bytes.end(), records.bytes.begin(),
                 records.bytes.begin() + static_cast<std::ptrdiff_t>(
                                             records.count * encoder.header().point_record_length));
    EXPECT_EQ(std::string(bytes.begin(), bytes.end()), test::read_file(dir / "a.las"));
    LasWriter no_file(config);
    EXPECT_THROW(no_file.close(), OutputError);  // an encoder has no file to close
}

}  // namespace
}  // namespace beamtrace
