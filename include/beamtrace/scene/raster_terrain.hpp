// Elevation rasters (ESRI ASCII grid, GeoTIFF) and their triangulation into a height field.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <vector>

#include "beamtrace/core/crs.hpp"
#include "beamtrace/core/vec3.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

/// A single-band elevation grid, row-major from the top (first) row. Cell (col, row) has its
/// centre at (x0_m + col * cell_x_m, y0_m + row * cell_y_m) in world coordinates (metres, the
/// raster's projected CRS); cell_y_m is negative when rows go south (north-up rasters).
struct Raster {
    int cols = 0;
    int rows = 0;
    double x0_m = 0.0;  ///< world x of the centre of the top-left cell
    double y0_m = 0.0;  ///< world y of the centre of the top-left cell
    double cell_x_m = 1.0;
    double cell_y_m = -1.0;
    std::vector<float> z;         ///< cols * rows elevations (metres)
    std::optional<float> nodata;  ///< cells equal to this (or NaN) have no data
    /// The raster's CRS where the file names one (GeoTIFF: the EPSG code of
    /// ProjectedCSTypeGeoKey 3072, else GeographicTypeGeoKey 2048); empty otherwise.
    Crs crs;

    [[nodiscard]] float at(int col, int row) const {
        return z[static_cast<std::size_t>(row) * static_cast<std::size_t>(cols) +
                 static_cast<std::size_t>(col)];
    }
    /// False for NaN and for the nodata value.
    [[nodiscard]] bool valid(float value) const {
        return value == value && !(nodata && value == *nodata);
    }
};

/// The most cells (columns x rows) a raster may have: 2^28 = 268435456, e.g. 16384 x 16384 (1 GiB
/// of elevations, about 10 GiB once triangulated). The loaders refuse a larger header before
/// allocating anything (docs/scene-file.md).
inline constexpr std::size_t kMaxRasterCells = std::size_t{1} << 28;

/// ESRI ASCII grid (.asc): header keys ncols, nrows, xllcorner|xllcenter, yllcorner|yllcenter,
/// cellsize (or dx and dy), optional NODATA_value (case-insensitive, any order), then nrows
/// lines of ncols values from the top row. Throws InputError naming the file and line for a
/// malformed or incomplete header, a malformed value, or too few or too many values, and, before
/// allocating, for ncols x nrows above kMaxRasterCells or more values than the rest of the file
/// can hold (at least a byte each).
[[nodiscard]] Raster load_esri_ascii_grid(const std::filesystem::path& path);

/// GeoTIFF with one band of float32/float64/int8/uint8/int16/uint16/int32/uint32 samples, in
/// strips or tiles, any compression libtiff decodes. Georeferencing from ModelPixelScaleTag
/// (33550) and ModelTiepointTag (33922), honouring GTRasterTypeGeoKey PixelIsPoint, or from
/// ModelTransformationTag (34264) without rotation; unit cells with the top-left corner at the
/// origin when there is none. Nodata from GDAL_NODATA (42113). The CRS from the GeoKey
/// directory (34735): ProjectedCSTypeGeoKey (3072), else GeographicTypeGeoKey (2048), as
/// crs_from_epsg builds it; none for user-defined (32767) or missing codes. Throws InputError
/// naming the file and the offending tag value for unsupported layouts, and, before allocating the
/// raster, for more than kMaxRasterCells cells or strips/tiles that do not lie inside the file (or,
/// when uncompressed, hold fewer bytes than their samples).
[[nodiscard]] Raster load_geotiff(const std::filesystem::path& path);

/// Chooses by extension: .asc, .tif or .tiff (case-insensitive).
[[nodiscard]] Raster load_raster(const std::filesystem::path& path);

/// One vertex per valid cell centre (row-major from the top row, cells with no data left out),
/// minus `origin_m` so that projected coordinates keep their precision in float; for every 2x2
/// block of cells two triangles, counter-clockwise seen from above (+z), split along the
/// diagonal from the block's bottom-left to its top-right cell. A triangle is emitted only if
/// its three cells are valid, so a nodata cell removes exactly the triangles touching it. Face
/// IDs run over the blocks row-major from the top. Throws std::invalid_argument if the raster is
/// inconsistent (z.size() != cols * rows) or has too many cells for 32-bit indices.
[[nodiscard]] TriangleMesh raster_to_mesh(const Raster& raster, const Vec3d& origin_m = {});

}  // namespace beamtrace
