// beamtrace.iter_survey (docs/python.md, "Surveys larger than memory"): the survey runs on a
// thread of its own whose callback sink cuts the points into blocks of `block_points` records and
// hands them over through a queue of a few blocks; Python takes them one by one (__next__, the
// GIL released while it waits). The queue being bounded, the run waits for Python, so memory
// stays bounded whatever the survey's size. Closing the iterator (close(), the end of a `with`
// block, or its deletion, e.g. by `break` in a for loop) cancels the run and joins its thread.
#include <pthread.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/callback_sink.hpp"
#include "survey_points.hpp"

namespace beamtrace::python {
namespace {

/// Blocks the run may have ready beyond the one being filled: the run waits while this many
/// wait for Python.
constexpr std::size_t kQueueBlocks = 2;

/// Bytes reserved for a block at once (a larger block grows as its points come).
constexpr std::size_t kReserveBytes = std::size_t{64} << 20;

/// The name of the run's thread (at most 15 characters).
constexpr const char* kThreadName = "bt-iter-survey";

using Report = std::pair<std::size_t, std::size_t>;  ///< (done, total) pulses

/// What __next__ takes from the queue at one wake-up.
struct Taken {
    std::optional<std::vector<std::uint8_t>> block;
    std::vector<Report> reports;
    bool done = false;  ///< the run ended (its error, if any, in error_) and every block was taken
};

class SurveyBlocks {
  public:
    SurveyBlocks(SurveySpec spec, const RunOptions& options, std::size_t block_points,
                 py::object progress);
    SurveyBlocks(const SurveyBlocks&) = delete;
    SurveyBlocks& operator=(const SurveyBlocks&) = delete;
    /// Closes the run; an error of the run that close() would raise goes to
    /// sys.unraisablehook, as Python reports exceptions in __del__.
    ~SurveyBlocks();

    /// The next block, or StopIteration; the run's error, a Ctrl-C or progress's exception.
    py::array next();
    /// Cancels the run (unless it ended) and joins its thread. Raises the run's own error if it
    /// failed before being cancelled and the error was not raised yet. Idempotent.
    void close();

  private:
    void produce();
    void take_points(std::span<const BlockPoint> points);
    void push_block();
    void report(std::size_t done, std::size_t total);
    Taken wait_for_news();
    void join();

    SurveySpec spec_;
    RecordLayout layout_;  ///< the records' columns (with `weather` when the survey has it)
    SurveyRunConfig run_;
    std::size_t block_bytes_;
    py::object progress_;
    CancelToken cancel_;
    std::mutex mutex_;
    std::condition_variable changed_;  ///< a block, a report, room, the end or a cancel
    std::deque<std::vector<std::uint8_t>> queue_;
    std::vector<Report> reports_;
    bool finished_ = false;
    std::exception_ptr error_;           ///< the run's, set before finished_
    std::vector<std::uint8_t> current_;  ///< the block being filled (the run's thread only)
    bool joined_ = false;                ///< Python's side: the thread was joined
    std::thread thread_;                 ///< last: started once the rest is ready
};

SurveyBlocks::SurveyBlocks(SurveySpec spec, const RunOptions& options, std::size_t block_points,
                           py::object progress)
    : spec_(std::move(spec)),
      layout_(record_layout(spec_)),
      run_(run_config(options)),
      block_bytes_(block_points * layout_.bytes()),
      progress_(std::move(progress)) {
    run_.cancel = &cancel_;
    run_.extra_sinks.emplace_back([this](const SinkFacts& facts) {
        return make_callback_sink(
            facts, [this](std::span<const BlockPoint> points) { take_points(points); });
    });
    current_.reserve(std::min(block_bytes_, kReserveBytes));
    thread_ = std::thread([this] { produce(); });
}

SurveyBlocks::~SurveyBlocks() {
    try {
        close();
    } catch (const std::exception& e) {
        const std::string what = std::string("beamtrace.iter_survey: ") + e.what();
        PyErr_SetString(PyExc_RuntimeError, what.c_str());
        PyErr_WriteUnraisable(nullptr);
    }
}

// The run's thread: no Python here.
void SurveyBlocks::produce() {
    // Its name (and that of the pool threads it starts): `top -H`, /proc/PID/task/*/comm.
    (void)pthread_setname_np(pthread_self(), kThreadName);
    std::exception_ptr error;
    try {
        (void)run_survey(spec_, run_, [this](std::size_t d, std::size_t t) { report(d, t); });
        if (!current_.empty()) {
            push_block();
        }
    } catch (...) {
        error = std::current_exception();
    }
    const std::lock_guard lock(mutex_);
    error_ = error;
    finished_ = true;
    changed_.notify_all();
}

// Cuts the points into blocks of block_bytes_, pushing each full one.
void SurveyBlocks::take_points(std::span<const BlockPoint> points) {
    while (!points.empty()) {
        const std::size_t room = (block_bytes_ - current_.size()) / layout_.bytes();
        const std::size_t n = std::min(room, points.size());
        append_records(points.first(n), layout_, current_);
        points = points.subspan(n);
        if (current_.size() == block_bytes_) {
            push_block();
        }
    }
}

// Hands current_ to the queue once it has room; throws Interrupted when the run is cancelled.
void SurveyBlocks::push_block() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return queue_.size() < kQueueBlocks || cancel_.requested(); });
    throw_if_cancelled(&cancel_, "survey");
    queue_.push_back(std::move(current_));
    changed_.notify_all();
    lock.unlock();
    current_ = std::vector<std::uint8_t>();
    current_.reserve(std::min(block_bytes_, kReserveBytes));
}

void SurveyBlocks::report(std::size_t done, std::size_t total) {
    const std::lock_guard lock(mutex_);
    reports_.emplace_back(done, total);
    changed_.notify_all();
}

Taken SurveyBlocks::wait_for_news() {
    const py::gil_scoped_release release;
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, std::chrono::milliseconds(50),
                      [&] { return !queue_.empty() || !reports_.empty() || finished_; });
    Taken taken;
    taken.reports.swap(reports_);
    if (!queue_.empty()) {
        taken.block = std::move(queue_.front());
        queue_.pop_front();
        changed_.notify_all();  // room for the run
    } else {
        taken.done = finished_;
    }
    return taken;
}

void SurveyBlocks::join() {
    if (!joined_) {
        {
            const std::lock_guard lock(mutex_);
            queue_.clear();
            changed_.notify_all();
        }
        const py::gil_scoped_release release;
        thread_.join();
        joined_ = true;
    }
}

py::array SurveyBlocks::next() {
    while (!joined_) {
        Taken taken = wait_for_news();
        try {
            if (PyErr_CheckSignals() != 0) {
                throw py::error_already_set();
            }
            for (const auto& [done, total] : taken.reports) {
                if (!progress_.is_none()) {
                    progress_(done, total);
                }
            }
        } catch (...) {
            cancel_.request();
            join();  // the run's own error (Interrupted) is this one's consequence
            error_ = nullptr;
            throw;
        }
        if (taken.block) {
            return records_array(std::move(*taken.block), layout_);
        }
        if (taken.done) {
            join();
            if (const std::exception_ptr error = std::exchange(error_, nullptr)) {
                std::rethrow_exception(error);
            }
        }
    }
    throw py::stop_iteration();
}

void SurveyBlocks::close() {
    if (joined_) {
        return;
    }
    cancel_.request();
    join();
    if (const std::exception_ptr error = std::exchange(error_, nullptr)) {
        try {
            std::rethrow_exception(error);
        } catch (const Interrupted&) {
            // the cancel just requested: what closing means
        }
    }
}

std::unique_ptr<SurveyBlocks> make_blocks(const SurveySpec& spec, const RunOptions& options,
                                          std::int64_t block_points, py::object progress) {
    constexpr auto kMostPoints = static_cast<std::int64_t>(std::size_t{1} << 40);
    if (block_points <= 0 || block_points > kMostPoints) {
        throw py::value_error("block_points: " + std::to_string(block_points) +
                              ", expected a positive number of points (at most 2^40)");
    }
    return std::make_unique<SurveyBlocks>(spec, options, static_cast<std::size_t>(block_points),
                                          std::move(progress));
}

void add_iter_survey(py::module_& m, const char* name, SurveySpec (*load)(const std::string&),
                     const char* doc) {
    m.def(
        name,
        [load](const std::string& survey, std::uint64_t seed, unsigned threads,
               std::optional<std::string> backend, std::uint64_t max_pulses,
               std::int64_t block_points, py::object progress) {
            const SurveySpec spec = load(survey);
            const RunOptions options{seed, threads, std::move(backend), max_pulses, {}};
            return make_blocks(spec, options, block_points, std::move(progress));
        },
        doc, py::arg("survey"), py::arg("seed") = 1, py::arg("threads") = 0u,
        py::arg("backend") = py::none(), py::arg("max_pulses") = 0, py::arg("block_points") = 65536,
        py::arg("progress") = py::none());
}

}  // namespace

void bind_survey_blocks(py::module_& m) {
    py::class_<SurveyBlocks>(m, "SurveyBlocks",
                             "The blocks of points of beamtrace.iter_survey: an iterator and a "
                             "context manager; closing it stops the survey")
        .def("__iter__", [](py::object self) { return self; })
        .def("__next__", &SurveyBlocks::next)
        .def("close", &SurveyBlocks::close,
             "Stops the survey (if it is still running) and waits for its thread")
        .def("__enter__", [](py::object self) { return self; })
        .def("__exit__", [](SurveyBlocks& self, const py::args& /*exc*/) {
            self.close();
            return false;
        });
    add_iter_survey(
        m, "_iter_survey_file", [](const std::string& path) { return load_survey_spec(path); },
        "iter_survey on a survey file (see beamtrace.iter_survey)");
    add_iter_survey(
        m, "_iter_survey_text",
        [](const std::string& text) { return parse_survey_spec(text, "<dict>"); },
        "iter_survey on survey text, YAML or JSON (see beamtrace.iter_survey)");
}

}  // namespace beamtrace::python
