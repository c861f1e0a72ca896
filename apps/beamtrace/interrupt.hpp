// SIGINT and SIGTERM in the CLI: the handlers request the process's cancellation token, which
// the commands pass to the library; the library stops between blocks and throws Interrupted.
#pragma once

#include "beamtrace/core/cancel.hpp"

namespace beamtrace::cli {

/// The token the signal handlers request, with the signal number as the reason.
[[nodiscard]] const CancelToken& interrupt_token();

/// Installs the SIGINT and SIGTERM handlers (sigaction). A handler only requests
/// interrupt_token(); it runs once (SA_RESETHAND), so a second signal during the clean-up
/// ends the process at once. Call it just before the library call that checks the token.
void catch_interrupts();

/// The exit status of an interrupted command: 128 + the signal (130 for SIGINT, 143 for SIGTERM).
[[nodiscard]] int interrupted_exit_code(const Interrupted& e);

}  // namespace beamtrace::cli
