// The registry entries of the scan pattern types, one function per type in the type's own file
// (scan_pattern_registry.hpp says how to add one).
#pragma once

#include "beamtrace/sensor/scan_pattern_registry.hpp"

namespace beamtrace::detail {

[[nodiscard]] ScanPatternEntry rotating_scanner_entry();  // rotating_scanner.cpp
[[nodiscard]] ScanPatternEntry line_scanner_entry();      // line_scanner.cpp
[[nodiscard]] ScanPatternEntry pinhole_pattern_entry();   // image_pattern.cpp
[[nodiscard]] ScanPatternEntry scan_pattern_entry();      // image_pattern.cpp
[[nodiscard]] ScanPatternEntry rays_file_entry();         // rays_file.cpp

}  // namespace beamtrace::detail
