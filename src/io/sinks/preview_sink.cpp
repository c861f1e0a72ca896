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
#include "io/sinks/preview_cells.hpp"
#include "io/sinks/preview_font.hpp"
#include "io/sinks/preview_shading.hpp"
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

struct Crop {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< [x0, x1) x [y0, y1)
    float z_lo = 0.0f, z_hi = 0.0f;
    [[nodiscard]] int width() const { return x1 - x0; }
    [[nodiscard]] int height() const { return y1 - y0; }
};

/// No hit yet: a box and height range that any hit replaces.
constexpr Crop kNoHit{std::numeric_limits<int>::max(),
                      std::numeric_limits<int>::max(),
                      -1,
                      -1,
                      std::numeric_limits<float>::infinity(),
                      kEmpty};

/// The box and height range of the hits of both.
Crop merged(const Crop& a, const Crop& b) {
    return {std::min(a.x0, b.x0), std::min(a.y0, b.y0),     std::max(a.x1, b.x1),
            std::max(a.y1, b.y1), std::min(a.z_lo, b.z_lo), std::max(a.z_hi, b.z_hi)};
}

/// The box and height range of the hits of rows [y0, y1) (row_hits()).
Crop hits_of_rows(const Raster& r, int y0, int y1) {
    Crop c = kNoHit;
    for (int y = y0; y < y1; ++y) {
        const detail::RowHits h =
            detail::row_hits(&r.z[static_cast<std::size_t>(y) * r.width], r.width, kEmpty);
        if (h.first >= 0) {
            c = merged(c, {h.first, y, h.last + 1, y + 1, h.lo, h.hi});
        }
    }
    return c;
}

/// Closes runs of at most kGapPixels empty pixels between two hits along rows [y0, y1), columns
/// [box.x0, box.x1) (the hits' box: nothing to close outside it), at the lower of the two heights.
void close_row_gaps(Raster& r, const Crop& box, int y0, int y1) {
    for (int y = y0; y < y1; ++y) {
        float* row = &r.at(0, y);
        int last = -1;
        for (int x = box.x0; x < box.x1; ++x) {
            const float z = row[x];
            if (z == kEmpty) {
                continue;
            }
            if (last >= 0 && x - last - 1 > 0 && x - last - 1 <= kGapPixels) {
                const float fill = std::min(z, row[last]);
                std::fill(row + last + 1, row + x, fill);
            }
            last = x;
        }
    }
}

/// The same down columns [x0, x1), rows [box.y0, box.y1) walked in order (each column's last hit
/// kept) rather than each column down the raster: the same fills, the memory read in order.
void close_column_gaps(Raster& r, const Crop& box, int x0, int x1) {
    std::vector<int> last(static_cast<std::size_t>(x1 - x0), -1);
    for (int y = box.y0; y < box.y1; ++y) {
        const float* row = &r.at(0, y);
        for (int x = x0; x < x1; ++x) {
            const float z = row[x];
            if (z == kEmpty) {
                continue;
            }
            int& l = last[static_cast<std::size_t>(x - x0)];
            if (l >= 0 && y - l - 1 > 0 && y - l - 1 <= kGapPixels) {
                const float fill = std::min(z, r.at(x, l));
                for (int j = l + 1; j < y; ++j) {
                    r.at(x, j) = fill;
                }
            }
            l = y;
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

/// Closes runs of at most kGapPixels empty pixels between two hits along each row, then along
/// each column, at the lower of the two heights; returns the hits' box with a margin, and their
/// height range (nullopt without hits). The box and range are the same before and after: the
/// closing fills between two hits at one of their heights.
std::optional<Crop> close_gaps_and_crop(Raster& r) {
    Crop halves[2] = {kNoHit, kNoHit};
    in_halves(static_cast<std::size_t>(r.height), [&](std::size_t y0, std::size_t y1) {
        halves[y0 == 0 ? 0 : 1] = hits_of_rows(r, static_cast<int>(y0), static_cast<int>(y1));
    });
    Crop c = merged(halves[0], halves[1]);
    if (c.x1 < 0) {
        return std::nullopt;
    }
    in_halves(static_cast<std::size_t>(c.height()), [&](std::size_t a, std::size_t b) {
        close_row_gaps(r, c, c.y0 + static_cast<int>(a), c.y0 + static_cast<int>(b));
    });
    in_halves(static_cast<std::size_t>(c.width()), [&](std::size_t a, std::size_t b) {
        close_column_gaps(r, c, c.x0 + static_cast<int>(a), c.x0 + static_cast<int>(b));
    });
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
        const auto crop = close_gaps_and_crop(raster_);
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
    /// into `out` (preview_cells()).
    void pixels_of(const PointBlock& block, PreviewBuffer& out) const {
        out.pixel.resize(block.points.size());
        out.height.resize(block.points.size());
        const detail::PreviewGrid grid{raster_.west,         raster_.north, raster_.cell_m,
                                       1.0 / raster_.cell_m, raster_.width, raster_.height};
        const std::size_t n =
            detail::preview_cells(block.points, grid, out.pixel.data(), out.height.data());
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
