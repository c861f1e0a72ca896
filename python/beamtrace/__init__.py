"""beamtrace: ray tracing of scenes and LAS/LAZ reading on NumPy arrays (docs/python.md).

    import numpy as np, beamtrace
    scene = beamtrace.Scene.load("examples/scenes/sphere_targets.yaml")
    hits = scene.trace(np.zeros((1, 3)) + [0, 0, 1.6], [[1.0, 0.0, 0.0]])
    points, header = beamtrace.read_las("cloud.laz")
"""

from ._beamtrace import (
    ConfigError,
    Error,
    Hits,
    InputError,
    OutputError,
    Scene,
    __version__,
    read_las,
)

__all__ = [
    "ConfigError",
    "Error",
    "Hits",
    "InputError",
    "OutputError",
    "Scene",
    "__version__",
    "read_las",
]
