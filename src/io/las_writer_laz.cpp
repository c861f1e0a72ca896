// LAZ output: the chunk writer (records in, chunks out in order, a batch encoded in parallel)
// and LasWriter's compression laz (the LASzip VLR, the chunk table's offset at the start of the
// point data, the table after the last chunk).
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "beamtrace/core/atomic_file.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "io/detail/direct_sink.hpp"
#include "io/detail/laz_chunk_writer.hpp"
#include "laz/laz_encode.hpp"
#include "laz/pointwise_chunk.hpp"

namespace beamtrace {

namespace detail {

LasVlr laszip_vlr(int point_format, std::size_t record_length, std::uint32_t chunk_size,
                  const std::filesystem::path& path) {
    LasVlr v;
    v.user_id = "laszip encoded";
    v.record_id = 22204;
    v.description = "by beamtrace " BEAMTRACE_VERSION;
    v.description.resize(std::min<std::size_t>(v.description.size(), 32));
    try {
        v.data = laz::serialize_laz_vlr(laz::laz_vlr_for(point_format, record_length, chunk_size));
    } catch (const std::invalid_argument& e) {
        throw OutputError(path.string() + ": LAZ: " + e.what());
    }
    v.length = v.data.size();
    return v;
}

LazChunkWriter::LazChunkWriter(laz::LazVlr vlr, unsigned threads, std::uint64_t first_chunk_offset,
                               Emit emit, std::filesystem::path path)
    : vlr_(std::move(vlr)),
      record_length_(vlr_.record_length()),
      chunk_points_(vlr_.chunk_size),
      pool_(std::make_unique<ThreadPool>(threads)),
      batch_chunks_(pool_->size()),
      offset_(first_chunk_offset),
      emit_(std::move(emit)),
      path_(std::move(path)) {
    if (chunk_points_ == 0 || vlr_.variable_chunks()) {
        throw OutputError(path_.string() + ": LAZ: chunk size " + std::to_string(chunk_points_) +
                          " (expected 1 to 4294967294 points)");
    }
    records_.resize(batch_chunks_ * chunk_points_ * record_length_);
    encoded_.resize(batch_chunks_);
}

LazChunkWriter::~LazChunkWriter() = default;

void LazChunkWriter::append(const std::uint8_t* records, std::size_t count) {
    const std::size_t capacity = batch_chunks_ * chunk_points_;
    while (count > 0) {
        const std::size_t n = std::min(count, capacity - buffered_);
        std::memcpy(records_.data() + buffered_ * record_length_, records, n * record_length_);
        buffered_ += n;
        records += n * record_length_;
        count -= n;
        if (buffered_ == capacity) {
            encode_buffered();
        }
    }
}

void LazChunkWriter::encode_buffered() {
    const std::size_t count = (buffered_ + chunk_points_ - 1) / chunk_points_;
    const bool layered = vlr_.compressor == laz::Compressor::layered_chunked;
    try {
        pool_->parallel_for(count, 1, [&](std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k) {
                const std::size_t first = k * chunk_points_;
                const std::size_t n = std::min(chunk_points_, buffered_ - first);
                const std::span records(records_.data() + first * record_length_,
                                        n * record_length_);
                encoded_[k].clear();
                if (layered) {
                    laz::encode_layered_chunk(vlr_.items, records, n, encoded_[k]);
                } else {
                    laz::encode_pointwise_chunk(vlr_.items, records, n, encoded_[k]);
                }
            }
        });
    } catch (const std::invalid_argument& e) {
        throw OutputError(path_.string() + ": LAZ chunk " + std::to_string(chunks_.size() + 1) +
                          ": " + e.what());
    }
    for (std::size_t k = 0; k < count; ++k) {
        const std::size_t n = std::min(chunk_points_, buffered_ - k * chunk_points_);
        chunks_.push_back({offset_, encoded_[k].size(), points_, n});
        emit_(encoded_[k].data(), encoded_[k].size());
        offset_ += encoded_[k].size();
        points_ += n;
    }
    buffered_ = 0;
}

std::vector<std::uint8_t> LazChunkWriter::finish() {
    if (buffered_ > 0) {
        encode_buffered();
    }
    try {
        return laz::encode_chunk_table(chunks_, false);
    } catch (const std::invalid_argument& e) {
        throw OutputError(path_.string() + ": LAZ: " + e.what());
    }
}

}  // namespace detail

// LasWriter's compression laz.

void LasWriter::open_laz() {
    LasHeader& h = header_;
    laz_vlr_ = std::make_unique<LasVlr>(
        detail::laszip_vlr(h.point_format, h.point_record_length, config_.laz_chunk_size, path_));
    ++h.number_of_vlrs;
    const std::uint64_t offset = h.offset_to_point_data + 54 + laz_vlr_->data.size();
    if (offset > 0xFFFFFFFFU) {
        throw ConfigError(path_.string() + ": LAS writer settings: the VLRs are too large");
    }
    h.offset_to_point_data = static_cast<std::uint32_t>(offset);
}

void LasWriter::start_laz_points() {
    const laz::LazVlr vlr =
        laz::laz_vlr_for(header_.point_format, header_.point_record_length, config_.laz_chunk_size);
    const std::int64_t placeholder = -1;  // the chunk table's offset, set by close()
    sink_->append(&placeholder, sizeof placeholder);
    laz_ = std::make_unique<detail::LazChunkWriter>(
        vlr, config_.threads, header_.offset_to_point_data + std::uint64_t{8},
        [this](const std::uint8_t* data, std::size_t size) { sink_->append(data, size); }, path_);
}

void LasWriter::append_records(const std::uint8_t* records, std::size_t count) {
    if (laz_) {
        laz_->append(records, count);
    } else {
        sink_->append(records, count * std::size_t{header_.point_record_length});
    }
}

std::uint64_t LasWriter::finish_points() {
    if (!laz_) {
        sink_->finish(file_->stream());
        return header_.offset_to_point_data +
               header_.point_count * std::uint64_t{header_.point_record_length};
    }
    const std::vector<std::uint8_t> table = laz_->finish();
    sink_->finish(file_->stream());
    file_->write(table.data(), table.size());
    return laz_->table_offset() + table.size();
}

void LasWriter::write_laz_table_offset() {
    if (!laz_) {
        return;
    }
    const auto at = static_cast<std::int64_t>(laz_->table_offset());
    if (::fseeko(file_->stream(), static_cast<::off_t>(header_.offset_to_point_data), SEEK_SET) !=
        0) {
        fail("cannot seek back to the LAZ chunk table offset");
    }
    file_->write(&at, sizeof at);
}

}  // namespace beamtrace
