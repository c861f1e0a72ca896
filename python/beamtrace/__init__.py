"""beamtrace: ray tracing, surveys, renders and LAS/LAZ reading on NumPy arrays (docs/python.md).

    import numpy as np, beamtrace
    scene = beamtrace.Scene.load("examples/scenes/sphere_targets.yaml")
    hits = scene.trace(np.zeros((1, 3)) + [0, 0, 1.6], [[1.0, 0.0, 0.0]])
    points, header = beamtrace.read_las("cloud.laz")
    points = beamtrace.run_survey("examples/surveys/tripod_panorama.yaml", seed=1)
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
    __version__,
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
    "__version__",
    "read_las",
    "render",
    "view",
    "run_survey",
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
        # JSON is YAML: the survey file's parser checks the dict, with the same messages.
        text = json.dumps(survey, indent=1, default=_json_value)
        return _run_survey_text(text, **options)
    return _run_survey_file(os.fspath(survey), **options)
