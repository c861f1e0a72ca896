// The parts of the extension module _beamtrace (one file per area), joined by module.cpp.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace beamtrace::python {

namespace py = pybind11;

/// beamtrace.Error and its subclasses, and the translation of the library's exceptions to them.
void bind_errors(py::module_& m);
/// beamtrace.Scene (load, from_arrays, trace, occluded) and beamtrace.Hits.
void bind_scene(py::module_& m);
/// beamtrace.read_las.
void bind_las(py::module_& m);
/// beamtrace.render.
void bind_render(py::module_& m);
/// beamtrace.view.
void bind_view(py::module_& m);
/// beamtrace.run_survey's C++ part (_run_survey_file, _run_survey_text).
void bind_survey(py::module_& m);
/// beamtrace.iter_survey's C++ part (SurveyBlocks, _iter_survey_file, _iter_survey_text); called
/// by bind_survey.
void bind_survey_blocks(py::module_& m);

}  // namespace beamtrace::python
