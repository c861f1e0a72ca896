// convert_las: the input's bytes copied around its point records, which stream through
// LasReader (decoded from LAZ where it is compressed) and out plain or through the LAZ chunk
// writer. The header is the input's with the fields that follow patched in place.
#include "beamtrace/io/las_convert.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "beamtrace/core/atomic_file.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "io/detail/laz_chunk_writer.hpp"
#include "laz/laz_encode.hpp"

namespace beamtrace {

namespace {

constexpr std::size_t kVlrHeaderBytes = 54;
constexpr std::size_t kCopyBytes = std::size_t{1} << 20;

template <typename T>
[[nodiscard]] T load(const std::uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
template <typename T>
void store(std::uint8_t* p, T v) {
    std::memcpy(p, &v, sizeof v);
}

/// The input's bytes around its points: the header, the VLRs to keep, the bytes between the
/// last VLR and the points, and where the records after the points (EVLRs, waveform data) start.
struct Layout {
    std::vector<std::uint8_t> header;
    std::vector<std::uint8_t> vlrs;
    std::uint32_t vlr_count = 0;
    std::vector<std::uint8_t> padding;
    std::uint64_t tail = 0;  ///< file offset of the first byte after the points to copy; 0: none
    std::uint64_t file_size = 0;
};

void read_exact(std::ifstream& f, const std::filesystem::path& in, std::uint64_t at,
                std::uint8_t* data, std::size_t size) {
    f.seekg(static_cast<std::streamoff>(at));
    f.read(reinterpret_cast<char*>(data), static_cast<std::streamsize>(size));
    if (!f || static_cast<std::size_t>(f.gcount()) != size) {
        throw InputError(in.string(), "cannot read " + std::to_string(size) + " bytes at byte " +
                                          std::to_string(at));
    }
}

/// Where the records after the points start: the first EVLR, or the waveform data of LAS 1.3.
[[nodiscard]] std::uint64_t tail_start(const LasHeader& h) {
    std::uint64_t tail = 0;
    const auto consider = [&](std::uint64_t at) {
        if (at > h.offset_to_point_data) {
            tail = tail == 0 ? at : std::min(tail, at);
        }
    };
    if (h.version_minor >= 4 && h.number_of_evlrs > 0) {
        consider(h.start_of_first_evlr);
    }
    if (h.version_minor >= 3 && (h.global_encoding & kLasGlobalEncodingInternalWaveform) != 0) {
        consider(h.start_of_waveform_data);
    }
    return tail;
}

Layout read_layout(const std::filesystem::path& in, const LasHeader& h) {
    std::ifstream f(in, std::ios::binary);
    if (!f) {
        throw InputError(in.string(), "cannot open");
    }
    Layout l;
    l.file_size = std::filesystem::file_size(in);
    l.header.resize(h.header_size);
    read_exact(f, in, 0, l.header.data(), l.header.size());
    std::vector<std::uint8_t> vlrs(h.offset_to_point_data - h.header_size);
    read_exact(f, in, h.header_size, vlrs.data(), vlrs.size());
    std::size_t at = 0;
    for (std::uint32_t i = 0; i < h.number_of_vlrs; ++i) {
        // LasReader checked that every VLR lies before the points.
        const std::size_t size = kVlrHeaderBytes + load<std::uint16_t>(vlrs.data() + at + 20);
        const bool laszip = std::memcmp(vlrs.data() + at + 2, "laszip encoded\0", 15) == 0 &&
                            load<std::uint16_t>(vlrs.data() + at + 18) == 22204;
        if (!laszip) {
            l.vlrs.insert(l.vlrs.end(), vlrs.begin() + static_cast<std::ptrdiff_t>(at),
                          vlrs.begin() + static_cast<std::ptrdiff_t>(at + size));
            ++l.vlr_count;
        }
        at += size;
    }
    l.padding.assign(vlrs.begin() + static_cast<std::ptrdiff_t>(at), vlrs.end());
    l.tail = tail_start(h);
    return l;
}

/// The LASzip VLR's bytes for records of `h`'s format.
std::vector<std::uint8_t> laszip_vlr_bytes(const LasVlr& v) {
    std::vector<std::uint8_t> b(kVlrHeaderBytes + v.data.size(), 0);
    std::memcpy(b.data() + 2, v.user_id.data(), std::min<std::size_t>(v.user_id.size(), 16));
    store<std::uint16_t>(b.data() + 18, v.record_id);
    store<std::uint16_t>(b.data() + 20, static_cast<std::uint16_t>(v.data.size()));
    std::memcpy(b.data() + 22, v.description.data(),
                std::min<std::size_t>(v.description.size(), 32));
    std::memcpy(b.data() + kVlrHeaderBytes, v.data.data(), v.data.size());
    return b;
}

void copy_tail(const std::filesystem::path& in, const Layout& l, AtomicFile& out) {
    if (l.tail == 0 || l.tail >= l.file_size) {
        return;
    }
    std::ifstream f(in, std::ios::binary);
    std::vector<std::uint8_t> buffer(kCopyBytes);
    for (std::uint64_t at = l.tail; at < l.file_size;) {
        const auto n =
            static_cast<std::size_t>(std::min<std::uint64_t>(kCopyBytes, l.file_size - at));
        read_exact(f, in, at, buffer.data(), n);
        out.write(buffer.data(), n);
        at += n;
    }
}

/// The header's offsets and counts for the new layout; `tail_shift`: new - old start of the
/// records after the points.
void patch_header(std::vector<std::uint8_t>& b, const LasHeader& h, const Layout& l,
                  std::uint32_t offset, std::uint32_t vlr_count, bool laz, std::uint64_t new_tail) {
    store<std::uint32_t>(b.data() + 96, offset);
    store<std::uint32_t>(b.data() + 100, vlr_count);
    b[104] = static_cast<std::uint8_t>(h.point_format | (laz ? 0x80 : 0));
    const auto shift = [&](std::size_t field) {
        if (b.size() >= field + 8) {
            const auto v = load<std::uint64_t>(b.data() + field);
            if (l.tail != 0 && v >= l.tail) {
                store<std::uint64_t>(b.data() + field, v - l.tail + new_tail);
            }
        }
    };
    if (h.version_minor >= 3) {
        shift(227);  // start of waveform data
    }
    if (h.version_minor >= 4) {
        shift(235);  // start of the first EVLR
    }
}

void seek(AtomicFile& out, std::uint64_t at) {
    if (::fseeko(out.stream(), static_cast<::off_t>(at), SEEK_SET) != 0) {
        throw OutputError(out.path().string() + ": cannot seek to byte " + std::to_string(at));
    }
}

}  // namespace

LasConvertResult convert_las(const std::filesystem::path& in, const std::filesystem::path& out,
                             const LasConvertConfig& config, const ProgressFn& progress) {
    LasReader reader(in, config.threads);
    const LasHeader& h = reader.header();
    Layout l = read_layout(in, h);
    const bool laz = config.compression == LasCompression::laz;
    std::vector<std::uint8_t> laszip;
    if (laz) {
        laszip = laszip_vlr_bytes(
            detail::laszip_vlr(h.point_format, h.point_record_length, config.laz_chunk_size, out));
    }
    const std::uint64_t offset = l.header.size() + l.vlrs.size() + laszip.size() + l.padding.size();
    if (offset > 0xFFFFFFFFU) {
        throw OutputError(out.string() + ": the VLRs are too large");
    }
    AtomicFile file(out);
    file.write(l.header.data(), l.header.size());
    file.write(l.vlrs.data(), l.vlrs.size());
    file.write(laszip.data(), laszip.size());
    file.write(l.padding.data(), l.padding.size());
    std::unique_ptr<detail::LazChunkWriter> chunks;
    if (laz) {
        const std::int64_t placeholder = -1;  // the chunk table's offset, set below
        file.write(&placeholder, sizeof placeholder);
        chunks = std::make_unique<detail::LazChunkWriter>(
            laz::laz_vlr_for(h.point_format, h.point_record_length, config.laz_chunk_size),
            config.threads, offset + 8,
            [&file](const std::uint8_t* data, std::size_t size) { file.write(data, size); }, out);
    }
    LasConvertResult result;
    result.input_compressed = reader.compressed();
    std::vector<std::uint8_t> records(LasReader::kChunkPoints * h.point_record_length);
    while (const std::size_t n = reader.read_records(records)) {
        if (chunks) {
            chunks->append(records.data(), n);
        } else {
            file.write(records.data(), n * std::size_t{h.point_record_length});
        }
        result.points += n;
        if (progress) {
            progress(static_cast<std::size_t>(result.points),
                     static_cast<std::size_t>(h.point_count));
        }
    }
    std::uint64_t points_end = offset + result.points * h.point_record_length;
    if (chunks) {
        const std::vector<std::uint8_t> table = chunks->finish();
        file.write(table.data(), table.size());
        points_end = chunks->table_offset() + table.size();
    }
    copy_tail(in, l, file);
    patch_header(l.header, h, l, static_cast<std::uint32_t>(offset), l.vlr_count + (laz ? 1u : 0u),
                 laz, points_end);
    seek(file, 0);
    file.write(l.header.data(), l.header.size());
    if (chunks) {
        const auto at = static_cast<std::int64_t>(chunks->table_offset());
        seek(file, offset);
        file.write(&at, sizeof at);
    }
    file.commit();
    result.input_bytes = l.file_size;
    result.output_bytes = std::filesystem::file_size(out);
    return result;
}

}  // namespace beamtrace
