// Sample statistics for the tests of random processes (noise, georeferencing errors).
#pragma once

#include <cmath>
#include <vector>

namespace beamtrace::test {

struct SampleStats {
    double mean = 0, std = 0;  ///< sample mean and standard deviation (n - 1)
};

inline SampleStats sample_stats(const std::vector<double>& v) {
    double s = 0, s2 = 0;
    for (const double x : v) {
        s += x;
    }
    const double mean = s / static_cast<double>(v.size());
    for (const double x : v) {
        s2 += (x - mean) * (x - mean);
    }
    return {mean, std::sqrt(s2 / static_cast<double>(v.size() - 1))};
}

}  // namespace beamtrace::test
