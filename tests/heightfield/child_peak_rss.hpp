// The peak resident memory of a program run as a child process, measured by the kernel.
//
// Why not wait4()'s ru_maxrss: a child forked from this (large, multi-threaded) test process
// starts with a copy of its resident pages, and execve() records that copy's size in the
// child's ru_maxrss, so a 30 MB program run from a test process holding 300 MB reports 300 MB.
// Instead the child is traced (PTRACE_TRACEME) and stopped as it exits (PTRACE_O_TRACEEXIT),
// before its memory is released, and its own high-water mark VmHWM (of the address space that
// execve() made, nothing of ours) is read from /proc/PID/status.
#pragma once

#include <fcntl.h>
#include <sys/ptrace.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace beamtrace::test {

struct ChildPeak {
    int exit_code = -1;              ///< -1: killed by a signal or not run
    std::size_t peak_rss_bytes = 0;  ///< VmHWM at exit; 0 when it could not be read
    std::string error;               ///< why nothing was measured (empty when it was)
};

/// VmHWM of process `pid` in bytes (0 when unreadable).
inline std::size_t vm_hwm_bytes(pid_t pid) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmHWM:", 0) == 0) {
            std::istringstream fields(line.substr(6));
            std::size_t kib = 0;
            fields >> kib;
            return kib * 1024;
        }
    }
    return 0;
}

/// Runs `argv` (argv[0] a path) with stdout and stderr into `log`, and returns its exit code and
/// peak RSS (see above).
inline ChildPeak run_measuring_peak_rss(const std::vector<std::string>& argv,
                                        const std::filesystem::path& log) {
    ChildPeak result;
    std::vector<char*> args;
    for (const auto& a : argv) {
        args.push_back(const_cast<char*>(a.c_str()));
    }
    args.push_back(nullptr);
    // The child's environment; LeakSanitizer cannot run under ptrace, so a sanitized child
    // gets detect_leaks=0 (its leaks are checked by the tests that run it without ptrace).
    std::vector<std::string> env_text;
    for (char** e = environ; *e != nullptr; ++e) {
        const std::string_view v(*e);
        if (v.substr(0, 13) != "ASAN_OPTIONS=") {
            env_text.emplace_back(v);
        }
    }
#ifdef BEAMTRACE_SANITIZED
    const char* asan = std::getenv("ASAN_OPTIONS");
    env_text.push_back(std::string("ASAN_OPTIONS=") + (asan != nullptr ? asan : "") +
                       (asan != nullptr && *asan != '\0' ? ":" : "") + "detect_leaks=0");
#else
    if (const char* asan = std::getenv("ASAN_OPTIONS")) {
        env_text.push_back(std::string("ASAN_OPTIONS=") + asan);
    }
#endif
    std::vector<char*> env;
    for (auto& e : env_text) {
        env.push_back(e.data());
    }
    env.push_back(nullptr);
    const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (out < 0) {
        result.error = "cannot create " + log.string();
        return result;
    }
    const pid_t pid = ::fork();
    if (pid == 0) {  // only async-signal-safe calls until execv
        ::dup2(out, 1);
        ::dup2(out, 2);
        if (::ptrace(PTRACE_TRACEME, 0, nullptr, nullptr) != 0) {
            ::_exit(126);
        }
        ::execve(args[0], args.data(), env.data());
        ::_exit(127);
    }
    ::close(out);
    if (pid < 0) {
        result.error = "fork failed";
        return result;
    }
    int status = 0;
    // The first stop is the SIGTRAP of the traced execve.
    if (::waitpid(pid, &status, 0) != pid || !WIFSTOPPED(status)) {
        result.error = "the child did not stop at exec (ptrace refused?)";
        return result;
    }
    ::ptrace(PTRACE_SETOPTIONS, pid, nullptr,
             reinterpret_cast<void*>(PTRACE_O_TRACEEXIT | PTRACE_O_EXITKILL));
    ::ptrace(PTRACE_CONT, pid, nullptr, nullptr);
    while (::waitpid(pid, &status, 0) == pid) {
        if (WIFEXITED(status) || WIFSIGNALED(status)) {
            break;
        }
        int forward = 0;
        if ((status >> 8) == (SIGTRAP | (PTRACE_EVENT_EXIT << 8))) {
            result.peak_rss_bytes = vm_hwm_bytes(pid);  // still alive, memory not yet released
        } else {
            forward = WSTOPSIG(status);  // a signal for the child: deliver it
        }
        ::ptrace(PTRACE_CONT, pid, nullptr, reinterpret_cast<void*>(static_cast<long>(forward)));
    }
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (result.peak_rss_bytes == 0) {
        result.error = "no VmHWM read at the child's exit";
    }
    return result;
}

}  // namespace beamtrace::test
