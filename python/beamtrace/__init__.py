"""beamtrace: ray tracing, surveys, renders and LAS/LAZ reading on NumPy arrays (docs/python.md).

    import numpy as np, beamtrace
    scene = beamtrace.Scene.load("examples/scenes/sphere_targets.yaml")
    hits = scene.trace(np.zeros((1, 3)) + [0, 0, 1.6], [[1.0, 0.0, 0.0]])
    points, header = beamtrace.read_las("cloud.laz")
    points = beamtrace.run_survey("examples/surveys/tripod_panorama.yaml", seed=1)
    with beamtrace.iter_survey("examples/surveys/airborne_srtm_1e8.yaml") as blocks:
        for block in blocks: ...  # structured arrays of 65536 points, bounded memory
    image = beamtrace.render("demo", size=(320, 240))  # (240, 320, 3) uint8
    image = beamtrace.view("cloud.las", size=(640, 360))  # (360, 640, 3) uint8
"""

import json
import os
from collections.abc import Mapping

from ._beamtrace import (
    AllHits,
    ConfigError,
    Error,
    Hits,
    InputError,
    OutputError,
    Scene,
    SurveyBlocks,
    __version__,
    _iter_survey_file,
    _iter_survey_text,
    _run_survey_file,
    _run_survey_text,
    read_las,
    render,
    view,
)

__all__ = [
    "AllHits",
    "ConfigError",
    "Error",
    "Hits",
    "InputError",
    "OutputError",
    "Scene",
    "SurveyBlocks",
    "__version__",
    "read_las",
    "render",
    "view",
    "run_survey",
    "iter_survey",
]


def _json_value(value):
    """NumPy arrays and scalars in a survey dict as lists and numbers."""
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"survey dict: {type(value).__name__} {value!r} is not a YAML value")


def run_survey(survey, seed=1, threads=0, backend=None, max_pulses=0, progress=None,
               output_dir=None):
    """Runs a survey in memory; returns its points as a NumPy structured array, one row per point
    in the order of the points.las that `beamtrace survey` writes (docs/python.md).

    survey: a survey file (str or path-like), or a dict with the keys of a survey file (checked
    by the same code; relative paths in it resolve against the current directory).
    seed, threads, backend: as `beamtrace survey --seed/--threads/--backend` (backend None: the
    CLI's default). max_pulses: only the first pulses (0: all). progress: None or a function
    called with (done, total) pulses on the calling thread. output_dir: None (no files), or a
    folder that also gets the files the CLI writes. Ctrl-C stops the run (KeyboardInterrupt).
    """
    options = dict(seed=seed, threads=threads, backend=backend, max_pulses=max_pulses,
                   progress=progress, output_dir=output_dir)
    if isinstance(survey, Mapping):
        return _run_survey_text(_survey_text(survey), **options)
    return _run_survey_file(os.fspath(survey), **options)


def iter_survey(survey, seed=1, threads=0, backend=None, max_pulses=0, block_points=65536,
                progress=None):
    """Runs a survey block by block, for surveys larger than memory: returns an iterator of
    NumPy structured arrays of `block_points` rows each (the last one fewer), whose
    concatenation is run_survey's array for the same survey and seed (docs/python.md).

    The arguments are run_survey's (no output_dir). The survey runs on a thread of its own, at
    most a few blocks ahead of the caller, so memory stays bounded whatever its size. The
    iterator is a context manager; closing it (close(), the end of a `with` block, or its
    deletion, e.g. `break` out of a for loop) stops the survey and waits for its thread. An
    error of the survey, progress's exception and Ctrl-C are raised by the next().
    """
    options = dict(seed=seed, threads=threads, backend=backend, max_pulses=max_pulses,
                   block_points=block_points, progress=progress)
    if isinstance(survey, Mapping):
        return _iter_survey_text(_survey_text(survey), **options)
    return _iter_survey_file(os.fspath(survey), **options)


def _survey_text(survey):
    """A survey dict as the text of a survey file: JSON is YAML, so the survey file's parser
    checks the dict, with the same messages."""
    return json.dumps(survey, indent=1, default=_json_value)
