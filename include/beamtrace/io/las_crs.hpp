// The CRS records of LAS files (user ID "LASF_Projection"): the OGC WKT record (2112), written
// for a known CRS and read back, and the GeoTIFF GeoKeyDirectoryTag record (34735) of older
// files, whose projected or geographic CRS key gives an EPSG code.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/core/crs.hpp"
#include "beamtrace/io/las.hpp"

namespace beamtrace {

inline constexpr const char* kLasProjectionUserId = "LASF_Projection";
inline constexpr std::uint16_t kLasWktRecordId = 2112;
inline constexpr std::uint16_t kLasGeoKeyDirectoryRecordId = 34735;

/// The OGC WKT VLR of `wkt`: LASF_Projection / 2112, the WKT's bytes and a terminating NUL.
/// Throws ConfigError for a WKT that holds a NUL or does not fit a VLR (64 KiB).
[[nodiscard]] LasVlr las_wkt_vlr(const std::string& wkt);

/// Where a file's CRS came from.
enum class LasCrsSource : std::uint8_t { none, wkt, geotiff };

/// A file's CRS as its records state it, with what is wrong with those records.
struct LasFileCrs {
    LasCrsSource source = LasCrsSource::none;
    Crs crs;                 ///< the WKT (or, from GeoTIFF keys, crs_from_epsg of their code)
    bool projected = false;  ///< GeoTIFF: ProjectedCSTypeGeoKey (else geographic)
    std::uint32_t vertical_epsg = 0;  ///< GeoTIFF: VerticalCSTypeGeoKey, 0 when absent
    std::string citation;  ///< GeoTIFF: PCSCitationGeoKey, GeogCitationGeoKey or GTCitationGeoKey
    std::vector<std::string> warnings;  ///< malformed or contradicting records, one line each
};

/// The CRS of a file from its header and (E)VLRs: the WKT record when the global encoding's WKT
/// bit is set (or there are no GeoTIFF keys), else the GeoKeyDirectoryTag's ProjectedCSTypeGeoKey
/// (3072) or GeographicTypeGeoKey (2048). Malformed records never throw: they give a warning.
[[nodiscard]] LasFileCrs las_file_crs(const LasHeader& header, std::span<const LasVlr> vlrs);

}  // namespace beamtrace
