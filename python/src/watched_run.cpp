#include "watched_run.hpp"

#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace beamtrace::python {
namespace {

/// What the call's thread tells the waiting one.
struct Mailbox {
    std::mutex mutex;
    std::condition_variable changed;
    bool finished = false;
    std::vector<std::pair<std::size_t, std::size_t>> reports;  ///< (done, total), not yet handed on
};

/// What the waiting thread takes from the mailbox at each wake-up.
struct News {
    bool finished = false;
    std::vector<std::pair<std::size_t, std::size_t>> reports;
};

News wait_for_news(Mailbox& box) {
    const py::gil_scoped_release release;
    std::unique_lock lock(box.mutex);
    box.changed.wait_for(lock, std::chrono::milliseconds(50),
                         [&] { return box.finished || !box.reports.empty(); });
    News news{box.finished, {}};
    news.reports.swap(box.reports);
    return news;
}

/// Joins the call's thread however the wait ends (cancelling it first if it has not finished).
struct JoinGuard {
    CancelToken& cancel;
    std::thread& thread;
    ~JoinGuard() {
        if (thread.joinable()) {
            cancel.request();
            const py::gil_scoped_release release;
            thread.join();
        }
    }
};

}  // namespace

void run_watched(
    const std::function<void(const CancelToken& cancel, const ProgressFn& report)>& call,
    const py::object& progress) {
    CancelToken cancel;
    Mailbox box;
    std::exception_ptr call_error;
    const ProgressFn report = [&box](std::size_t done, std::size_t total) {
        const std::lock_guard lock(box.mutex);
        box.reports.emplace_back(done, total);
        box.changed.notify_one();
    };
    std::thread thread([&] {
        try {
            call(cancel, report);
        } catch (...) {
            call_error = std::current_exception();
        }
        const std::lock_guard lock(box.mutex);
        box.finished = true;
        box.changed.notify_one();
    });
    const JoinGuard guard{cancel, thread};
    std::exception_ptr stop;  // why this thread cancelled the call (a Python exception)
    for (bool finished = false; !finished;) {
        const News news = wait_for_news(box);
        finished = news.finished;
        if (stop) {
            continue;  // cancelled: wait for the call to end
        }
        try {
            if (PyErr_CheckSignals() != 0) {
                throw py::error_already_set();
            }
            for (const auto& [done, total] : news.reports) {
                if (!progress.is_none()) {
                    progress(done, total);
                }
            }
        } catch (...) {
            stop = std::current_exception();
            cancel.request();
        }
    }
    {
        const py::gil_scoped_release release;
        thread.join();
    }
    if (stop) {
        std::rethrow_exception(stop);
    }
    if (call_error) {
        std::rethrow_exception(call_error);
    }
}

}  // namespace beamtrace::python
