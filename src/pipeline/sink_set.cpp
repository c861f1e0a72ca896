#include "pipeline/detail/sink_set.hpp"

#include <exception>
#include <system_error>
#include <thread>

namespace beamtrace::detail {

namespace {

/// Runs sink.commit() into `files`, or keeps its error in `error`.
void commit_one(PointSink& sink, std::vector<std::filesystem::path>& files,
                std::exception_ptr& error) noexcept {
    try {
        files = sink.commit();
    } catch (...) {
        error = std::current_exception();
    }
}

}  // namespace

std::vector<std::filesystem::path> SinkSet::commit() {
    const std::size_t n = sinks_.size();
    std::vector<std::vector<std::filesystem::path>> files(n);
    std::vector<std::exception_ptr> errors(n);
    std::vector<char> started(n, 0);
    // The sinks that may commit beside the others start first, each on a thread of its own
    // (none to be had: on this one, in order, below).
    std::vector<std::thread> beside;
    for (std::size_t i = 0; i < n; ++i) {
        if (!sinks_[i]->commits_beside()) {
            continue;
        }
        try {
            beside.emplace_back(
                [this, i, &files, &errors] { commit_one(*sinks_[i], files[i], errors[i]); });
            started[i] = 1;
        } catch (const std::system_error&) {
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (started[i] == 0) {
            started[i] = 1;
            commit_one(*sinks_[i], files[i], errors[i]);
            if (errors[i]) {
                break;  // the sinks after it are aborted below
            }
        }
    }
    for (std::thread& t : beside) {
        t.join();
    }
    std::exception_ptr first_error;  // in sink order
    std::vector<std::filesystem::path> out;
    for (std::size_t i = 0; i < n; ++i) {
        first_error = first_error ? first_error : errors[i];
        for (auto& f : files[i]) {
            out.push_back(std::move(f));
        }
    }
    if (first_error) {
        // The sinks whose commit failed or never ran are aborted; the files of the others go.
        for (std::size_t i = 0; i < n; ++i) {
            if (started[i] != 0 && !errors[i]) {
                sinks_[i].reset();
            }
        }
        abort();
        for (const auto& f : out) {
            std::error_code ignored;
            std::filesystem::remove(f, ignored);
        }
        std::rethrow_exception(first_error);
    }
    for (auto& sink : sinks_) {
        for (auto& note : sink->notes()) {
            notes_.push_back(std::move(note));
        }
    }
    sinks_.clear();
    return out;
}

void SinkSet::abort() noexcept {
    for (auto& sink : sinks_) {
        if (sink) {
            sink->abort();
            sink.reset();
        }
    }
    sinks_.clear();
}

}  // namespace beamtrace::detail
