// A small fixed-size thread pool with a blocking parallel_for over index ranges.
// Work is cut into fixed chunks, so which thread runs a chunk never changes a result.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace beamtrace {

/// The cores this process may run on (its CPU affinity: `taskset`, cgroup cpusets, `mpirun`'s
/// binding of each rank), at least 1; every hardware thread where the affinity cannot be read.
[[nodiscard]] unsigned available_cores();

class ThreadPool {
  public:
    /// `threads == 0` uses every core the process may run on (available_cores()). The calling
    /// thread takes part in the work, so a pool of N threads starts N-1 workers.
    explicit ThreadPool(unsigned threads = 0);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    [[nodiscard]] unsigned size() const { return size_; }

    /// Calls `fn(begin, end)` for consecutive chunks of `[0, count)` of at most `grain` items, on
    /// all threads; returns when every chunk is done. The first exception thrown is rethrown.
    void parallel_for(std::size_t count, std::size_t grain,
                      const std::function<void(std::size_t, std::size_t)>& fn);

  private:
    void worker_loop();
    void run_chunks();

    unsigned size_ = 1;
    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::condition_variable done_;
    bool stop_ = false;
    std::size_t generation_ = 0;

    // The job in flight (guarded by mutex_ except the atomic-free counters read under lock).
    const std::function<void(std::size_t, std::size_t)>* job_ = nullptr;
    std::size_t count_ = 0;
    std::size_t grain_ = 1;
    std::size_t next_chunk_ = 0;
    std::size_t chunks_ = 0;
    std::size_t chunks_done_ = 0;
    unsigned busy_ = 0;
    std::exception_ptr error_;
};

}  // namespace beamtrace
