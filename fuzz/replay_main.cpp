// The corpus replay: a main() for one fuzz harness, built with the default compiler and no
// libFuzzer, that feeds it every file of the folders given on the command line (in name order).
// Used by ctest (FuzzReplay.<target>), so every seed and every saved reproducer stays accepted
// or cleanly rejected.
//
// usage: beamtrace_fuzz_replay_<target> FOLDER...
// Exit status 0 when every file passed; 1 when an exception other than beamtrace::Error left the
// harness (the file and the exception are printed), or a folder is missing or empty. A crash or
// a sanitizer report ends the process on its own, naming the file last printed with -v, which
// also prints whether the harness accepted or rejected each file (and why).
#include <stdlib.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

std::vector<std::uint8_t> read_all(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::filesystem::path> files_in(const std::filesystem::path& folder) {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        if (entry.is_regular_file() && entry.path().filename().string().front() != '.') {
            files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

/// Feeds one file to the harness; false (with a line on stderr) if an exception escaped it.
bool replay(const std::filesystem::path& file, bool verbose) {
    if (verbose) {
        std::cerr << "replay: " << file.string() << std::endl;
    }
    const std::vector<std::uint8_t> bytes = read_all(file);
    try {
        // An empty file still needs a valid pointer, as libFuzzer gives.
        const std::uint8_t none = 0;
        LLVMFuzzerTestOneInput(bytes.empty() ? &none : bytes.data(), bytes.size());
        return true;
    } catch (const std::exception& e) {
        std::cerr << file.string() << ": exception escaped the harness: " << e.what() << "\n";
    } catch (...) {
        std::cerr << file.string() << ": a non-std exception escaped the harness\n";
    }
    return false;
}

}  // namespace

int main(int argc, char** argv) {
    bool verbose = false;
    std::size_t total = 0, failed = 0;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "-v") == 0) {
            verbose = true;
            ::setenv("BEAMTRACE_FUZZ_SHOW_REJECTIONS", "1", 1);
            continue;
        }
        const std::filesystem::path folder = argv[i];
        if (!std::filesystem::is_directory(folder) || files_in(folder).empty()) {
            std::cerr << folder.string() << ": no such folder, or no files in it\n";
            return 1;
        }
        for (const auto& file : files_in(folder)) {
            ++total;
            failed += replay(file, verbose) ? 0 : 1;
        }
    }
    std::cout << "replayed " << total << " files, " << failed << " failed\n";
    return failed == 0 && total > 0 ? 0 : 1;
}
