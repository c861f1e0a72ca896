// Single-band GeoTIFF elevation rasters through libtiff (strips or tiles, any codec it has).
#include <tiffio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/raster_terrain.hpp"

namespace beamtrace {
namespace {

constexpr ttag_t kModelPixelScaleTag = 33550;
constexpr ttag_t kModelTiepointTag = 33922;
constexpr ttag_t kModelTransformationTag = 34264;
constexpr ttag_t kGeoKeyDirectoryTag = 34735;
constexpr ttag_t kGdalNodataTag = 42113;
constexpr std::uint16_t kGTRasterTypeGeoKey = 1025;
constexpr std::uint16_t kRasterPixelIsPoint = 2;
constexpr std::uint16_t kGeographicTypeGeoKey = 2048;
constexpr std::uint16_t kProjectedCSTypeGeoKey = 3072;
constexpr std::uint16_t kUserDefinedGeoKey = 32767;
constexpr std::uint64_t kMaxTileCells = std::uint64_t{1} << 20;

/// libtiff's messages for this file, collected by per-handle handlers (no global state).
struct TiffMessages {
    std::string last_error;
    std::string lost_tag;  ///< a tag whose data libtiff could not read, and so dropped
};

int on_tiff_error(TIFF*, void* user, const char* module, const char* fmt, va_list ap) {
    std::array<char, 512> buffer{};
    std::vsnprintf(buffer.data(), buffer.size(), fmt, ap);
    auto* messages = static_cast<TiffMessages*>(user);
    messages->last_error =
        std::string(module != nullptr ? module : "libtiff") + ": " + buffer.data();
    return 1;
}

int on_tiff_warning(TIFF*, void* user, const char* module, const char* fmt, va_list ap) {
    // Unknown GeoTIFF tags and the like are not our concern, but libtiff also only warns when a
    // tag's data lies past the end of a truncated file, and then opens the file without it.
    std::array<char, 512> buffer{};
    std::vsnprintf(buffer.data(), buffer.size(), fmt, ap);
    const std::string message = buffer.data();
    if (message.find("IO error") != std::string::npos) {
        static_cast<TiffMessages*>(user)->lost_tag =
            std::string(module != nullptr ? module : "libtiff") + ": " + message;
    }
    return 1;
}

struct TiffCloser {
    void operator()(TIFF* tif) const { TIFFClose(tif); }
};
using TiffHandle = std::unique_ptr<TIFF, TiffCloser>;

/// The values of a tag that libtiff passes with a count (custom and unknown tags).
template <typename T>
[[nodiscard]] std::optional<std::vector<T>> counted_tag(TIFF* tif, ttag_t tag, TIFFDataType type) {
    const TIFFField* field = TIFFFindField(tif, tag, TIFF_ANY);
    if (field == nullptr || !TIFFFieldPassCount(field) || TIFFFieldDataType(field) != type) {
        return std::nullopt;
    }
    const T* data = nullptr;
    std::size_t count = 0;
    if (TIFFFieldReadCount(field) == TIFF_VARIABLE2) {
        std::uint32_t n = 0;
        if (TIFFGetField(tif, tag, &n, &data) != 1) {
            return std::nullopt;
        }
        count = n;
    } else {
        std::uint16_t n = 0;
        if (TIFFGetField(tif, tag, &n, &data) != 1) {
            return std::nullopt;
        }
        count = n;
    }
    if (data == nullptr) {
        return std::nullopt;
    }
    return std::vector<T>(data, data + count);
}

/// The value of a SHORT GeoKey stored in the GeoKey directory itself (TIFFTagLocation 0).
[[nodiscard]] std::optional<std::uint16_t> short_geokey(TIFF* tif, std::uint16_t id) {
    const auto keys = counted_tag<std::uint16_t>(tif, kGeoKeyDirectoryTag, TIFF_SHORT);
    if (!keys || keys->size() < 4) {
        return std::nullopt;
    }
    const std::size_t n = (*keys)[3];
    for (std::size_t k = 0; k < n && 4 * k + 7 < keys->size(); ++k) {
        const std::uint16_t* entry = keys->data() + 4 + 4 * k;
        if (entry[0] == id && entry[1] == 0) {
            return entry[3];
        }
    }
    return std::nullopt;
}

/// GTRasterTypeGeoKey from the GeoKey directory: PixelIsArea (1, the default) or PixelIsPoint.
[[nodiscard]] bool pixel_is_point(TIFF* tif) {
    return short_geokey(tif, kGTRasterTypeGeoKey) == kRasterPixelIsPoint;
}

/// The CRS of ProjectedCSTypeGeoKey, else GeographicTypeGeoKey (0 and 32767, user-defined, name
/// no EPSG code).
[[nodiscard]] Crs read_crs(TIFF* tif) {
    const auto code = [](std::optional<std::uint16_t> v) -> std::uint16_t {
        return v && *v != 0 && *v != kUserDefinedGeoKey ? *v : 0;
    };
    if (const std::uint16_t projected = code(short_geokey(tif, kProjectedCSTypeGeoKey))) {
        return crs_from_epsg(projected, true);
    }
    if (const std::uint16_t geographic = code(short_geokey(tif, kGeographicTypeGeoKey))) {
        return crs_from_epsg(geographic, false);
    }
    return {};
}

void read_georeferencing(TIFF* tif, const std::string& path, Raster& r) {
    const double centre = pixel_is_point(tif) ? 0.0 : 0.5;
    const auto scale = counted_tag<double>(tif, kModelPixelScaleTag, TIFF_DOUBLE);
    const auto tie = counted_tag<double>(tif, kModelTiepointTag, TIFF_DOUBLE);
    if (scale && tie && scale->size() >= 2 && tie->size() >= 6) {
        const double sx = (*scale)[0], sy = (*scale)[1];
        if (!(sx > 0.0) || !(sy > 0.0) || !std::isfinite(sx) || !std::isfinite(sy)) {
            throw InputError(path, "ModelPixelScaleTag (" + std::to_string(sx) + ", " +
                                       std::to_string(sy) + ") is not positive");
        }
        r.cell_x_m = sx;
        r.cell_y_m = -sy;
        r.x0_m = (*tie)[3] + (centre - (*tie)[0]) * sx;
        r.y0_m = (*tie)[4] - (centre - (*tie)[1]) * sy;
        return;
    }
    const auto m = counted_tag<double>(tif, kModelTransformationTag, TIFF_DOUBLE);
    if (m && m->size() >= 16) {
        if ((*m)[1] != 0.0 || (*m)[4] != 0.0) {
            throw InputError(path, "ModelTransformationTag has a rotation or shear (" +
                                       std::to_string((*m)[1]) + ", " + std::to_string((*m)[4]) +
                                       "), which is not supported");
        }
        r.cell_x_m = (*m)[0];
        r.cell_y_m = (*m)[5];
        r.x0_m = (*m)[3] + centre * r.cell_x_m;
        r.y0_m = (*m)[7] + centre * r.cell_y_m;
        return;
    }
    r.cell_x_m = 1.0;  // no georeferencing: pixel units, north up, top-left corner at 0
    r.cell_y_m = -1.0;
    r.x0_m = 0.5;
    r.y0_m = -0.5;
}

[[nodiscard]] std::optional<float> read_nodata(TIFF* tif) {
    const auto text = counted_tag<char>(tif, kGdalNodataTag, TIFF_ASCII);
    if (!text || text->empty()) {
        return std::nullopt;
    }
    const std::string s(text->begin(), text->end());
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end == s.c_str()) {
        return std::nullopt;
    }
    if (std::isnan(v)) {
        return std::numeric_limits<float>::quiet_NaN();
    }
    constexpr double kMax = std::numeric_limits<float>::max();
    return static_cast<float>(std::fmax(-kMax, std::fmin(kMax, v)));
}

/// Sample type: SampleFormat (1 uint, 2 int, 3 float) and BitsPerSample.
struct SampleType {
    std::uint16_t format = SAMPLEFORMAT_UINT;
    std::uint16_t bits = 1;

    [[nodiscard]] bool supported() const {
        if (format == SAMPLEFORMAT_IEEEFP) {
            return bits == 32 || bits == 64;
        }
        return (format == SAMPLEFORMAT_UINT || format == SAMPLEFORMAT_INT) &&
               (bits == 8 || bits == 16 || bits == 32);
    }
    [[nodiscard]] std::size_t bytes() const { return bits / 8u; }

    [[nodiscard]] float decode(const unsigned char* p) const {
        auto get = [p](auto v) {
            std::memcpy(&v, p, sizeof(v));
            return static_cast<float>(v);
        };
        if (format == SAMPLEFORMAT_IEEEFP) {
            return bits == 32 ? get(float{}) : get(double{});
        }
        if (format == SAMPLEFORMAT_INT) {
            return bits == 8 ? get(std::int8_t{})
                             : (bits == 16 ? get(std::int16_t{}) : get(std::int32_t{}));
        }
        return bits == 8 ? get(std::uint8_t{})
                         : (bits == 16 ? get(std::uint16_t{}) : get(std::uint32_t{}));
    }
};

/// Copies a block of `block_rows` x `block_cols` samples (row stride `stride` samples) to the
/// raster at (col0, row0), clipped to the raster.
void copy_block(const std::vector<unsigned char>& buffer, const SampleType& type,
                std::size_t stride, std::size_t col0, std::size_t row0, std::size_t block_cols,
                std::size_t block_rows, Raster& r) {
    const auto cols = static_cast<std::size_t>(r.cols);
    const auto rows = static_cast<std::size_t>(r.rows);
    const std::size_t nr = std::min(block_rows, rows - row0);
    const std::size_t nc = std::min(block_cols, cols - col0);
    for (std::size_t i = 0; i < nr; ++i) {
        const unsigned char* src = buffer.data() + i * stride * type.bytes();
        float* dst = r.z.data() + (row0 + i) * cols + col0;
        for (std::size_t j = 0; j < nc; ++j) {
            dst[j] = type.decode(src + j * type.bytes());
        }
    }
}

/// Makes the InputError for `what`, adding libtiff's last message.
using FailFn = std::function<InputError(const std::string&)>;

/// Reads every tile into `r` (sized already).
void read_tiles(TIFF* tif, const std::string& p, const FailFn& fail, const SampleType& type,
                std::uint32_t width, std::uint32_t height, Raster& r) {
    std::uint32_t tile_w = 0, tile_h = 0;
    TIFFGetField(tif, TIFFTAG_TILEWIDTH, &tile_w);
    TIFFGetField(tif, TIFFTAG_TILELENGTH, &tile_h);
    if (tile_w == 0 || tile_h == 0) {
        throw InputError(p, "TileWidth " + std::to_string(tile_w) + " / TileLength " +
                                std::to_string(tile_h) + " is not valid");
    }
    // A tile may overhang a small raster, but not by more than 2^20 cells (one tile's buffer).
    const std::uint64_t tile_cells = std::uint64_t{tile_w} * tile_h;
    if (tile_cells > std::max<std::uint64_t>(std::uint64_t{width} * height, kMaxTileCells)) {
        throw InputError(p, "TileWidth x TileLength = " + std::to_string(tile_w) + " x " +
                                std::to_string(tile_h) + " is larger than the raster (" +
                                std::to_string(width) + " x " + std::to_string(height) +
                                ") and than " + std::to_string(kMaxTileCells) + " cells");
    }
    const auto tile_bytes = static_cast<std::size_t>(TIFFTileSize64(tif));
    if (tile_bytes < std::size_t{tile_w} * tile_h * type.bytes()) {
        throw fail("tile size " + std::to_string(tile_bytes) + " bytes is too small");
    }
    std::vector<unsigned char> buffer(tile_bytes);
    for (std::uint32_t y = 0; y < height; y += tile_h) {
        for (std::uint32_t x = 0; x < width; x += tile_w) {
            const ttile_t tile = TIFFComputeTile(tif, x, y, 0, 0);
            if (TIFFReadEncodedTile(tif, tile, buffer.data(), static_cast<tmsize_t>(tile_bytes)) <
                0) {
                throw fail("cannot read tile " + std::to_string(tile));
            }
            copy_block(buffer, type, tile_w, x, y, tile_w, tile_h, r);
        }
    }
}

/// Reads every strip into `r` (sized already).
void read_strips(TIFF* tif, const FailFn& fail, const SampleType& type, std::uint32_t width,
                 std::uint32_t height, Raster& r) {
    std::uint32_t rows_per_strip = 0;
    TIFFGetFieldDefaulted(tif, TIFFTAG_ROWSPERSTRIP, &rows_per_strip);
    rows_per_strip = std::max<std::uint32_t>(1, std::min(rows_per_strip, height));
    const std::size_t row_bytes = std::size_t{width} * type.bytes();
    std::vector<unsigned char> buffer(row_bytes * rows_per_strip);
    for (std::uint32_t y = 0; y < height; y += rows_per_strip) {
        const std::uint32_t n = std::min(rows_per_strip, height - y);
        const tstrip_t strip = TIFFComputeStrip(tif, y, 0);
        const tmsize_t want = static_cast<tmsize_t>(row_bytes * n);
        if (TIFFReadEncodedStrip(tif, strip, buffer.data(), want) < want) {
            throw fail("cannot read strip " + std::to_string(strip));
        }
        copy_block(buffer, type, width, 0, y, width, n, r);
    }
}

/// Refuses, before the raster is allocated, more than kMaxRasterCells cells, and strips or tiles
/// that lie outside the file or, uncompressed, hold fewer bytes than the samples: a small file
/// cannot claim a huge raster.
void check_claimed_size(TIFF* tif, const std::string& path, std::uint32_t width,
                        std::uint32_t height, const SampleType& type) {
    const std::uint64_t cells = std::uint64_t{width} * height;
    const std::string size = "ImageWidth x ImageLength = " + std::to_string(width) + " x " +
                             std::to_string(height) + " = " + std::to_string(cells) + " cells";
    if (cells > kMaxRasterCells) {
        throw InputError(path, size + " is above the limit of " + std::to_string(kMaxRasterCells) +
                                   " cells per raster");
    }
    std::error_code ec;
    const std::uintmax_t file_size = std::filesystem::file_size(path, ec);
    if (ec) {
        throw InputError(path, "cannot read the file's size (" + ec.message() + ")");
    }
    const bool tiled = TIFFIsTiled(tif) != 0;
    const std::uint32_t n = tiled ? TIFFNumberOfTiles(tif) : TIFFNumberOfStrips(tif);
    std::uint64_t stored = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        int err = 0;
        const std::uint64_t offset = TIFFGetStrileOffsetWithErr(tif, i, &err);
        const std::uint64_t count = TIFFGetStrileByteCountWithErr(tif, i, &err);
        if (err != 0 || offset > file_size || count > file_size - offset) {
            throw InputError(path, std::string(tiled ? "tile " : "strip ") + std::to_string(i) +
                                       ": its " + std::to_string(count) + " bytes at byte " +
                                       std::to_string(offset) + " lie outside the file (" +
                                       std::to_string(file_size) + " bytes)");
        }
        stored += count;
    }
    std::uint16_t compression = COMPRESSION_NONE;
    TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &compression);
    const std::uint64_t samples = cells * type.bytes();
    if (compression == COMPRESSION_NONE && (stored < samples || samples > file_size)) {
        throw InputError(path, size + " of " + std::to_string(type.bytes()) + " bytes need " +
                                   std::to_string(samples) + " bytes, but the uncompressed " +
                                   (tiled ? "tiles" : "strips") + " hold only " +
                                   std::to_string(stored) + " (the file has " +
                                   std::to_string(file_size) + ")");
    }
}

}  // namespace

Raster load_geotiff(const std::filesystem::path& path) {
    const std::string p = path.string();
    TiffMessages messages;
    TIFFOpenOptions* options = TIFFOpenOptionsAlloc();
    TIFFOpenOptionsSetErrorHandlerExtR(options, on_tiff_error, &messages);
    TIFFOpenOptionsSetWarningHandlerExtR(options, on_tiff_warning, &messages);
    TiffHandle tif(TIFFOpenExt(p.c_str(), "r", options));
    TIFFOpenOptionsFree(options);
    if (!tif) {
        throw InputError(p, "cannot open as TIFF (" + messages.last_error + ")");
    }
    if (!messages.lost_tag.empty()) {
        // The georeferencing or the nodata value would otherwise be lost without a word.
        throw InputError(p, "a tag's data runs past the end of the file (" + messages.lost_tag +
                                "): the file is truncated or damaged");
    }
    const FailFn fail = [&](const std::string& what) -> InputError {
        return InputError(
            p, messages.last_error.empty() ? what : what + " (" + messages.last_error + ")");
    };
    std::uint32_t width = 0, height = 0;
    if (TIFFGetField(tif.get(), TIFFTAG_IMAGEWIDTH, &width) != 1 ||
        TIFFGetField(tif.get(), TIFFTAG_IMAGELENGTH, &height) != 1 || width == 0 || height == 0) {
        throw fail("no ImageWidth/ImageLength");
    }
    std::uint16_t samples = 1;
    SampleType type;
    TIFFGetFieldDefaulted(tif.get(), TIFFTAG_SAMPLESPERPIXEL, &samples);
    TIFFGetFieldDefaulted(tif.get(), TIFFTAG_BITSPERSAMPLE, &type.bits);
    TIFFGetFieldDefaulted(tif.get(), TIFFTAG_SAMPLEFORMAT, &type.format);
    if (samples != 1) {
        throw InputError(p, "SamplesPerPixel " + std::to_string(samples) +
                                ": only single-band rasters are supported");
    }
    if (!type.supported()) {
        throw InputError(p, "SampleFormat " + std::to_string(type.format) + " with BitsPerSample " +
                                std::to_string(type.bits) +
                                " is not supported (expected float32/64 or (u)int8/16/32)");
    }
    check_claimed_size(tif.get(), p, width, height, type);
    const std::size_t cells = static_cast<std::size_t>(width) * height;
    Raster r;
    r.cols = static_cast<int>(width);
    r.rows = static_cast<int>(height);
    r.z.assign(cells, 0.0f);
    if (TIFFIsTiled(tif.get())) {
        read_tiles(tif.get(), p, fail, type, width, height, r);
    } else {
        read_strips(tif.get(), fail, type, width, height, r);
    }
    read_georeferencing(tif.get(), p, r);
    r.nodata = read_nodata(tif.get());
    r.crs = read_crs(tif.get());
    return r;
}

}  // namespace beamtrace
