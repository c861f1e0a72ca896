// Camera and position arguments as the CLI's text, for the bindings that hand them to the
// library's parsers (render's --camera/--look-at, view's --camera).
#pragma once

#include <cstdio>
#include <string>

#include "bindings.hpp"

namespace beamtrace::python {

/// "X,Y,Z,..." as given (a str), or a sequence of numbers joined with commas (every digit).
[[nodiscard]] inline std::string position_text(const py::handle& value) {
    if (py::isinstance<py::str>(value)) {
        return value.cast<std::string>();
    }
    std::string text;
    for (const py::handle item : value) {
        char number[32];
        std::snprintf(number, sizeof number, "%.17g", item.cast<double>());
        text += (text.empty() ? "" : ",") + std::string(number);
    }
    return text;
}

}  // namespace beamtrace::python
