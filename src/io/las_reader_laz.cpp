// The LAZ path of LasReader: the LASzip VLR and chunk table at open, then the chunks decoded a
// batch at a time, in parallel, into the reader's buffer of raw records, the next batch while the
// caller reads the current one. The records are those of the uncompressed twin, so decoding them
// into points is the LAS path's.
#include <algorithm>
#include <future>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "io/detail/las_reader_laz.hpp"
#include "laz/laz_items.hpp"

namespace beamtrace {

namespace {

/// The most decoded bytes one chunk may hold: a larger one is refused (not allocated).
constexpr std::uint64_t kMaxChunkRecordBytes = std::uint64_t{256} << 20;

[[nodiscard]] bool supported(const laz::Item& item) {
    switch (item.type) {
        case laz::ItemType::point10:
        case laz::ItemType::gpstime11:
        case laz::ItemType::rgb12:
        case laz::ItemType::byte:
        case laz::ItemType::wavepacket13:
        case laz::ItemType::point14:
        case laz::ItemType::rgb14:
        case laz::ItemType::rgbnir14:
        case laz::ItemType::byte14:
        case laz::ItemType::wavepacket14:
            return true;
        default:
            return false;
    }
}

}  // namespace

void LasReader::open_laz(std::uint64_t file_size) {
    const LasHeader& h = header_;
    if (laszip_vlr_ == 0) {
        fail(
            "header: point format byte marks a LAZ file, but it has no LASzip VLR "
            "(laszip encoded/22204)");
    }
    auto state = std::make_unique<Laz>();
    try {
        state->vlr =
            laz::parse_laz_vlr(vlrs_[laszip_vlr_ - 1].data, h.point_format, h.point_record_length);
    } catch (const laz::CorruptData& e) {
        fail("VLR " + std::to_string(laszip_vlr_) + ": " + e.what());
    }
    for (const laz::Item& item : state->vlr.items) {
        if (!supported(item)) {
            fail("LAZ: " + laz::item_name(item.type) +
                 " items (wave packets of the layered formats 9 and 10) are not supported");
        }
    }
    laz::PointDataExtent extent;
    extent.start = h.offset_to_point_data;
    extent.file_size = file_size;
    extent.end = h.number_of_evlrs > 0 && h.start_of_first_evlr > h.offset_to_point_data &&
                         h.start_of_first_evlr <= file_size
                     ? h.start_of_first_evlr
                     : file_size;
    extent.point_count = h.point_count;
    const laz::ReadAt read = [this](void* data, std::size_t size, std::uint64_t offset) {
        read_exact(data, size, offset, "LAZ chunk table");
    };
    try {
        state->chunks = laz::read_chunk_table(state->vlr, extent, read);
    } catch (const laz::CorruptData& e) {
        fail(std::string("LAZ ") + e.what());
    }
    const bool stream = state->vlr.compressor == laz::Compressor::pointwise;
    for (std::size_t i = 0; i < state->chunks.size() && !stream; ++i) {
        const laz::Chunk& c = state->chunks[i];
        if (c.points > kMaxChunkRecordBytes / h.point_record_length) {
            fail("LAZ chunk " + std::to_string(i + 1) + " of " +
                 std::to_string(state->chunks.size()) + ": " + std::to_string(c.points) +
                 " points decode to more than the " + std::to_string(kMaxChunkRecordBytes >> 20) +
                 " MiB a chunk may hold");
        }
    }
    laz_ = std::move(state);
}

void LasReader::fill_laz_stream() {
    Laz& z = *laz_;
    const std::size_t record = header_.point_record_length;
    try {
        if (!z.stream) {
            const laz::Chunk& c = z.chunks.at(0);
            z.compressed.resize(1);
            z.compressed[0].resize(static_cast<std::size_t>(c.bytes));
            read_exact(z.compressed[0].data(), z.compressed[0].size(), c.offset, "LAZ points");
            z.stream = std::make_unique<laz::PointwiseChunkDecoder>(z.vlr.items, z.compressed[0]);
        }
        if (chunk_.size() < kChunkPoints * record) {
            chunk_.resize(kChunkPoints * record);
        }
        for (;;) {
            const std::uint64_t done = z.stream->decoded();
            const auto n = static_cast<std::size_t>(
                std::min<std::uint64_t>(kChunkPoints, header_.point_count - done));
            z.stream->decode(n, chunk_);
            chunk_points_ = n;
            if (z.skip < n) {
                chunk_next_ = static_cast<std::size_t>(z.skip);
                z.skip = 0;
                return;
            }
            z.skip -= n;  // after a seek: decode up to the point
        }
    } catch (const laz::CorruptData& e) {
        fail("LAZ point stream (compressor 1), near point " +
             std::to_string(z.stream ? z.stream->decoded() : 0) + ": " + e.what());
    }
}

namespace {

/// The chunks of a batch from `first`: one per decoding thread at least, and more while they
/// hold fewer than `threads` times LasReader::kChunkPoints points (small COPC nodes).
std::size_t batch_chunks(const std::vector<laz::Chunk>& chunks, std::size_t first,
                         unsigned threads) {
    std::size_t count = 0;
    std::uint64_t points = 0;
    while (first + count < chunks.size() &&
           (count < threads || points + chunks[first + count].points <=
                                   std::uint64_t{threads} * LasReader::kChunkPoints)) {
        points += chunks[first + count].points;
        ++count;
    }
    return count;
}

}  // namespace

void LasReader::decode_laz_batch(LazBatch& b, std::size_t first) const {
    const Laz& z = *laz_;
    const std::size_t record = header_.point_record_length;
    b.first = first;
    b.count = batch_chunks(z.chunks, first, z.pool->size());
    b.points = 0;
    b.starts.assign(b.count + 1, 0);
    b.compressed.resize(std::max(b.compressed.size(), b.count));
    b.errors.assign(b.count, {});
    for (std::size_t k = 0; k < b.count; ++k) {
        const laz::Chunk& c = z.chunks[first + k];
        b.points += c.points;
        b.starts[k + 1] = b.starts[k] + static_cast<std::size_t>(c.points) * record;
        b.compressed[k].resize(static_cast<std::size_t>(c.bytes));
        read_exact(b.compressed[k].data(), b.compressed[k].size(), c.offset, "LAZ chunk");
    }
    if (b.records.size() < b.starts[b.count]) {
        b.records.resize(b.starts[b.count]);
    }
    const laz::LazVlr& vlr = z.vlr;
    z.pool->parallel_for(b.count, 1, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
            const std::span out(b.records.data() + b.starts[k], b.starts[k + 1] - b.starts[k]);
            const auto n = static_cast<std::size_t>(z.chunks[first + k].points);
            try {
                if (vlr.compressor == laz::Compressor::layered_chunked) {
                    laz::decode_layered_chunk(vlr.items, b.compressed[k], n, out);
                } else {
                    laz::decode_pointwise_chunk(vlr.items, b.compressed[k], n, out);
                }
            } catch (const laz::CorruptData& e) {
                b.errors[k] = e.what();
            } catch (const std::exception& e) {
                b.errors[k] = std::string("decoder failed: ") + e.what();
            }
        }
    });
}

void LasReader::start_laz_batch(std::size_t first) {
    Laz& z = *laz_;
    if (!z.pool) {  // a seek may start the first batch before any read did
        z.pool = std::make_unique<ThreadPool>(threads_);
    }
    if (first < z.chunks.size()) {
        z.ready =
            std::async(std::launch::async, [this, &z, first] { decode_laz_batch(z.ahead, first); });
    }
}

void LasReader::fill_laz_chunk() {
    Laz& z = *laz_;
    if (z.vlr.compressor == laz::Compressor::pointwise) {
        fill_laz_stream();
        return;
    }
    if (!z.ready.valid()) {
        start_laz_batch(z.next_chunk);
    }
    if (!z.ready.valid()) {
        fail("LAZ: no chunk holds point " + std::to_string(next_));
    }
    std::future<void> ready = std::move(z.ready);
    ready.get();  // rethrows a read error of the batch
    LazBatch& b = z.ahead;
    for (std::size_t k = 0; k < b.count; ++k) {
        if (!b.errors[k].empty()) {
            const laz::Chunk& c = z.chunks[b.first + k];
            fail("LAZ chunk " + std::to_string(b.first + k + 1) + " of " +
                 std::to_string(z.chunks.size()) + " (points " + std::to_string(c.first_point) +
                 " to " + std::to_string(c.first_point + c.points - 1) + ", byte " +
                 std::to_string(c.offset) + "): " + b.errors[k]);
        }
    }
    chunk_.swap(b.records);
    z.next_chunk = b.first + b.count;
    chunk_points_ = static_cast<std::size_t>(b.points);
    chunk_next_ = static_cast<std::size_t>(z.skip);
    z.skip = 0;
    start_laz_batch(z.next_chunk);
}

void LasReader::seek_laz(std::uint64_t index) {
    Laz& z = *laz_;
    if (z.ready.valid()) {
        z.ready.wait();  // a batch decoded ahead from where the reader stood: dropped
        z.ready = {};
    }
    if (z.vlr.compressor == laz::Compressor::pointwise) {
        z.stream.reset();  // one stream: decode again from its start
        z.skip = index;
        return;
    }
    const auto it =
        std::upper_bound(z.chunks.begin(), z.chunks.end(), index,
                         [](std::uint64_t i, const laz::Chunk& c) { return i < c.first_point; });
    if (it == z.chunks.begin()) {
        z.next_chunk = z.chunks.size();
        z.skip = 0;
        return;
    }
    const auto k = static_cast<std::size_t>(it - z.chunks.begin()) - 1;
    z.next_chunk = k;
    z.skip = index - z.chunks[k].first_point;
}

}  // namespace beamtrace
