#include "beamtrace/core/memory_usage.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

namespace beamtrace {
namespace {

/// A "Name:   1234 kB" line of /proc/self/status, in bytes.
std::size_t status_kb(const char* name) {
    std::ifstream in("/proc/self/status");
    std::string line;
    const std::size_t n = std::strlen(name);
    while (std::getline(in, line)) {
        if (line.compare(0, n, name) == 0 && line.size() > n && line[n] == ':') {
            return std::stoull(line.substr(n + 1)) * 1024;
        }
    }
    return 0;
}

}  // namespace

std::size_t current_rss_bytes() {
    return status_kb("VmRSS");
}

std::size_t peak_rss_bytes() {
    return status_kb("VmHWM");
}

void trim_free_memory() {
#if defined(__GLIBC__)
    ::malloc_trim(0);
#endif
}

bool reset_peak_rss() {
    std::FILE* f = std::fopen("/proc/self/clear_refs", "w");
    if (f == nullptr) {
        return false;
    }
    const bool ok = std::fputs("5", f) >= 0;
    return std::fclose(f) == 0 && ok;
}

}  // namespace beamtrace
