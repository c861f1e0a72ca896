// Coordinate reference systems as the user or an input file states them: an OGC WKT string and,
// where known, its EPSG code. There is no CRS database: WKT is built only for the codes whose
// definition follows from the code itself (crs_wkt_for_epsg), and otherwise taken as given.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace beamtrace {

/// A scene's or a file's CRS. Empty (no WKT) means unknown: outputs then record none.
struct Crs {
    std::string wkt;         ///< OGC WKT (WKT1 as LAS 1.4 asks, or whatever the user gave)
    std::uint32_t epsg = 0;  ///< EPSG code of the whole CRS, 0 when unknown

    [[nodiscard]] bool empty() const { return wkt.empty(); }
    friend bool operator==(const Crs&, const Crs&) = default;
};

/// The full OGC WKT1 of the EPSG codes that need no database: WGS 84 (4326), ETRS89 (4258),
/// WGS 84 / UTM zones 1-60 north (32601-32660) and south (32701-32760), ETRS89 / UTM zones
/// 28-38 north (25828-25838). Nothing for any other code.
[[nodiscard]] std::optional<std::string> crs_wkt_for_epsg(std::uint32_t code);

/// The CRS of an EPSG code: the full WKT where crs_wkt_for_epsg knows it, else a minimal WKT1
/// that only names the code, PROJCS["EPSG:2056",AUTHORITY["EPSG","2056"]] (GEOGCS[...] when not
/// `projected`), which readers with a CRS database (PROJ, GDAL) resolve by its authority.
[[nodiscard]] Crs crs_from_epsg(std::uint32_t code, bool projected);

/// The longest WKT a LAS VLR holds (65 535 bytes with the terminating NUL).
inline constexpr std::size_t kMaxWktBytes = 65534;

/// A `crs:` setting: "EPSG:<code>" (any case; only the codes crs_wkt_for_epsg knows) or an OGC
/// WKT string (WKT1 or WKT2: KEYWORD[...] with balanced brackets and quotes), kept as written.
/// Nothing, with `problem` set to a one-line reason, when the text is neither or is longer than
/// kMaxWktBytes.
[[nodiscard]] std::optional<Crs> parse_crs_text(std::string_view text, std::string& problem);

/// What a WKT string says of itself: its top-level keyword (PROJCS, GEOGCS, PROJCRS...), its
/// name (the first quoted string) and its top-level EPSG code (WKT1 AUTHORITY["EPSG","n"], WKT2
/// ID["EPSG",n]; 0 when it has none). Never throws; a malformed string gives what could be read.
struct WktSummary {
    std::string keyword;
    std::string name;
    std::uint32_t epsg = 0;
};
[[nodiscard]] WktSummary summarize_wkt(std::string_view wkt);

/// One line for people: "EPSG:32632 (WGS 84 / UTM zone 32N)", or the WKT's name and keyword.
[[nodiscard]] std::string describe_crs(const Crs& crs);

}  // namespace beamtrace
