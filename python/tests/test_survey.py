"""run_survey: surveys from a file or a dict, in memory, equal to the CLI's points.las."""

import _thread
import json
import subprocess
import threading

import numpy as np
import pytest

import beamtrace

# The fields that points.las stores (read_las's names); run_survey's arrays hold them too.
LAS_FIELDS = ["x", "y", "z", "intensity", "return_number", "number_of_returns", "classification",
              "gps_time", "scan_angle", "point_source_id", "user_data"]


def tripod(width=360, height=100):
    """A reduced tripod_panorama.yaml (examples/surveys) as a dict."""
    return {
        "scene": "demo",
        "scanner": {"type": "scan", "width": width, "height": height, "hfov_deg": 360,
                    "vfov_deg": 90, "pulse_rate_hz": 1000000, "range_max_m": 300},
        "platform": {"type": "static", "position_m": [20, -25, 1.944]},
        "output": {"trajectory_rate_hz": 0},
    }


def airborne_physics(duration_s=0.1):
    """A shorter airborne_line_physics.yaml: sub-rays, range noise, up to 5 returns a pulse."""
    return {
        "scene": "demo",
        "scanner": {"type": "line", "pulse_rate_hz": 100000, "scan_rate_hz": 80,
                    "scan_angle_max_deg": 25, "waveform": "triangle", "duration_s": duration_s},
        "platform": {"type": "legs", "speed_mps": 50,
                     "waypoints_m": [[-10, 0, 150], [90, 0, 150]]},
        "mount": {"boresight_deg": [0, -90, 0]},
        "physics": {"beam": {"divergence_mrad": 2, "rings": 2}, "noise": {"range_sigma_m": 0.02},
                    "returns": {"mode": "all", "max": 5}},
        "output": {"point_format": 6, "trajectory_rate_hz": 10},
    }


def long_line():
    """An airborne line scanner over 1000 s: 10^8 pulses, far more than a test waits for."""
    return {
        "scene": "demo",
        "scanner": {"type": "line", "pulse_rate_hz": 100000, "scan_rate_hz": 80,
                    "scan_angle_max_deg": 25, "duration_s": 1000},
        "platform": {"type": "legs", "speed_mps": 0.1, "waypoints_m": [[-50, 0, 150], [50, 0, 150]]},
        "mount": {"boresight_deg": [0, -90, 0]},
    }


def cli_points(cli, survey_file, out, seed):
    subprocess.run([str(cli), "survey", str(survey_file), "--output", str(out), "--seed", str(seed),
                    "--threads", "2", "--quiet"], check=True)
    points, _ = beamtrace.read_las(out / "points.las")
    return points


def assert_same_las_points(a, b):
    assert len(a) == len(b)
    for name in LAS_FIELDS:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)


@pytest.mark.parametrize("make", [tripod, airborne_physics])
def test_arrays_equal_the_cli_las(cli, tmp_path, make):
    survey = make()
    survey_file = tmp_path / "survey.yaml"  # JSON is YAML: the CLI reads the dict's text
    survey_file.write_text(json.dumps(survey))
    las = cli_points(cli, survey_file, tmp_path / "out", seed=7)
    assert len(las) > 5000
    from_dict = beamtrace.run_survey(survey, seed=7, threads=2)
    from_file = beamtrace.run_survey(survey_file, seed=7, threads=2)
    assert_same_las_points(from_dict, las)
    assert_same_las_points(from_file, las)
    np.testing.assert_array_equal(from_dict, from_file)
    # beyond the LAS fields: the channel (user_data is its low byte), the pulse, the range
    np.testing.assert_array_equal(from_dict["user_data"], from_dict["channel"] & 0xFF)
    assert np.all(np.diff(from_dict["pulse"].astype(np.int64)) >= 0)  # pulse order
    assert np.all(from_dict["range_m"] > 0)


def test_tripod_ranges_are_distances_from_the_scanner():
    points = beamtrace.run_survey(tripod(90, 30), threads=1)
    assert len(points) > 500
    xyz = np.column_stack([points["x"], points["y"], points["z"]])
    distance = np.linalg.norm(xyz - [20, -25, 1.944], axis=1)
    # x, y, z are rounded to the LAS file's 1 mm grid: within half a step per axis
    np.testing.assert_allclose(points["range_m"], distance, atol=0.0009, rtol=1e-6)
    assert set(np.unique(points["return_number"])) == {1}  # no physics: one return a pulse


def test_output_dir_writes_the_cli_files_too(tmp_path):
    points = beamtrace.run_survey(tripod(90, 30), output_dir=tmp_path / "out")
    las, header = beamtrace.read_las(tmp_path / "out" / "points.las")
    assert header["point_count"] == len(points) > 500
    assert_same_las_points(points, las)


def test_same_seed_same_arrays_any_thread_count():
    survey = airborne_physics(0.05)
    a = beamtrace.run_survey(survey, seed=3, threads=1)
    b = beamtrace.run_survey(survey, seed=3, threads=2)
    c = beamtrace.run_survey(survey, seed=3, threads=2)
    assert len(a) > 2000
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(b, c)
    other = beamtrace.run_survey(survey, seed=4, threads=2)
    assert len(other) != len(a) or not np.array_equal(other["z"], a["z"])  # the noise moved


def test_max_pulses_keeps_the_first_pulses():
    whole = beamtrace.run_survey(tripod(90, 30))
    first = beamtrace.run_survey(tripod(90, 30), max_pulses=1000)
    assert 0 < len(first) < len(whole)
    assert first["pulse"].max() < 1000
    np.testing.assert_array_equal(first, whole[: len(first)])


def test_a_bad_key_raises_config_error_naming_it():
    survey = tripod()
    survey["scanner"]["widht"] = 10
    with pytest.raises(beamtrace.ConfigError, match=r"<dict>:\d+: scanner.widht: unknown key"):
        beamtrace.run_survey(survey)
    survey = tripod()
    survey["platfrom"] = survey.pop("platform")
    with pytest.raises(ValueError, match="platfrom"):
        beamtrace.run_survey(survey)
    survey = tripod()
    survey["scanner"]["width"] = -3
    with pytest.raises(beamtrace.ConfigError, match="width"):
        beamtrace.run_survey(survey)


def test_dict_paths_resolve_against_the_current_directory(examples, monkeypatch):
    survey = tripod(90, 30)
    survey["scene"] = "scenes/sphere_targets.yaml"
    survey["platform"]["position_m"] = [0, 0, 1.5]
    monkeypatch.chdir(examples)
    points = beamtrace.run_survey(survey)
    assert set(np.unique(points["classification"])) <= {2, 64}
    assert len(points) > 500
    monkeypatch.chdir(examples / "surveys")  # no scenes/ here
    with pytest.raises(beamtrace.Error, match="sphere_targets.yaml"):
        beamtrace.run_survey(survey)


def test_numpy_values_in_the_dict():
    survey = tripod(90, 30)
    survey["platform"]["position_m"] = np.array([20.0, -25.0, 1.944])
    survey["scanner"]["width"] = np.int64(90)
    np.testing.assert_array_equal(beamtrace.run_survey(survey), beamtrace.run_survey(tripod(90, 30)))


def test_progress_on_the_calling_thread():
    calls = []
    caller = threading.get_ident()

    def progress(done, total):
        assert threading.get_ident() == caller
        calls.append((done, total))

    beamtrace.run_survey(tripod(360, 100), progress=progress, threads=2)
    total = 360 * 100
    assert calls[0] == (0, total) and calls[-1] == (total, total)
    assert all(t == total for _, t in calls)
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)


def test_an_exception_in_progress_stops_the_run(tmp_path):
    def progress(done, total):
        raise RuntimeError(f"stop at {done} of {total}")

    with pytest.raises(RuntimeError, match="stop at 0 of 100000000"):
        beamtrace.run_survey(long_line(), progress=progress, output_dir=tmp_path / "out")
    assert not (tmp_path / "out").exists()  # cancelled before anything was committed


def test_ctrl_c_stops_the_run(tmp_path):
    # SIGINT (Ctrl-C) 0.2 s into a survey of 10^8 pulses, with no progress callback
    timer = threading.Timer(0.2, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            beamtrace.run_survey(long_line(), output_dir=tmp_path / "out")
    finally:
        timer.cancel()
    assert not (tmp_path / "out").exists()
    # the module still works afterwards
    assert len(beamtrace.run_survey(tripod(90, 30))) > 500


def test_backends_give_the_same_points():
    survey = tripod(90, 30)
    bvh = beamtrace.run_survey(survey, backend="bvh")
    np.testing.assert_array_equal(beamtrace.run_survey(survey, backend="kdtree"), bvh)
    with pytest.raises(beamtrace.ConfigError, match="octree"):
        beamtrace.run_survey(survey, backend="octree")


def test_weather_column_marks_the_mediums_points(cli, examples, tmp_path):
    """With a `weather:` block the arrays gain `weather` (0 the scene, 2 rain): its points are
    those the CLI's points.las classes 7 (the medium's class; no part of the demo has it) and
    that its summary counts; the blocks of iter_survey carry it too. Without weather: no column."""
    survey = examples / "surveys" / "weather_rain.yaml"
    points = beamtrace.run_survey(str(survey), seed=3, threads=2)
    assert points.dtype.names[-1] == "weather"
    assert points.dtype["weather"] == np.uint8
    assert set(np.unique(points["weather"])) == {0, 2}
    summary = subprocess.run([str(cli), "survey", str(survey), "--output", str(tmp_path / "rain"),
                              "--seed", "3", "--threads", "2"], check=True,
                             capture_output=True, text=True).stdout
    counted = [line for line in summary.splitlines() if line.startswith("weather: ")]
    assert counted == [f"weather: {np.count_nonzero(points['weather'])} of the points are the "
                       "medium's (fog, rain or snow)"]
    las, _ = beamtrace.read_las(tmp_path / "rain" / "points.las")
    assert_same_las_points(points, las)
    np.testing.assert_array_equal(points["weather"] != 0, las["classification"] == 7)
    blocks = list(beamtrace.iter_survey(str(survey), seed=3, threads=2, block_points=10000))
    assert len(blocks) > 1
    np.testing.assert_array_equal(np.concatenate(blocks), points)
    clear = beamtrace.run_survey(str(examples / "surveys" / "weather_clear.yaml"), max_pulses=100)
    assert "weather" not in clear.dtype.names
