"""Runs repeated in one process do not grow memory (issue 19, item 4): 200 surveys and traces in a
loop grow the peak resident set by less than 5 MB after the first few."""

import numpy as np

import beamtrace


def peak_rss_bytes():
    """VmHWM of /proc/self/status: the most resident memory this process has had."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) * 1024
    raise AssertionError("no VmHWM in /proc/self/status")


# A small survey of the sphere targets' scene: about 3 800 points (270 KB of arrays) a run, so
# that a run leaking its points, its scene or its backend would exceed the bound many times over.
def small_survey(examples):
    return {
        "scene": str(examples / "scenes" / "sphere_targets.yaml"),
        "scanner": {"type": "scan", "width": 200, "height": 40, "hfov_deg": 360, "vfov_deg": 60,
                    "pulse_rate_hz": 100000, "range_max_m": 100},
        "platform": {"type": "static", "position_m": [0, 0, 1.5]},
        "output": {"trajectory_rate_hz": 0},
    }


def one_round(survey, scene, origins, directions):
    points = beamtrace.run_survey(survey, threads=2)
    hits = scene.trace(origins, directions, threads=2)
    return len(points), int(np.isfinite(hits.range_m).sum())


def test_200_surveys_and_traces_do_not_grow_memory(examples):
    survey = small_survey(examples)
    scene = beamtrace.Scene.load(examples / "scenes" / "sphere_targets.yaml")
    rng = np.random.default_rng(1)
    origins = np.tile([0.0, 0.0, 1.5], (20000, 1))
    directions = rng.normal(size=(20000, 3))
    first = None
    for _ in range(5):  # warm up: the allocator's pools, NumPy's caches
        first = one_round(survey, scene, origins, directions)
    assert first[0] > 3000 and first[1] > 5000
    before = peak_rss_bytes()
    for _ in range(200):
        assert one_round(survey, scene, origins, directions) == first
    grown = peak_rss_bytes() - before
    assert grown < 5 * 1024 * 1024, f"peak RSS grew by {grown / 1e6:.1f} MB over 200 runs"
