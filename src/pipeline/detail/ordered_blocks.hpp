// Survey blocks: filled by pool threads in any order, written in block order by one writer
// thread as they complete (no barrier; a window of blocks in flight bounds the memory).
#pragma once

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "pipeline/detail/sink_set.hpp"

namespace beamtrace::detail {

/// Blocks filled by pool threads in any order and written strictly in block order by one writer
/// thread, with at most `window` blocks between the oldest one not yet written and the newest
/// one taken: memory stays bounded, nothing waits at a barrier, and writing overlaps everything.
/// Blocks must be acquired in increasing order overall (ThreadPool hands out ranges in order),
/// which is what makes the wait in acquire() always end.
///
/// The writer is woken once per `batch` blocks ready in order (or when all the rest are), not
/// per block: waking a sleeping thread costs a system call and, in a virtual machine, an
/// interrupt to the other CPU, which per 1024-pulse block took 10 % of a survey's time.
class OrderedBlocks {
  public:
    using WriteFn = std::function<void(std::size_t block, BlockOutput& output)>;
    /// Blocks ready in order that wake the writer.
    static constexpr std::size_t kWakeBatch = 8;

    OrderedBlocks(std::size_t blocks, std::size_t window, WriteFn write)
        : blocks_(blocks),
          window_(std::max<std::size_t>(1, window)),
          batch_(std::min(kWakeBatch, window_)),
          write_(std::move(write)),
          ring_(std::min(blocks_, window_)),
          ready_(ring_.size(), 0) {
        writer_ = std::thread([this] { run_writer(); });
    }
    ~OrderedBlocks() {
        abort();
        if (writer_.joinable()) {
            writer_.join();
        }
    }
    OrderedBlocks(const OrderedBlocks&) = delete;
    OrderedBlocks& operator=(const OrderedBlocks&) = delete;

    /// Waits until block k may be filled and returns its (emptied) output; null when the run
    /// is being aborted.
    BlockOutput* acquire(std::size_t k) {
        std::unique_lock lock(mutex_);
        free_.wait(lock, [&] { return k < written_ + window_ || abort_; });
        if (abort_) {
            return nullptr;
        }
        BlockOutput& out = ring_[k % window_];
        out.clear();
        return &out;
    }
    /// Block k is complete.
    void publish(std::size_t k) {
        bool wake = false;
        {
            const std::lock_guard lock(mutex_);
            ready_[k % window_] = 1;
            // Extend the run of blocks ready in order from the next one to write.
            while (in_order_ < blocks_ && in_order_ < written_ + window_ &&
                   ready_[in_order_ % window_] != 0) {
                ++in_order_;
            }
            // Every block of the window ready also wakes it: producers may be waiting for room.
            wake = writer_waiting_ && (in_order_ >= written_ + batch_ || in_order_ == blocks_);
        }
        if (wake) {
            ready_cv_.notify_one();
        }
    }
    /// Stops the writer and every acquire() (after a worker's error).
    void abort() {
        {
            const std::lock_guard lock(mutex_);
            abort_ = true;
        }
        ready_cv_.notify_all();
        free_.notify_all();
    }
    /// Waits until the writer is done; rethrows its error.
    void finish() {
        writer_.join();
        if (error_) {
            std::rethrow_exception(error_);
        }
    }

  private:
    void run_writer() {
        for (std::size_t k = 0; k < blocks_; ++k) {
            const std::size_t slot = k % window_;
            {
                std::unique_lock lock(mutex_);
                if (ready_[slot] == 0 && !abort_) {
                    // Sleep until a batch is ready in order (k, k + 1, ...), or all the rest.
                    writer_waiting_ = true;
                    ready_cv_.wait(lock, [&] {
                        return in_order_ >= k + batch_ || in_order_ == blocks_ || abort_;
                    });
                    writer_waiting_ = false;
                }
                if (abort_) {
                    return;
                }
            }
            try {
                write_(k, ring_[slot]);
            } catch (...) {
                error_ = std::current_exception();
                abort();
                return;
            }
            {
                const std::lock_guard lock(mutex_);
                ready_[slot] = 0;
                written_ = k + 1;
            }
            free_.notify_all();
        }
    }

    std::size_t blocks_, window_, batch_;
    WriteFn write_;
    std::vector<BlockOutput> ring_;
    std::vector<std::uint8_t> ready_;
    std::size_t written_ = 0;
    std::size_t in_order_ = 0;  ///< blocks [0, in_order_) are written or ready
    bool writer_waiting_ = false;
    bool abort_ = false;
    std::exception_ptr error_;  ///< set by the writer thread before it ends
    std::mutex mutex_;
    std::condition_variable ready_cv_, free_;
    std::thread writer_;
};

}  // namespace beamtrace::detail
