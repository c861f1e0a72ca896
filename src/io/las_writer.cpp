#include "beamtrace/io/las_writer.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <limits>
#include <string_view>
#include <type_traits>

#include "beamtrace/core/atomic_file.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_crs.hpp"
#include "beamtrace/io/point_sink.hpp"
#include "core/simd_level.hpp"
#include "io/detail/direct_sink.hpp"
#include "io/detail/laz_chunk_writer.hpp"
#include "io/detail/round_int32.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace beamtrace {

static_assert(std::endian::native == std::endian::little,
              "the LAS writer encodes little-endian records with memcpy");

namespace {

using detail::round_to_int32;
using detail::rounds_into_int32;

constexpr std::size_t kChunkPoints = std::size_t{1} << 16;
constexpr std::size_t kHeaderBytes = 375;
constexpr std::size_t kVlrHeaderBytes = 54;
constexpr std::size_t kEvlrHeaderBytes = 60;

template <typename T>
void store(std::uint8_t* p, T value) {
    std::memcpy(p, &value, sizeof(T));
}

constexpr std::size_t kWavePacketBytes = 29;

/// The 29 bytes of a wave packet: index, offset, size, location, dx, dy, dz.
void store_wave_packet(const LasWavePacket& w, std::uint8_t* r) {
    r[0] = w.descriptor_index;
    store<std::uint64_t>(r + 1, w.offset);
    store<std::uint32_t>(r + 9, w.size);
    store<float>(r + 13, w.location_ps);
    store<float>(r + 17, w.dx);
    store<float>(r + 21, w.dy);
    store<float>(r + 25, w.dz);
}

/// Copies `text` into a fixed-size, NUL-padded character field (validate() checked the length).
void store_text(std::uint8_t* p, std::string_view text, std::size_t size) {
    std::memset(p, 0, size);
    std::memcpy(p, text.data(), std::min(text.size(), size));
}

[[nodiscard]] std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

/// Formats 9 and 10 need a place for the packets and at least one descriptor VLR; the others
/// have no packets.
void wave_packet_problems(const LasWriterConfig& c, std::vector<std::string>& problems) {
    const bool packets = las_format_has_wave_packet(c.point_format);
    const bool stored = c.waveform_storage != LasWaveformStorage::none;
    if (packets && !stored) {
        problems.push_back("point_format " + std::to_string(c.point_format) +
                           ": wave packets need waveform_storage internal or external");
    }
    if (!packets && stored) {
        problems.push_back("waveform_storage: point_format " + std::to_string(c.point_format) +
                           " has no wave packets");
    }
    const bool described = std::any_of(c.vlrs.begin(), c.vlrs.end(), [](const LasVlr& v) {
        return !v.extended && v.user_id == "LASF_Spec" && v.record_id >= 100 && v.record_id <= 354;
    });
    if (packets && !described) {
        problems.push_back("point_format " + std::to_string(c.point_format) +
                           ": no Wave Packet Descriptor VLR (LASF_Spec / 100-354) in vlrs");
    }
}

}  // namespace

std::vector<std::string> LasWriterConfig::validate() const {
    std::vector<std::string> problems;
    if (point_format < 6 || point_format > 10) {
        problems.push_back("point_format: " + std::to_string(point_format) +
                           " is not supported (expected 6, 7, 8, 9 or 10)");
    }
    wave_packet_problems(*this, problems);
    for (std::size_t k = 0; k < 3; ++k) {
        const std::string axis(1, "xyz"[k]);
        if (!std::isfinite(scale[k]) || scale[k] <= 0.0) {
            problems.push_back("scale." + axis + ": " + number(scale[k]) +
                               " must be finite and > 0");
        }
        if (!std::isfinite(offset[k])) {
            problems.push_back("offset." + axis + ": " + number(offset[k]) + " must be finite");
        }
    }
    if (compression == LasCompression::laz &&
        (laz_chunk_size == 0 || laz_chunk_size == 0xFFFFFFFFU)) {
        problems.push_back("laz_chunk_size: " + std::to_string(laz_chunk_size) +
                           " (expected 1 to 4294967294 points)");
    }
    if (system_identifier.size() > 32) {
        problems.push_back("system_identifier: '" + system_identifier + "' is longer than 32");
    }
    if (generating_software.size() > 32) {
        problems.push_back("generating_software: '" + generating_software + "' is longer than 32");
    }
    if ((creation_year == 0) != (creation_day_of_year == 0) || creation_day_of_year > 366) {
        problems.push_back("creation date: day " + std::to_string(creation_day_of_year) +
                           " of year " + std::to_string(creation_year) +
                           " (set both, day 1-366, or neither)");
    }
    for (std::size_t i = 0; i < vlrs.size(); ++i) {
        const LasVlr& v = vlrs[i];
        const std::string where = "vlrs[" + std::to_string(i) + "] (" + v.user_id + "/" +
                                  std::to_string(v.record_id) + ")";
        if (v.user_id.size() > 16) {
            problems.push_back(where + ": user_id is longer than 16 characters");
        }
        if (v.description.size() > 32) {
            problems.push_back(where + ": description is longer than 32 characters");
        }
        if (!v.extended && v.data.size() > std::numeric_limits<std::uint16_t>::max()) {
            problems.push_back(where + ": " + std::to_string(v.data.size()) +
                               " bytes do not fit in a VLR (max 65535); mark it extended");
        }
    }
    return problems;
}

LasWriterConfig las_config_for_extent(const Vec3d& lo, const Vec3d& hi, double resolution_m) {
    if (!std::isfinite(resolution_m) || resolution_m <= 0.0) {
        throw ConfigError("las_config_for_extent: resolution " + number(resolution_m) +
                          " m must be finite and > 0");
    }
    LasWriterConfig config;
    constexpr double kMaxSteps = static_cast<double>(std::numeric_limits<std::int32_t>::max()) - 1;
    for (std::size_t k = 0; k < 3; ++k) {
        if (!std::isfinite(lo[k]) || !std::isfinite(hi[k]) || lo[k] > hi[k]) {
            throw ConfigError("las_config_for_extent: bounds " + std::string(1, "xyz"[k]) + " [" +
                              number(lo[k]) + ", " + number(hi[k]) +
                              "] must be finite with min <= max");
        }
        const double centre = 0.5 * (lo[k] + hi[k]);
        const double offset = resolution_m <= 1.0
                                  ? std::round(centre)
                                  : std::round(centre / resolution_m) * resolution_m;
        const double half = std::max(hi[k] - offset, offset - lo[k]);
        // 1-2-5 steps: resolution, 2x, 5x, 10x, 20x, ...
        double scale = resolution_m;
        for (int step = 0; half / scale > kMaxSteps; ++step) {
            scale *= step % 3 == 1 ? 2.5 : 2.0;
        }
        config.offset[k] = offset;
        config.scale[k] = scale;
    }
    return config;
}

LasWriterConfig las_config_for_extent(const Aabb& box, double resolution_m) {
    if (box.empty()) {
        throw ConfigError("las_config_for_extent: the bounding box is empty");
    }
    return las_config_for_extent(Vec3d(box.lo), Vec3d(box.hi), resolution_m);
}

LasWriter::LasWriter(std::filesystem::path path, LasWriterConfig config)
    : path_(std::move(path)), config_(std::move(config)) {
    set_up_header();
    if (config_.compression == LasCompression::laz) {
        open_laz();
    }
    file_ = std::make_unique<AtomicFile>(path_);
    sink_ = std::make_unique<detail::DirectSink>(file_->temp_path(), path_);
    // The header is a placeholder until close() knows the counts and bounds.
    const std::vector<std::uint8_t> head = header_and_vlrs(header_);
    sink_->append(head.data(), head.size());
    if (laz_vlr_) {
        std::vector<std::uint8_t> vlr;
        append_vlr(*laz_vlr_, vlr);
        sink_->append(vlr.data(), vlr.size());
        start_laz_points();
    }
    chunk_.resize(kChunkPoints * header_.point_record_length);
}

LasWriter::LasWriter(LasWriterConfig config) : config_(std::move(config)) {
    if (config_.compression != LasCompression::none) {
        throw ConfigError("LAS record encoder: compressed records cannot be encoded apart");
    }
    set_up_header();
    failed_ = true;  // write(), write_block() and close() refuse: there is no file
}

void LasWriter::append_vlr(const LasVlr& v, std::vector<std::uint8_t>& out) {
    std::uint8_t b[kVlrHeaderBytes] = {};
    store_text(b + 2, v.user_id, 16);
    store<std::uint16_t>(b + 18, v.record_id);
    store<std::uint16_t>(b + 20, static_cast<std::uint16_t>(v.data.size()));
    store_text(b + 22, v.description, 32);
    out.insert(out.end(), b, b + sizeof b);
    out.insert(out.end(), v.data.begin(), v.data.end());
}

std::vector<std::uint8_t> LasWriter::header_and_vlrs(const LasHeader& h) const {
    const auto header = encode_header(h);
    std::vector<std::uint8_t> out(header.begin(), header.end());
    for (const auto& v : config_.vlrs) {
        if (!v.extended) {
            append_vlr(v, out);
        }
    }
    return out;
}

std::vector<std::uint8_t> LasWriter::header_bytes(const LasRecordBlock& totals) const {
    if (header_.number_of_evlrs > 0 || laz_vlr_) {
        throw ConfigError(
            "LAS header of records placed apart: EVLRs and compression are not "
            "supported there");
    }
    LasHeader h = header_;
    h.point_count = totals.count;
    h.points_by_return = totals.by_return;
    for (std::size_t k = 0; k < 3; ++k) {
        h.min[k] = totals.count == 0 ? 0.0 : totals.lo[k] * h.scale[k] + h.offset[k];
        h.max[k] = totals.count == 0 ? 0.0 : totals.hi[k] * h.scale[k] + h.offset[k];
    }
    return header_and_vlrs(h);
}

void las_add_totals(LasRecordBlock& totals, const LasRecordBlock& block) {
    if (block.count == 0) {
        return;
    }
    for (std::size_t k = 0; k < 3; ++k) {
        totals.lo[k] = totals.count == 0 ? block.lo[k] : std::min(totals.lo[k], block.lo[k]);
        totals.hi[k] = totals.count == 0 ? block.hi[k] : std::max(totals.hi[k], block.hi[k]);
    }
    for (std::size_t i = 0; i < 15; ++i) {
        totals.by_return[i] += block.by_return[i];
    }
    totals.count += block.count;
}

void LasWriter::set_up_header() {
    const auto problems = config_.validate();
    if (!problems.empty()) {
        std::string message = path_.string() + ": LAS writer settings:";
        for (const auto& p : problems) {
            message += "\n  " + p;
        }
        throw ConfigError(message);
    }
    LasHeader& h = header_;
    h.version_major = 1;
    h.version_minor = 4;
    h.file_source_id = config_.file_source_id;
    // WKT bit: required for formats 6-10; for others only when a WKT record (2112) is written.
    const bool has_wkt = std::any_of(config_.vlrs.begin(), config_.vlrs.end(), [](const LasVlr& v) {
        return v.user_id == kLasProjectionUserId && v.record_id == kLasWktRecordId;
    });
    h.global_encoding =
        las_format_is_extended(config_.point_format) || has_wkt ? kLasGlobalEncodingWkt : 0;
    if (config_.gps_time_is_standard) {
        h.global_encoding |= kLasGlobalEncodingStandardGpsTime;
    }
    if (config_.waveform_storage == LasWaveformStorage::internal) {
        h.global_encoding |= kLasGlobalEncodingInternalWaveform;
        ++h.number_of_evlrs;  // the Waveform Data Packets record, written by close()
    } else if (config_.waveform_storage == LasWaveformStorage::external) {
        h.global_encoding |= kLasGlobalEncodingExternalWaveform;
    }
    h.system_identifier = config_.system_identifier;
    h.generating_software = config_.generating_software;
    h.creation_day_of_year = config_.creation_day_of_year;
    h.creation_year = config_.creation_year;
    if (h.creation_year == 0) {
        const std::time_t now = std::time(nullptr);
        std::tm utc{};
        ::gmtime_r(&now, &utc);
        h.creation_day_of_year = static_cast<std::uint16_t>(utc.tm_yday + 1);
        h.creation_year = static_cast<std::uint16_t>(utc.tm_year + 1900);
    }
    h.header_size = static_cast<std::uint16_t>(kHeaderBytes);
    std::uint64_t offset = kHeaderBytes;
    for (const auto& v : config_.vlrs) {
        if (!v.extended) {
            offset += kVlrHeaderBytes + v.data.size();
            ++h.number_of_vlrs;
        } else {
            ++h.number_of_evlrs;
        }
    }
    if (offset > std::numeric_limits<std::uint32_t>::max()) {
        throw ConfigError(path_.string() + ": LAS writer settings: the VLRs are too large");
    }
    h.offset_to_point_data = static_cast<std::uint32_t>(offset);
    h.point_format = config_.point_format;
    h.point_record_length = static_cast<std::uint16_t>(las_point_record_size(h.point_format) +
                                                       config_.extra_bytes_per_point);
    h.scale = config_.scale;
    for (std::size_t k = 0; k < 3; ++k) {
        steps_per_unit_[k] = 1.0 / h.scale[k];
    }
    h.offset = config_.offset;
}

LasWriter::~LasWriter() = default;

void LasWriter::fail(const std::string& what) {
    failed_ = true;
    file_.reset();  // removes the temporary file
    throw OutputError(path_.string() + ": " + what);
}

std::array<std::uint8_t, 375> LasWriter::encode_header(const LasHeader& h) const {
    static_assert(kHeaderBytes == 375);
    std::array<std::uint8_t, kHeaderBytes> header{};
    std::uint8_t* b = header.data();
    std::memcpy(b, "LASF", 4);
    store<std::uint16_t>(b + 4, h.file_source_id);
    store<std::uint16_t>(b + 6, h.global_encoding);
    std::memcpy(b + 8, h.project_guid.data(), 16);
    b[24] = 1;
    b[25] = 4;
    store_text(b + 26, h.system_identifier, 32);
    store_text(b + 58, h.generating_software, 32);
    store<std::uint16_t>(b + 90, h.creation_day_of_year);
    store<std::uint16_t>(b + 92, h.creation_year);
    store<std::uint16_t>(b + 94, h.header_size);
    store<std::uint32_t>(b + 96, h.offset_to_point_data);
    store<std::uint32_t>(b + 100, h.number_of_vlrs);
    b[104] = static_cast<std::uint8_t>(h.point_format | (laz_vlr_ ? 0x80 : 0));
    store<std::uint16_t>(b + 105, h.point_record_length);
    // 107-130: legacy point counts stay 0 for formats 6-10.
    for (std::size_t k = 0; k < 3; ++k) {
        store<double>(b + 131 + 8 * k, h.scale[k]);
        store<double>(b + 155 + 8 * k, h.offset[k]);
        store<double>(b + 179 + 16 * k, h.max[k]);
        store<double>(b + 187 + 16 * k, h.min[k]);
    }
    store<std::uint64_t>(b + 227, h.start_of_waveform_data);
    store<std::uint64_t>(b + 235, h.start_of_first_evlr);
    store<std::uint32_t>(b + 243, h.number_of_evlrs);
    store<std::uint64_t>(b + 247, h.point_count);
    for (std::size_t i = 0; i < 15; ++i) {
        store<std::uint64_t>(b + 255 + 8 * i, h.points_by_return[i]);
    }
    return header;
}

void LasRecordBlock::clear() {
    count = 0;  // the bytes stay allocated (and are overwritten) for the next use
    by_return.fill(0);
}

namespace {

/// The OutputError of a point the file cannot hold (out of the encoders' hot loops).
[[noreturn, gnu::cold, gnu::noinline]] void reject_point(const std::filesystem::path& path,
                                                         std::uint64_t index,
                                                         const std::string& what) {
    throw OutputError(path.string() + ": point " + std::to_string(index) + ": " + what);
}

[[noreturn, gnu::cold, gnu::noinline]] void reject_coordinate(const std::filesystem::path& path,
                                                              std::uint64_t index, std::size_t k,
                                                              double value, double scale,
                                                              double offset) {
    reject_point(path, index,
                 std::string(1, "xyz"[k]) + " = " + number(value) +
                     " does not fit in a 32-bit LAS coordinate with scale " + number(scale) +
                     " and offset " + number(offset) + " (see las_config_for_extent)");
}

[[noreturn, gnu::cold, gnu::noinline]] void reject_returns(const std::filesystem::path& path,
                                                           std::uint64_t index,
                                                           const LasSimplePoint& p) {
    reject_point(path, index,
                 "return " + std::to_string(p.return_number) + " of " +
                     std::to_string(p.number_of_returns) + " exceeds 15");
}

[[noreturn, gnu::cold, gnu::noinline]] void reject_scanner_channel(
    const std::filesystem::path& path, std::uint64_t index, std::uint8_t channel) {
    reject_point(path, index, "scanner channel " + std::to_string(channel) + " exceeds 3");
}

/// Bytes 0-29: the part of a record every format 6-10 has (LasWriter::encode_base).
constexpr std::size_t kBaseRecordBytes = 30;

[[noreturn, gnu::cold, gnu::noinline]] void reject_angle(const std::filesystem::path& path,
                                                         std::uint64_t index, float angle_deg) {
    reject_point(path, index, "scan angle " + number(angle_deg) + " deg is outside [-180, 180]");
}

}  // namespace

LasWriter::RecordConstants LasWriter::record_constants() const {
    return {{header_.offset[0], header_.offset[1], header_.offset[2]},
            {steps_per_unit_[0], steps_per_unit_[1], steps_per_unit_[2]},
            header_.point_record_length,
            header_.point_format};
}

namespace {

/// Bytes 12-29 of a record (intensity to GPS time; flags: byte 15); false, with the bytes
/// meaningless, for a point whose returns or scan angle the record cannot hold.
[[gnu::always_inline]] inline bool encode_fields(const LasSimplePoint& p, std::uint8_t flags,
                                                 std::uint8_t* r) {
    if (p.return_number > 15 || p.number_of_returns > 15) [[unlikely]] {
        return false;
    }
    const double angle = static_cast<double>(p.scan_angle_deg) * (1.0 / kScanAngleStepDeg);
    const std::int32_t angle_steps = rounds_into_int32(angle) ? round_to_int32(angle) : 1 << 30;
    if (!(angle_steps >= -30000 && angle_steps <= 30000)) [[unlikely]] {
        return false;
    }
    store<std::uint16_t>(r + 12, p.intensity);
    r[14] = static_cast<std::uint8_t>(p.return_number | (p.number_of_returns << 4));
    r[15] = flags;
    r[16] = p.classification;
    r[17] = p.user_data;
    store<std::int16_t>(r + 18, static_cast<std::int16_t>(angle_steps));
    store<std::uint16_t>(r + 20, p.point_source_id);
    store<double>(r + 22, p.gps_time);
    return true;
}

/// Why encode_fields() refused `p`.
[[noreturn, gnu::cold, gnu::noinline]] void reject_fields(const std::filesystem::path& path,
                                                          std::uint64_t index,
                                                          const LasSimplePoint& p) {
    if (p.return_number > 15 || p.number_of_returns > 15) {
        reject_returns(path, index, p);
    }
    reject_angle(path, index, p.scan_angle_deg);
}

#if defined(__x86_64__) && defined(__GNUC__)
/// What encode_bare_avx2() keeps across a block's points: the integer bounds (lanes 0-2: x, y,
/// z) and the counts by return.
struct BareTotals {
    __m128i lo = _mm_set1_epi32(std::numeric_limits<std::int32_t>::max());
    __m128i hi = _mm_set1_epi32(std::numeric_limits<std::int32_t>::min());
    std::array<std::uint64_t, 15> by_return{};
};

/// The 30-byte records of format 6 from the front of `points` into `r`, as encode_base() writes
/// them, with x, y and z in the lanes of one vector: (x - offset) * steps, range-checked and
/// rounded (halves away from zero) as round_to_int32() does, lane by lane. Returns how many
/// points it encoded: it stops before the first point encode_base() would reject (whose
/// rejection the scalar path then gives). Lane 3 holds the GPS time times 0: its integer lands
/// in bytes 12-15, which encode_fields() writes over.
template <class Point>
__attribute__((target("avx2"))) std::size_t encode_bare_avx2(std::span<const Point> points,
                                                             const double offset[3],
                                                             const double steps_per_unit[3],
                                                             std::uint8_t* r, BareTotals& t) {
    static_assert(offsetof(LasSimplePoint, y) == 8 && offsetof(LasSimplePoint, z) == 16 &&
                  offsetof(LasSimplePoint, gps_time) == 24);
    const __m256d off = _mm256_setr_pd(offset[0], offset[1], offset[2], 0.0);
    const __m256d steps =
        _mm256_setr_pd(steps_per_unit[0], steps_per_unit[1], steps_per_unit[2], 0.0);
    const __m256d low = _mm256_set1_pd(-2147483648.5), high = _mm256_set1_pd(2147483647.5);
    const __m256d half = _mm256_set1_pd(0.5), minus_half = _mm256_set1_pd(-0.5);
    const __m256d one = _mm256_set1_pd(1.0);
    for (std::size_t i = 0; i < points.size(); ++i, r += kBaseRecordBytes) {
        const LasSimplePoint& p = points[i];
        const __m256d x = _mm256_mul_pd(_mm256_sub_pd(_mm256_loadu_pd(&p.x), off), steps);
        const __m256d fits =
            _mm256_and_pd(_mm256_cmp_pd(x, low, _CMP_GT_OQ), _mm256_cmp_pd(x, high, _CMP_LT_OQ));
        if ((_mm256_movemask_pd(fits) & 7) != 7 || p.scanner_channel > 3) [[unlikely]] {
            return i;
        }
        const __m256d whole = _mm256_round_pd(x, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
        const __m256d f = _mm256_sub_pd(x, whole);
        const __m256d up = _mm256_and_pd(_mm256_cmp_pd(f, half, _CMP_GE_OQ), one);
        const __m256d down = _mm256_and_pd(_mm256_cmp_pd(f, minus_half, _CMP_LE_OQ), one);
        const __m128i q = _mm256_cvttpd_epi32(_mm256_add_pd(whole, _mm256_sub_pd(up, down)));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(r), q);  // before bytes 12-29
        if (!encode_fields(p, static_cast<std::uint8_t>(p.scanner_channel << 4), r)) [[unlikely]] {
            return i;
        }
        t.lo = _mm_min_epi32(t.lo, q);
        t.hi = _mm_max_epi32(t.hi, q);
        if (p.return_number >= 1) {
            ++t.by_return[p.return_number - 1u];
        }
    }
    return points.size();
}
#endif

}  // namespace

void LasWriter::encode_base(const LasSimplePoint& p, std::uint8_t flags, std::uint64_t index,
                            std::uint8_t* r, std::int32_t q[3], const RecordConstants& c) const {
    const double xyz[3] = {p.x, p.y, p.z};
    for (std::size_t k = 0; k < 3; ++k) {
        // A multiplication, not a division (a quarter of the encoding time): the same steps
        // except where (x - offset) / scale falls within an ulp of a half step.
        const double steps = (xyz[k] - c.offset[k]) * c.steps_per_unit[k];
        if (!rounds_into_int32(steps)) [[unlikely]] {
            reject_coordinate(path_, index, k, xyz[k], header_.scale[k], header_.offset[k]);
        }
        q[k] = round_to_int32(steps);
    }
    if (!encode_fields(p, flags, r)) [[unlikely]] {
        reject_fields(path_, index, p);
    }
    // Each value from its register (a 12-byte copy of q read back just-stored 4-byte values
    // as 8 bytes, which stalls store forwarding).
    store<std::int32_t>(r, q[0]);
    store<std::int32_t>(r + 4, q[1]);
    store<std::int32_t>(r + 8, q[2]);
}

void LasWriter::encode_record(const LasPoint& p, std::uint64_t index, std::uint8_t* r,
                              std::int32_t q[3]) const {
    if (p.scanner_channel > 3) {
        throw OutputError(path_.string() + ": point " + std::to_string(index) +
                          ": scanner channel " + std::to_string(p.scanner_channel) + " exceeds 3");
    }
    if (p.extra_bytes.size() != config_.extra_bytes_per_point) {
        throw OutputError(path_.string() + ": point " + std::to_string(index) + ": " +
                          std::to_string(p.extra_bytes.size()) + " extra bytes, expected " +
                          std::to_string(config_.extra_bytes_per_point));
    }
    const auto flags = static_cast<std::uint8_t>(
        (p.synthetic ? 0x01 : 0) | (p.key_point ? 0x02 : 0) | (p.withheld ? 0x04 : 0) |
        (p.overlap ? 0x08 : 0) | (p.scanner_channel << 4) | (p.scan_direction ? 0x40 : 0) |
        (p.edge_of_flight_line ? 0x80 : 0));
    encode_base({p.x, p.y, p.z, p.gps_time, p.scan_angle_deg, p.intensity, p.point_source_id,
                 p.return_number, p.number_of_returns, p.classification, p.user_data, p.red,
                 p.green, p.blue, p.nir, p.scanner_channel},
                flags, index, r, q, record_constants());
    std::size_t pos = 30;
    if (las_format_has_rgb(header_.point_format)) {
        store<std::uint16_t>(r + 30, p.red);
        store<std::uint16_t>(r + 32, p.green);
        store<std::uint16_t>(r + 34, p.blue);
        pos = 36;
    }
    if (las_format_has_nir(header_.point_format)) {
        store<std::uint16_t>(r + 36, p.nir);
        pos = 38;
    }
    if (las_format_has_wave_packet(header_.point_format)) {
        store_wave_packet({p.wave_descriptor_index, p.wave_data_offset, p.wave_packet_size,
                           p.wave_return_location, p.wave_dx, p.wave_dy, p.wave_dz},
                          r + pos);
        pos += kWavePacketBytes;
    }
    if (!p.extra_bytes.empty()) {
        std::memcpy(r + pos, p.extra_bytes.data(), p.extra_bytes.size());
    }
}

void LasWriter::encode_record(const LasSimplePoint& p, std::uint64_t index, std::uint8_t* r,
                              std::int32_t q[3], const RecordConstants& c) const {
    if (p.scanner_channel > 3) [[unlikely]] {
        reject_scanner_channel(path_, index, p.scanner_channel);
    }
    encode_base(p, static_cast<std::uint8_t>(p.scanner_channel << 4), index, r, q, c);
    // Extra bytes (and wave packet fields, written after) are zero: block bytes are reused.
    if (c.record_length > 30u) {
        std::memset(r + 30, 0, c.record_length - 30u);
    }
    if (las_format_has_rgb(c.point_format)) {
        store<std::uint16_t>(r + 30, p.red);
        store<std::uint16_t>(r + 32, p.green);
        store<std::uint16_t>(r + 34, p.blue);
    }
    if (las_format_has_nir(c.point_format)) {
        store<std::uint16_t>(r + 36, p.nir);
    }
}

void LasWriter::encode(const LasPoint& p, std::uint64_t index, std::uint8_t* r) {
    std::int32_t q[3];
    try {
        encode_record(p, index, r, q);
    } catch (...) {
        failed_ = true;
        file_.reset();  // removes the temporary file
        throw;
    }
    for (std::size_t k = 0; k < 3; ++k) {
        if (header_.point_count == 0 && chunk_points_ == 0) {
            lo_[k] = hi_[k] = q[k];
        } else {
            lo_[k] = std::min(lo_[k], q[k]);
            hi_[k] = std::max(hi_[k], q[k]);
        }
    }
    if (p.return_number >= 1) {
        ++header_.points_by_return[p.return_number - 1u];
    }
}

template <class Point>
void LasWriter::encode_into(const Point& p, LasRecordBlock& block) const {
    const std::size_t size = header_.point_record_length;
    const std::size_t need = (block.count + 1) * size;
    if (block.bytes.size() < need) {
        block.bytes.resize(std::max(need, 2 * block.bytes.size()));
    }
    std::int32_t q[3];
    if constexpr (std::is_same_v<Point, LasPoint>) {
        encode_record(p, block.count, block.bytes.data() + block.count * size, q);
    } else {
        encode_record(p, block.count, block.bytes.data() + block.count * size, q,
                      record_constants());
    }
    for (std::size_t k = 0; k < 3; ++k) {
        block.lo[k] = block.count == 0 ? q[k] : std::min(block.lo[k], q[k]);
        block.hi[k] = block.count == 0 ? q[k] : std::max(block.hi[k], q[k]);
    }
    if (p.return_number >= 1) {
        ++block.by_return[p.return_number - 1u];
    }
    ++block.count;
}

void LasWriter::encode(const LasPoint& point, LasRecordBlock& block) const {
    encode_into(point, block);
}

template <class Point>
// Flattened: encode_record() and encode_base() inlined into the loop (not the cold rejections).
[[gnu::flatten]] void LasWriter::encode_points(std::span<const Point> points,
                                               LasRecordBlock& block) const {
    static_assert(std::is_base_of_v<LasSimplePoint, Point>);
    if (points.empty()) {
        return;
    }
    const std::size_t size = header_.point_record_length;
    const std::size_t need = (block.count + points.size()) * size;
    if (block.bytes.size() < need) {
        block.bytes.resize(std::max(need, 2 * block.bytes.size()));
    }
    std::int32_t lo[3] = {std::numeric_limits<std::int32_t>::max(),
                          std::numeric_limits<std::int32_t>::max(),
                          std::numeric_limits<std::int32_t>::max()};
    std::int32_t hi[3] = {std::numeric_limits<std::int32_t>::min(),
                          std::numeric_limits<std::int32_t>::min(),
                          std::numeric_limits<std::int32_t>::min()};
    std::uint8_t* r = block.bytes.data() + block.count * size;
    // In locals, kept in registers: see RecordConstants.
    const RecordConstants c = record_constants();
    std::size_t count = block.count;
    std::array<std::uint64_t, 15> by_return = block.by_return;
    // Bare: the 30 bytes every record has and nothing after them (format 6, no extra bytes),
    // chosen once for the block rather than for each point after its first 30 bytes.
    const auto encode_all = [&]<bool Bare>(std::span<const Point> rest) {
        for (const LasSimplePoint& p : rest) {
            std::int32_t q[3];
            if constexpr (Bare) {
                if (p.scanner_channel > 3) [[unlikely]] {
                    reject_scanner_channel(path_, count, p.scanner_channel);
                }
                encode_base(p, static_cast<std::uint8_t>(p.scanner_channel << 4), count, r, q, c);
            } else {
                encode_record(p, count, r, q, c);
            }
            for (std::size_t k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], q[k]);
                hi[k] = std::max(hi[k], q[k]);
            }
            if (p.return_number >= 1) {
                ++by_return[p.return_number - 1u];
            }
            ++count;
            r += size;
        }
    };
    if (c.point_format == 6 && c.record_length == kBaseRecordBytes) {
        std::size_t done = 0;
#if defined(__x86_64__) && defined(__GNUC__)
        if (detail::cpu_simd_level() != detail::SimdLevel::scalar) {
            BareTotals t;
            done = encode_bare_avx2(points, c.offset, c.steps_per_unit, r, t);
            alignas(16) std::int32_t tlo[4], thi[4];
            _mm_store_si128(reinterpret_cast<__m128i*>(tlo), t.lo);
            _mm_store_si128(reinterpret_cast<__m128i*>(thi), t.hi);
            for (std::size_t k = 0; k < 3; ++k) {
                lo[k] = tlo[k];
                hi[k] = thi[k];
            }
            for (std::size_t i = 0; i < by_return.size(); ++i) {
                by_return[i] += t.by_return[i];
            }
            count += done;
            r += done * size;
        }
#endif
        encode_all.template operator()<true>(points.subspan(done));
    } else {
        encode_all.template operator()<false>(points);
    }
    block.count = count;
    block.by_return = by_return;
    const bool first = block.count == points.size();  // the block held no point before
    for (std::size_t k = 0; k < 3; ++k) {
        block.lo[k] = first ? lo[k] : std::min(block.lo[k], lo[k]);
        block.hi[k] = first ? hi[k] : std::max(block.hi[k], hi[k]);
    }
}

template void LasWriter::encode_points(std::span<const LasSimplePoint>, LasRecordBlock&) const;
template void LasWriter::encode_points(std::span<const BlockPoint>, LasRecordBlock&) const;

void LasWriter::encode(const LasSimplePoint& point, LasRecordBlock& block) const {
    encode_into(point, block);
}

void LasWriter::write_block(const LasRecordBlock& block) {
    if (failed_ || closed_ || !file_) {
        throw OutputError(path_.string() + ": LAS writer used after " +
                          (closed_ ? "close()" : "an error"));
    }
    if (block.count == 0) {
        return;
    }
    flush_chunk();  // points written one by one go first
    const bool first = header_.point_count == 0;
    for (std::size_t k = 0; k < 3; ++k) {
        lo_[k] = first ? block.lo[k] : std::min(lo_[k], block.lo[k]);
        hi_[k] = first ? block.hi[k] : std::max(hi_[k], block.hi[k]);
    }
    for (std::size_t i = 0; i < 15; ++i) {
        header_.points_by_return[i] += block.by_return[i];
    }
    try {
        append_records(block.bytes.data(), block.count);
    } catch (...) {
        failed_ = true;
        file_.reset();
        throw;
    }
    header_.point_count += block.count;
}

void LasWriter::flush_chunk() {
    append_records(chunk_.data(), chunk_points_);
    header_.point_count += chunk_points_;
    chunk_points_ = 0;
}

void LasWriter::write(std::span<const LasPoint> points) {
    if (failed_ || closed_ || !file_) {
        throw OutputError(path_.string() + ": LAS writer used after " +
                          (closed_ ? "close()" : "an error"));
    }
    for (const LasPoint& p : points) {
        encode(p, header_.point_count + chunk_points_,
               chunk_.data() + chunk_points_ * header_.point_record_length);
        if (++chunk_points_ == kChunkPoints) {
            flush_chunk();
        }
    }
}

void LasWriter::close() {
    if (failed_ || closed_ || !file_) {
        throw OutputError(path_.string() + ": LAS writer closed after " +
                          (closed_ ? "close()" : "an error"));
    }
    try {
        flush_chunk();
        // The stream continues at the end of the points.
        const std::uint64_t points_end = finish_points();
        sink_.reset();
        LasHeader& h = header_;
        for (std::size_t k = 0; k < 3; ++k) {
            h.min[k] = h.point_count == 0 ? 0.0 : lo_[k] * h.scale[k] + h.offset[k];
            h.max[k] = h.point_count == 0 ? 0.0 : hi_[k] * h.scale[k] + h.offset[k];
        }
        h.start_of_first_evlr = h.number_of_evlrs > 0 ? points_end : 0;
        if (config_.waveform_storage == LasWaveformStorage::internal) {
            h.start_of_waveform_data = points_end;
            write_waveform_evlr();
        }
        std::uint8_t b[kEvlrHeaderBytes];
        for (const auto& v : config_.vlrs) {
            if (!v.extended) {
                continue;
            }
            std::memset(b, 0, sizeof b);
            store_text(b + 2, v.user_id, 16);
            store<std::uint16_t>(b + 18, v.record_id);
            store<std::uint64_t>(b + 20, v.data.size());
            store_text(b + 28, v.description, 32);
            file_->write(b, sizeof b);
            file_->write(v.data.data(), v.data.size());
        }
        write_laz_table_offset();
        if (::fseeko(file_->stream(), 0, SEEK_SET) != 0) {
            fail("cannot seek back to the header");
        }
        const auto header = encode_header(header_);
        file_->write(header.data(), header.size());
        file_->commit();
        closed_ = true;
    } catch (...) {
        failed_ = true;
        file_.reset();
        throw;
    }
}

// Wave packets (formats 9, 10).

std::size_t LasWriter::wave_packet_field() const {
    return header_.point_format == 10 ? 38 : 30;
}

void LasWriter::encode(const LasSimplePoint& point, const LasWavePacket& packet,
                       LasRecordBlock& block) const {
    encode_into(point, block);
    std::uint8_t* r = block.bytes.data() + (block.count - 1) * header_.point_record_length;
    store_wave_packet(packet, r + wave_packet_field());
}

void LasWriter::close_with_waveform_data(const std::filesystem::path& packets) {
    waveform_data_ = packets;
    close();
}

void LasWriter::write_waveform_evlr() {
    std::FILE* in = waveform_data_.empty() ? nullptr : std::fopen(waveform_data_.c_str(), "rb");
    if (in == nullptr) {
        fail("internal waveform data: cannot read the staged packets '" + waveform_data_.string() +
             "' (close_with_waveform_data)");
    }
    std::error_code ec;
    const std::uint64_t size = std::filesystem::file_size(waveform_data_, ec);
    std::uint8_t b[kEvlrHeaderBytes] = {};
    store_text(b + 2, "LASF_Spec", 16);
    store<std::uint16_t>(b + 18, 65535);
    store<std::uint64_t>(b + 20, ec ? 0 : size);
    store_text(b + 28, "Waveform Data Packets", 32);
    file_->write(b, sizeof b);
    std::vector<std::uint8_t> buffer(std::size_t{1} << 20);
    std::uint64_t copied = 0;
    for (std::size_t n; (n = std::fread(buffer.data(), 1, buffer.size(), in)) > 0;) {
        file_->write(buffer.data(), n);
        copied += n;
    }
    std::fclose(in);
    if (ec || copied != size) {
        fail("internal waveform data: short read of the staged packets");
    }
}

}  // namespace beamtrace
