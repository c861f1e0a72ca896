#include "beamtrace/heightfield/camera_path.hpp"

#include <fstream>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

[[nodiscard]] std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) {
        return {};
    }
    const auto e = s.find_last_not_of(" \t\r");
    return s.substr(b, e - b + 1);
}

[[nodiscard]] std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> out;
    std::size_t start = 0;
    for (;;) {
        const auto comma = line.find(',', start);
        out.push_back(trim(line.substr(start, comma - start)));
        if (comma == std::string::npos) {
            return out;
        }
        start = comma + 1;
    }
}

}  // namespace

std::vector<CameraPose> read_camera_path(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) {
        throw InputError(path.string(), "cannot open camera path");
    }
    std::vector<CameraPose> poses;
    std::string line;
    long number = 0;
    bool header = false;
    while (std::getline(in, line)) {
        ++number;
        const std::string text = trim(line);
        if (text.empty() || text[0] == '#') {
            continue;
        }
        if (!header) {
            const auto names = split(text);
            if (names != std::vector<std::string>{"x", "y", "z", "yaw", "pitch"}) {
                throw InputError(path.string(), number,
                                 "header must be 'x,y,z,yaw,pitch', found '" + text + "'");
            }
            header = true;
            continue;
        }
        std::string why;
        const auto pose = try_parse_camera_pose(text, {}, why);
        if (!pose) {
            throw InputError(path.string(), number, why);
        }
        poses.push_back(pose->pose);
    }
    if (poses.empty()) {
        throw InputError(path.string(), header ? "camera path has no poses after the header"
                                               : "camera path is empty (expected the header "
                                                 "'x,y,z,yaw,pitch' and one pose per line)");
    }
    return poses;
}

}  // namespace beamtrace
