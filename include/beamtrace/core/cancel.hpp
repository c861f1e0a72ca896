// Cancelling a long library call from another thread or a signal handler: the caller owns a
// CancelToken and passes it in the call's config; the library checks it between blocks of work
// and throws Interrupted, so the ordinary unwinding removes every temporary file.
#pragma once

#include <atomic>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

/// A request to stop, with a reason (an integer of the caller's, e.g. the signal number; any
/// value but 0). request() is lock-free and async-signal-safe; the library only reads the token.
class CancelToken {
  public:
    static_assert(std::atomic<int>::is_always_lock_free, "signal handlers need a lock-free flag");

    CancelToken() = default;
    CancelToken(const CancelToken&) = delete;
    CancelToken& operator=(const CancelToken&) = delete;

    /// Asks the calls that hold this token to stop; the first reason given is kept.
    void request(int reason = 1) noexcept {
        int expected = 0;
        reason_.compare_exchange_strong(expected, reason == 0 ? 1 : reason,
                                        std::memory_order_relaxed);
    }
    [[nodiscard]] bool requested() const noexcept {
        return reason_.load(std::memory_order_relaxed) != 0;
    }
    /// The reason given to request(); 0 while none was requested.
    [[nodiscard]] int reason() const noexcept { return reason_.load(std::memory_order_relaxed); }

  private:
    std::atomic<int> reason_{0};
};

/// Throws Interrupted (naming `what`, e.g. "survey") when `token` is set and was requested.
inline void throw_if_cancelled(const CancelToken* token, const char* what) {
    if (token != nullptr && token->requested()) {
        throw Interrupted(what, token->reason());
    }
}

}  // namespace beamtrace
