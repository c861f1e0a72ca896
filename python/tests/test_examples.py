"""The Python examples (examples/python/) run, with small counts so that the suite stays fast."""

import importlib.util
import os
import subprocess
import sys

import numpy as np

from conftest import REPO

EXAMPLES = REPO / "examples" / "python"


def run_example(name, *args, cwd):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    return subprocess.run([sys.executable, str(EXAMPLES / name), *args], cwd=cwd, env=env,
                          check=True, capture_output=True, text=True).stdout


def load_example(name):
    spec = importlib.util.spec_from_file_location(name.removesuffix(".py"), EXAMPLES / name)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_birds_eye_grid():
    birds_eye = load_example("vlp16_birds_eye.py").birds_eye
    points = np.zeros(3, dtype=[("x", "f8"), ("y", "f8"), ("z", "f8")])
    points["x"], points["y"], points["z"] = [0.0, 0.05, 1.0], [1.0, 1.0, 0.0], [2.0, 3.0, 5.0]
    image, extent = birds_eye(points, cell_m=0.5)
    assert image.shape == (3, 3)
    assert image[0, 0] == 3.0  # the highest of the two points at the top left (north-west)
    assert image[2, 2] == 5.0
    assert np.isnan(image).sum() == 7
    assert extent == (0.0, 1.5, -0.5, 1.0)


def test_vlp16_drive_example(tmp_path):
    out = run_example("vlp16_birds_eye.py", "--duration-s", "0.2", "--out", "drive.png",
                      cwd=tmp_path)
    count = int(out.split()[0])
    assert count > 10000  # 0.2 s of a VLP-16: 57 600 pulses
    if importlib.util.find_spec("matplotlib") is None:
        assert "matplotlib is not installed" in out
        assert not (tmp_path / "drive.png").exists()
    else:
        assert (tmp_path / "drive.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_training_poses_example(tmp_path):
    out = run_example("training_poses.py", "--count", "3", "--out", "data", "--threads", "2",
                      cwd=tmp_path)
    assert out.startswith("3 poses")
    poses = np.load(tmp_path / "data" / "poses.npy")
    assert poses.shape == (3, 4)
    scans = [np.load(tmp_path / "data" / f"scan_{i:04d}.npy") for i in range(3)]
    for pose, scan in zip(poses, scans):
        assert len(scan) > 5000
        xyz = np.column_stack([scan["x"], scan["y"], scan["z"]])
        # every point within the VLP-16's 100 m of its pose, on the LAS grid (1 mm)
        assert np.linalg.norm(xyz - pose[:3], axis=1).max() <= 100.01
    assert len({len(s) for s in scans}) == 3  # three different poses
    # the same count again gives the same files
    run_example("training_poses.py", "--count", "3", "--out", "again", "--threads", "1",
                cwd=tmp_path)
    np.testing.assert_array_equal(np.load(tmp_path / "again" / "scan_0002.npy"), scans[2])
