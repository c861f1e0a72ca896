// The extension module _beamtrace, imported by the package beamtrace (python/beamtrace/).
#include "bindings.hpp"

#ifndef BEAMTRACE_VERSION
#define BEAMTRACE_VERSION "0"
#endif

PYBIND11_MODULE(_beamtrace, m) {
    namespace bp = beamtrace::python;
    m.doc() = "beamtrace: ray tracing, surveys, renders and LAS/LAZ reading on NumPy arrays";
    m.attr("__version__") = BEAMTRACE_VERSION;
    bp::bind_errors(m);
    bp::bind_scene(m);
    bp::bind_las(m);
    bp::bind_survey(m);
    bp::bind_render(m);
    bp::bind_view(m);
}
