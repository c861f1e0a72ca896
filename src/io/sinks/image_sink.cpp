// range.npy, range.png and (for surveys) labels.png of an image scanner firing one frame: each
// pulse's first point is pixel (row v, column u) of pulse u * height + v; pixels without a
// point are 0 (black in the PNGs). labels.png shows each pixel's class in its ASPRS colour;
// range.png has a colour bar of its ranges below the image.
#include <cstdio>
#include <future>
#include <new>
#include <string>
#include <system_error>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/colormap.hpp"
#include "beamtrace/io/npy.hpp"
#include "beamtrace/io/png_writer.hpp"
#include "beamtrace/io/point_sink.hpp"

namespace beamtrace {

namespace {

struct Pixel {
    std::size_t index;
    float range_m;
    std::uint16_t label;
};

struct PixelBuffer final : SinkBuffer {
    std::vector<Pixel> pixels;
    void clear() override { pixels.clear(); }
};

class ImageSink final : public PointSink {
  public:
    explicit ImageSink(const SinkFacts& facts)
        : dir_(facts.output_dir),
          grid_(*facts.image),
          labels_(facts.image_labels),
          range_(static_cast<std::size_t>(grid_.width) * static_cast<std::size_t>(grid_.height),
                 0.0f),
          label_(labels_ ? range_.size() : 0, 0) {}

    [[nodiscard]] std::unique_ptr<SinkBuffer> make_buffer() const override {
        return std::make_unique<PixelBuffer>();
    }
    void encode(const PointBlock& block, SinkBuffer& out) const override {
        auto& pixels = static_cast<PixelBuffer&>(out).pixels;
        const auto h = static_cast<std::uint64_t>(grid_.height);
        for (std::size_t i = 0; i < block.points.size(); ++i) {
            const BlockPoint& p = block.points[i];
            if (i > 0 && block.points[i - 1].pulse == p.pulse) {
                continue;  // not the pulse's first point
            }
            const auto u = static_cast<std::size_t>(p.pulse / h);
            const auto v = static_cast<std::size_t>(p.pulse % h);
            if (u >= static_cast<std::size_t>(grid_.width)) {
                throw OutputError((dir_ / "range.npy").string() + ": pulse " +
                                  std::to_string(p.pulse) + " is outside the image");
            }
            pixels.push_back(
                {v * static_cast<std::size_t>(grid_.width) + u, p.range_m, p.classification});
        }
    }
    void write(const SinkBuffer& encoded) override {
        for (const Pixel& p : static_cast<const PixelBuffer&>(encoded).pixels) {
            range_[p.index] = p.range_m;
            if (labels_) {
                label_[p.index] = p.label;
            }
        }
    }
    std::vector<std::filesystem::path> commit() override {
        const int w = grid_.width, h = grid_.height;
        std::vector<std::filesystem::path> files{dir_ / "range.npy", dir_ / "range.png"};
        if (labels_) {
            files.push_back(dir_ / "labels.png");
        }
        // The PNGs beside the .npy (PNG compression is most of it: 40 ms of a 110 ms panorama
        // survey when written one after the other).
        std::string note;
        auto png =
            std::async(std::launch::async, [&] { note = write_range_png(files[1], range_, w, h); });
        auto labels = std::async(std::launch::async, [&] {
            if (labels_) {
                write_png_rgb8(files[2], w, h, class_image_rgb(label_, range_, w, h));
            }
        });
        try {
            write_npy_f32(files[0], static_cast<std::size_t>(h), static_cast<std::size_t>(w),
                          range_);
        } catch (...) {
            png.wait();
            labels.wait();
            remove(files);
            throw;
        }
        try {
            png.get();
            labels.get();
        } catch (...) {
            labels.wait();
            remove(files);
            throw;
        }
        notes_.push_back(std::move(note));
        return files;
    }
    void abort() noexcept override {}  // nothing is written before commit()
    [[nodiscard]] std::vector<std::string> notes() const override { return notes_; }

  private:
    /// After a failure: none of the three is left.
    static void remove(const std::vector<std::filesystem::path>& files) noexcept {
        for (const auto& f : files) {
            std::error_code ignored;
            std::filesystem::remove(f, ignored);
        }
    }

    std::filesystem::path dir_;
    ImageGrid grid_;
    bool labels_;
    std::vector<float> range_;
    std::vector<std::uint16_t> label_;
    std::vector<std::string> notes_;
};

}  // namespace

std::unique_ptr<PointSink> make_image_sink(const SinkFacts& facts) {
    try {
        return std::make_unique<ImageSink>(facts);
    } catch (const std::bad_alloc&) {
        // The images are held whole (ImagePatternConfig::validate bounds their size).
        throw OutputError((facts.output_dir / "range.npy").string() + ": out of memory for the " +
                          std::to_string(facts.image->width) + " x " +
                          std::to_string(facts.image->height) +
                          " range and label images (the scanner's width x height)");
    }
}

}  // namespace beamtrace
