#include "beamtrace/heightfield/data_framing.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"

namespace beamtrace {
namespace {

constexpr std::size_t kLazRun = 4096;
constexpr std::size_t kLazRuns = 16;

struct Samples {
    std::vector<double> x, y;
    void add(const LasHeader& h, const std::uint8_t* record) {
        std::int32_t raw[2];
        std::memcpy(raw, record, sizeof raw);
        x.push_back(raw[0] * h.scale.x + h.offset.x);
        y.push_back(raw[1] * h.scale.y + h.offset.y);
    }
};

/// `count` records of an uncompressed file at evenly spaced indices (a short read ends it).
void sample_las(const LasSource& source, std::size_t count, Samples& out) {
    const LasHeader& h = source.header;
    const int fd = ::open(source.path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        return;  // the ingest names the file
    }
    std::vector<std::uint8_t> record(h.point_record_length);
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint64_t index = (2 * k + 1) * h.point_count / (2 * count);
        const auto at = static_cast<::off_t>(h.offset_to_point_data + index * record.size());
        if (::pread(fd, record.data(), record.size(), at) !=
            static_cast<::ssize_t>(record.size())) {
            break;
        }
        out.add(h, record.data());
    }
    ::close(fd);
}

/// Runs of kLazRun points decoded at up to kLazRuns evenly spaced places, `count` in all.
void sample_laz(const LasSource& source, std::size_t count, Samples& out) {
    const LasHeader& h = source.header;
    LasReader reader(source.path, 1);
    const std::size_t runs = std::clamp<std::size_t>(count / kLazRun, 1, kLazRuns);
    const std::size_t run = std::min<std::uint64_t>(kLazRun, h.point_count / runs);
    std::vector<std::uint8_t> records(run * h.point_record_length);
    for (std::size_t k = 0; k < runs; ++k) {
        reader.seek(k * (h.point_count / runs));
        const std::size_t got = reader.read_records(records);
        for (std::size_t i = 0; i < got; ++i) {
            out.add(h, records.data() + i * h.point_record_length);
        }
    }
}

double quantile(std::vector<double>& v, double q) {
    const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
}

}  // namespace

PointsBox points_box(const LasSourceSet& sources, double trim, std::size_t samples) {
    PointsBox box{sources.min(), sources.max(), 0};
    if (sources.point_count() == 0) {
        return box;
    }
    Samples s;
    try {
        for (const LasSource& f : sources.files()) {
            const auto share = static_cast<std::size_t>(
                std::ceil(static_cast<double>(samples) * static_cast<double>(f.header.point_count) /
                          static_cast<double>(sources.point_count())));
            const std::size_t count = std::min<std::uint64_t>(share, f.header.point_count);
            if (count > 0) {
                (f.compressed ? sample_laz : sample_las)(f, count, s);
            }
        }
    } catch (const Error&) {
        // A broken file: the ingest reports it; frame what was read.
    }
    if (s.x.empty()) {
        return box;
    }
    box.samples = s.x.size();
    Vec3d lo = box.lo, hi = box.hi;
    lo.x = std::max(lo.x, quantile(s.x, trim));
    hi.x = std::min(hi.x, quantile(s.x, 1.0 - trim));
    lo.y = std::max(lo.y, quantile(s.y, trim));
    hi.y = std::min(hi.y, quantile(s.y, 1.0 - trim));
    const double area = (hi.x - lo.x) * (hi.y - lo.y);
    const double header_area = (box.hi.x - box.lo.x) * (box.hi.y - box.lo.y);
    if (!(lo.x < hi.x) || !(lo.y < hi.y) || !(area < kFramingShrink * header_area)) {
        return box;  // the points fill their headers' box: frame all of it
    }
    // The quantile box and a margin, so that the edges of the dense part show.
    const double mx = kFramingMargin * (hi.x - lo.x), my = kFramingMargin * (hi.y - lo.y);
    box.lo.x = std::max(box.lo.x, lo.x - mx);
    box.hi.x = std::min(box.hi.x, hi.x + mx);
    box.lo.y = std::max(box.lo.y, lo.y - my);
    box.hi.y = std::min(box.hi.y, hi.y + my);
    return box;
}

}  // namespace beamtrace
