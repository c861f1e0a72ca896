# install(): the module libraries, the public headers (include/beamtrace), the CLI, and a CMake
# package, so that a C++ project can write
#
#   find_package(beamtrace REQUIRED)
#   target_link_libraries(app PRIVATE beamtrace::beamtrace)
#
# (docs/cpp.md; tests/install builds examples/pushbroom_rays.cpp against an installed copy).
# Headers under src/ (module internals) and the benchmark harness are not installed.
include(CMakePackageConfigHelpers)

set(BEAMTRACE_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/beamtrace")
set(BEAMTRACE_INSTALL_TARGETS beamtrace_lib)
foreach(module IN LISTS BEAMTRACE_MODULES)
  list(APPEND BEAMTRACE_INSTALL_TARGETS beamtrace_${module})
endforeach()
install(TARGETS ${BEAMTRACE_INSTALL_TARGETS} EXPORT beamtraceTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY include/beamtrace DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS beamtrace RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT beamtraceTargets NAMESPACE beamtrace:: DESTINATION ${BEAMTRACE_INSTALL_CMAKEDIR})

configure_package_config_file(cmake/beamtraceConfig.cmake.in
  "${PROJECT_BINARY_DIR}/beamtraceConfig.cmake" INSTALL_DESTINATION ${BEAMTRACE_INSTALL_CMAKEDIR})
write_basic_package_version_file("${PROJECT_BINARY_DIR}/beamtraceConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/beamtraceConfig.cmake"
              "${PROJECT_BINARY_DIR}/beamtraceConfigVersion.cmake"
        DESTINATION ${BEAMTRACE_INSTALL_CMAKEDIR})
