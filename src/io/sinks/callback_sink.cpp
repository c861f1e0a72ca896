// The callback sink (io/callback_sink.hpp): the points of each block, rounded on the pool threads
// as points.las stores them, handed to a function on the writer thread.
#include "beamtrace/io/callback_sink.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_writer.hpp"

namespace beamtrace {
namespace {

struct PointBuffer final : SinkBuffer {
    std::vector<BlockPoint> points;
    void clear() override { points.clear(); }
};

/// The grid of points.las: scale and offset per axis.
struct LasGrid {
    Vec3d scale, offset, steps_per_unit;

    explicit LasGrid(const SinkFacts& facts) {
        // The LAS sink's scale and offset (src/io/sinks/las_sink.cpp).
        const LasWriterConfig las = las_config_for_extent(facts.lo_m, facts.hi_m, 0.001);
        scale = las.scale;
        offset = las.offset;
        for (std::size_t k = 0; k < 3; ++k) {
            steps_per_unit[k] = 1.0 / scale[k];  // as LasWriter quantises: a multiplication
        }
    }

    /// `v` on axis k as LasWriter stores it and LasReader decodes it.
    [[nodiscard]] double round(double v, std::size_t k) const {
        const double steps = (v - offset[k]) * steps_per_unit[k];
        if (!(steps > -2147483648.5 && steps < 2147483647.5)) {
            throw OutputError(
                std::string("in-memory points: ") + "xyz"[k] + " = " + std::to_string(v) +
                " does not fit in a 32-bit LAS coordinate (see las_config_for_extent)");
        }
        const auto q = static_cast<std::int32_t>(std::round(steps));  // halves away from zero
        return static_cast<double>(q) * scale[k] + offset[k];
    }
};

/// A scan angle as points.las stores it (a signed count of 0.006 degree) and reads it back.
float las_scan_angle(float deg) {
    const double steps = std::round(static_cast<double>(deg) * (1.0 / kScanAngleStepDeg));
    if (!(steps >= -30000.0 && steps <= 30000.0)) {
        throw OutputError("in-memory points: scan angle " + std::to_string(deg) +
                          " deg is outside [-180, 180]");
    }
    return static_cast<float>(static_cast<std::int16_t>(steps) * kScanAngleStepDeg);
}

class CallbackSink final : public PointSink {
  public:
    CallbackSink(const SinkFacts& facts, PointBlockFn fn) : grid_(facts), fn_(std::move(fn)) {}

    [[nodiscard]] std::unique_ptr<SinkBuffer> make_buffer() const override {
        return std::make_unique<PointBuffer>();
    }
    void encode(const PointBlock& block, SinkBuffer& out) const override {
        auto& points = static_cast<PointBuffer&>(out).points;
        points.assign(block.points.begin(), block.points.end());
        for (BlockPoint& p : points) {
            p.x = grid_.round(p.x, 0);
            p.y = grid_.round(p.y, 1);
            p.z = grid_.round(p.z, 2);
            p.scan_angle_deg = las_scan_angle(p.scan_angle_deg);
        }
    }
    void write(const SinkBuffer& encoded) override {
        if (fn_) {
            fn_(static_cast<const PointBuffer&>(encoded).points);
        }
    }
    std::vector<std::filesystem::path> commit() override {
        fn_ = nullptr;
        return {};
    }
    void abort() noexcept override { fn_ = nullptr; }

  private:
    LasGrid grid_;
    PointBlockFn fn_;
};

}  // namespace

std::unique_ptr<PointSink> make_callback_sink(const SinkFacts& facts, PointBlockFn fn) {
    return std::make_unique<CallbackSink>(facts, std::move(fn));
}

}  // namespace beamtrace
