// One survey on many processes (MPI ranks, or any Communicator): each rank traces a share of
// the pulses with its own threads, and all of them write ONE points.las together, byte for byte
// the file run_survey writes, for any number of ranks and threads per rank (docs/cluster.md).
#pragma once

#include "beamtrace/core/communicator.hpp"
#include "beamtrace/core/progress.hpp"
#include "beamtrace/pipeline/survey.hpp"

namespace beamtrace {

/// Runs `spec` on every rank of `comm`; every rank calls it with the same spec and run (same
/// seed, backend and output_dir, the latter on a file system all ranks share; run.threads is
/// each rank's own).
///
/// Blocks of 1024 pulses are dealt in rounds of size() x W blocks (W = run.chunk_pulses / 1024,
/// at least 1): rank i takes the W consecutive blocks i W.. of the round, so the ranks' records
/// of a round follow each other in the file; each rank encodes its records, all_gather of the
/// ranks' byte counts gives each its offset (the sum of the counts below it), and each writes
/// its part there (SharedFile::write_at) while the next round is traced.
/// The header (counts, counts by return, bounds) comes from reductions, written by rank 0 with
/// the VLRs. The file is written under a temporary name and renamed by rank 0 once every rank
/// has succeeded. trajectory.csv is written by rank 0; preview.png is not made (a note says so).
///
/// Errors are agreed on at every step: when any rank fails, every rank throws and nothing
/// appears. The failing rank rethrows its own error; the others throw the same kind of error
/// with the message of the lowest failing rank (so rank 0 alone can report it). Throws
/// ConfigError, on every rank, for outputs other than points.las, trajectory.csv and
/// preview.png, for kept waveforms and for image scanners.
///
/// `progress(done, total)` is called on every rank after each round with the pulses done by all
/// ranks; run.cancel is checked between rounds (any rank's request stops all of them).
/// Memory per rank: two rounds of W blocks of points and records (one traced while the other
/// is written).
[[nodiscard]] SurveyResult run_survey_distributed(const SurveySpec& spec,
                                                  const SurveyRunConfig& run, Communicator& comm,
                                                  const ProgressFn& progress = {});

}  // namespace beamtrace
