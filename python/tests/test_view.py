"""beamtrace.view: `beamtrace view FILES --output v.png` in memory, the same pixels as the CLI's
PNG."""

import subprocess
import warnings

import numpy as np
import pytest

import beamtrace
from test_render import read_png_rgb8


@pytest.fixture(scope="module")
def autzen(shared_data):
    path = shared_data / "las" / "las" / "autzen_trim.las"
    if not path.is_file():
        pytest.skip(f"no {path}")
    return path


def cli_view(cli, tmp_path, files, *options):
    out = tmp_path / "cli.png"
    subprocess.run([str(cli), "view", *map(str, files), *options, "--quiet", "--output",
                    str(out)], check=True)
    return read_png_rgb8(out)


def test_view_overview_equals_the_cli_png(cli, autzen, tmp_path):
    expected = cli_view(cli, tmp_path, [autzen], "--size", "96x64")
    image = beamtrace.view(autzen, size=(96, 64))
    assert image.shape == (64, 96, 3) and image.dtype == np.uint8
    np.testing.assert_array_equal(image, expected)
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 100  # coloured by height, shaded


def test_view_camera_and_settings_equal_the_cli_png(cli, autzen, tmp_path):
    _, header = beamtrace.read_las(autzen)
    (x0, y0, _), (x1, y1, z1) = header["min"], header["max"]
    camera = ((x0 + x1) / 2, y0 - 50.0, z1 + 150.0, -90.0, -35.0)  # south of it, facing north
    options = ["--camera", ",".join(f"{c:.17g}" for c in camera), "--size", "80x48",
               "--fov", "75", "--color", "intensity", "--eye-dome", "1", "--fog", "800",
               "--fill-gaps", "0", "--cell-size", "2", "--levels", "6", "--section-cells", "16",
               "--sections", "3x3", "--memory-budget", "64MB",
               "--threads", "1"]
    expected = cli_view(cli, tmp_path, [autzen], *options)
    image = beamtrace.view([str(autzen)], camera=camera, size=(80, 48), fov_deg=75,
                           color="intensity", eye_dome=1.0, fog=800.0, fill_gaps=0,
                           cell_size=2.0, levels=6, section_cells=16, sections=3,
                           memory_budget="64MB", threads=1)
    np.testing.assert_array_equal(image, expected)
    sky = np.all(image == [150, 180, 220], axis=-1)
    assert 0 < sky.sum() < sky.size  # the horizon is in the frame
    # The settings matter: the defaults from the same camera give another image.
    assert not np.array_equal(image, beamtrace.view(autzen, camera=camera, size=(80, 48)))
    same = beamtrace.view(autzen, camera=",".join(map(str, camera)), size=(80, 48), fov_deg=75,
                          color="intensity", eye_dome=1.0, fog=800.0, fill_gaps=0, cell_size=2.0,
                          levels=6, section_cells=16, sections=3, memory_budget=64_000_000,
                          threads=2)
    np.testing.assert_array_equal(same, image)


def test_view_errors(autzen, tmp_path):
    with pytest.raises(beamtrace.ConfigError, match="--camera"):
        beamtrace.view(autzen, camera=(1, 2, 3))
    with pytest.raises(beamtrace.ConfigError, match="colour|color|rainbow"):
        beamtrace.view(autzen, color="rainbow")
    with pytest.raises(beamtrace.ConfigError, match="eye-dome"):
        beamtrace.view(autzen, eye_dome=-1.0)
    with pytest.raises(beamtrace.ConfigError, match="lots"):
        beamtrace.view(autzen, memory_budget="lots")
    with pytest.raises(beamtrace.InputError, match="nothing.las"):
        beamtrace.view(tmp_path / "nothing.las")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        beamtrace.view(autzen, size=(8, 8))  # no warning for a good file
