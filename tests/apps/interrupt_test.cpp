// SIGINT and SIGTERM sent to a running `beamtrace survey` / `beamtrace scan`: the command stops,
// removes its temporary files, prints one line and exits with 130 / 143; the output directory
// holds exactly what it held before.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "test_support.hpp"

namespace beamtrace {
namespace {

using Clock = std::chrono::steady_clock;

std::set<std::string> names_in(const std::filesystem::path& dir) {
    std::set<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        names.insert(e.path().filename().string());
    }
    return names;
}

/// The CLI as a child process, its stderr into a file.
struct Child {
    pid_t pid = -1;

    Child(const std::vector<std::string>& args, const std::filesystem::path& err) {
        std::vector<std::string> argv{BEAMTRACE_CLI_PATH};
        argv.insert(argv.end(), args.begin(), args.end());
        std::vector<char*> cargv;
        for (auto& a : argv) {
            cargv.push_back(a.data());
        }
        cargv.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
        posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                         0644);
        const int rc = posix_spawn(&pid, cargv[0], &actions, nullptr, cargv.data(), environ);
        posix_spawn_file_actions_destroy(&actions);
        if (rc != 0) {
            pid = -1;
        }
    }
    ~Child() {
        if (pid > 0) {  // a failed test: do not leave it running
            ::kill(pid, SIGKILL);
            (void)wait();
        }
    }
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;

    /// Whether it is still running (not exited).
    [[nodiscard]] bool running() const {
        siginfo_t info{};
        return ::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
               info.si_pid == 0;
    }
    /// Its threads, from /proc (0 when unreadable).
    [[nodiscard]] int threads() const {
        std::ifstream in("/proc/" + std::to_string(pid) + "/status");
        std::string key;
        while (in >> key) {
            if (key == "Threads:") {
                int n = 0;
                in >> n;
                return n;
            }
        }
        return 0;
    }
    /// Waits for the exit; the wait status.
    int wait() {
        int status = 0;
        ::waitpid(pid, &status, 0);
        pid = -1;
        return status;
    }
};

/// Polls `ready` every millisecond for at most 20 s, while the child runs.
template <class Ready>
bool wait_until(const Child& child, Ready ready) {
    const auto end = Clock::now() + std::chrono::seconds(20);
    while (Clock::now() < end && child.running()) {
        if (ready()) {
            return true;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
}

bool has_temporary(const std::filesystem::path& dir) {
    for (const auto& name : names_in(dir)) {
        if (name.starts_with(".points.las.") && name.ends_with(".tmp")) {
            return true;
        }
    }
    return false;
}

/// The stderr lines.
std::vector<std::string> lines_of(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) {
        lines.push_back(line);
    }
    return lines;
}

/// Exit status, stderr and the directory after `signal` reached a command that was ready.
void expect_clean_interrupt(Child& child, int signal, const std::filesystem::path& err,
                            const std::string& command, const std::filesystem::path& out) {
    ASSERT_TRUE(child.running()) << "the " << command << " ended before the signal";
    ASSERT_EQ(::kill(child.pid, signal), 0);
    const int status = child.wait();
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 128 + signal);
    EXPECT_EQ(lines_of(err), std::vector<std::string>{"beamtrace: " + command +
                                                      ": interrupted; nothing was written"});
    EXPECT_EQ(names_in(out), std::set<std::string>{"keep.txt"});
    EXPECT_EQ(test::read_file(out / "keep.txt"), "mine");
}

constexpr const char* kLongSurvey = R"(scene: demo
scanner: {type: rotating, preset: hdl64, duration_s: 1000}
platform: {type: static, position_m: [0, 0, 2]}
output: {csv: true}
)";

TEST(Interrupt, SurveyStopsCleanlyOnSigintAndSigterm) {
    for (const int signal : {SIGINT, SIGTERM}) {
        test::TempDir dir;
        test::write_file(dir / "long.yaml", kLongSurvey);
        std::filesystem::create_directories(dir / "out");
        test::write_file(dir / "out" / "keep.txt", "mine");
        Child child({"survey", (dir / "long.yaml").string(), "--output", (dir / "out").string(),
                     "--threads", "2"},
                    dir / "err.txt");
        ASSERT_GT(child.pid, 0);
        // The LAS sink's temporary file is there: the survey is writing.
        ASSERT_TRUE(wait_until(child, [&] { return has_temporary(dir / "out"); }));
        expect_clean_interrupt(child, signal, dir / "err.txt", "survey", dir / "out");
    }
}

TEST(Interrupt, SurveyRemovesTheOutputDirectoryItCreated) {
    test::TempDir dir;
    test::write_file(dir / "long.yaml", kLongSurvey);
    Child child({"survey", (dir / "long.yaml").string(), "--output", (dir / "new" / "out").string(),
                 "--threads", "2"},
                dir / "err.txt");
    ASSERT_GT(child.pid, 0);
    ASSERT_TRUE(wait_until(child, [&] {
        std::error_code ec;
        return std::filesystem::exists(dir / "new" / "out", ec) &&
               has_temporary(dir / "new" / "out");
    }));
    ASSERT_EQ(::kill(child.pid, SIGINT), 0);
    const int status = child.wait();
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130);
    EXPECT_EQ(names_in(dir.path()), (std::set<std::string>{"err.txt", "long.yaml"}));
}

TEST(Interrupt, ScanStopsCleanlyOnSigintAndSigterm) {
    for (const int signal : {SIGINT, SIGTERM}) {
        test::TempDir dir;
        std::filesystem::create_directories(dir / "out");
        test::write_file(dir / "out" / "keep.txt", "mine");
        // 4 M rays: the signal comes long before the first chunk is traced.
        Child child({"scan", "--demo", "--width", "2000", "--height", "2000", "--threads", "2",
                     "--output", (dir / "out").string()},
                    dir / "err.txt");
        ASSERT_GT(child.pid, 0);
        // Its thread pool is up: the handlers are installed and the scan is under way.
        ASSERT_TRUE(wait_until(child, [&] { return child.threads() > 1; }));
        expect_clean_interrupt(child, signal, dir / "err.txt", "scan", dir / "out");
    }
}

}  // namespace
}  // namespace beamtrace
