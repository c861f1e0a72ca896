"""iter_survey: a survey block by block, equal to run_survey's array, in bounded memory; closing
the iterator early stops the run and joins its thread."""

import _thread
import os
import pathlib
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import beamtrace

from test_survey import airborne_physics, long_line, tripod


def survey_threads():
    """The threads of this process that a survey of iter_survey runs on (by thread ID): its own,
    named bt-iter-survey, and the pool threads it starts, which inherit the name. (So do the
    threads that Embree starts for itself and keeps: the tests of the run's life use bvh.)"""
    found = set()
    for task in os.listdir("/proc/self/task"):
        try:
            with open(f"/proc/self/task/{task}/comm") as f:
                if f.read().strip() == "bt-iter-survey":
                    found.add(task)
        except OSError:
            pass  # the thread ended meanwhile
    return found


def threads_left(before, timeout_s=5.0):
    """The survey threads that were not there `before` and still are, once none is or after
    timeout_s (a joined thread may take a moment to leave /proc)."""
    end = time.monotonic() + timeout_s
    while survey_threads() - before and time.monotonic() < end:
        time.sleep(0.01)
    return survey_threads() - before


@pytest.mark.parametrize("make, block_points, threads",
                         [(tripod, 1000, 2), (tripod, 7777, 1), (airborne_physics, 2500, 2)])
def test_blocks_concatenate_to_run_surveys_array(make, block_points, threads):
    survey = make()
    whole = beamtrace.run_survey(survey, seed=5, threads=2)
    blocks = list(beamtrace.iter_survey(survey, seed=5, threads=threads,
                                        block_points=block_points))
    assert len(whole) > 5000 and len(blocks) > 2
    assert all(len(b) == block_points for b in blocks[:-1])
    assert 0 < len(blocks[-1]) <= block_points
    assert all(b.dtype == whole.dtype for b in blocks)
    joined = np.concatenate(blocks)
    assert joined.tobytes() == whole.tobytes()  # byte for byte


def test_a_survey_file_and_max_pulses(examples):
    path = examples / "surveys" / "tripod_panorama.yaml"
    whole = beamtrace.run_survey(path, max_pulses=30000, threads=2)
    with beamtrace.iter_survey(pathlib.Path(path), max_pulses=30000, block_points=4096) as blocks:
        joined = np.concatenate(list(blocks))
    assert len(whole) > 10000
    assert joined.tobytes() == whole.tobytes()


def test_break_stops_the_run_and_joins_its_thread():
    before = survey_threads()
    start = time.monotonic()
    seen = 0
    # 10^8 pulses: far more than the test waits for
    for block in beamtrace.iter_survey(long_line(), backend="bvh", threads=2, block_points=1000):
        assert survey_threads() - before  # the survey's thread (and its pool) run
        seen += len(block)
        if seen >= 5000:
            break
    # the iterator went with the loop: the run was cancelled and its thread joined
    assert not threads_left(before)
    assert time.monotonic() - start < 10
    # a second iteration works, and gives the same first points
    again = beamtrace.iter_survey(long_line(), backend="bvh", threads=1, block_points=1000)
    first = [next(again) for _ in range(5)]
    again.close()
    again.close()  # idempotent
    assert not threads_left(before)
    with pytest.raises(StopIteration):
        next(again)
    whole = beamtrace.run_survey(long_line(), backend="bvh", max_pulses=20000, threads=2)
    assert np.concatenate(first).tobytes() == whole[:5000].tobytes()


def test_context_manager_and_deletion_close_the_run():
    before = survey_threads()
    with beamtrace.iter_survey(long_line(), backend="bvh", block_points=500) as blocks:
        assert len(next(blocks)) == 500
        assert survey_threads() - before
    assert not threads_left(before)
    with pytest.raises(StopIteration):
        next(blocks)
    blocks = beamtrace.iter_survey(long_line(), backend="bvh", block_points=500)
    next(blocks)
    del blocks  # garbage: the destructor cancels and joins
    assert not threads_left(before)
    # closed before the first block: nothing is waited for but the cancel
    beamtrace.iter_survey(long_line(), backend="bvh").close()
    assert not threads_left(before)


def test_errors_of_the_survey_come_from_next(tmp_path):
    # the scene file is read by the run, on its thread: its error comes from next()
    scene = tmp_path / "scene.yaml"
    scene.write_text("parts:\n  - mesh: nothere.obj\n")
    survey = tripod(90, 30)
    survey["scene"] = str(scene)
    before = survey_threads()
    blocks = beamtrace.iter_survey(survey, backend="bvh")
    with pytest.raises(beamtrace.ConfigError, match=r"scene.yaml:2: parts\[0\].mesh: file not found"):
        next(blocks)
    assert not threads_left(before)
    with pytest.raises(StopIteration):
        next(blocks)
    # settings that the survey file's parser rejects: at once, from iter_survey itself
    survey = tripod()
    survey["scanner"]["widht"] = 10
    with pytest.raises(beamtrace.ConfigError, match=r"<dict>:\d+: scanner.widht: unknown key"):
        beamtrace.iter_survey(survey)
    with pytest.raises(beamtrace.ConfigError, match="octree"):
        beamtrace.iter_survey(tripod(), backend="octree")
    with pytest.raises(ValueError, match="block_points: 0, expected a positive"):
        beamtrace.iter_survey(tripod(), block_points=0)
    with pytest.raises(ValueError, match="block_points: 1099511627777, expected"):
        beamtrace.iter_survey(tripod(), block_points=2**40 + 1)
    assert not threads_left(before)


def test_an_error_not_yet_raised_comes_from_close_or_goes_to_unraisablehook(tmp_path,
                                                                             monkeypatch):
    scene = tmp_path / "scene.yaml"
    scene.write_text("parts:\n  - mesh: nothere.obj\n")
    survey = tripod(90, 30)
    survey["scene"] = str(scene)
    blocks = beamtrace.iter_survey(survey, backend="bvh")
    time.sleep(0.5)  # the run fails meanwhile; no next() saw it
    with pytest.raises(beamtrace.ConfigError, match="nothere.obj"):
        blocks.close()
    blocks.close()  # raised once
    seen = []
    monkeypatch.setattr(sys, "unraisablehook", seen.append)
    blocks = beamtrace.iter_survey(survey, backend="bvh")
    time.sleep(0.5)
    del blocks
    assert len(seen) == 1 and "nothere.obj" in str(seen[0].exc_value)


def test_progress_on_the_calling_thread():
    calls = []
    caller = threading.get_ident()

    def progress(done, total):
        assert threading.get_ident() == caller
        calls.append((done, total))

    count = sum(len(b) for b in beamtrace.iter_survey(tripod(360, 100), progress=progress,
                                                      block_points=3000, threads=2))
    assert count == len(beamtrace.run_survey(tripod(360, 100)))
    total = 360 * 100
    assert calls[0] == (0, total) and calls[-1] == (total, total)
    assert all(t == total for _, t in calls)
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)


def test_an_exception_in_progress_is_raised_by_next_and_stops_the_run():
    def progress(done, total):
        if done > 0:
            raise RuntimeError(f"stop at {done} of {total}")

    before = survey_threads()
    blocks = beamtrace.iter_survey(long_line(), backend="bvh", progress=progress, block_points=1000)
    with pytest.raises(RuntimeError, match="of 100000000"):
        for _ in blocks:
            pass
    assert not threads_left(before)
    with pytest.raises(StopIteration):
        next(blocks)


def test_ctrl_c_stops_the_run():
    before = survey_threads()
    for block_points, pause_s in ((1000, 0.01), (10**8, 0)):
        # a slow consumer (the run waits for it), then one waiting in next() for a block that
        # would take minutes (10^8 pulses): next() checks for Ctrl-C while it waits
        timer = threading.Timer(0.3, _thread.interrupt_main)
        start = time.monotonic()
        timer.start()
        try:
            with pytest.raises(KeyboardInterrupt):
                for _ in beamtrace.iter_survey(long_line(), backend="bvh",
                                               block_points=block_points):
                    time.sleep(pause_s)
        finally:
            timer.cancel()
        assert time.monotonic() - start < 10
        assert not threads_left(before)

# Run in a fresh interpreter, so that the peak resident set (VmHWM) is this survey's alone and not
# that of an earlier test. About 8 * 10^6 pulses, 4 * 10^6 points of 69 bytes: 290 MB in all.
MEMORY_SCRIPT = r"""
import time, beamtrace

def peak_kb():
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            return int(line.split()[1])

survey = {
    "scene": "demo",
    "scanner": {"type": "scan", "width": 4000, "height": 2000, "hfov_deg": 360, "vfov_deg": 90,
                "pulse_rate_hz": 1000000, "range_max_m": 300},
    "platform": {"type": "static", "position_m": [20, -25, 1.944]},
    "output": {"trajectory_rate_hz": 0},
}
first = beamtrace.iter_survey(survey, max_pulses=20000, threads=2)  # loads and warms up the module
sum(len(b) for b in first)
before = peak_kb()
points = blocks = 0
start = time.monotonic()
for block in beamtrace.iter_survey(survey, threads=2, block_points=65536):
    if blocks == 0:
        time.sleep(1.0)  # a slow consumer: a run not bounded by the queue would run ahead
    points += len(block)
    blocks += 1
print(points, block.dtype.itemsize, blocks, peak_kb() - before, time.monotonic() - start)
"""


def test_memory_stays_bounded_whatever_the_survey_size():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    out = subprocess.run([sys.executable, "-c", MEMORY_SCRIPT], capture_output=True, text=True,
                         env=env, check=True, timeout=120).stdout
    points, itemsize, blocks, grown_kb, seconds = out.split()
    whole_bytes = int(points) * int(itemsize)
    assert whole_bytes > 200e6, f"only {whole_bytes / 1e6:.0f} MB of points"
    assert int(blocks) > 40
    # Bounded: far under the 290 MB of points. Measured 41-51 MB since the blocks are handed over
    # on whichever pool thread writes them (two malloc arenas keep freed block arrays; 29 MB
    # with MALLOC_ARENA_MAX=1), 33-37 MB when one writer thread did it all.
    assert int(grown_kb) * 1024 < 64e6, (
        f"peak RSS grew by {int(grown_kb) / 1e3:.0f} MB for {whole_bytes / 1e6:.0f} MB of points "
        f"({seconds} s)")
