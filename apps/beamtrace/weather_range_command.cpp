// `beamtrace weather-range`: the maximum detection range of Lambertian targets against the fog's
// meteorological optical range (max_detection_range_in_fog_m, physics/weather.hpp), as a PNG plot
// (log MOR axis, one curve per reflectance) and a CSV table (docs/weather.md).
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/png_writer.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/physics/weather.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "commands.hpp"
#include "io/sinks/raster_text.hpp"

namespace beamtrace::cli {
namespace {

using detail::Rgb8Pixel;

struct WeatherRangeOptions {
    std::string survey;  ///< a survey file whose physics gives the range equation's constants
    std::vector<double> reflectances{0.1, 0.5};
    double mor_min_m = 20.0, mor_max_m = 2000.0;
    int points = 50;     ///< rows of the CSV per reflectance
    std::string output;  ///< the PNG plot; empty: none
    std::string csv;     ///< the table; empty: none ("-": standard output)
};

/// The physics whose radiometry and air the curves use: the survey's, or the defaults.
PhysicsConfig physics_of(const WeatherRangeOptions& o) {
    if (o.survey.empty()) {
        return PhysicsConfig{};
    }
    const SurveySpec spec = load_survey_spec(o.survey);
    return spec.physics.value_or(PhysicsConfig{});
}

/// The shortest text that reads back as `v` (0.1, 2000, 63.245553203367592).
std::string number_text(double v) {
    char buf[64];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
    return ec == std::errc() ? std::string(buf, end) : std::string("?");
}

void check(const WeatherRangeOptions& o) {
    if (!(o.mor_min_m > 0.0 && o.mor_max_m > o.mor_min_m) || !std::isfinite(o.mor_max_m)) {
        throw ConfigError(
            "weather-range: --mor-min and --mor-max must be positive metres, "
            "--mor-min below --mor-max");
    }
    if (o.points < 2 || o.points > 100000) {
        throw ConfigError("weather-range: --points must be 2 to 100000");
    }
    for (const double rho : o.reflectances) {
        if (!(rho > 0.0 && rho <= 1.0)) {
            throw ConfigError("weather-range: --reflectance " + number_text(rho) +
                              ": must be in (0, 1]");
        }
    }
}

/// MOR at the fraction `t` of the log axis from mor_min_m (0) to mor_max_m (1).
double mor_at(const WeatherRangeOptions& o, double t) {
    return o.mor_min_m * std::pow(o.mor_max_m / o.mor_min_m, t);
}

/// `reflectance,mor_m,max_range_m` rows, `points` MORs per reflectance evenly spaced in log MOR,
/// each number in its shortest text that reads back as the double it is.
std::string csv_table(const WeatherRangeOptions& o, const PhysicsConfig& p) {
    std::string text = "reflectance,mor_m,max_range_m\n";
    for (const double rho : o.reflectances) {
        for (int k = 0; k < o.points; ++k) {
            const double mor = mor_at(o, k / static_cast<double>(o.points - 1));
            const double r = max_detection_range_in_fog_m(p.radiometry, p.atmosphere, rho, mor);
            text += number_text(rho) + "," + number_text(mor) + "," + number_text(r) + "\n";
        }
    }
    return text;
}

/// The plot's frame: the image and where the axes' box lies in it.
struct Plot {
    static constexpr int kWidth = 720, kHeight = 440;
    static constexpr int kLeft = 84, kRight = 660, kTop = 20, kBottom = 390;
    std::vector<std::uint8_t> rgb = std::vector<std::uint8_t>(3 * kWidth * kHeight, 255);
    double range_max_m = 1.0;  ///< the top of the vertical axis

    void pixel(int x, int y, Rgb8Pixel c) { detail::put_pixel(rgb, kWidth, kHeight, x, y, c); }
    void text(int x, int y, const std::string& s, Rgb8Pixel c) {
        detail::draw_text(rgb, kWidth, kHeight, x, y, 2, s, c);
    }
    [[nodiscard]] int y_of(double range_m) const {
        return kBottom - static_cast<int>(std::lround((kBottom - kTop) * range_m / range_max_m));
    }
};

constexpr Rgb8Pixel kBlack{0, 0, 0}, kGrid{225, 225, 225};
constexpr std::array<Rgb8Pixel, 6> kCurveColours{
    {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {255, 127, 14}, {148, 103, 189}, {140, 86, 75}}};

/// The tick step of a linear axis up to `top`: 1, 2 or 5 x 10^k, four to ten ticks.
double tick_step(double top) {
    const double decade = std::pow(10.0, std::floor(std::log10(top / 4.0)));
    for (const double m : {1.0, 2.0, 5.0, 10.0}) {
        if (top / (m * decade) <= 10.0) {
            return m * decade;
        }
    }
    return 10.0 * decade;
}

/// The vertical axis: grid lines and labels every tick step, in metres.
void draw_range_axis(Plot& plot, double step) {
    for (int k = 0; k * step <= plot.range_max_m * (1 + 1e-12); ++k) {
        const int y = plot.y_of(k * step);
        for (int x = Plot::kLeft; x <= Plot::kRight; ++x) {
            plot.pixel(x, y, kGrid);
        }
        const std::string label = number_text(k * step) + " m";
        plot.text(Plot::kLeft - 8 - detail::text_width(label, 2), y - 7, label, kBlack);
    }
}

/// The horizontal (log MOR) axis: grid lines at 1, 2 and 5 x 10^k m, labelled.
void draw_mor_axis(Plot& plot, const WeatherRangeOptions& o) {
    const double span = std::log(o.mor_max_m / o.mor_min_m);
    for (double decade = std::pow(10.0, std::floor(std::log10(o.mor_min_m))); decade <= o.mor_max_m;
         decade *= 10.0) {
        for (const double m : {1.0, 2.0, 5.0}) {
            const double mor = m * decade;
            if (mor < o.mor_min_m * (1 - 1e-12) || mor > o.mor_max_m * (1 + 1e-12)) {
                continue;
            }
            const int x =
                Plot::kLeft + static_cast<int>(std::lround((Plot::kRight - Plot::kLeft) *
                                                           std::log(mor / o.mor_min_m) / span));
            for (int y = Plot::kTop; y <= Plot::kBottom; ++y) {
                plot.pixel(x, y, kGrid);
            }
            const std::string label = number_text(mor);
            plot.text(x - detail::text_width(label, 2) / 2, Plot::kBottom + 10, label, kBlack);
        }
    }
    // The unit right of the last label (the largest MOR's at most).
    plot.text(Plot::kRight + detail::text_width(number_text(o.mor_max_m), 2) / 2 + 10,
              Plot::kBottom + 10, "m", kBlack);
}

void draw_box(Plot& plot) {
    for (int x = Plot::kLeft; x <= Plot::kRight; ++x) {
        plot.pixel(x, Plot::kTop, kBlack);
        plot.pixel(x, Plot::kBottom, kBlack);
    }
    for (int y = Plot::kTop; y <= Plot::kBottom; ++y) {
        plot.pixel(Plot::kLeft, y, kBlack);
        plot.pixel(Plot::kRight, y, kBlack);
    }
}

/// A line three pixels wide from (x0, y0) to (x1, y1), x1 = x0 + 1.
void draw_segment(Plot& plot, int x0, int y0, int x1, int y1, Rgb8Pixel c) {
    const int lo = std::min(y0, y1), hi = std::max(y0, y1), mid = (lo + hi) / 2;
    for (int y = lo; y <= hi; ++y) {
        const int x = y <= mid ? x0 : x1;
        for (int d = -1; d <= 1; ++d) {
            plot.pixel(x + d, y, c);
            plot.pixel(x, y + d, c);
        }
    }
}

/// Each reflectance's curve, one solver call per pixel column, labelled at its right end.
void draw_curves(Plot& plot, const WeatherRangeOptions& o, const PhysicsConfig& p) {
    for (std::size_t i = 0; i < o.reflectances.size(); ++i) {
        const Rgb8Pixel c = kCurveColours[i % kCurveColours.size()];
        int last_y = 0;
        for (int x = Plot::kLeft; x <= Plot::kRight; ++x) {
            const double mor =
                mor_at(o, (x - Plot::kLeft) / static_cast<double>(Plot::kRight - Plot::kLeft));
            const int y = plot.y_of(
                max_detection_range_in_fog_m(p.radiometry, p.atmosphere, o.reflectances[i], mor));
            draw_segment(plot, x == Plot::kLeft ? x : x - 1, x == Plot::kLeft ? y : last_y, x, y,
                         c);
            last_y = y;
        }
        plot.text(Plot::kRight + 8, last_y - 7, number_text(o.reflectances[i]), c);
    }
}

void write_plot(const WeatherRangeOptions& o, const PhysicsConfig& p) {
    Plot plot;
    double top = 0.0;
    for (const double rho : o.reflectances) {
        top = std::max(top,
                       max_detection_range_in_fog_m(p.radiometry, p.atmosphere, rho, o.mor_max_m));
    }
    const double step = tick_step(top);
    plot.range_max_m = std::ceil(top / step) * step;
    draw_range_axis(plot, step);
    draw_mor_axis(plot, o);
    draw_box(plot);
    draw_curves(plot, o, p);
    write_png_rgb8(o.output, Plot::kWidth, Plot::kHeight, plot.rgb);
}

int run(const WeatherRangeOptions& o) {
    check(o);
    const PhysicsConfig p = physics_of(o);
    if (o.output.empty() && o.csv.empty()) {
        std::fputs(csv_table(o, p).c_str(), stdout);
        return 0;
    }
    if (!o.csv.empty()) {
        const std::string table = csv_table(o, p);
        if (o.csv == "-") {
            std::fputs(table.c_str(), stdout);
        } else {
            std::ofstream out(o.csv, std::ios::binary);
            out << table;
            if (!out.flush()) {
                throw OutputError("weather-range: cannot write '" + o.csv + "'");
            }
        }
    }
    if (!o.output.empty()) {
        write_plot(o, p);
    }
    return 0;
}

}  // namespace

std::function<int()> add_weather_range_command(CLI::App& app) {
    auto opts = std::make_shared<WeatherRangeOptions>();
    CLI::App* cmd = app.add_subcommand(
        "weather-range",
        "The maximum detection range of Lambertian targets against the fog's MOR, solved from "
        "the range equation: a PNG plot and a CSV table (see docs/weather.md)");
    cmd->add_option("--survey", opts->survey,
                    "Survey file whose physics (power, aperture, efficiency, threshold, "
                    "wavelength, air) the curves use; default: the physics' defaults");
    cmd->add_option("--reflectance", opts->reflectances, "Target reflectances, one curve each")
        ->capture_default_str();
    cmd->add_option("--mor-min", opts->mor_min_m, "Smallest MOR [m]")->capture_default_str();
    cmd->add_option("--mor-max", opts->mor_max_m, "Largest MOR [m]")->capture_default_str();
    cmd->add_option("--points", opts->points, "MORs per reflectance in the CSV (log-spaced)")
        ->capture_default_str();
    cmd->add_option("--output", opts->output, "The plot (PNG)");
    cmd->add_option("--csv", opts->csv,
                    "The table: reflectance,mor_m,max_range_m (- for standard output)");
    return [opts] { return run(*opts); };
}

}  // namespace beamtrace::cli
