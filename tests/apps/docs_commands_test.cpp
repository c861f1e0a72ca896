// Every shell block (```sh) of README.md and docs/*.md runs as written from the repository root
// after the set-up, with files that exist: here in a copy of the root's layout (build/beamtrace
// and build/beamtrace_pushbroom_rays are this build's, examples/ and ../shared/data the real
// ones, out/ empty), each block as one bash script under `set -euo pipefail`. A block preceded
// by `<!-- docs-test: skip: REASON -->` is not run (the set-up itself, builds and installs).
// Every `--output PATH` a block names must exist afterwards, and every picture the docs show
// (`](images/NAME.png)`) must be what the blocks made: out/images/NAME.png, byte for byte.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

struct ShellBlock {
    std::string where;  ///< file:line of the opening fence
    std::string text;
};

/// The ```sh blocks of `file` not marked to be skipped.
std::vector<ShellBlock> shell_blocks(const fs::path& file, const std::string& name) {
    std::ifstream in(file);
    std::vector<ShellBlock> out;
    std::string line, previous;
    int number = 0;
    bool skip_next = false;
    while (std::getline(in, line)) {
        ++number;
        if (line.rfind("<!-- docs-test: skip", 0) == 0) {
            skip_next = true;
            continue;
        }
        if (line != "```sh") {
            if (!line.empty()) {
                skip_next = false;
            }
            continue;
        }
        ShellBlock block{name + ":" + std::to_string(number), {}};
        while (std::getline(in, line) && line.rfind("```", 0) != 0) {
            ++number;
            block.text += line + "\n";
        }
        ++number;
        if (!skip_next) {
            out.push_back(std::move(block));
        }
        skip_next = false;
    }
    return out;
}

std::vector<ShellBlock> all_blocks() {
    const fs::path root = BEAMTRACE_SOURCE_DIR;
    std::vector<ShellBlock> blocks = shell_blocks(root / "README.md", "README.md");
    std::vector<fs::path> docs;
    for (const auto& e : fs::directory_iterator(root / "docs")) {
        if (e.path().extension() == ".md") {
            docs.push_back(e.path());
        }
    }
    std::sort(docs.begin(), docs.end());
    for (const auto& d : docs) {
        for (auto& b : shell_blocks(d, "docs/" + d.filename().string())) {
            blocks.push_back(std::move(b));
        }
    }
    return blocks;
}

/// TMP/repo laid out like the repository root after the set-up; returns TMP/repo.
fs::path make_root(const test::TempDir& dir) {
    const fs::path repo = dir / "repo";
    fs::create_directories(repo / "build");
    fs::create_directories(repo / "out");
    fs::create_directories(dir / "shared");
    const fs::path source = BEAMTRACE_SOURCE_DIR;
    for (const char* d : {"examples", "scripts", "docs"}) {
        fs::create_directory_symlink(source / d, repo / d);
    }
    fs::create_symlink(BEAMTRACE_CLI_PATH, repo / "build" / "beamtrace");
    fs::create_symlink(BEAMTRACE_PUSHBROOM_PATH, repo / "build" / "beamtrace_pushbroom_rays");
    fs::create_directory_symlink(fs::absolute(BEAMTRACE_SHARED_DATA_DIR), dir / "shared" / "data");
    return repo;
}

/// What follows each `marker` in `text` up to the first character of `stops` (or the end).
std::vector<std::string> words_after(const std::string& text, const std::string& marker,
                                     const std::string& stops) {
    std::vector<std::string> out;
    for (std::size_t at = text.find(marker); at != std::string::npos;
         at = text.find(marker, at + 1)) {
        const std::size_t from = at + marker.size();
        out.push_back(text.substr(from, text.find_first_of(stops, from) - from));
    }
    return out;
}

/// Every picture docs/*.md shows equals the file of that name the blocks wrote to out/images.
void expect_pictures_made_by_the_blocks(const fs::path& repo) {
    const fs::path docs = fs::path(BEAMTRACE_SOURCE_DIR) / "docs";
    std::size_t shown = 0;
    for (const auto& e : fs::directory_iterator(docs)) {
        if (e.path().extension() != ".md") {
            continue;
        }
        const std::string text = test::read_file(e.path());
        for (const std::string& name : words_after(text, "](images/", ")")) {
            ++shown;
            SCOPED_TRACE(e.path().filename().string() + ": images/" + name);
            const fs::path made = repo / "out" / "images" / name;
            ASSERT_TRUE(fs::exists(made)) << "no command in the docs makes it";
            if (const char* update = std::getenv("BEAMTRACE_UPDATE_GOLDEN");
                update != nullptr && std::string(update) == "1") {
                fs::copy_file(made, docs / "images" / name, fs::copy_options::overwrite_existing);
            }
            EXPECT_TRUE(test::read_file(made) == test::read_file(docs / "images" / name))
                << "docs/images/" << name << " is not what the commands make now (copy "
                << "out/images/" << name << " there)";
        }
    }
    EXPECT_GE(shown, 4u);  // the tutorial's
}

TEST(DocsCommands, EveryShellBlockOfTheReadmeAndDocsRunsAsWritten) {
    if (!fs::exists(BEAMTRACE_SHARED_DATA_DIR)) {
        BEAMTRACE_SKIP_OR_FAIL("../shared/data is missing: " BEAMTRACE_SHARED_DATA_DIR);
    }
    const std::vector<ShellBlock> blocks = all_blocks();
    ASSERT_GE(blocks.size(), 2u);  // the README's usage, render.md, ... (the parser works)
    test::TempDir dir;
    const fs::path repo = make_root(dir);
    for (const ShellBlock& b : blocks) {
        SCOPED_TRACE(b.where);
        const fs::path script = dir / "block.sh";
        test::write_file(script, "set -euo pipefail\n" + b.text);
        const auto r =
            test::run_command("cd '" + repo.string() + "' && PATH=\"" + (repo / "build").string() +
                              ":$PATH\" bash '" + script.string() + "'");
        EXPECT_EQ(r.exit_code, 0) << b.text << "\n--- output:\n" << r.out;
        for (const std::string& promised : words_after(b.text, "--output ", " \\\n;|&")) {
            EXPECT_TRUE(fs::exists(repo / promised)) << promised << " was not written";
        }
    }
    expect_pictures_made_by_the_blocks(repo);
}

}  // namespace
}  // namespace beamtrace
