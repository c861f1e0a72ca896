// `beamtrace convert IN OUT`: LAS <-> LAZ by OUT's extension (.las, .laz), every point record,
// VLR and EVLR carried over unchanged (docs/convert.md).
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <memory>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_convert.hpp"
#include "commands.hpp"
#include "progress_bar.hpp"

namespace beamtrace::cli {
namespace {

struct ConvertOptions {
    std::string in, out;
    LasConvertConfig config;
    bool quiet = false;
    bool progress = false;
};

/// The output's storage from its extension; ConfigError for any other.
LasCompression compression_for(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".las") {
        return LasCompression::none;
    }
    if (ext == ".laz") {
        return LasCompression::laz;
    }
    throw ConfigError("convert: output '" + path + "': unknown extension '" + ext +
                      "' (expected .las or .laz)");
}

int run(ConvertOptions& o) {
    o.config.compression = compression_for(o.out);
    if (o.config.laz_chunk_size == 0 || o.config.laz_chunk_size == 0xFFFFFFFFU) {
        throw ConfigError("convert: --chunk-size " + std::to_string(o.config.laz_chunk_size) +
                          " (expected 1 to 4294967294 points)");
    }
    ProgressBar bar("converting", !o.quiet && (o.progress || stderr_is_terminal()));
    const LasConvertResult r =
        convert_las(o.in, o.out, o.config,
                    [&](std::size_t done, std::size_t total) { bar.update(done, total); });
    bar.finish();
    if (!o.quiet) {
        std::printf("%s (%s, %llu bytes) -> %s (%s, %llu bytes): %llu points\n", o.in.c_str(),
                    r.input_compressed ? "LAZ" : "LAS",
                    static_cast<unsigned long long>(r.input_bytes), o.out.c_str(),
                    o.config.compression == LasCompression::laz ? "LAZ" : "LAS",
                    static_cast<unsigned long long>(r.output_bytes),
                    static_cast<unsigned long long>(r.points));
    }
    return 0;
}

}  // namespace

std::function<int()> add_convert_command(CLI::App& app) {
    auto opts = std::make_shared<ConvertOptions>();
    CLI::App* cmd = app.add_subcommand(
        "convert",
        "Convert LAS <-> LAZ by the output's extension (.las, .laz), records, VLRs "
        "and EVLRs unchanged (see docs/convert.md)");
    cmd->add_option("in", opts->in, "Input LAS or LAZ file")->required();
    cmd->add_option("out", opts->out, "Output file: .las (uncompressed) or .laz (LASzip)")
        ->required();
    cmd->add_option("--chunk-size", opts->config.laz_chunk_size, "Points per LAZ chunk")
        ->capture_default_str();
    cmd->add_option("--threads", opts->config.threads,
                    "LAZ chunks decoded/encoded at once (0 = all cores; the output is the same)")
        ->capture_default_str();
    cmd->add_flag("--quiet", opts->quiet, "No progress bar and no summary");
    cmd->add_flag("--progress", opts->progress,
                  "Show the progress bar even when not on a terminal");
    return [opts] { return run(*opts); };
}

}  // namespace beamtrace::cli
