"""Bad arrays raise ValueError naming the argument; library errors keep their messages."""

import re

import numpy as np
import pytest

import beamtrace

GOOD = np.array([[0.0, 0.0, 1.0]] * 5)


@pytest.fixture(scope="module")
def scene():
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=float)
    return beamtrace.Scene.from_arrays(vertices, [[0, 1, 2]])


def nan_at(row, array=GOOD):
    bad = array.copy()
    bad[row, 1] = np.nan
    return bad


@pytest.mark.parametrize(
    "origins, directions, message",
    [
        (GOOD, np.zeros((5, 2)) + 1, "directions: shape (5, 2), expected (N, 3)"),
        (np.zeros(3), GOOD, "origins: shape (3,), expected (N, 3)"),
        (np.zeros((5, 3, 1)), GOOD, "origins: shape (5, 3, 1), expected (N, 3)"),
        (GOOD, GOOD[:4], "directions: 4 rows, but origins has 5"),
        (np.array([["a", "b", "c"]]), GOOD[:1], "origins: dtype <U1, expected float32 or float64"),
        (GOOD, GOOD.astype(complex), "directions: dtype complex128, expected float32 or float64"),
        (GOOD, GOOD.astype(object), "directions: dtype object, expected float32 or float64"),
        (nan_at(2), GOOD, "origins: row 2 is not finite"),
        (GOOD, nan_at(3), "directions: row 3 is not finite"),
        (GOOD, np.where(np.arange(5)[:, None] == 4, np.inf, GOOD), "directions: row 4 is not finite"),
        (GOOD, np.where(np.arange(5)[:, None] == 1, 0.0, GOOD), "directions: row 1 has zero length"),
    ],
)
def test_bad_rays_name_the_argument(scene, origins, directions, message):
    for query in (scene.trace, scene.occluded):
        with pytest.raises(ValueError, match="^" + re.escape(message) + "$"):
            query(origins, directions)


def test_bad_max_range(scene):
    with pytest.raises(ValueError, match="^max_range_m: "):
        scene.trace(GOOD, GOOD, max_range_m=0.0)


def test_unknown_backend_is_a_config_error(scene):
    with pytest.raises(beamtrace.ConfigError, match="nope") as info:
        scene.trace(GOOD, GOOD, backend="nope")
    assert isinstance(info.value, ValueError) and isinstance(info.value, beamtrace.Error)
    assert "bvh" in str(info.value)  # the message lists the choices


VERTS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=float)


@pytest.mark.parametrize(
    "vertices, faces, labels, message",
    [
        (VERTS[:, :2], [[0, 1, 2]], None, "vertices: shape (3, 2), expected (N, 3)"),
        (nan_at(1, VERTS), [[0, 1, 2]], None, "vertices: row 1 is not finite"),
        (VERTS, [[0.0, 1.0, 2.0]], None, "faces: dtype float64, expected an integer dtype"),
        (VERTS, [[0, 1]], None, "faces: shape (1, 2), expected (M, 3)"),
        (VERTS, np.zeros((0, 3), dtype=int), None, "faces: shape (0, 3), expected at least one face"),
        (VERTS, [[0, 1, 3]], None, "faces: row 0 has vertex index 3, expected 0 to 2"),
        (VERTS, [[0, -1, 2]], None, "faces: row 0 has vertex index -1, expected 0 to 2"),
        (VERTS, [[0, 1, 2]], [1, 2], "labels: shape (2,), expected (1,), one per face"),
        (VERTS, [[0, 1, 2]], [[1]], "labels: shape (1, 1), expected (M,)"),
        (VERTS, [[0, 1, 2]], [300], "labels: row 0 is 300, expected a class 0-255"),
        (VERTS, [[0, 1, 2]], [1.5], "labels: dtype float64, expected an integer dtype"),
    ],
)
def test_bad_mesh_arrays_name_the_argument(vertices, faces, labels, message):
    with pytest.raises(ValueError, match="^" + re.escape(message) + "$"):
        beamtrace.Scene.from_arrays(vertices, faces, labels=labels)


def test_missing_file_is_an_input_error_naming_it(tmp_path):
    missing = tmp_path / "nothing.obj"
    with pytest.raises(beamtrace.InputError, match=re.escape(str(missing))):
        beamtrace.Scene.load(missing)
    with pytest.raises(ValueError, match=re.escape(str(missing))):
        beamtrace.read_las(str(missing))


def test_bad_scene_file_keeps_the_key_message(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("parts:\n  - name: x\n    sphere: {center_m: [0, 0, 0], radius_m: -1}\n")
    with pytest.raises(beamtrace.Error, match="radius_m") as info:
        beamtrace.Scene.load(path)
    assert str(path) in str(info.value)


def test_bad_mesh_file_names_the_line(tmp_path):
    path = tmp_path / "bad.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(beamtrace.InputError, match=re.escape(f"{path}:4")):
        beamtrace.Scene.load(path)


def test_the_lowest_bad_row_is_named_whichever_thread_finds_it(scene):
    # Rows are checked in blocks on several threads: the message names the lowest bad row.
    origins = np.zeros((200_000, 3))
    directions = np.tile([0.0, 0.0, -1.0], (200_000, 1))
    for row in (180_000, 120_000, 70_000):
        directions[row] = 0.0
    origins[150_000, 0] = np.inf
    for threads in (1, 2, 4):
        with pytest.raises(ValueError, match="^directions: row 70000 has zero length$"):
            scene.trace(origins, directions, threads=threads)
    directions[70_000] = [0.0, 0.0, 1.0]
    origins[100_000, 2] = np.nan
    with pytest.raises(ValueError, match="^origins: row 100000 is not finite$"):
        scene.occluded(origins, directions, threads=4)
