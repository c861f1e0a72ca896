#include "beamtrace/core/crs.hpp"

#include <cctype>
#include <charconv>

namespace beamtrace {
namespace {

/// A datum's geographic CRS, WKT1 as GDAL writes it (EPSG names and authority codes).
struct Geographic {
    const char* name;
    const char* datum;
    const char* datum_code;
    const char* spheroid;
    const char* inverse_flattening;
    const char* spheroid_code;
    const char* code;
};

constexpr Geographic kWgs84{"WGS 84",        "WGS_1984", "6326", "WGS 84",
                            "298.257223563", "7030",     "4326"};
constexpr Geographic kEtrs89{"ETRS89",        "European_Terrestrial_Reference_System_1989",
                             "6258",          "GRS 1980",
                             "298.257222101", "7019",
                             "4258"};

[[nodiscard]] std::string authority(const std::string& code) {
    return "AUTHORITY[\"EPSG\",\"" + code + "\"]";
}

[[nodiscard]] std::string geogcs(const Geographic& g) {
    return std::string("GEOGCS[\"") + g.name + "\",DATUM[\"" + g.datum + "\",SPHEROID[\"" +
           g.spheroid + "\",6378137," + g.inverse_flattening + "," + authority(g.spheroid_code) +
           "]," + authority(g.datum_code) + "],PRIMEM[\"Greenwich\",0," + authority("8901") +
           "],UNIT[\"degree\",0.0174532925199433," + authority("9122") + "]," + authority(g.code) +
           "]";
}

/// A transverse Mercator UTM zone (1-60) on `g`, north or south of the equator.
[[nodiscard]] std::string utm(const Geographic& g, int zone, bool south, std::uint32_t code) {
    const std::string name =
        std::string(g.name) + " / UTM zone " + std::to_string(zone) + (south ? "S" : "N");
    return "PROJCS[\"" + name + "\"," + geogcs(g) +
           ",PROJECTION[\"Transverse_Mercator\"],PARAMETER[\"latitude_of_origin\",0],"
           "PARAMETER[\"central_meridian\"," +
           std::to_string(-183 + 6 * zone) +
           "],PARAMETER[\"scale_factor\",0.9996],PARAMETER[\"false_easting\",500000],"
           "PARAMETER[\"false_northing\"," +
           (south ? "10000000" : "0") + "],UNIT[\"metre\",1," + authority("9001") +
           "],AXIS[\"Easting\",EAST],AXIS[\"Northing\",NORTH]," + authority(std::to_string(code)) +
           "]";
}

[[nodiscard]] std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())) != 0) {
        s.remove_prefix(1);
    }
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())) != 0) {
        s.remove_suffix(1);
    }
    return s;
}

[[nodiscard]] bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) {
        return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (std::toupper(static_cast<unsigned char>(a[i])) !=
            std::toupper(static_cast<unsigned char>(b[i]))) {
            return false;
        }
    }
    return true;
}

/// Brackets ([ ] or ( )) balance outside quoted strings ("" escapes a quote inside one).
[[nodiscard]] bool balanced(std::string_view s) {
    int depth = 0;
    bool quoted = false;
    for (const char ch : s) {
        if (ch == '"') {
            quoted = !quoted;  // "" toggles twice
        } else if (!quoted && (ch == '[' || ch == '(')) {
            ++depth;
        } else if (!quoted && (ch == ']' || ch == ')')) {
            if (--depth < 0) {
                return false;
            }
        }
    }
    return depth == 0 && !quoted;
}

/// The code of AUTHORITY["EPSG","n"] / ID["EPSG",n] whose body starts at `body` (after '['),
/// or 0.
[[nodiscard]] std::uint32_t epsg_code_at(std::string_view wkt, std::size_t body) {
    std::string_view rest = wkt.substr(body);
    if (rest.size() < 7 || !iequals(rest.substr(0, 6), "\"EPSG\"") || rest[6] != ',') {
        return 0;
    }
    rest.remove_prefix(7);
    if (!rest.empty() && rest.front() == '"') {
        rest.remove_prefix(1);
    }
    std::uint32_t code = 0;
    const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), code);
    return ec == std::errc() && end != rest.data() ? code : 0;
}

}  // namespace

std::optional<std::string> crs_wkt_for_epsg(std::uint32_t code) {
    if (code == 4326) {
        return geogcs(kWgs84);
    }
    if (code == 4258) {
        return geogcs(kEtrs89);
    }
    if (code >= 32601 && code <= 32660) {
        return utm(kWgs84, static_cast<int>(code - 32600), false, code);
    }
    if (code >= 32701 && code <= 32760) {
        return utm(kWgs84, static_cast<int>(code - 32700), true, code);
    }
    if (code >= 25828 && code <= 25838) {
        return utm(kEtrs89, static_cast<int>(code - 25800), false, code);
    }
    return std::nullopt;
}

Crs crs_from_epsg(std::uint32_t code, bool projected) {
    if (auto wkt = crs_wkt_for_epsg(code)) {
        return {std::move(*wkt), code};
    }
    const std::string c = std::to_string(code);
    return {
        std::string(projected ? "PROJCS" : "GEOGCS") + "[\"EPSG:" + c + "\"," + authority(c) + "]",
        code};
}

std::optional<Crs> parse_crs_text(std::string_view text, std::string& problem) {
    const std::string_view s = trim(text);
    if (s.size() > 5 && iequals(s.substr(0, 5), "EPSG:")) {
        std::uint32_t code = 0;
        const std::string_view digits = s.substr(5);
        const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), code);
        if (ec != std::errc() || end != digits.data() + digits.size()) {
            problem = "'" + std::string(s) + "': expected EPSG:<code> with a decimal code";
            return std::nullopt;
        }
        if (auto wkt = crs_wkt_for_epsg(code)) {
            return Crs{std::move(*wkt), code};
        }
        problem = "EPSG:" + std::to_string(code) +
                  ": no WKT is built in for this code (only 4326, 4258, 326xx, 327xx, 25828-25838"
                  "); give the CRS's OGC WKT string instead";
        return std::nullopt;
    }
    std::size_t k = 0;
    while (k < s.size() && (std::isalnum(static_cast<unsigned char>(s[k])) != 0 || s[k] == '_')) {
        ++k;
    }
    const bool wkt = k > 0 && k < s.size() && (s[k] == '[' || s[k] == '(') &&
                     (s.back() == ']' || s.back() == ')') && balanced(s) &&
                     s.find('\0') == std::string_view::npos;
    if (!wkt) {
        problem = "expected EPSG:<code> or an OGC WKT string (KEYWORD[...] with balanced brackets)";
        return std::nullopt;
    }
    if (s.size() > kMaxWktBytes) {
        problem = "the WKT string has " + std::to_string(s.size()) + " bytes, more than the " +
                  std::to_string(kMaxWktBytes) + " a LAS VLR holds";
        return std::nullopt;
    }
    Crs crs{std::string(s), 0};
    crs.epsg = summarize_wkt(crs.wkt).epsg;
    return crs;
}

WktSummary summarize_wkt(std::string_view wkt) {
    WktSummary out;
    wkt = trim(wkt);
    std::size_t k = 0;
    while (k < wkt.size() &&
           (std::isalnum(static_cast<unsigned char>(wkt[k])) != 0 || wkt[k] == '_')) {
        ++k;
    }
    out.keyword = std::string(wkt.substr(0, k));
    int depth = 0;
    bool quoted = false;
    std::size_t word = 0;  // start of the current keyword
    for (std::size_t i = 0; i < wkt.size(); ++i) {
        const char ch = wkt[i];
        if (ch == '"') {
            if (!quoted && depth == 1 && out.name.empty()) {
                const std::size_t close = wkt.find('"', i + 1);
                out.name = std::string(wkt.substr(i + 1, close == std::string_view::npos
                                                             ? std::string_view::npos
                                                             : close - i - 1));
            }
            quoted = !quoted;
        } else if (quoted) {
            continue;
        } else if (ch == '[' || ch == '(') {
            const std::string_view key = trim(wkt.substr(word, i - word));
            if (depth == 1 && (iequals(key, "AUTHORITY") || iequals(key, "ID"))) {
                out.epsg = epsg_code_at(wkt, i + 1);  // the last one at the top level wins
            }
            ++depth;
            word = i + 1;
        } else if (ch == ']' || ch == ')') {
            --depth;
            word = i + 1;
        } else if (ch == ',') {
            word = i + 1;
        }
    }
    return out;
}

std::string describe_crs(const Crs& crs) {
    if (crs.empty()) {
        return "none";
    }
    const WktSummary s = summarize_wkt(crs.wkt);
    const std::uint32_t code = crs.epsg != 0 ? crs.epsg : s.epsg;
    std::string text = code != 0 ? "EPSG:" + std::to_string(code) : s.keyword;
    if (!s.name.empty() && s.name != text) {
        text += " (" + s.name + ")";
    }
    return text.empty() ? "WKT" : text;
}

}  // namespace beamtrace
