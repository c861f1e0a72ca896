// Survey blocks: filled by pool threads in any order, written in block order as they complete
// (no barrier; a window of blocks in flight bounds the memory), either by the pool threads
// themselves (a combining hand-off) or by one writer thread of its own.
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

/// How OrderedBlocks writes: on the pool threads, or on a thread of its own.
enum class BlockWriter {
    /// The thread that publishes the next block in order writes it and every block ready after
    /// it, outside the lock, while the others go on filling blocks; one writer at a time. No
    /// extra thread and no wake-ups: for a pool with as many threads as the machine has cores,
    /// where a writer thread would compete with the workers for them.
    combining,
    /// A writer thread of its own, woken once per `kWakeBatch` blocks ready in order: writing
    /// then overlaps the filling on a core the pool leaves idle.
    own_thread,
};

/// Blocks filled by pool threads in any order and written strictly in block order, with at
/// most `window` blocks between the oldest one not yet written and the newest one taken:
/// memory stays bounded, nothing waits at a barrier. Blocks must be acquired in increasing
/// order overall (ThreadPool hands out ranges in order), which is what makes the wait in
/// acquire() always end: the oldest block not written is either being filled, or ready and
/// then being written (a thread never waits in acquire() with a block of its own unpublished).
///
/// With its own thread, the writer is woken once per `batch` blocks ready in order (or when all
/// the rest are), not per block: waking a sleeping thread costs a system call and, in a virtual
/// machine, an interrupt to the other CPU, which per 1024-pulse block took 10 % of a survey's
/// time.
class OrderedBlocks {
  public:
    using WriteFn = std::function<void(std::size_t block, BlockOutput& output)>;
    /// Blocks ready in order that wake the writer thread.
    static constexpr std::size_t kWakeBatch = 8;

    OrderedBlocks(std::size_t blocks, std::size_t window, WriteFn write,
                  BlockWriter mode = BlockWriter::combining)
        : blocks_(blocks),
          window_(std::max<std::size_t>(1, window)),
          batch_(std::min(kWakeBatch, window_)),
          write_(std::move(write)),
          ring_(std::min(blocks_, window_)),
          ready_(ring_.size(), 0) {
        if (mode == BlockWriter::own_thread) {
            writer_ = std::thread([this] { run_writer(); });
        }
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
    /// Blocks before block k not yet written: how far the writing is behind the filling.
    [[nodiscard]] std::size_t behind(std::size_t k) {
        const std::lock_guard lock(mutex_);
        return k - std::min(k, written_);
    }
    /// Block k is complete. Combining: writes it, and the blocks ready after it, when it is the
    /// next in order and no other thread is writing. Never throws: a write's error aborts the
    /// run and finish() rethrows it.
    void publish(std::size_t k) {
        std::unique_lock lock(mutex_);
        ready_[k % window_] = 1;
        // Extend the run of blocks ready in order from the next one to write.
        while (in_order_ < blocks_ && in_order_ < written_ + window_ &&
               ready_[in_order_ % window_] != 0) {
            ++in_order_;
        }
        if (!writer_.joinable()) {
            write_ready(lock);
            return;
        }
        // Every block of the window ready also wakes it: producers may be waiting for room.
        const bool wake =
            writer_waiting_ && (in_order_ >= written_ + batch_ || in_order_ == blocks_);
        lock.unlock();
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
    /// Waits until every block is written; rethrows the first write's error.
    void finish() {
        if (writer_.joinable()) {
            writer_.join();
        }
        const std::lock_guard lock(mutex_);
        if (error_) {
            std::rethrow_exception(error_);
        }
    }

  private:
    /// Combining: unless another thread is writing, writes blocks [written_, in_order_) outside
    /// the lock, and again while publishers added more meanwhile. Called with `lock` held.
    void write_ready(std::unique_lock<std::mutex>& lock) {
        if (writing_) {
            return;  // the writer looks again before it stops: it will write these
        }
        writing_ = true;
        while (written_ < in_order_ && !abort_) {
            const std::size_t begin = written_, end = in_order_;
            lock.unlock();
            const bool ok = write_range(begin, end);
            lock.lock();
            for (std::size_t k = begin; k < end; ++k) {
                ready_[k % window_] = 0;
            }
            written_ = end;
            if (!ok) {
                abort_ = true;
            }
            free_.notify_all();
        }
        writing_ = false;
    }
    /// Writes blocks [begin, end); false (the error kept for finish()) when one throws.
    bool write_range(std::size_t begin, std::size_t end) {
        try {
            for (std::size_t k = begin; k < end; ++k) {
                write_(k, ring_[k % window_]);
            }
            return true;
        } catch (...) {
            error_ = std::current_exception();  // one writer at a time: no race
            return false;
        }
    }
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
            if (!write_range(k, k + 1)) {
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
    bool writing_ = false;  ///< combining: a pool thread is writing blocks
    bool abort_ = false;
    std::exception_ptr error_;  ///< the first write's error
    std::mutex mutex_;
    std::condition_variable ready_cv_, free_;
    std::thread writer_;
};

}  // namespace beamtrace::detail
