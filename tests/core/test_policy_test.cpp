// The suite's own rules: a test skips only through the macros of test_support.hpp, so that
// under BEAMTRACE_REQUIRE_ALL=1 (CI) a missing prerequisite fails instead of passing silently.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(TestPolicy, EverySkipGoesThroughTheRequireAllMacros) {
    const std::filesystem::path tests =
        std::filesystem::path(BEAMTRACE_TEST_DATA_DIR).parent_path();
    ASSERT_TRUE(std::filesystem::exists(tests / "test_support.hpp")) << tests;
    std::size_t files = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(tests)) {
        const auto ext = entry.path().extension();
        if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".hpp") ||
            entry.path().filename() == "test_support.hpp" ||
            entry.path().filename() == "test_policy_test.cpp") {
            continue;
        }
        ++files;
        const std::string text = test::read_file(entry.path());
        EXPECT_EQ(text.find("GTEST_SKIP"), std::string::npos)
            << entry.path() << ": skip with BEAMTRACE_SKIP_OR_FAIL or BEAMTRACE_SKIP_HARDWARE";
    }
    EXPECT_GT(files, 50u);
}

TEST(TestPolicy, RequireAllIsReadFromTheEnvironment) {
    const char* saved = std::getenv("BEAMTRACE_REQUIRE_ALL");
    const std::string keep = saved != nullptr ? saved : "";
    ::setenv("BEAMTRACE_REQUIRE_ALL", "1", 1);
    EXPECT_TRUE(test::require_all());
    ::setenv("BEAMTRACE_REQUIRE_ALL", "0", 1);
    EXPECT_FALSE(test::require_all());
    if (saved != nullptr) {
        ::setenv("BEAMTRACE_REQUIRE_ALL", keep.c_str(), 1);
    } else {
        ::unsetenv("BEAMTRACE_REQUIRE_ALL");
    }
}

}  // namespace
}  // namespace beamtrace
