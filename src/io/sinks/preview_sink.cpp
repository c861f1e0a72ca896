// preview.png: a quick look at a survey's points from straight above, north up. The highest
// point of each pixel (the survey's footprint, from its pilot, or the scene's, on
// kPreviewPixels across; points beyond it are left out) coloured by height (jet,
// blue low) and hill-shaded from the north-west, short gaps between scan lines closed, cropped
// to the data, with a scale bar. Written at commit; the summary names its scale and heights.
// The encoding threads (the pool's, or the writer thread of its own) find the pixels of their
// blocks' points; the writer raises those pixels in the one raster, block after block.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/io/png_writer.hpp"
#include "beamtrace/io/point_sink.hpp"
#include "io/sinks/preview_font.hpp"
#include "io/sinks/preview_shading.hpp"
#include "io/sinks/raster_cells.hpp"
#include "io/sinks/raster_text.hpp"

namespace beamtrace {

namespace {

constexpr int kPreviewPixels = 1024;  ///< the footprint's longer side, before cropping
constexpr int kGapPixels = 2;         ///< runs of empty pixels closed between two hits
constexpr float kEmpty = -std::numeric_limits<float>::infinity();
constexpr std::size_t kPrefetchAhead = 8;  ///< points between a pixel's prefetch and its raise

/// What encode() finds for write(): the block's points that fall on the raster, as pixel and
/// height.
struct PreviewBuffer final : SinkBuffer {
    std::vector<std::uint32_t> pixel;
    std::vector<float> height;
    void clear() override {}
};

/// Heights of pixels, rows from the north edge down.
struct Raster {
    int width = 1, height = 1;
    double cell_m = 1.0, west = 0.0, north = 0.0;
    std::vector<float> z;
    [[nodiscard]] float at(int x, int y) const {
        return z[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                 static_cast<std::size_t>(x)];
    }
    float& at(int x, int y) {
        return z[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                 static_cast<std::size_t>(x)];
    }
};

/// kPreviewPixels across the longer side of [lo, hi], or coarser: 1.5 mean point spacings
/// where `points` would leave finer pixels mostly empty.
Raster raster_for(const Vec3d& lo, const Vec3d& hi, std::uint64_t points) {
    Raster r;
    const double dx = std::max(hi.x - lo.x, 1e-6), dy = std::max(hi.y - lo.y, 1e-6);
    const double spacing = points > 0 ? std::sqrt(dx * dy / static_cast<double>(points)) : 0.0;
    r.cell_m = std::max(std::max(dx, dy) / kPreviewPixels, 1.5 * spacing);
    r.width = std::clamp(static_cast<int>(std::ceil(dx / r.cell_m)), 1, kPreviewPixels);
    r.height = std::clamp(static_cast<int>(std::ceil(dy / r.cell_m)), 1, kPreviewPixels);
    r.west = lo.x;
    r.north = hi.y;
    r.z.assign(static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height), kEmpty);
    return r;
}

/// close_gaps() on lines [l0, l1).
void close_gaps(Raster& r, bool rows, int l0, int l1) {
    const int n = rows ? r.width : r.height;
    for (int l = l0; l < l1; ++l) {
        int last = -1;
        for (int k = 0; k < n; ++k) {
            const float z = rows ? r.at(k, l) : r.at(l, k);
            if (z == kEmpty) {
                continue;
            }
            if (last >= 0 && k - last - 1 > 0 && k - last - 1 <= kGapPixels) {
                const float fill = std::min(z, rows ? r.at(last, l) : r.at(l, last));
                for (int j = last + 1; j < k; ++j) {
                    (rows ? r.at(j, l) : r.at(l, j)) = fill;
                }
            }
            last = k;
        }
    }
}

/// Runs f(begin, end) over [0, n) in two halves, the second on a thread of its own where the
/// machine has a second core: the commit's work per line or pixel, each independent of the
/// others (the result does not depend on the split). The survey's pool is idle by then.
template <class F>
void in_halves(std::size_t n, const F& f) {
    if (n >= 64 && available_cores() >= 2) {
        std::thread other;
        try {
            other = std::thread([&] { f(n / 2, n); });
        } catch (const std::system_error&) {  // no thread to be had: all on this one
            f(0, n);
            return;
        }
        f(0, n / 2);
        other.join();
        return;
    }
    f(0, n);
}

/// Closes runs of at most kGapPixels empty pixels between two hits along a row (dx = 1) or a
/// column (dx = 0) at the lower of the two heights.
void close_gaps(Raster& r, bool rows) {
    const int lines = rows ? r.height : r.width;
    in_halves(static_cast<std::size_t>(lines), [&](std::size_t l0, std::size_t l1) {
        close_gaps(r, rows, static_cast<int>(l0), static_cast<int>(l1));
    });
}

struct Crop {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< [x0, x1) x [y0, y1)
    float z_lo = 0.0f, z_hi = 0.0f;
    [[nodiscard]] int width() const { return x1 - x0; }
    [[nodiscard]] int height() const { return y1 - y0; }
};

/// The hits' box with a margin, and their height range; nullopt without hits.
std::optional<Crop> crop_of(const Raster& r) {
    Crop c{r.width, r.height, -1, -1, std::numeric_limits<float>::infinity(), kEmpty};
    for (int y = 0; y < r.height; ++y) {
        for (int x = 0; x < r.width; ++x) {
            if (const float z = r.at(x, y); z != kEmpty) {
                c = {std::min(c.x0, x),     std::min(c.y0, y),   std::max(c.x1, x + 1),
                     std::max(c.y1, y + 1), std::min(c.z_lo, z), std::max(c.z_hi, z)};
            }
        }
    }
    if (c.x1 < 0) {
        return std::nullopt;
    }
    const int margin = std::max(8, std::max(c.width(), c.height()) / 50);
    c.x0 = std::max(0, c.x0 - margin);
    c.y0 = std::max(0, c.y0 - margin);
    c.x1 = std::min(r.width, c.x1 + margin);
    c.y1 = std::min(r.height, c.y1 + margin);
    return c;
}

/// The 1-2-5 length nearest below a quarter of `width_m`, and its text ("50 m", "2 km").
std::pair<double, std::string> scale_bar_length(double width_m) {
    const double want = width_m / 4.0;
    double step = std::pow(10.0, std::floor(std::log10(want)));
    for (const double m : {5.0, 2.0, 1.0}) {
        if (m * step <= want) {
            step *= m;
            break;
        }
    }
    char text[32];
    if (step >= 1000.0) {
        std::snprintf(text, sizeof text, "%g km", step / 1000.0);
    } else {
        std::snprintf(text, sizeof text, "%g m", step);
    }
    return {step, text};
}

/// A white bar with a black edge and its length above it, at the bottom left.
void draw_scale_bar(std::vector<std::uint8_t>& rgb, int w, int h, double cell_m) {
    const auto [length_m, text] = scale_bar_length(w * cell_m);
    const int px = static_cast<int>(std::lround(length_m / cell_m));
    const int s = w >= 400 ? 2 : 1;
    const int x0 = 6 * s, y0 = h - 8 * s, thick = 2 * s;
    if (px < 4 || h < 40 * s) {
        return;
    }
    for (int y = y0 - 1; y <= y0 + thick; ++y) {
        for (int x = x0 - 1; x <= x0 + px; ++x) {
            const bool edge = y == y0 - 1 || y == y0 + thick || x == x0 - 1 || x == x0 + px;
            detail::put_pixel(rgb, w, h, x, y,
                              edge ? std::array<std::uint8_t, 3>{0, 0, 0}
                                   : std::array<std::uint8_t, 3>{255, 255, 255});
        }
    }
    const int ty = y0 - (detail::kGlyphHeight + 3) * s;
    for (const auto& [dx, dy] : {std::pair{1, 1}, {-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
        detail::draw_text(rgb, w, h, x0 + dx, ty + dy, s, text, {0, 0, 0});
    }
    detail::draw_text(rgb, w, h, x0, ty, s, text, {255, 255, 255});
}

/// The pixels of rows [y0, y1) of the crop into `rgb` (shade_preview_row()).
void render_rows(const Raster& r, const Crop& c, int y0, int y1, std::vector<std::uint8_t>& rgb) {
    const detail::PreviewShading shading{static_cast<double>(c.z_lo),
                                         static_cast<double>(c.z_hi) - static_cast<double>(c.z_lo),
                                         r.cell_m};
    const auto line = [&](int y) { return &r.z[static_cast<std::size_t>(y) * r.width]; };
    for (int y = y0; y < y1; ++y) {
        const detail::PreviewRows rows{line(std::max(y - 1, 0)), line(y),
                                       line(std::min(y + 1, r.height - 1)), r.width, kEmpty};
        detail::shade_preview_row(rows, shading, c.x0, c.x1,
                                  rgb.data() + 3 * static_cast<std::size_t>(y - c.y0) * c.width());
    }
}

/// The first row draw_scale_bar() may touch: its text's top, the text's outline included.
int scale_bar_top(int w, int h) {
    const int s = w >= 400 ? 2 : 1;
    return std::max(0, h - 8 * s - (detail::kGlyphHeight + 3) * s - 1);
}

/// Rows rendered at a time: a strip, the unit of the rendering's hand-off to the compression.
constexpr int kStripRows = 16;

/// The crop's image, with the scale bar, as `path`: rendered in strips of rows by this thread and
/// a second one (where the machine has a second core) while this one compresses the rows done,
/// rendering a strip itself whenever the next row is not yet done. The compression (serial)
/// overlaps the rendering; each row is the same as rendered whole, so are the file's bytes.
void render_and_write(const std::filesystem::path& path, const Raster& r, const Crop& c) {
    const int w = c.width(), h = c.height();
    std::vector<std::uint8_t> rgb(3 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h),
                                  40);
    const int strips = (h + kStripRows - 1) / kStripRows;
    std::atomic<int> next{0};
    std::vector<std::atomic<bool>> done(static_cast<std::size_t>(strips));
    const auto render_next = [&] {  // false when every strip is taken
        const int s = next.fetch_add(1);
        if (s >= strips) {
            return false;
        }
        render_rows(r, c, c.y0 + s * kStripRows, c.y0 + std::min(h, (s + 1) * kStripRows), rgb);
        done[static_cast<std::size_t>(s)].store(true, std::memory_order_release);
        done[static_cast<std::size_t>(s)].notify_all();
        return true;
    };
    std::thread other;
    if (h >= 4 * kStripRows && available_cores() >= 2) {
        try {
            other = std::thread([&] {
                while (render_next()) {
                }
            });
        } catch (const std::system_error&) {  // no thread to be had: all on this one
        }
    }
    const struct Join {
        std::thread& t;
        ~Join() {
            if (t.joinable()) {
                t.join();
            }
        }
    } join{other};
    const int bar_top = scale_bar_top(w, h);
    int ready = 0;  // strips [0, ready) are done
    write_png_rgb8_rows(path, w, h, rgb, [&](int y) {
        // The scale bar's rows wait for every row, then the bar is drawn over them.
        const int need = y < bar_top ? y / kStripRows + 1 : strips;
        for (; ready < need; ++ready) {
            std::atomic<bool>& d = done[static_cast<std::size_t>(ready)];
            while (!d.load(std::memory_order_acquire) && render_next()) {
            }
            d.wait(false, std::memory_order_acquire);
        }
        if (y == bar_top) {
            draw_scale_bar(rgb, w, h, r.cell_m);
        }
    });
}

class PreviewSink final : public PointSink {
  public:
    explicit PreviewSink(const SinkFacts& facts)
        : path_(facts.output_dir / "preview.png"),
          raster_(facts.footprint_m ? raster_for(facts.footprint_m->first,
                                                 facts.footprint_m->second, facts.pulses)
                                    : raster_for(facts.lo_m, facts.hi_m, facts.pulses)) {}

    [[nodiscard]] std::unique_ptr<SinkBuffer> make_buffer() const override {
        return std::make_unique<PreviewBuffer>();
    }
    /// The pixel and height of each point of `block` that falls on the raster; any thread, blocks
    /// in any order.
    void encode(const PointBlock& block, SinkBuffer& out) const override {
        pixels_of(block, static_cast<PreviewBuffer&>(out));
    }
    /// Raises each pixel that encode() found to its point's height, in the raster itself: one
    /// thread at a time, blocks in order (the maximum would not depend on the order: -0 is taken
    /// as +0, so not even its sign does). A survey's points land all over a raster of several MB
    /// (a spinning scanner's beams fan out from the car), so each raise would be a cache miss: the
    /// pixel kPrefetchAhead points on is fetched meanwhile.
    void write(const SinkBuffer& encoded) override {
        const auto& b = static_cast<const PreviewBuffer&>(encoded);
        float* z = raster_.z.data();
        const std::uint32_t* pixel = b.pixel.data();
        const float* height = b.height.data();
        const std::size_t n = b.pixel.size();
        for (std::size_t i = 0; i < n; ++i) {
            if (i + kPrefetchAhead < n) {
                __builtin_prefetch(z + pixel[i + kPrefetchAhead], 1);
            }
            float& p = z[pixel[i]];
            p = height[i] > p ? height[i] : p;
        }
    }
    std::vector<std::filesystem::path> commit() override {
        close_gaps(raster_, true);
        close_gaps(raster_, false);
        const auto crop = crop_of(raster_);
        if (!crop) {
            notes_.emplace_back("preview.png: not written (no point)");
            return {};
        }
        render_and_write(path_, raster_, *crop);
        char line[256];
        std::snprintf(line, sizeof line,
                      "preview.png: %d x %d pixels of %.3g m, north up, heights %.2f to %.2f m "
                      "(jet: blue low), scale bar %s",
                      crop->width(), crop->height(), raster_.cell_m, crop->z_lo, crop->z_hi,
                      scale_bar_length(crop->width() * raster_.cell_m).second.c_str());
        notes_.emplace_back(line);
        return {path_};
    }
    /// The commit is work for the CPU (gaps, shading, compressing), on this sink alone.
    [[nodiscard]] bool commits_beside() const override { return true; }
    void abort() noexcept override {}  // nothing is written before commit()
    [[nodiscard]] std::vector<std::string> notes() const override { return notes_; }

  private:
    /// The pixel and height of each point of `block` that falls on the raster, in block order,
    /// into `out`.
    void pixels_of(const PointBlock& block, PreviewBuffer& out) const {
        out.pixel.resize(block.points.size());
        out.height.resize(block.points.size());
        std::size_t n = 0;
        const double per_cell = 1.0 / raster_.cell_m;
        for (const BlockPoint& p : block.points) {
            double uv[2];
            detail::cells_floor_pair(p.x - raster_.west, raster_.north - p.y, raster_.cell_m,
                                     per_cell, uv);
            const double u = uv[0], v = uv[1];
            if (u >= 0 && v >= 0 && u < raster_.width && v < raster_.height) {
                const auto pixel = static_cast<std::uint32_t>(v * raster_.width + u);
                out.pixel[n] = pixel;
                out.height[n] = static_cast<float>(p.z) + 0.0f;
                ++n;
            }
        }
        out.pixel.resize(n);
        out.height.resize(n);
    }
    std::filesystem::path path_;
    Raster raster_;  ///< its heights raised by write(), allocated (and touched) when opened
    std::vector<std::string> notes_;
};

}  // namespace

std::unique_ptr<PointSink> make_preview_sink(const SinkFacts& facts) {
    return std::make_unique<PreviewSink>(facts);
}

}  // namespace beamtrace
