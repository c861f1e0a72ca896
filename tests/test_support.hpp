// Helpers shared by the tests: data paths, temporary folders, procedural meshes.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <cstdio>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <string>
#include <string_view>
#include <utility>

#include <unistd.h>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/accel/backend_registry.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace::test {

inline std::filesystem::path shared_data(const std::string& rel) {
    return std::filesystem::path(BEAMTRACE_SHARED_DATA_DIR) / rel;
}

/// A mesh under the shared data's `meshes/` folder.
inline std::filesystem::path shared_mesh(const std::string& rel) {
    return shared_data("meshes/" + rel);
}

/// True when every test that CI expects to run must run: `BEAMTRACE_REQUIRE_ALL=1`, which
/// `.ci/run` sets. Then a missing prerequisite (a tool, a data file, an optional part) fails the
/// test instead of skipping it.
inline bool require_all() {
    const char* v = std::getenv("BEAMTRACE_REQUIRE_ALL");
    return v != nullptr && std::string_view(v) == "1";
}

/// Skips the current test because a prerequisite that set-up installs is missing (`why` says
/// which and how to get it); under BEAMTRACE_REQUIRE_ALL=1 the test fails instead. The only
/// way tests skip, but for BEAMTRACE_SKIP_HARDWARE (a test checks that no raw GTEST_SKIP is left).
#define BEAMTRACE_SKIP_OR_FAIL(why)                                                              \
    do {                                                                                         \
        if (::beamtrace::test::require_all()) {                                                  \
            GTEST_FAIL() << "expected to run but would skip (BEAMTRACE_REQUIRE_ALL=1): " << why; \
        }                                                                                        \
        GTEST_SKIP() << why;                                                                     \
    } while (0)

/// Skips the current test because this machine's hardware cannot run it whatever is installed
/// (a CPU without AVX-512, say): a skip even under BEAMTRACE_REQUIRE_ALL=1.
#define BEAMTRACE_SKIP_HARDWARE(why) GTEST_SKIP() << "hardware: " << why

/// Whether a test's part for the registry backend `entry` should run: true when it is built and
/// available here. When it is not, the test says so on stdout, and under
/// BEAMTRACE_REQUIRE_ALL=1 fails (set-up installs every backend's library).
inline bool with_backend(const BackendEntry& entry) {
    if (entry.usable()) {
        return true;
    }
    if (require_all()) {
        ADD_FAILURE() << "built without " << entry.summary << " (backend " << entry.name
                      << "), so its part of this test cannot run (BEAMTRACE_REQUIRE_ALL=1; "
                      << entry.how_to_build << ")";
    } else {
        std::printf("  note: built without %s: its part of this test did not run\n",
                    std::string(entry.summary).c_str());
    }
    return false;
}

/// Whether a test's Embree part should run (with_backend of the Embree entry).
inline bool with_embree() {
    return with_backend(backend_entry(BackendKind::embree));
}

/// Every backend of the registry usable here, in table order; `brute` (the oracle) only with
/// `with_brute`. Inside a test (`inside_test`), each registered backend left out is noted, as
/// with_backend does; outside one (test parameter lists) it is silently left out.
inline std::vector<BackendKind> backends(bool with_brute = true, bool inside_test = true) {
    std::vector<BackendKind> kinds;
    for (const BackendEntry& e : backend_registry()) {
        const bool usable = inside_test ? with_backend(e) : e.usable();
        if (usable && (with_brute || e.kind != BackendKind::brute)) {
            kinds.push_back(e.kind);
        }
    }
    return kinds;
}

/// The usable backends that trace instances in place (BackendTraits::instances_natively).
inline std::vector<BackendKind> instancing_backends() {
    std::vector<BackendKind> kinds;
    for (const BackendEntry& e : backend_registry()) {
        if (e.traits.instances_natively && with_backend(e)) {
            kinds.push_back(e.kind);
        }
    }
    return kinds;
}

/// Skips the current test when a shared data file is missing (CI has ../shared too).
#define BEAMTRACE_REQUIRE_FILE(path)                                         \
    do {                                                                     \
        if (!std::filesystem::exists(path)) {                                \
            BEAMTRACE_SKIP_OR_FAIL("missing test data " << (path).string()); \
        }                                                                    \
    } while (0)

/// A fresh empty folder, removed with everything in it when the object dies.
class TempDir {
  public:
    TempDir() {
        static std::atomic<int> counter{0};
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        std::string name = "beamtrace-test-";
        if (info != nullptr) {
            name += std::string(info->test_suite_name()) + "-" + info->name();
        }
        for (auto& ch : name) {
            if (ch == '/') {
                ch = '_';
            }
        }
        name += "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
        path_ = std::filesystem::temp_directory_path() / name;
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }
    [[nodiscard]] std::filesystem::path operator/(const std::string& rel) const {
        return path_ / rel;
    }

  private:
    std::filesystem::path path_;
};

/// Writes `bytes` to `path`, replacing any file there, and returns `path`.
inline std::filesystem::path write_file(const std::filesystem::path& path, std::string_view bytes) {
    // Removing first is much faster than truncating: ext4 flushes files rewritten that way.
    std::error_code ec;
    std::filesystem::remove(path, ec);
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
        ADD_FAILURE() << "cannot write " << path;
    }
    return path;
}

/// The whole content of `path` (empty, with a test failure, if it cannot be opened).
inline std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        ADD_FAILURE() << "cannot open " << path;
        return {};
    }
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Appends the bytes of `value` to `out` in the given byte order.
template <typename T>
void append_bytes(std::string& out, T value, std::endian order = std::endian::little) {
    std::array<char, sizeof(T)> bytes{};
    std::memcpy(bytes.data(), &value, sizeof(T));
    if (order != std::endian::native) {
        std::reverse(bytes.begin(), bytes.end());
    }
    out.append(bytes.data(), bytes.size());
}

/// Expects `read(path)` to throw InputError naming `path` (in path() and in the message) whose
/// message contains `fragment`. Returns the message, or "" when nothing was thrown.
template <typename Read>
std::string expect_input_error(Read&& read, const std::filesystem::path& path,
                               std::string_view fragment = {}) {
    try {
        static_cast<void>(read(path));
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(e.path(), path.string()) << message;
        EXPECT_NE(message.find(path.string()), std::string::npos) << message;
        EXPECT_NE(message.find(fragment), std::string::npos) << message;
        return message;
    }
    ADD_FAILURE() << "expected InputError reading " << path << " with '" << fragment << "'";
    return {};
}

/// Calls `load(prefix)` for every proper prefix of `bytes`, as if the file had been cut short.
/// `load` may throw InputError (the reader rejects the file); anything else fails the test.
template <typename Load>
void load_every_truncation(const std::string& bytes, Load&& load) {
    for (std::size_t n = 0; n < bytes.size(); ++n) {
        try {
            load(bytes.substr(0, n));
        } catch (const InputError&) {
        }
    }
}

/// Calls `load(corrupt)` for `trials` copies of `bytes`, each with one byte replaced at random.
/// `load` may throw InputError (the reader rejects the file); anything else fails the test.
template <typename Load>
void load_random_byte_flips(const std::string& bytes, std::mt19937& rng, int trials, Load&& load) {
    for (int trial = 0; trial < trials; ++trial) {
        std::string corrupt = bytes;
        corrupt[rng() % corrupt.size()] = static_cast<char>(rng() % 256);
        try {
            load(corrupt);
        } catch (const InputError&) {
        }
    }
}

/// A fixture with a fresh temporary folder `dir_` and a way to write files into it.
class TempDirTest : public ::testing::Test {
  protected:
    /// Writes `bytes` to `name` in the temporary folder and returns its path.
    [[nodiscard]] std::filesystem::path write(const std::string& name,
                                              std::string_view bytes) const {
        return write_file(dir_ / name, bytes);
    }

    TempDir dir_;
};

/// A closed, outward-facing icosphere of the given radius around the origin.
inline TriangleMesh make_icosphere(int subdivisions, float radius) {
    TriangleMesh m;
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    const float base[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                               {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                               {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (auto& v : base) {
        m.vertices.push_back(normalize(Vec3f(v[0], v[1], v[2])) * radius);
    }
    m.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
               {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
               {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) {
                return it->second;
            }
            const Vec3f p = normalize((m.vertices[a] + m.vertices[b]) * 0.5f) * radius;
            m.vertices.push_back(p);
            const auto idx = static_cast<std::uint32_t>(m.vertices.size() - 1);
            mid.emplace(key, idx);
            return idx;
        };
        std::vector<Face> faces;
        for (const auto& f : m.faces) {
            const auto a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
            faces.push_back({f[0], a, c});
            faces.push_back({f[1], b, a});
            faces.push_back({f[2], c, b});
            faces.push_back({a, b, c});
        }
        m.faces = std::move(faces);
    }
    return m;
}

/// A flat grid in the plane z = `z` over [0, n] x [0, n] with unit cells (two triangles each,
/// counter-clockwise seen from above).
inline TriangleMesh make_grid(int n, float z = 0.0f) {
    TriangleMesh m;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            m.vertices.emplace_back(static_cast<float>(i), static_cast<float>(j), z);
        }
    }
    auto idx = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            m.faces.push_back({idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)});
            m.faces.push_back({idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)});
        }
    }
    return m;
}

/// Rays from a sphere around box `b` (1.5 x its diagonal) aimed at random points of the box (most
/// hit); with `stray_every` = k > 0, every k-th ray goes in a random direction instead (many miss).
inline RayBatch rays_toward(const Aabb& b, std::size_t n, unsigned seed,
                            std::size_t stray_every = 0) {
    const Vec3d c(b.center());
    const double radius = 1.5 * length(Vec3d(b.extent()));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::normal_distribution<double> g(0.0, 1.0);
    RayBatch rays;
    rays.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3d o = c + normalize(Vec3d{g(rng), g(rng), g(rng)}) * radius;
        Vec3d d;
        if (stray_every > 0 && i % stray_every == stray_every - 1) {
            d = normalize(Vec3d{g(rng), g(rng), g(rng)});
        } else {
            const Vec3d target{b.lo.x + uni(rng) * (b.hi.x - b.lo.x),
                               b.lo.y + uni(rng) * (b.hi.y - b.lo.y),
                               b.lo.z + uni(rng) * (b.hi.z - b.lo.z)};
            d = normalize(target - o);
        }
        rays.push_back(o, d);
    }
    return rays;
}

/// Scale factor for heavy tests: 1 in optimised builds, smaller under sanitizers.
inline std::size_t heavy_scale(std::size_t full) {
#ifdef BEAMTRACE_SANITIZED
    return full / 20;
#else
    return full;
#endif
}

/// Output and exit code of a shell command (stderr folded into stdout).
struct RunResult {
    int exit_code = -1;
    std::string out;  ///< stdout and stderr together
};

inline RunResult run_command(const std::string& cmd) {
    RunResult r;
    FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
    if (p == nullptr) {
        return r;
    }
    std::array<char, 4096> buf{};
    std::size_t n = 0;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) {
        r.out.append(buf.data(), n);
    }
    const int status = ::pclose(p);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

/// Puts our tests/tools/lasdump.mjs (it only calls the npm readers) beside them in `lasval`,
/// replacing any older copy atomically (other tests may be running it).
inline void install_lasdump(const std::filesystem::path& lasval) {
    const auto source =
        std::filesystem::path(BEAMTRACE_TEST_DATA_DIR).parent_path() / "tools" / "lasdump.mjs";
    const auto staging = lasval / ("lasdump.mjs." + std::to_string(::getpid()));
    std::filesystem::copy_file(source, staging, std::filesystem::copy_options::overwrite_existing);
    std::filesystem::rename(staging, lasval / "lasdump.mjs");
}

/// The lasval folder inside the build tree with its npm packages installed, or "" and `why`.
inline std::filesystem::path install_lasval(std::string& why) {
    if (run_command("node --version").exit_code != 0) {
        why = "node is not on PATH";
        return {};
    }
    const std::filesystem::path source =
        std::filesystem::path(BEAMTRACE_SHARED_DATA_DIR) / ".." / "tools" / "lasval";
    if (!std::filesystem::exists(source / "read.mjs")) {
        why = "missing " + source.string();
        return {};
    }
    const std::filesystem::path target =
        std::filesystem::path(BEAMTRACE_CLI_PATH).parent_path() / "lasval-cache";
    if (std::filesystem::exists(target / "node_modules")) {
        install_lasdump(target);
        return target;
    }
    // Install into a private folder and rename it into place, so concurrent runs never see a
    // half-installed cache.
    const std::filesystem::path staging = target.string() + "." + std::to_string(::getpid());
    std::filesystem::remove_all(staging);
    std::filesystem::create_directories(staging);
    for (const char* name : {"read.mjs", "package.json", "package-lock.json"}) {
        std::filesystem::copy_file(source / name, staging / name);
    }
    const auto r = run_command("cd '" + staging.string() + "' && npm ci --no-audit --no-fund");
    if (r.exit_code != 0) {
        std::filesystem::remove_all(staging);
        why = "npm ci failed: " + r.out.substr(0, 500);
        return {};
    }
    std::error_code ec;
    std::filesystem::rename(staging, target, ec);
    if (ec) {
        std::filesystem::remove_all(staging);  // another run installed it first
    }
    if (!std::filesystem::exists(target / "node_modules")) {
        why = "npm ci left no node_modules in " + target.string();
        return {};
    }
    install_lasdump(target);
    return target;
}

/// Number of entries in a folder (to check that nothing, not even a temporary file, was left).
inline std::size_t entry_count(const std::filesystem::path& dir) {
    return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(dir),
                                                  std::filesystem::directory_iterator()));
}

}  // namespace beamtrace::test
