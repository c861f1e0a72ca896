// LAZ output: the chunk writer (records in, chunks out in order, encoded on its threads meanwhile)
// and LasWriter's compression laz (the LASzip VLR, the chunk table's offset at the start of the
// point data, the table after the last chunk).
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>

#include "beamtrace/core/atomic_file.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/core/thread_pool.hpp"
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
      offset_(first_chunk_offset),
      emit_(std::move(emit)),
      path_(std::move(path)) {
    if (chunk_points_ == 0 || vlr_.variable_chunks()) {
        throw OutputError(path_.string() + ": LAZ: chunk size " + std::to_string(chunk_points_) +
                          " (expected 1 to 4294967294 points)");
    }
    const unsigned n = threads != 0 ? threads : available_cores();
    slots_.resize(n + 2);
    for (unsigned k = 0; k < n; ++k) {
        workers_.emplace_back([this] { worker_loop(); });
    }
}

LazChunkWriter::~LazChunkWriter() {
    {
        const std::lock_guard lock(mutex_);
        stop_ = true;
    }
    work_.notify_all();
    for (auto& t : workers_) {
        t.join();
    }
}

void LazChunkWriter::worker_loop() {
    for (;;) {
        Slot* slot = nullptr;
        {
            std::unique_lock lock(mutex_);
            work_.wait(lock, [&] { return stop_ || !queue_.empty(); });
            if (stop_) {
                return;
            }
            slot = queue_.front();
            queue_.pop_front();
        }
        encode(*slot);
        {
            const std::lock_guard lock(mutex_);
            slot->done = true;
        }
        done_.notify_all();
    }
}

void LazChunkWriter::encode(Slot& slot) const {
    const std::span records(slot.records.data(), slot.count * record_length_);
    slot.encoded.clear();
    try {
        if (vlr_.compressor == laz::Compressor::layered_chunked) {
            laz::encode_layered_chunk(vlr_.items, records, slot.count, slot.encoded);
        } else {
            laz::encode_pointwise_chunk(vlr_.items, records, slot.count, slot.encoded);
        }
    } catch (...) {
        slot.error = std::current_exception();
    }
}

void LazChunkWriter::append(const std::uint8_t* records, std::size_t count) {
    while (count > 0) {
        if (in_flight_ == slots_.size()) {
            emit_oldest(true);  // no slot free to fill
        }
        Slot& slot = slots_[(oldest_ + in_flight_) % slots_.size()];
        slot.records.resize(chunk_points_ * record_length_);
        const std::size_t n = std::min(count, chunk_points_ - slot.count);
        std::memcpy(slot.records.data() + slot.count * record_length_, records, n * record_length_);
        slot.count += n;
        records += n * record_length_;
        count -= n;
        if (slot.count == chunk_points_) {
            submit_filling();
            while (in_flight_ > 0 && emit_oldest(false)) {
            }
        }
    }
}

void LazChunkWriter::submit_filling() {
    Slot& slot = slots_[(oldest_ + in_flight_) % slots_.size()];
    {
        const std::lock_guard lock(mutex_);
        slot.done = false;
        slot.error = nullptr;
        queue_.push_back(&slot);
    }
    ++in_flight_;
    work_.notify_one();
}

bool LazChunkWriter::emit_oldest(bool wait) {
    Slot& slot = slots_[oldest_];
    {
        std::unique_lock lock(mutex_);
        if (!slot.done && !wait) {
            return false;
        }
        done_.wait(lock, [&] { return slot.done; });
    }
    if (slot.error) {
        try {
            std::rethrow_exception(slot.error);
        } catch (const std::invalid_argument& e) {
            throw OutputError(path_.string() + ": LAZ chunk " + std::to_string(chunks_.size() + 1) +
                              ": " + e.what());
        }
    }
    chunks_.push_back({offset_, slot.encoded.size(), points_, slot.count});
    emit_(slot.encoded.data(), slot.encoded.size());
    offset_ += slot.encoded.size();
    points_ += slot.count;
    slot.count = 0;
    oldest_ = (oldest_ + 1) % slots_.size();
    --in_flight_;
    return true;
}

std::vector<std::uint8_t> LazChunkWriter::finish() {
    if (in_flight_ < slots_.size() && slots_[(oldest_ + in_flight_) % slots_.size()].count > 0) {
        submit_filling();
    }
    while (in_flight_ > 0) {
        emit_oldest(true);
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
