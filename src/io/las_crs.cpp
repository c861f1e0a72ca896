#include "beamtrace/io/las_crs.hpp"

#include <cstring>
#include <optional>

#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

constexpr std::uint16_t kGeoAsciiParamsRecordId = 34737;
constexpr std::uint16_t kGTCitationGeoKey = 1026;
constexpr std::uint16_t kGeographicTypeGeoKey = 2048;
constexpr std::uint16_t kGeogCitationGeoKey = 2049;
constexpr std::uint16_t kProjectedCSTypeGeoKey = 3072;
constexpr std::uint16_t kPCSCitationGeoKey = 3073;
constexpr std::uint16_t kVerticalCSTypeGeoKey = 4096;
constexpr std::uint16_t kUserDefined = 32767;

[[nodiscard]] const LasVlr* find_record(std::span<const LasVlr> vlrs, std::uint16_t id) {
    for (const LasVlr& v : vlrs) {
        if (v.user_id == kLasProjectionUserId && v.record_id == id) {
            return &v;
        }
    }
    return nullptr;
}

/// The WKT of a 2112 record: its bytes up to the first NUL.
[[nodiscard]] std::string record_text(const LasVlr& v) {
    std::string text(v.data.begin(), v.data.end());
    const std::size_t nul = text.find('\0');
    return nul == std::string::npos ? text : text.substr(0, nul);
}

/// One GeoKey entry (KeyID, TIFFTagLocation, Count, Value_Offset).
struct GeoKey {
    std::uint16_t id, location, count, value;
};

/// A citation string from GeoAsciiParamsTag (each ends with '|').
[[nodiscard]] std::string ascii_param(const LasVlr* ascii, const GeoKey& k) {
    if (ascii == nullptr || k.location != kGeoAsciiParamsRecordId || k.count == 0 ||
        std::size_t{k.value} + k.count > ascii->data.size()) {
        return {};
    }
    std::string s(ascii->data.begin() + k.value, ascii->data.begin() + k.value + k.count);
    while (!s.empty() && (s.back() == '|' || s.back() == '\0')) {
        s.pop_back();
    }
    return s.find('\0') == std::string::npos ? s : std::string{};
}

/// The code of a SHORT key stored in the directory itself, or nothing (with a warning).
[[nodiscard]] std::optional<std::uint16_t> inline_code(const GeoKey& k, const char* name,
                                                       LasFileCrs& out) {
    if (k.location != 0 || k.count != 1) {
        out.warnings.push_back(std::string("GeoTIFF keys: ") + name + " is not a SHORT value " +
                               "(TIFFTagLocation " + std::to_string(k.location) + ", count " +
                               std::to_string(k.count) + ")");
        return std::nullopt;
    }
    if (k.value == 0 || k.value == kUserDefined) {
        out.warnings.push_back(std::string("GeoTIFF keys: ") + name + " is " +
                               (k.value == 0 ? "0 (undefined)" : "32767 (user-defined)") +
                               ": no EPSG code");
        return std::nullopt;
    }
    return k.value;
}

void read_geotiff_keys(const LasVlr& dir, const LasVlr* ascii, LasFileCrs& out) {
    const std::size_t shorts = dir.data.size() / 2;
    auto at = [&](std::size_t i) {
        std::uint16_t v = 0;
        std::memcpy(&v, dir.data.data() + 2 * i, 2);
        return v;
    };
    if (shorts < 4) {
        out.warnings.push_back("GeoTIFF keys: the GeoKeyDirectoryTag record has " +
                               std::to_string(dir.data.size()) + " bytes, fewer than its header");
        return;
    }
    std::size_t n = at(3);
    if (4 + 4 * n > shorts) {
        out.warnings.push_back("GeoTIFF keys: the directory claims " + std::to_string(n) +
                               " keys but its " + std::to_string(dir.data.size()) + " bytes hold " +
                               std::to_string((shorts - 4) / 4));
        n = (shorts - 4) / 4;
    }
    std::size_t blank = 0;
    std::uint32_t projected = 0, geographic = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const GeoKey k{at(4 + 4 * i), at(5 + 4 * i), at(6 + 4 * i), at(7 + 4 * i)};
        if (k.id == 0) {
            ++blank;
        } else if (k.id == kProjectedCSTypeGeoKey) {
            projected = inline_code(k, "ProjectedCSTypeGeoKey", out).value_or(0);
        } else if (k.id == kGeographicTypeGeoKey) {
            geographic = inline_code(k, "GeographicTypeGeoKey", out).value_or(0);
        } else if (k.id == kVerticalCSTypeGeoKey) {
            out.vertical_epsg = inline_code(k, "VerticalCSTypeGeoKey", out).value_or(0);
        } else if (k.id == kPCSCitationGeoKey ||
                   (out.citation.empty() &&
                    (k.id == kGTCitationGeoKey || k.id == kGeogCitationGeoKey))) {
            const std::string c = ascii_param(ascii, k);
            out.citation = c.empty() ? out.citation : c;
        }
    }
    if (blank > 0) {
        out.warnings.push_back("GeoTIFF keys: " + std::to_string(blank) + " of " +
                               std::to_string(n) + " key entries have KeyID 0 (blank)");
    }
    if (projected != 0 || geographic != 0) {
        out.projected = projected != 0;
        out.crs = crs_from_epsg(projected != 0 ? projected : geographic, out.projected);
    } else {
        out.warnings.push_back(
            "GeoTIFF keys: neither ProjectedCSTypeGeoKey (3072) nor GeographicTypeGeoKey (2048) "
            "gives an EPSG code");
    }
}

}  // namespace

LasVlr las_wkt_vlr(const std::string& wkt) {
    if (wkt.find('\0') != std::string::npos) {
        throw ConfigError("CRS WKT holds a NUL character");
    }
    if (wkt.size() > kMaxWktBytes) {
        throw ConfigError("CRS WKT of " + std::to_string(wkt.size()) +
                          " bytes does not fit in a LAS VLR (65534 at most)");
    }
    LasVlr v;
    v.user_id = kLasProjectionUserId;
    v.record_id = kLasWktRecordId;
    v.description = "OGC COORDINATE SYSTEM WKT";
    v.data.assign(wkt.begin(), wkt.end());
    v.data.push_back(0);
    v.length = v.data.size();
    return v;
}

LasFileCrs las_file_crs(const LasHeader& header, std::span<const LasVlr> vlrs) {
    LasFileCrs out;
    const LasVlr* wkt = find_record(vlrs, kLasWktRecordId);
    const LasVlr* keys = find_record(vlrs, kLasGeoKeyDirectoryRecordId);
    if (wkt != nullptr && (header.crs_is_wkt() || keys == nullptr)) {
        out.source = LasCrsSource::wkt;
        out.crs.wkt = record_text(*wkt);
        out.crs.epsg = summarize_wkt(out.crs.wkt).epsg;
        if (out.crs.wkt.empty()) {
            out.warnings.push_back("the OGC WKT record (LASF_Projection 2112) is empty");
        }
        if (!header.crs_is_wkt()) {
            out.warnings.push_back("a WKT record but the global encoding's WKT bit is clear");
        }
        if (keys != nullptr) {
            out.warnings.push_back(
                "both a WKT record and GeoTIFF keys (LAS 1.4 allows one); "
                "the WKT bit chooses the WKT");
        }
        return out;
    }
    if (keys != nullptr) {
        out.source = LasCrsSource::geotiff;
        read_geotiff_keys(*keys, find_record(vlrs, kGeoAsciiParamsRecordId), out);
        if (header.crs_is_wkt()) {
            out.warnings.push_back("GeoTIFF keys but the global encoding's WKT bit is set");
        }
        if (wkt != nullptr) {
            out.warnings.push_back(
                "both a WKT record and GeoTIFF keys (LAS 1.4 allows one); "
                "the clear WKT bit chooses the GeoTIFF keys");
        }
        if (las_format_is_extended(header.point_format)) {
            out.warnings.push_back("GeoTIFF keys in a point format " +
                                   std::to_string(header.point_format) +
                                   " file (LAS 1.4 requires WKT for formats 6-10)");
        }
    }
    return out;
}

}  // namespace beamtrace
