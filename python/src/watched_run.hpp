// A long library call run on a thread of its own while the calling (Python) thread, the GIL
// released, waits: it hands the call's progress to a Python callback and checks for Ctrl-C
// (PyErr_CheckSignals works on the main thread only), cancelling the call through its
// CancelToken when either raises.
#pragma once

#include <cstddef>
#include <functional>

#include "beamtrace/core/cancel.hpp"
#include "beamtrace/core/progress.hpp"
#include "bindings.hpp"

namespace beamtrace::python {

/// Runs `call(cancel, report)` on a new thread; `call` must not touch Python. Meanwhile, on
/// this thread: `progress(done, total)` for every report, in order (unless `progress` is None),
/// and PyErr_CheckSignals, at each report or every 50 ms. When either raises, `cancel` is
/// requested, the call is waited for and the Python exception (KeyboardInterrupt for Ctrl-C)
/// re-raised; otherwise the call's own exception, if any, is rethrown. Call with the GIL held.
void run_watched(
    const std::function<void(const CancelToken& cancel, const ProgressFn& report)>& call,
    const py::object& progress);

}  // namespace beamtrace::python
