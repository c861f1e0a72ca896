# One library target per module of cmake/modules.txt (the module graph, declared once; the
# include check, scripts/check_includes.py, reads the same file). Module <m> is beamtrace_<m>
# (alias beamtrace::<m>, exported as beamtrace::<m>), built from every src/<m>/**/*.cpp, linking
# the modules its line names. Public headers: include/beamtrace/<m>/. Headers in src/<m>/ are
# reachable by the modules above <m> but not installed; src/<m>/detail/ is private to <m>.
# beamtrace_lib (exported as beamtrace::beamtrace) aggregates them all.

# Reads the [library] section of cmake/modules.txt: sets BEAMTRACE_MODULES (bottom first) and
# BEAMTRACE_MODULE_DEPS_<m> (the direct dependencies of <m>) in the caller's scope.
function(beamtrace_read_modules file)
  file(STRINGS "${file}" lines)
  set(section "")
  set(modules "")
  foreach(line IN LISTS lines)
    string(STRIP "${line}" line)
    if(line MATCHES "^\\[([a-z]+)\\]$")
      set(section "${CMAKE_MATCH_1}")
    elseif(section STREQUAL "library" AND line MATCHES "^([a-z_]+):(.*)$")
      set(module "${CMAKE_MATCH_1}")
      string(STRIP "${CMAKE_MATCH_2}" deps)
      string(REGEX REPLACE "[ \t]+" ";" deps "${deps}")
      foreach(dep IN LISTS deps)
        if(NOT dep IN_LIST modules)
          message(FATAL_ERROR "${file}: module ${module} uses ${dep}, which is not declared above it")
        endif()
      endforeach()
      list(APPEND modules ${module})
      set(BEAMTRACE_MODULE_DEPS_${module} "${deps}" PARENT_SCOPE)
    endif()
  endforeach()
  set(BEAMTRACE_MODULES "${modules}" PARENT_SCOPE)
endfunction()

# The library target of one module.
function(beamtrace_add_module module)
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/src/${module}/*.cpp")
  # The Embree backend's files are compiled only when Embree is found (beamtrace_add_embree).
  list(FILTER sources EXCLUDE REGEX "/src/accel/embree_[^/]*\\.cpp$")
  set(target beamtrace_${module})
  add_library(${target} ${sources})
  add_library(beamtrace::${module} ALIAS ${target})
  target_include_directories(${target}
    PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE ${PROJECT_SOURCE_DIR}/src)
  foreach(dep IN LISTS BEAMTRACE_MODULE_DEPS_${module})
    target_link_libraries(${target} PUBLIC beamtrace_${dep})
  endforeach()
  target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:beamtrace_warnings>)
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${module})
endfunction()

# Adds src/accel/embree_*.cpp to the accel module, with Embree as a public dependency.
function(beamtrace_add_embree)
  file(GLOB sources CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/src/accel/embree_*.cpp")
  target_sources(beamtrace_accel PRIVATE ${sources})
  # Embree's headers are not ours: include them as system headers (no -Werror on them).
  get_target_property(includes embree INTERFACE_INCLUDE_DIRECTORIES)
  foreach(dir IN LISTS includes)
    target_include_directories(beamtrace_accel SYSTEM PUBLIC $<BUILD_INTERFACE:${dir}>)
  endforeach()
  target_link_libraries(beamtrace_accel PUBLIC embree)
  target_compile_definitions(beamtrace_accel PUBLIC BEAMTRACE_HAVE_EMBREE=1)
endfunction()

include(GNUInstallDirs)
beamtrace_read_modules("${PROJECT_SOURCE_DIR}/cmake/modules.txt")
foreach(module IN LISTS BEAMTRACE_MODULES)
  beamtrace_add_module(${module})
endforeach()
# The BVH's packets must round every product as the scalar test does (no FMA contraction).
set_source_files_properties("${PROJECT_SOURCE_DIR}/src/accel/packet_trace.cpp" PROPERTIES
  COMPILE_OPTIONS "-ffp-contract=off" COMPILE_DEFINITIONS BEAMTRACE_FP_CONTRACT_OFF)

# The physics of every sub-ray: without errno, sqrt is one instruction and the loops over
# sub-rays vectorise (the results are the same: errno is all that -fno-math-errno drops).
set_source_files_properties("${PROJECT_SOURCE_DIR}/src/physics/pulse.cpp"
  "${PROJECT_SOURCE_DIR}/src/physics/waveform.cpp" PROPERTIES COMPILE_OPTIONS "-fno-math-errno")
# Our exp: every path (scalar, SSE2, AVX2, AVX-512) rounds each product and sum alone, so all
# give the same bits (src/physics/detail/fast_exp.hpp).
set_source_files_properties("${PROJECT_SOURCE_DIR}/src/physics/fast_exp.cpp" PROPERTIES
  COMPILE_OPTIONS "-ffp-contract=off" COMPILE_DEFINITIONS BEAMTRACE_FP_CONTRACT_OFF)

# AVX2 lanes that must give the scalar path's bits (the preview's pixels, the line scanner's
# angles, the spinning scanner's beams, the legs' positions, the sub-rays' directions, the
# survey's rays): each product and sum rounded alone, also where a build enables FMA everywhere.
set_source_files_properties("${PROJECT_SOURCE_DIR}/src/io/sinks/preview_shading.cpp"
  "${PROJECT_SOURCE_DIR}/src/io/sinks/preview_cells.cpp"
  "${PROJECT_SOURCE_DIR}/src/physics/beam_divergence.cpp"
  "${PROJECT_SOURCE_DIR}/src/pipeline/survey_rays.cpp"
  "${PROJECT_SOURCE_DIR}/src/sensor/line_angles.cpp"
  "${PROJECT_SOURCE_DIR}/src/sensor/rotating_lanes.cpp"
  "${PROJECT_SOURCE_DIR}/src/sensor/rotating_scanner.cpp"
  "${PROJECT_SOURCE_DIR}/src/sensor/trajectory.cpp" PROPERTIES
  COMPILE_OPTIONS "-ffp-contract=off" COMPILE_DEFINITIONS BEAMTRACE_FP_CONTRACT_OFF)

# Third-party libraries, each on the module that uses it.
target_link_libraries(beamtrace_core PUBLIC Threads::Threads)
target_compile_definitions(beamtrace_core PUBLIC BEAMTRACE_VERSION="${PROJECT_VERSION}")
target_link_libraries(beamtrace_text PUBLIC yaml-cpp)  # text/yaml_checker.hpp includes yaml-cpp
target_link_libraries(beamtrace_scene PRIVATE TIFF::TIFF nlohmann_json::nlohmann_json)
target_link_libraries(beamtrace_io PRIVATE PNG::PNG nlohmann_json::nlohmann_json)
if(BEAMTRACE_WITH_EMBREE)
  beamtrace_add_embree()
  message(STATUS "beamtrace: Embree ${embree_VERSION} backend enabled")
else()
  message(STATUS "beamtrace: Embree backend disabled")
endif()

# Everything, for the CLI, the tests and C++ users (beamtrace::beamtrace).
add_library(beamtrace_lib INTERFACE)
add_library(beamtrace::beamtrace ALIAS beamtrace_lib)
foreach(module IN LISTS BEAMTRACE_MODULES)
  target_link_libraries(beamtrace_lib INTERFACE beamtrace_${module})
endforeach()
set_target_properties(beamtrace_lib PROPERTIES EXPORT_NAME beamtrace)
