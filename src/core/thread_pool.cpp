#include "beamtrace/core/thread_pool.hpp"

#include <sched.h>

#include <algorithm>

namespace beamtrace {

unsigned available_cores() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) != 0) {
        return std::max(1u, std::thread::hardware_concurrency());
    }
    return static_cast<unsigned>(std::max(1, CPU_COUNT(&set)));
}

ThreadPool::ThreadPool(unsigned threads) {
    if (threads == 0) {
        threads = available_cores();
    }
    size_ = threads;
    workers_.reserve(threads - 1);
    for (unsigned i = 1; i < threads; ++i) {
        workers_.emplace_back([this] { worker_loop(); });
    }
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    for (auto& t : workers_) {
        t.join();
    }
}

void ThreadPool::run_chunks() {
    std::unique_lock lock(mutex_);
    ++busy_;
    while (next_chunk_ < chunks_) {
        const std::size_t chunk = next_chunk_++;
        const auto* job = job_;
        const bool skip = error_ != nullptr;
        lock.unlock();
        const std::size_t begin = chunk * grain_;
        const std::size_t end = std::min(count_, begin + grain_);
        try {
            if (!skip) {
                (*job)(begin, end);
            }
        } catch (...) {
            std::lock_guard g(mutex_);
            if (!error_) {
                error_ = std::current_exception();
            }
        }
        lock.lock();
        ++chunks_done_;
    }
    --busy_;
    if (chunks_done_ == chunks_ && busy_ == 0) {
        done_.notify_all();
    }
}

void ThreadPool::worker_loop() {
    std::size_t seen = 0;
    for (;;) {
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
            if (stop_) {
                return;
            }
            seen = generation_;
        }
        run_chunks();
    }
}

void ThreadPool::parallel_for(std::size_t count, std::size_t grain,
                              const std::function<void(std::size_t, std::size_t)>& fn) {
    if (count == 0) {
        return;
    }
    grain = std::max<std::size_t>(1, grain);
    if (workers_.empty() || count <= grain) {
        fn(0, count);
        return;
    }
    {
        std::lock_guard lock(mutex_);
        job_ = &fn;
        count_ = count;
        grain_ = grain;
        next_chunk_ = 0;
        chunks_ = (count + grain - 1) / grain;
        chunks_done_ = 0;
        error_ = nullptr;
        ++generation_;
    }
    wake_.notify_all();
    run_chunks();
    std::exception_ptr err;
    {
        std::unique_lock lock(mutex_);
        done_.wait(lock, [&] { return chunks_done_ == chunks_ && busy_ == 0; });
        job_ = nullptr;
        err = error_;
        error_ = nullptr;
    }
    if (err) {
        std::rethrow_exception(err);
    }
}

}  // namespace beamtrace
