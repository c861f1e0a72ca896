#include "interrupt.hpp"

#include <csignal>

namespace beamtrace::cli {
namespace {

// The one process-level object of the CLI: a signal handler can reach nothing else. Constant-
// initialized, so it exists before any signal can arrive.
constinit CancelToken g_interrupt;  // NOLINT(cppcoreguidelines-avoid-non-const-global-variables)

extern "C" void on_interrupt(int signal_number) {
    g_interrupt.request(signal_number);  // a lock-free atomic: async-signal-safe
}

}  // namespace

const CancelToken& interrupt_token() {
    return g_interrupt;
}

void catch_interrupts() {
    struct sigaction action = {};
    action.sa_handler = &on_interrupt;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;  // the second signal gets the default action: ends us
    for (const int s : {SIGINT, SIGTERM}) {
        sigaction(s, &action, nullptr);
    }
}

int interrupted_exit_code(const Interrupted& e) {
    return e.reason() > 0 && e.reason() < 128 ? 128 + e.reason() : 128 + SIGINT;
}

}  // namespace beamtrace::cli
