#include "harness/child_run.hpp"

#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <new>
#include <stdexcept>

#include "beamtrace/core/error.hpp"

namespace beamtrace::detail {
namespace {

/// What the child sends first: how its work ended.
enum class Outcome : char { ok = 'o', beamtrace_error = 'e', bad_alloc = 'm', other = 'x' };

void write_all(int fd, const std::string& bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return;  // the parent reports a short message
        }
        done += static_cast<std::size_t>(n);
    }
}

std::string read_all(int fd) {
    std::string out;
    char buf[4096];
    for (;;) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return out;
        }
        out.append(buf, static_cast<std::size_t>(n));
    }
}

[[noreturn]] void child_main(int fd, const std::function<std::string()>& work) {
    std::string message;
    try {
        message = static_cast<char>(Outcome::ok) + work();
    } catch (const Error& e) {
        message = static_cast<char>(Outcome::beamtrace_error) + std::string(e.what());
    } catch (const std::bad_alloc&) {
        message = static_cast<char>(Outcome::bad_alloc);
    } catch (const std::exception& e) {
        message = static_cast<char>(Outcome::other) + std::string(e.what());
    } catch (...) {
        message = static_cast<char>(Outcome::other) + std::string("unknown exception");
    }
    write_all(fd, message);
    ::close(fd);
    std::fflush(nullptr);
    ::_exit(0);  // no atexit handlers or static destructors of the parent's state
}

}  // namespace

bool process_is_single_threaded() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("Threads:", 0) == 0) {
            return std::stoi(line.substr(8)) == 1;
        }
    }
    return false;
}

ChildRun run_in_child(const std::function<std::string()>& work) {
    int fds[2];
    if (::pipe(fds) != 0) {
        throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
    }
    std::fflush(nullptr);  // nothing buffered is written twice
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int err = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        throw std::runtime_error(std::string("fork: ") + std::strerror(err));
    }
    if (pid == 0) {
        ::close(fds[0]);
        child_main(fds[1], work);
    }
    ::close(fds[1]);
    const std::string message = read_all(fds[0]);
    ::close(fds[0]);
    int status = 0;
    rusage usage{};
    pid_t waited = 0;
    do {
        waited = ::wait4(pid, &status, 0, &usage);
    } while (waited < 0 && errno == EINTR);
    if (waited != pid) {
        throw std::runtime_error(std::string("wait4: ") + std::strerror(errno));
    }
    if (WIFSIGNALED(status)) {
        throw std::runtime_error("the child process was killed by signal " +
                                 std::to_string(WTERMSIG(status)) +
                                 (WTERMSIG(status) == SIGKILL ? " (out of memory?)" : ""));
    }
    if (message.empty()) {
        throw std::runtime_error("the child process ended without a result");
    }
    const std::string rest = message.substr(1);
    switch (static_cast<Outcome>(message[0])) {
        case Outcome::ok:
            return {rest, static_cast<std::size_t>(usage.ru_maxrss) * 1024};
        case Outcome::beamtrace_error:
            throw ConfigError(rest);
        case Outcome::bad_alloc:
            throw std::bad_alloc();
        case Outcome::other:
            break;
    }
    throw std::runtime_error(rest);
}

}  // namespace beamtrace::detail
