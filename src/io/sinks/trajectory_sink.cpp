// trajectory.csv: the platform over the run, in world coordinates, sampled at
// output.trajectory_rate_hz (the samples come with the facts; points are ignored).
#include "beamtrace/io/point_sink.hpp"

namespace beamtrace {

namespace {

class TrajectorySink final : public PointSink {
  public:
    explicit TrajectorySink(const SinkFacts& facts)
        : path_(facts.output_dir / "trajectory.csv"),
          trajectory_(*facts.trajectory),
          rate_hz_(facts.trajectory_rate_hz) {}

    void encode(const PointBlock& /*block*/, SinkBuffer& /*out*/) const override {}
    void write(const SinkBuffer& /*encoded*/) override {}
    std::vector<std::filesystem::path> commit() override {
        write_trajectory_csv(path_, trajectory_, rate_hz_);
        return {path_};
    }
    void abort() noexcept override {}  // nothing is written before commit()

  private:
    std::filesystem::path path_;
    SampledTrajectory trajectory_;
    double rate_hz_;
};

}  // namespace

std::unique_ptr<PointSink> make_trajectory_sink(const SinkFacts& facts) {
    return std::make_unique<TrajectorySink>(facts);
}

}  // namespace beamtrace
