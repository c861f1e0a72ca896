"""read_las: LAS and LAZ files to a structured array and a header dict."""

import re
import subprocess

import numpy as np

import beamtrace

FIELDS = ["x", "y", "z", "intensity", "return_number", "number_of_returns", "classification",
          "gps_time", "scan_angle", "point_source_id", "red", "green", "blue", "user_data"]


def test_las_and_laz_twins_read_the_same(shared_data):
    las_points, las_header = beamtrace.read_las(shared_data / "las" / "las" / "autzen_trim.las")
    laz_points, laz_header = beamtrace.read_las(str(shared_data / "las" / "laz" / "autzen_trim.laz"))
    assert list(las_points.dtype.names) == FIELDS
    assert las_points.dtype["x"] == np.float64 and las_points.dtype["intensity"] == np.uint16
    assert las_points.dtype["classification"] == np.uint8 and las_points.dtype["scan_angle"] == np.float32
    assert len(las_points) == las_header["point_count"] > 1000
    assert not las_header["compressed"] and laz_header["compressed"]
    np.testing.assert_array_equal(las_points, laz_points)
    for key in ("version", "point_format", "point_count", "scale", "offset", "min", "max"):
        assert las_header[key] == laz_header[key], key
    # the points lie within the header's bounds
    for axis, name in enumerate("xyz"):
        assert las_header["min"][axis] <= las_points[name].min()
        assert las_points[name].max() <= las_header["max"][axis]


def parse_info(text):
    """The point count and the first point of `beamtrace info FILE --points 1`."""
    count = int(re.search(r"^point count: +(\d+)$", text, re.M).group(1))
    m = re.search(
        r"#0: xyz (\S+) (\S+) (\S+), intensity (\d+), return (\d+) of (\d+), class (\d+), "
        r"scan angle (\S+) deg, source (\d+), gps time (\S+), rgb (\d+) (\d+) (\d+)", text)
    assert m, text
    return count, [float(v) for v in m.groups()]


def test_first_point_matches_the_cli(shared_data, cli):
    path = shared_data / "las" / "las" / "autzen_trim.las"
    points, header = beamtrace.read_las(path)
    out = subprocess.run([str(cli), "info", str(path), "--points", "1"], check=True,
                         capture_output=True, text=True).stdout
    count, values = parse_info(out)
    assert header["point_count"] == count == len(points)
    p = points[0]
    # the CLI prints xyz with the scale's 2 decimals (0.01 m)
    np.testing.assert_allclose([p["x"], p["y"], p["z"]], values[:3], rtol=0, atol=1e-6)
    assert [p["intensity"], p["return_number"], p["number_of_returns"], p["classification"]] == values[3:7]
    assert p["scan_angle"] == values[7] and p["point_source_id"] == values[8]
    np.testing.assert_allclose(p["gps_time"], values[9], rtol=1e-15)
    assert [p["red"], p["green"], p["blue"]] == values[10:]
    assert header["version"] == "1.2" and header["point_format"] == 3
    assert header["scale"] == (0.01, 0.01, 0.01)
